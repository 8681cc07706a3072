//! `contact_detect`: test each preselected slave particle against the master triangles
//! (physics.md §4, paper §3): a slave inside a master triangle ABC is a hit. Where a slave lies
//! in several, the one whose segment AB is nearest wins. Hits come out in slave order.

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
    let [r_max, z_min, z_max] = bounds(nodes, 0.0);
    let (nr, nz) = (&nodes.r, &nodes.z);
    slaves
        .par_iter()
        .filter_map(|&s| {
            let (pr, pz) = (particles.r[s as usize], particles.z[s as usize]);
            if pr > r_max || pz < z_min || pz > z_max {
                return None;
            }
            let mut best: Option<(f32, u32)> = None;
            for (k, m) in masters.iter().enumerate() {
                let (a, b, c) = (m.a as usize, m.b as usize, m.c as usize);
                // Material lies left of A→B, so ABC is counter-clockwise.
                let d_ab = orient(nr[a], nz[a], nr[b], nz[b], pr, pz);
                if d_ab < 0.0 {
                    continue;
                }
                if orient(nr[b], nz[b], nr[c], nz[c], pr, pz) < 0.0
                    || orient(nr[c], nz[c], nr[a], nz[a], pr, pz) < 0.0
                {
                    continue;
                }
                let len = (nr[b] - nr[a]).hypot(nz[b] - nz[a]);
                let depth = d_ab / len;
                if best.is_none_or(|(d, _)| depth < d) {
                    best = Some((depth, k as u32));
                }
            }
            best.map(|(_, master)| Hit { slave: s, master })
        })
        .collect()
}
