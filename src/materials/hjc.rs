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

impl Hjc {
    /// The 48 MPa reference set of Holmquist, Johnson & Cook (1993), physics.md §3.1.
    pub fn reference_48mpa() -> Hjc {
        Hjc {
            density: 2440.0,
            shear_modulus: 14.86e9,
            a: 0.79,
            b: 1.60,
            n: 0.61,
            c: 0.007,
            s_max: 7.0,
            fc: 48.0e6,
            t: 4.0e6,
            eps_rate_ref: 1.0,
            ef_min: 0.01,
            d1: 0.04,
            d2: 1.0,
            p_crush: 16.0e6,
            mu_crush: 0.001,
            k1: 85.0e9,
            k2: -171.0e9,
            k3: 208.0e9,
            p_lock: 0.8e9,
            mu_lock: 0.10,
        }
    }

    /// The one rule for other strengths (physics.md §3.1): from f_c (Pa) and ρ₀ (kg/m³) keep the
    /// reference A, B, N, C, S_max, D₁, D₂, EF_min, K₁–K₃, P_lock, μ_lock and set
    /// P_crush = f_c/3, E = 4730 √f_c[MPa] MPa (ACI 318), ν = 0.2, G and K_el from E and ν,
    /// μ_crush = P_crush/K_el, T = 0.62 √f_c[MPa] MPa (ACI 318 modulus of rupture).
    pub fn from_fc(fc: f32, density: f32) -> Hjc {
        let fc_mpa = fc / 1.0e6;
        let youngs = 4730.0e6 * fc_mpa.sqrt();
        let nu = 0.2;
        let shear = youngs / (2.0 * (1.0 + nu));
        let bulk_elastic = youngs / (3.0 * (1.0 - 2.0 * nu));
        let p_crush = fc / 3.0;
        Hjc {
            density,
            shear_modulus: shear,
            fc,
            t: 0.62e6 * fc_mpa.sqrt(),
            p_crush,
            mu_crush: p_crush / bulk_elastic,
            ..Hjc::reference_48mpa()
        }
    }
}
