// `sph_forces` (CPU twin: src/cpu/sph_forces.rs): particle accelerations gathered over
// neighbours and axis ghosts (physics.md §3): the symmetric planar pair term with
// per-radian-area masses, a_i = Σ_j m̃_j [σ_i/ρ_i² + σ_j/ρ_j² − Π_ij I (+ R_ij f_ij^n)] · ∇_i W_ij,
// plus the hoop sources a_r += (S_rr − S_θθ)/(ρ r), a_z += S_rz/(ρ r); Monaghan–Gingold
// viscosity Π_ij with its heating, Gray–Monaghan artificial stress R when enabled.
// Two entry points over one binding list: `prologue` (σ/ρ² and R per particle), then `forces`.
// Needs params.wgsl and grid.wgsl.

@group(0) @binding(0) var<uniform> u: SphUniform;
@group(0) @binding(1) var<storage, read> grid: GridInfo;
@group(0) @binding(2) var<storage, read> cell_start: array<u32>;
@group(0) @binding(3) var<storage, read> sorted: array<u32>;
@group(0) @binding(4) var<storage, read> r: array<f32>;
@group(0) @binding(5) var<storage, read> z: array<f32>;
@group(0) @binding(6) var<storage, read> vr: array<f32>;
@group(0) @binding(7) var<storage, read> vz: array<f32>;
@group(0) @binding(8) var<storage, read> rho: array<f32>;
@group(0) @binding(9) var<storage, read> p: array<f32>;
@group(0) @binding(10) var<storage, read> s_rr: array<f32>;
@group(0) @binding(11) var<storage, read> s_zz: array<f32>;
@group(0) @binding(12) var<storage, read> s_rz: array<f32>;
@group(0) @binding(13) var<storage, read> s_tt: array<f32>;
@group(0) @binding(14) var<storage, read> sound: array<f32>;
@group(0) @binding(15) var<storage, read> m_tilde: array<f32>;
// Written by `prologue`, read by `forces`.
@group(0) @binding(16) var<storage, read_write> stress_rho2: array<array<f32, 3>>;
@group(0) @binding(17) var<storage, read_write> art_stress: array<array<f32, 3>>;
@group(0) @binding(18) var<storage, read_write> ar: array<f32>;
@group(0) @binding(19) var<storage, read_write> az: array<f32>;
@group(0) @binding(20) var<storage, read_write> de_visc: array<f32>;
@group(0) @binding(21) var<storage, read_write> mu_visc: array<f32>;

// η² of the viscosity's singularity guard, in units of h².
const ETA2: f32 = 0.01;
// Smallest base handed to pow (undefined for a base <= 0); W > 0 inside the support anyway.
const POW_BASE_FLOOR: f32 = 1.0e-30;

// sph_rates::hoop_radius: r floored at 0.1 h so the hoop terms stay finite on the axis.
fn hoop_radius(ri: f32, h: f32) -> f32 {
    return max(ri, 0.1 * h);
}

fn vec3_of(a: array<f32, 3>) -> vec3<f32> {
    return vec3<f32>(a[0], a[1], a[2]);
}

// Gray–Monaghan (2001) artificial stress over ρ² in (rr, zz, rz): R = −ε σ'/ρ² on each tensile
// principal stress σ' of the r–z plane, rotated back; zero for compression.
fn artificial_stress(eps: f32, srr: f32, szz: f32, srz: f32, density: f32) -> vec3<f32> {
    let theta = 0.5 * atan2(2.0 * srz, srr - szz);
    let sn = sin(theta);
    let cs = cos(theta);
    let s1 = cs * cs * srr + 2.0 * cs * sn * srz + sn * sn * szz;
    let s2 = sn * sn * srr - 2.0 * cs * sn * srz + cs * cs * szz;
    let inv = -eps / (density * density);
    let r1 = select(0.0, inv * s1, s1 > 0.0);
    let r2 = select(0.0, inv * s2, s2 > 0.0);
    return vec3<f32>(cs * cs * r1 + sn * sn * r2, sn * sn * r1 + cs * cs * r2, cs * sn * (r1 - r2));
}

// Per particle: total stress over ρ², and the artificial stress when it is on.
@compute @workgroup_size(64)
fn prologue(@builtin(global_invocation_id) gid: vec3<u32>) {
    let j = gid.x;
    if (j >= u.n) { return; }
    let inv = 1.0 / (rho[j] * rho[j]);
    stress_rho2[j] = array<f32, 3>((s_rr[j] - p[j]) * inv, (s_zz[j] - p[j]) * inv, s_rz[j] * inv);
    if (u.art_stress_eps > 0.0) {
        let a = artificial_stress(u.art_stress_eps, s_rr[j] - p[j], s_zz[j] - p[j], s_rz[j], rho[j]);
        art_stress[j] = array<f32, 3>(a.x, a.y, a.z);
    }
}

// What the neighbour loop accumulates for particle i.
struct Gather {
    acc: vec2<f32>,
    heat: f32,
    mu_max: f32,
}

// The pair term of neighbour j (its mirror image when sign = −1) at separation d = x_i − x_j.
fn pair(g: ptr<function, Gather>, i: u32, j: u32, d: vec2<f32>, dist: f32, sign: f32) {
    let h = u.kernel.h;
    let mj = m_tilde[j];
    let gw = kernel_grad(u.kernel, d, dist);
    let si = vec3_of(stress_rho2[i]);
    let sj = vec3_of(stress_rho2[j]);
    var t = vec3<f32>(si.x + sj.x, si.y + sj.y, si.z + sign * sj.z);

    let dvr = vr[i] - sign * vr[j];
    let dvz = vz[i] - vz[j];
    let vx = dvr * d.x + dvz * d.y;
    if (vx < 0.0) {
        let mu = h * vx / (dist * dist + ETA2 * h * h);
        let c_mean = 0.5 * (sound[i] + sound[j]);
        let rho_mean = 0.5 * (rho[i] + rho[j]);
        let pi = (-u.alpha * c_mean * mu + u.beta * mu * mu) / rho_mean;
        t.x -= pi;
        t.y -= pi;
        (*g).heat += 0.5 * mj * pi * (dvr * gw.x + dvz * gw.y);
        (*g).mu_max = max((*g).mu_max, -mu);
    }
    if (u.art_stress_eps > 0.0) {
        let ri_art = vec3_of(art_stress[i]);
        let rj_art = vec3_of(art_stress[j]);
        let f = pow(max(kernel_w(u.kernel, dist) / u.w_spacing, POW_BASE_FLOOR), u.art_stress_n);
        t.x += f * (ri_art.x + rj_art.x);
        t.y += f * (ri_art.y + rj_art.y);
        t.z += f * (ri_art.z + sign * rj_art.z);
    }
    (*g).acc.x += mj * (t.x * gw.x + t.z * gw.y);
    (*g).acc.y += mj * (t.z * gw.x + t.y * gw.y);
}

// Per particle: the gather over the 5x5 cells in CellGrid::for_each_candidate's order, each
// candidate as a real neighbour (j != i) and, near the axis, as its mirror ghost (j = i too),
// as cpu::neighbours::for_each_neighbour; then the hoop sources.
@compute @workgroup_size(64)
fn forces(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if (i >= u.n) { return; }
    let info = grid;
    let ri = r[i];
    let zi = z[i];
    let support = 2.0 * u.kernel.h;
    let s2 = support * support;
    let near_axis = ri < support;
    var g = Gather(vec2<f32>(0.0, 0.0), 0.0, 0.0);

    let c = grid_cell(info, ri, zi);
    let r_lo = select(c.x - GRID_REACH, 0u, c.x < GRID_REACH);
    let r_hi = min(c.x + GRID_REACH, info.n_r - 1u);
    let z_lo = select(c.y - GRID_REACH, 0u, c.y < GRID_REACH);
    let z_hi = min(c.y + GRID_REACH, info.n_z - 1u);
    for (var cz = z_lo; cz <= z_hi; cz++) {
        let row = cz * info.n_r;
        let end = cell_start[row + r_hi + 1u];
        for (var k = cell_start[row + r_lo]; k < end; k++) {
            let j = sorted[k];
            let dz = zi - z[j];
            let dz2 = dz * dz;
            if (j != i) {
                let dr = ri - r[j];
                let d2 = dr * dr + dz2;
                if (d2 < s2) {
                    pair(&g, i, j, vec2<f32>(dr, dz), sqrt(d2), 1.0);
                }
            }
            if (near_axis) {
                let dr = ri + r[j];
                let d2 = dr * dr + dz2;
                if (d2 < s2) {
                    pair(&g, i, j, vec2<f32>(dr, dz), sqrt(d2), -1.0);
                }
            }
        }
    }

    let rr = hoop_radius(ri, u.kernel.h);
    var acc = g.acc;
    acc.x += (s_rr[i] - s_tt[i]) / (rho[i] * rr);
    acc.y += s_rz[i] / (rho[i] * rr);
    ar[i] = acc.x;
    az[i] = acc.y;
    de_visc[i] = g.heat;
    mu_visc[i] = g.mu_max;
}
