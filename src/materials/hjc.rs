//! Holmquist–Johnson–Cook concrete, physics.md §3.1.

/// HJC constants. Pressures and strengths in Pa, density in kg/m³.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hjc {
    pub density: f32,
    pub shear_modulus: f32,
    pub a: f32,
    pub b: f32,
    pub n: f32,
    pub c: f32,
    pub s_max: f32,
    pub fc: f32,
    /// Tensile strength T (Pa, positive).
    pub t: f32,
    pub eps_rate_ref: f32,
    pub ef_min: f32,
    pub d1: f32,
    pub d2: f32,
    pub p_crush: f32,
    pub mu_crush: f32,
    pub k1: f32,
    pub k2: f32,
    pub k3: f32,
    pub p_lock: f32,
    pub mu_lock: f32,
}
