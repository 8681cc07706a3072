//! Up-front estimates for `penetrate check`: counts, stable step, step count, memory.

use crate::cpu::fem_stress::Geometry;
use crate::mesh::{self, ProjectileMesh};
use crate::scene::Scene;
use crate::state::FemParams;

/// Bytes of state per particle (28 scalar arrays, 2 three-vectors and the 2 index arrays of
/// the cell grid), per element and per node (with its share of the node → element CSR).
const BYTES_PER_PARTICLE: usize = (28 + 6 + 2) * 4;
const BYTES_PER_ELEMENT: usize = 22 * 4;
const BYTES_PER_NODE: usize = 12 * 4;

#[derive(Clone, Copy, Debug)]
pub struct Estimate {
    pub particles: usize,
    pub slaves: usize,
    pub dt_fem: f64,
    pub dt_sph: f64,
    pub dt: f64,
    pub steps: u64,
    pub bytes: usize,
}

pub fn estimate(s: &Scene, m: &ProjectileMesh) -> Estimate {
    let fem = FemParams::new(&s.projectile.material);
    let k = fem.eos.k1 as f64 + 4.0 / 3.0 * fem.shear_modulus as f64;
    let c_steel = (k / fem.density as f64).sqrt();
    let l_min = m
        .elements
        .iter()
        .map(|el| Geometry::new(el, &m.node_r, &m.node_z).min_altitude() as f64)
        .fold(f64::MAX, f64::min);
    let dt_fem = l_min / c_steel;
    let (particles, slaves, dt_sph) = match &s.target {
        Some(t) => {
            let (cols, rows) = mesh::target::lattice_count(t.radius, t.thickness, t.spacing);
            let r_max = s.projectile.diameter / 2.0;
            let slave_cols =
                ((s.contact.slave_radius_factor * r_max / t.spacing).ceil() as usize).min(cols);
            let c = &t.concrete;
            let c_dense =
                ((c.k1 as f64 + 4.0 / 3.0 * c.shear_modulus as f64) / c.density as f64).sqrt();
            let h = t.spacing * t.smoothing_ratio;
            (
                cols * rows,
                slave_cols * rows,
                h / (c_dense * (1.0 + 1.2 * t.viscosity_alpha)),
            )
        }
        None => (0, 0, f64::MAX),
    };
    let dt = s.run.cfl * dt_fem.min(dt_sph);
    let steps = (s.run.end_time / dt).ceil().min(u64::MAX as f64) as u64;
    let bytes = particles * BYTES_PER_PARTICLE
        + m.elements.len() * BYTES_PER_ELEMENT
        + m.node_r.len() * BYTES_PER_NODE;
    Estimate {
        particles,
        slaves,
        dt_fem,
        dt_sph,
        dt,
        steps: steps.min(s.run.max_steps),
        bytes,
    }
}
