//! Projectile material presets: the constants `[projectile.material] preset = "…"` starts from,
//! before the scene's own constants override them (`scene::resolve`).

/// The constants of `[projectile.material]` before the f32 cast, one field per scene key.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteelConstants {
    /// kg/m³
    pub density: f64,
    /// Pa
    pub youngs_modulus: f64,
    /// -
    pub poisson_ratio: f64,
    /// J/(kg K)
    pub specific_heat: f64,
    /// Fraction β of plastic work that heats the metal.
    pub taylor_quinney: f64,
    /// K
    pub t_room: f64,
    /// K
    pub t_melt: f64,
    /// Johnson–Cook A (Pa).
    pub jc_a: f64,
    /// Johnson–Cook B (Pa).
    pub jc_b: f64,
    /// Johnson–Cook n.
    pub jc_n: f64,
    /// Johnson–Cook C.
    pub jc_c: f64,
    /// Johnson–Cook m.
    pub jc_m: f64,
    /// Reference strain rate (1/s).
    pub eps_rate_ref: f64,
    /// `Some`: the flow stress is Zerilli–Armstrong's, and `jc_a`…`jc_m` are unused.
    pub za: Option<ZaConstants>,
    /// `None`: the bulk modulus E/(3(1 − 2ν)) of the final E and ν.
    pub eos_k1: Option<f64>,
    /// Pa
    pub eos_k2: f64,
    /// Pa
    pub eos_k3: f64,
    /// Grüneisen Γ.
    pub eos_gamma: f64,
    /// `None`: the preset has no damage constants (damage off unless the scene gives them).
    pub damage: Option<DamageConstants>,
}

/// Zerilli–Armstrong fcc constants, one field per scene key `za_<field>`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZaConstants {
    /// Athermal stress C₀ (Pa).
    pub c0: f64,
    /// C₂ (Pa).
    pub c2: f64,
    /// C₃ (1/K).
    pub c3: f64,
    /// C₄ (1/K).
    pub c4: f64,
}

/// Johnson–Cook damage constants, one field per scene key.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DamageConstants {
    /// D₁
    pub d1: f64,
    /// D₂
    pub d2: f64,
    /// D₃
    pub d3: f64,
    /// D₄
    pub d4: f64,
    /// D₅
    pub d5: f64,
    /// Tensile mean stress that spalls the metal (Pa).
    pub spall_stress: f64,
    /// Least failure strain.
    pub eps_f_min: f64,
}

/// The preset names, as `projectile.material.preset` takes them.
pub const PRESETS: [&str; 4] = ["4340-rc30", "4340-rc45", "copper-ofhc", "copper-ofhc-za"];

/// The constants of the preset `name` (one of [`PRESETS`]).
pub fn preset(name: &str) -> Option<SteelConstants> {
    match name {
        "4340-rc30" => Some(steel_4340_rc30()),
        "4340-rc45" => Some(steel_4340_rc45()),
        "copper-ofhc" => Some(copper_ofhc()),
        "copper-ofhc-za" => Some(copper_ofhc_za()),
        _ => None,
    }
}
/// 4340 steel, Rc ≈ 30 temper: the seed paper's constants (physics.md §2.1-2.3; Johnson & Cook
/// 1983/1985 fits). ν = 0.29 is physics.md's choice (the paper gives none).
fn steel_4340_rc30() -> SteelConstants {
    SteelConstants {
        density: 7800.0,
        youngs_modulus: 211.0e9,
        poisson_ratio: 0.29,
        specific_heat: 477.0,
        // β, physics.md §2.1.
        taylor_quinney: 0.9,
        t_room: 293.0,
        t_melt: 1793.0,
        jc_a: 792.0e6,
        jc_b: 510.0e6,
        jc_n: 0.26,
        jc_c: 0.014,
        jc_m: 1.03,
        eps_rate_ref: 1.0,
        za: None,
        // Paper eq. (14), physics.md §2.2.
        eos_k1: Some(163.0e9),
        eos_k2: 294.0e9,
        eos_k3: 140.0e9,
        eos_gamma: 1.16,
        // Paper eq. (15)-(16), physics.md §2.3.
        damage: Some(DamageConstants {
            d1: 0.05,
            d2: 3.44,
            d3: -2.12,
            d4: 0.002,
            d5: 0.61,
            spall_stress: 6.0e9,
            eps_f_min: 0.19,
        }),
    }
}

/// 4340 at Rc 45, the Forrestal penetrators' hardness (Rc 43-45): the hardness-scaled fit of
/// physics.md §2.1, `A(Rc) = exp(0.0355 (Rc − 2) + 5.5312)` MPa and `B = 0.6439 A`; every other
/// constant as Rc 30.
fn steel_4340_rc45() -> SteelConstants {
    const ROCKWELL_C: f64 = 45.0;
    let jc_a = (0.0355 * (ROCKWELL_C - 2.0) + 5.5312).exp() * 1.0e6;
    SteelConstants {
        jc_a,
        jc_b: 0.6439 * jc_a,
        ..steel_4340_rc30()
    }
}

/// OFHC copper, Johnson & Cook (1983) as in `data/taylor.csv` (ρ, E, ν, c_p, A, B, n, C, m,
/// T_melt); T_room 295 K is the Taylor tests' T0. EOS: linear with K₁ the elastic bulk modulus
/// and Γ = 2.0 (copper's Grüneisen coefficient, e.g. Steinberg 1996). No damage constants.
fn copper_ofhc() -> SteelConstants {
    SteelConstants {
        density: 8960.0,
        youngs_modulus: 124.0e9,
        poisson_ratio: 0.34,
        specific_heat: 383.0,
        taylor_quinney: 0.9,
        t_room: 295.0,
        t_melt: 1356.0,
        jc_a: 90.0e6,
        jc_b: 292.0e6,
        jc_n: 0.31,
        jc_c: 0.025,
        jc_m: 1.09,
        eps_rate_ref: 1.0,
        za: None,
        eos_k1: None,
        eos_k2: 0.0,
        eos_k3: 0.0,
        eos_gamma: 2.0,
        damage: None,
    }
}

/// OFHC copper with Zerilli & Armstrong's (1987, J. Appl. Phys. 61, 1816) fcc flow stress
/// σ_y = C₀ + C₂√ε_p exp(−C₃T + C₄T ln ε̇) and their copper constants C₂ = 890 MPa,
/// C₃ = 0.0028/K, C₄ = 0.000115/K, with the athermal C₀ = 46.5 MPa as later evaluations
/// tabulate it (Banerjee 2005; some papers quote 65 MPa, a larger grain-size term:
/// docs/notes/2026-12-copper.md gives both results). Every other constant is `copper-ofhc`'s.
fn copper_ofhc_za() -> SteelConstants {
    SteelConstants {
        za: Some(ZaConstants {
            c0: 46.5e6,
            c2: 890.0e6,
            c3: 0.0028,
            c4: 0.000115,
        }),
        ..copper_ofhc()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_name_has_constants() {
        for name in PRESETS {
            assert!(preset(name).is_some(), "{name}");
        }
        assert!(preset("mild-steel").is_none());
    }
}
