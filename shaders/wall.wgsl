// A particle's wall (CPU twin: src/cpu/wall.rs `Wall`, the same layout): the master segment its
// foot is on (NO_WALL where it has none), the segment's nodes and the foot's weights on them,
// the foot moved into the projectile, the outward normal and the surface's velocity there;
// and how an image is reflected across it.

struct Wall {
    seg: u32,
    a: u32,
    b: u32,
    wa: f32,
    q: vec2<f32>,
    n: vec2<f32>,
    v: vec2<f32>,
    wb: f32,
    pad: f32,
}

// A particle without a wall.
fn no_wall() -> Wall {
    return Wall(NO_WALL, 0u, 0u, 0.0, vec2<f32>(0.0), vec2<f32>(0.0), vec2<f32>(0.0), 0.0, 0.0);
}

// wall.rs `velocity`: v mirrored in the wall's frame.
fn wall_velocity(w: Wall, v: vec2<f32>) -> vec2<f32> {
    let vn = (v.x - w.v.x) * w.n.x + (v.y - w.v.y) * w.n.y;
    return vec2<f32>(v.x - 2.0 * vn * w.n.x, v.y - 2.0 * vn * w.n.y);
}

// wall.rs `gradient`: R L R of a gradient (rr, rz, zr, zz), R = I − 2 n n.
fn wall_gradient(w: Wall, l: vec4<f32>) -> vec4<f32> {
    let a = w.n.x;
    let b = w.n.y;
    let r0 = 1.0 - 2.0 * a * a;
    let r1 = -2.0 * a * b;
    let r2 = 1.0 - 2.0 * b * b;
    let rl = vec4<f32>(r0 * l.x + r1 * l.z, r0 * l.y + r1 * l.w, r1 * l.x + r2 * l.z,
        r1 * l.y + r2 * l.w);
    return vec4<f32>(rl.x * r0 + rl.y * r1, rl.x * r1 + rl.y * r2, rl.z * r0 + rl.w * r1,
        rl.z * r1 + rl.w * r2);
}

// wall.rs `tensor`: R T R of an in-plane tensor (rr, zz, rz).
fn wall_tensor(w: Wall, t: vec3<f32>) -> vec3<f32> {
    let a = w.n.x;
    let b = w.n.y;
    let r0 = 1.0 - 2.0 * a * a;
    let r1 = -2.0 * a * b;
    let r2 = 1.0 - 2.0 * b * b;
    let rt = vec4<f32>(r0 * t.x + r1 * t.z, r0 * t.z + r1 * t.y, r1 * t.x + r2 * t.z,
        r1 * t.z + r2 * t.y);
    return vec3<f32>(rt.x * r0 + rt.y * r1, rt.z * r1 + rt.w * r2, rt.x * r1 + rt.y * r2);
}
