//! Johnson–Cook strength (paper eq. 13) and damage (eq. 15-16), physics.md §2.1 and §2.3.

/// Johnson–Cook flow-stress constants (physics.md §2.1). Units: Pa, K, 1/s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JcStrength {
    pub a: f32,
    pub b: f32,
    pub n: f32,
    pub c: f32,
    pub m: f32,
    /// Reference plastic strain rate ε̇₀ (1/s).
    pub eps_rate_ref: f32,
    pub t_room: f32,
    pub t_melt: f32,
}

/// Johnson–Cook failure-strain constants (physics.md §2.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JcDamage {
    pub d1: f32,
    pub d2: f32,
    pub d3: f32,
    pub d4: f32,
    pub d5: f32,
    /// Tensile mean stress (Pa, positive) beyond which an element spalls at once.
    pub spall_stress: f32,
    /// Failure strain used when the triaxiality σ* ≥ 1.5.
    pub eps_f_min: f32,
}
