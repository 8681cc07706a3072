//! `contact_detect`: test each preselected slave particle against the master triangles
//! (physics.md §4, paper §3). A slave is a hit on master ABC (AB on the surface) when it lies
//! under AB, its foot on AB within the segment, no deeper than C: the strip of AB. The paper
//! takes the triangle ABC itself; the strips also cover the wedge at each surface node between
//! two master triangles, where a slave inside the projectile was in no master (measured: slaves
//! left 0.3–1.4 µm inside). Where a slave lies in several strips, the one whose segment AB is
//! nearest wins. Hits come out in the order of the slave list.

use rayon::prelude::*;

use crate::contact::Hit;
use crate::mesh::MasterSegment;
use crate::state::{Nodes, Particles};

/// Bounding box of the projectile, grown by `margin`: slaves outside it are skipped.
fn bounds(nodes: &Nodes, margin: f32) -> [f32; 3] {
    let mut r_max = 0.0f32;
    let mut z_min = f32::MAX;
    let mut z_max = f32::MIN;
    for i in 0..nodes.len() {
        r_max = r_max.max(nodes.r[i]);
        z_min = z_min.min(nodes.z[i]);
        z_max = z_max.max(nodes.z[i]);
    }
    [r_max + margin, z_min - margin, z_max + margin]
}

/// The slaves inside the projectile's bounding box, with their positions (collected, they
/// keep slave order).
fn in_box<'a>(
    slaves: &'a [u32],
    particles: &'a Particles,
    nodes: &Nodes,
) -> impl ParallelIterator<Item = (u32, f32, f32)> + 'a {
    let [r_max, z_min, z_max] = bounds(nodes, 0.0);
    slaves.par_iter().filter_map(move |&s| {
        let (pr, pz) = (particles.r[s as usize], particles.z[s as usize]);
        (pr <= r_max && pz >= z_min && pz <= z_max).then_some((s, pr, pz))
    })
}

/// Twice the signed area of (a, b, p): positive when p is left of a → b.
#[inline]
fn orient(ar: f32, az: f32, br: f32, bz: f32, pr: f32, pz: f32) -> f32 {
    (br - ar) * (pz - az) - (bz - az) * (pr - ar)
}

pub fn run(
    slaves: &[u32],
    particles: &Particles,
    nodes: &Nodes,
    masters: &[MasterSegment],
) -> Vec<Hit> {
    let (nr, nz) = (&nodes.r, &nodes.z);
    in_box(slaves, particles, nodes)
        .filter_map(|(s, pr, pz)| {
            let mut best: Option<(f32, u32)> = None;
            for (k, m) in masters.iter().enumerate() {
                let (a, b, c) = (m.a as usize, m.b as usize, m.c as usize);
                // Material lies left of A→B, so ABC is counter-clockwise.
                let d_ab = orient(nr[a], nz[a], nr[b], nz[b], pr, pz);
                if d_ab < 0.0 {
                    continue;
                }
                let (er, ez) = (nr[b] - nr[a], nz[b] - nz[a]);
                let t = ((pr - nr[a]) * er + (pz - nz[a]) * ez) / (er * er + ez * ez);
                if !(0.0..=1.0).contains(&t)
                    || d_ab > orient(nr[a], nz[a], nr[b], nz[b], nr[c], nz[c])
                {
                    continue;
                }
                let len = er.hypot(ez);
                let depth = d_ab / len;
                if best.is_none_or(|(d, _)| depth < d) {
                    best = Some((depth, k as u32));
                }
            }
            best.map(|(_, master)| Hit { slave: s, master })
        })
        .collect()
}

/// Slaves inside the projectile's outline (the master chain, closed by the axis) by more than
/// `tol`, and the deepest such distance to the outline (m): after the correction there should
/// be none. Unlike `run`, this sees a slave however deep it went, not only in the masters.
pub fn inside(
    slaves: &[u32],
    particles: &Particles,
    nodes: &Nodes,
    masters: &[MasterSegment],
    tol: f32,
) -> (usize, f32) {
    let (nr, nz) = (&nodes.r, &nodes.z);
    in_box(slaves, particles, nodes)
        .filter_map(|(_, pr, pz)| {
            // Even-odd rule along +r; the axis closes the chain and a ray along +r never
            // crosses it.
            let mut crossings = 0u32;
            let mut dist = f32::MAX;
            for m in masters {
                let (a, b) = (m.a as usize, m.b as usize);
                let (ar, az, br, bz) = (nr[a], nz[a], nr[b], nz[b]);
                if (az > pz) != (bz > pz) {
                    let r_cross = ar + (pz - az) / (bz - az) * (br - ar);
                    if r_cross > pr {
                        crossings += 1;
                    }
                }
                let (er, ez) = (br - ar, bz - az);
                let t = (((pr - ar) * er + (pz - az) * ez) / (er * er + ez * ez)).clamp(0.0, 1.0);
                dist = dist.min((ar + t * er - pr).hypot(az + t * ez - pz));
            }
            (crossings % 2 == 1 && dist > tol).then_some(dist)
        })
        .fold(|| (0, 0.0f32), |(n, d), x| (n + 1, d.max(x)))
        .reduce(|| (0, 0.0f32), |a, b| (a.0 + b.0, a.1.max(b.1)))
}
