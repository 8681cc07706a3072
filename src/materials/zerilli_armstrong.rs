//! Zerilli–Armstrong flow stress for fcc metals (Zerilli & Armstrong 1987, J. Appl. Phys. 61,
//! 1816, eq. 7): the strength law of the `copper-ofhc-za` preset.
//!
//! In an fcc metal the thermally activated part of the flow stress is the strain-hardening
//! part: dislocations cut through forests that the strain itself builds, so the strain rate and
//! the temperature scale C₂√ε_p and leave the yield stress C₀ alone (Follansbee & Kocks 1988
//! measured the same for copper: the rate sensitivity is that of its hardening). Johnson–Cook's
//! (1 + C ln ε̇*) multiplies the whole flow stress, yield included.
//!
//! The law alone: which law a material takes, the hardening floor and the radial return are
//! flow.rs's, which calls into this module, never the other way round.

/// Zerilli–Armstrong fcc constants. Units: Pa, 1/K.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ZaFcc {
    /// C₀ = Δσ'_G + k l^(−1/2): the athermal stress, the grain-size term included.
    pub c0: f32,
    /// C₂: the strain-hardening coefficient.
    pub c2: f32,
    /// C₃: the thermal softening of the hardening term (1/K).
    pub c3: f32,
    /// C₄: the rate sensitivity of the hardening term (1/K).
    pub c4: f32,
}

/// The thermally activated factor exp(−C₃T + C₄T ln ε̇*), ε̇* = max(ε̇/ε̇₀, 1) with ε̇₀ = 1/s,
/// the unit Zerilli and Armstrong give ε̇ in (the same floor as Johnson–Cook's rate term). T in K.
/// The exponent is −T(C₃ − C₄ ln ε̇*), and C₃/C₄ is the log of the rate at which thermal
/// activation stops mattering (e^24.3 ≈ 3.6e10/s for copper): beyond it the factor is held at
/// its 0 K value 1, the full athermal hardening, so no rate or constant overflows it (an
/// infinite factor times C₂ = 0 would be NaN).
fn activation(z: &ZaFcc, eps_rate: f32, eps_rate_ref: f32, temperature: f32) -> f32 {
    let ln_rate = (eps_rate / eps_rate_ref).max(1.0).ln();
    (temperature.max(0.0) * (z.c4 * ln_rate - z.c3))
        .min(0.0)
        .exp()
}

/// Flow stress, Zerilli & Armstrong (1987) eq. (7): σ_y = C₀ + C₂ √ε_p exp(−C₃T + C₄T ln ε̇*),
/// ε_p < 0 read as 0. Pa.
pub fn flow_stress(
    z: &ZaFcc,
    eps_p: f32,
    eps_rate: f32,
    eps_rate_ref: f32,
    temperature: f32,
) -> f32 {
    z.c0 + z.c2 * eps_p.max(0.0).sqrt() * activation(z, eps_rate, eps_rate_ref, temperature)
}

/// Hardening modulus H = dσ_y/dε_p = C₂ exp(−C₃T + C₄T ln ε̇*)/(2√ε_p), Pa. Infinite at
/// ε_p = 0 (as Johnson–Cook's for n < 1): the caller floors ε_p first
/// (`flow::hardening_modulus`), so it must be > 0.
pub fn hardening_modulus(
    z: &ZaFcc,
    eps_p: f32,
    eps_rate: f32,
    eps_rate_ref: f32,
    temperature: f32,
) -> f32 {
    debug_assert!(
        eps_p > 0.0,
        "Zerilli–Armstrong H at ε_p = {eps_p}: floor it first"
    );
    let root = eps_p.sqrt();
    0.5 * z.c2 * activation(z, eps_rate, eps_rate_ref, temperature) / root
}

#[cfg(test)]
mod tests {
    use super::super::assert_rel;
    use super::*;

    /// Zerilli & Armstrong's (1987) OFHC copper set.
    fn copper() -> ZaFcc {
        ZaFcc {
            c0: 46.5e6,
            c2: 890.0e6,
            c3: 0.0028,
            c4: 0.000115,
        }
    }

    #[test]
    fn flow_stress_matches_hand_value() {
        // T = 295 K, ε̇ = 1e4/s: −0.0028·295 + 0.000115·295·ln 1e4 = −0.826 + 0.0339250·9.2103404
        // = −0.826 + 0.3124608 = −0.5135392, e^… = 0.5983741; √0.25 = 0.5
        // σ_y = 46.5 + 890·0.5·0.5983741 = 46.5 + 266.2765 = 312.7765 MPa
        assert_rel(
            flow_stress(&copper(), 0.25, 1.0e4, 1.0, 295.0),
            312.7765e6,
            1e-5,
        );
        // H = 890·0.5983741/(2·0.5) = 532.5529 MPa
        assert_rel(
            hardening_modulus(&copper(), 0.25, 1.0e4, 1.0, 295.0),
            532.5529e6,
            1e-5,
        );
    }

    /// The yield stress C₀ carries no rate or temperature: an fcc metal's first yield is
    /// athermal, which is what sets this law apart from Johnson–Cook's.
    #[test]
    fn yield_is_athermal_and_hardening_is_thermally_activated() {
        let z = copper();
        for (rate, temp) in [(1.0, 295.0), (1.0e5, 295.0), (1.0e3, 900.0)] {
            assert_eq!(flow_stress(&z, 0.0, rate, 1.0, temp), z.c0);
        }
        let slow = flow_stress(&z, 0.5, 1.0, 1.0, 295.0);
        let fast = flow_stress(&z, 0.5, 1.0e4, 1.0, 295.0);
        let hot = flow_stress(&z, 0.5, 1.0e4, 1.0, 600.0);
        assert!(fast > slow && hot < fast, "{slow} {fast} {hot}");
        // Below ε̇₀ the rate term is floored, as Johnson–Cook's.
        assert_eq!(
            flow_stress(&z, 0.5, 1.0e-3, 1.0, 295.0),
            flow_stress(&z, 0.5, 1.0, 1.0, 295.0)
        );
    }

    /// Beyond the rate C₃/C₄ sets, the factor stays at 1: a rate-only law (C₃ = 0) is the
    /// athermal C₀ + C₂√ε_p, finite, and with C₂ = 0 exactly C₀, not NaN.
    #[test]
    fn the_activation_never_exceeds_its_zero_kelvin_value() {
        let z = ZaFcc {
            c3: 0.0,
            c4: 0.1,
            ..copper()
        };
        let athermal = z.c0 + z.c2 * 0.5;
        assert_eq!(flow_stress(&z, 0.25, 1.0e5, 1.0, 295.0), athermal);
        let no_hardening = ZaFcc { c2: 0.0, ..z };
        assert_eq!(flow_stress(&no_hardening, 0.25, 1.0e5, 1.0, 295.0), z.c0);
        assert_eq!(
            hardening_modulus(&no_hardening, 0.25, 1.0e5, 1.0, 295.0),
            0.0
        );
        // Copper's own constants stay below it up to e^(C₃/C₄) ≈ 3.6e10/s.
        assert!(flow_stress(&copper(), 0.25, 1.0e10, 1.0, 295.0) < athermal);
    }

    /// H is the derivative of σ_y (central difference; flow.rs tests the floor at ε_p = 0).
    #[test]
    fn hardening_modulus_is_the_slope() {
        let z = copper();
        let (e, h) = (0.3_f64, 1.0e-4_f64);
        let up = flow_stress(&z, (e + h) as f32, 1.0e3, 1.0, 400.0) as f64;
        let down = flow_stress(&z, (e - h) as f32, 1.0e3, 1.0, 400.0) as f64;
        assert_rel(
            hardening_modulus(&z, e as f32, 1.0e3, 1.0, 400.0),
            (up - down) / (2.0 * h),
            2e-3,
        );
    }
}
