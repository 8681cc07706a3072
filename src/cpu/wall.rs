//! `wall`: the projectile's surface as the concrete's kernel sees it. A particle within the
//! kernel's support of the surface takes, besides its neighbours, their mirror images across
//! the tangent at its nearest surface point (its own image included), so its sums run over a
//! whole kernel: the compaction a nose drives into the particles lining it is read in full, and
//! the particle's own stress no longer pushes it against an empty side (docs/physics.md §4).
//!
//! An image moves as its source mirrored in the wall's frame (free slip: the normal velocity
//! relative to the wall reversed, the tangential kept) and carries its source's stress
//! reflected. What the images exert on a particle the projectile takes back at the foot, split
//! onto the segment's two nodes by the foot's weights, so momentum is conserved; the particle
//! books the images' whole work relative to the wall (`sph_forces`). Passes `walls` (find each
//! particle's wall, before `sph_rates`) and `wall_forces` (sum the reactions per master segment
//! and add them to the nodes, after the projectile's own forces); GPU twin shaders/wall.wgsl.

use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;

use super::neighbours::CellGrid;
use crate::kernel::Kernel;
use crate::mesh::MasterSegment;
use crate::state::Nodes;

/// `Wall::seg` of a particle without a wall.
pub const NO_WALL: u32 = u32::MAX;

/// The line the images mirror across lies this many particle spacings inside the projectile's
/// surface: the contact keeps the lining on the surface, and a lattice continued past its first
/// row would put its boundary half a spacing beyond it (docs/notes/2026-12-wall-images.md: on
/// the surface itself the first row sits on its own images and the wall is over-complete).
pub const OFFSET_SPACINGS: f32 = 0.5;

/// A particle's wall: its nearest point on the projectile's surface and the tangent there. The
/// layout is shaders/wall.wgsl's `Wall`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Wall {
    /// The master segment the foot is on, `NO_WALL` where the particle has no wall.
    pub seg: u32,
    /// The segment's nodes, and the foot's weight on A.
    pub a: u32,
    pub b: u32,
    pub wa: f32,
    /// The foot, moved `OFFSET_SPACINGS` into the projectile (m).
    pub qr: f32,
    pub qz: f32,
    /// The outward unit normal (into the concrete).
    pub nr: f32,
    pub nz: f32,
    /// The surface's velocity at the foot.
    pub vr: f32,
    pub vz: f32,
    /// The foot's weight on B.
    pub wb: f32,
    pub pad: f32,
}

impl Default for Wall {
    fn default() -> Wall {
        Wall {
            seg: NO_WALL,
            ..Zeroable::zeroed()
        }
    }
}

/// One image in a particle's sums.
pub struct Image {
    /// The source particle.
    pub j: usize,
    /// x_i − x_image, its length and ∇_i W.
    pub dr: f32,
    pub dz: f32,
    pub dist: f32,
    pub grad: [f32; 2],
    /// The image's radius (m, ≥ 0).
    pub r: f32,
}

impl Wall {
    /// Whether the particle has a wall.
    #[inline]
    pub fn on(&self) -> bool {
        self.seg != NO_WALL
    }

    /// The velocity (vr, vz) mirrored in the wall's frame.
    #[inline]
    pub fn velocity(&self, vr: f32, vz: f32) -> (f32, f32) {
        let vn = (vr - self.vr) * self.nr + (vz - self.vz) * self.nz;
        (vr - 2.0 * vn * self.nr, vz - 2.0 * vn * self.nz)
    }

    /// A velocity gradient (rr, rz, zr, zz) as an image has it: R L R with R = I − 2 n n.
    #[inline]
    pub fn gradient(&self, l: [f32; 4]) -> [f32; 4] {
        let (a, b) = (self.nr, self.nz);
        let (r0, r1, r2) = (1.0 - 2.0 * a * a, -2.0 * a * b, 1.0 - 2.0 * b * b);
        // R L: [[r0, r1], [r1, r2]] [[l0, l1], [l2, l3]]
        let rl = [
            r0 * l[0] + r1 * l[2],
            r0 * l[1] + r1 * l[3],
            r1 * l[0] + r2 * l[2],
            r1 * l[1] + r2 * l[3],
        ];
        [
            rl[0] * r0 + rl[1] * r1,
            rl[0] * r1 + rl[1] * r2,
            rl[2] * r0 + rl[3] * r1,
            rl[2] * r1 + rl[3] * r2,
        ]
    }

    /// The in-plane tensor (rr, zz, rz) reflected: R T R with R = I − 2 n n.
    #[inline]
    pub fn tensor(&self, t: [f32; 3]) -> [f32; 3] {
        let (a, b) = (self.nr, self.nz);
        let r = [1.0 - 2.0 * a * a, -2.0 * a * b, 1.0 - 2.0 * b * b]; // rr, rz, zz
                                                                      // R T: rows (r0, r1), (r1, r2); T = [[t0, t2], [t2, t1]]
        let rt = [
            r[0] * t[0] + r[1] * t[2],
            r[0] * t[2] + r[1] * t[1],
            r[1] * t[0] + r[2] * t[2],
            r[1] * t[2] + r[2] * t[1],
        ];
        [
            rt[0] * r[0] + rt[1] * r[1],
            rt[2] * r[1] + rt[3] * r[2],
            rt[0] * r[1] + rt[1] * r[2],
        ]
    }

    /// Every image within the support of particle i: of i itself, then of each of its
    /// neighbours (in the list's order) on the concrete's side of the mirror line. An image is
    /// never nearer to i than its source, so i's neighbours hold every image in reach.
    pub fn images(
        &self,
        i: usize,
        r: &[f32],
        z: &[f32],
        grid: &CellGrid,
        kernel: &Kernel,
        mut f: impl FnMut(Image),
    ) {
        let support = kernel.support();
        let (ri, zi) = (r[i], z[i]);
        let mut one = |j: usize| {
            let side = (r[j] - self.qr) * self.nr + (z[j] - self.qz) * self.nz;
            if side <= 0.0 {
                return;
            }
            let (gr, gz) = (r[j] - 2.0 * side * self.nr, z[j] - 2.0 * side * self.nz);
            let (dr, dz) = (ri - gr, zi - gz);
            let dist = dr.hypot(dz);
            if dist >= support {
                return;
            }
            f(Image {
                j,
                dr,
                dz,
                dist,
                grad: kernel.grad(dr, dz, dist),
                r: gr.max(0.0),
            })
        };
        one(i);
        for nb in grid.neighbours(i) {
            if !nb.mirror() {
                one(nb.j());
            }
        }
    }
}

/// The nodes' bounding box (r_max, z_min, z_max).
pub fn node_box(nodes: &Nodes) -> [f32; 3] {
    let mut b = [0.0f32, f32::MAX, f32::MIN];
    for k in 0..nodes.len() {
        b[0] = b[0].max(nodes.r[k]);
        b[1] = b[1].min(nodes.z[k]);
        b[2] = b[2].max(nodes.z[k]);
    }
    b
}

/// Particle (pr, pz)'s wall: the nearest point of the master chain within `support` of it and
/// outside the projectile, `None` where there is none. `bounds` is a box holding every node
/// (r_max, z_min, z_max), which only spares the search for particles out of reach.
#[allow(clippy::too_many_arguments)]
pub fn find_one(
    pr: f32,
    pz: f32,
    nodes: &Nodes,
    masters: &[MasterSegment],
    bounds: [f32; 3],
    support: f32,
    offset: f32,
) -> Option<Wall> {
    let (nr, nz) = (&nodes.r, &nodes.z);
    if pr > bounds[0] + support || pz < bounds[1] - support || pz > bounds[2] + support {
        return None;
    }
    let mut best: Option<(f32, usize, f32)> = None;
    for (k, m) in masters.iter().enumerate() {
        let (a, b) = (m.a as usize, m.b as usize);
        let (er, ez) = (nr[b] - nr[a], nz[b] - nz[a]);
        let t = (((pr - nr[a]) * er + (pz - nz[a]) * ez) / (er * er + ez * ez)).clamp(0.0, 1.0);
        let d = (nr[a] + t * er - pr).hypot(nz[a] + t * ez - pz);
        if best.is_none_or(|(bd, _, _)| d < bd) {
            best = Some((d, k, t));
        }
    }
    let (d, k, t) = best?;
    if d >= support || d <= 0.0 {
        return None;
    }
    let m = &masters[k];
    let (a, b) = (m.a as usize, m.b as usize);
    let (er, ez) = (nr[b] - nr[a], nz[b] - nz[a]);
    let len = er.hypot(ez);
    // The projectile lies left of A → B: the outward normal is (e_z, −e_r)/|e|.
    let (sr, sz) = (ez / len, -er / len);
    let (qr, qz) = (nr[a] + t * er, nz[a] + t * ez);
    if (pr - qr) * sr + (pz - qz) * sz <= 0.0 {
        return None; // inside: the contact's to correct
    }
    // Off a segment's end the nearest point is a node: the normal points at the particle.
    let (n_r, n_z) = if t > 0.0 && t < 1.0 {
        (sr, sz)
    } else {
        ((pr - qr) / d, (pz - qz) / d)
    };
    let (wa, wb) = (1.0 - t, t);
    Some(Wall {
        seg: k as u32,
        a: m.a,
        b: m.b,
        wa,
        qr: qr - offset * n_r,
        qz: qz - offset * n_z,
        nr: n_r,
        nz: n_z,
        vr: wa * nodes.vr[a] + wb * nodes.vr[b],
        vz: wa * nodes.vz[a] + wb * nodes.vz[b],
        wb,
        pad: 0.0,
    })
}

/// `walls`: each particle's wall (`NO_WALL` where it has none), into `walls`.
pub fn find(
    walls: &mut Vec<Wall>,
    r: &[f32],
    z: &[f32],
    nodes: &Nodes,
    masters: &[MasterSegment],
    support: f32,
    offset: f32,
) {
    let bounds = node_box(nodes);
    walls.resize(r.len(), Wall::default());
    walls.par_iter_mut().enumerate().for_each(|(i, w)| {
        *w = find_one(r[i], z[i], nodes, masters, bounds, support, offset).unwrap_or_default();
    });
}

/// Per master segment, the sums Σ w_a f and Σ w_b f (r, z of each: [A_r, A_z, B_r, B_z]) of
/// the ring forces `reaction` (N, per particle) that the images exert on the particles whose
/// foot is on it, in particle order.
pub fn segment_sums(walls: &[Wall], reaction: &[[f32; 2]], n_masters: usize) -> Vec<[f32; 4]> {
    let mut sums = vec![[0.0f32; 4]; n_masters];
    for (w, f) in walls.iter().zip(reaction) {
        if !w.on() {
            continue;
        }
        let s = &mut sums[w.seg as usize];
        s[0] += w.wa * f[0];
        s[1] += w.wa * f[1];
        s[2] += w.wb * f[0];
        s[3] += w.wb * f[1];
    }
    sums
}

/// `wall_forces`: the nodes take the segments' sums back, reversed, after their elements'
/// forces, segment by segment in order (as shaders/integrate.wgsl gathers them).
pub fn react(nodes: &mut Nodes, masters: &[MasterSegment], sums: &[[f32; 4]]) {
    for (m, s) in masters.iter().zip(sums) {
        let (a, b) = (m.a as usize, m.b as usize);
        nodes.fr[a] += -s[0];
        nodes.fz[a] += -s[1];
        nodes.fr[b] += -s[2];
        nodes.fz[b] += -s[3];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall(nr: f32, nz: f32) -> Wall {
        Wall {
            seg: 0,
            nr,
            nz,
            vr: 3.0,
            vz: -40.0,
            ..Wall::default()
        }
    }

    /// Across a wall of normal z an image keeps σ_rr and σ_zz and flips σ_rz; reflecting twice
    /// gives the tensor back; the image velocity reverses the normal part relative to the wall
    /// and keeps the tangential, so the wall's own velocity is its own image.
    #[test]
    fn images_reflect_stress_gradient_and_velocity() {
        let flat = wall(0.0, 1.0);
        assert_eq!(flat.tensor([1.0, 2.0, 3.0]), [1.0, 2.0, -3.0]);
        assert_eq!(flat.gradient([1.0, 2.0, 3.0, 4.0]), [1.0, -2.0, -3.0, 4.0]);
        assert_eq!(flat.velocity(5.0, -30.0), (5.0, -50.0));
        let (a, b) = (0.6f32, 0.8f32);
        let tilted = wall(a, b);
        let t = [1.5, -2.0, 0.7];
        let back = tilted.tensor(tilted.tensor(t));
        let l = [0.3, -1.1, 2.0, 0.4];
        let l_back = tilted.gradient(tilted.gradient(l));
        for k in 0..3 {
            assert!((back[k] - t[k]).abs() < 1e-6, "{back:?}");
        }
        for k in 0..4 {
            assert!((l_back[k] - l[k]).abs() < 1e-6, "{l_back:?}");
        }
        let (vr, vz) = tilted.velocity(tilted.vr, tilted.vz);
        assert!((vr - tilted.vr).abs() < 1e-5 && (vz - tilted.vz).abs() < 1e-5);
        // n·σ·n is kept: the normal traction on the wall is the source's.
        let nsn = |t: [f32; 3]| a * a * t[0] + b * b * t[1] + 2.0 * a * b * t[2];
        assert!((nsn(tilted.tensor(t)) - nsn(t)).abs() < 1e-6);
    }
}
