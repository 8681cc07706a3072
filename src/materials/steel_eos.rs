//! Polynomial equation of state of the steel, paper eq. (14), physics.md §2.2.

/// `p = K₁μ + K₂μ² + K₃μ³ + Γ E (1 + μ)` (Pa), linear term only for μ < 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolyEos {
    pub k1: f32,
    pub k2: f32,
    pub k3: f32,
    pub gamma: f32,
}

/// Floor of the bulk tangent as a fraction of K₁: with K₂ < 0 sets the cubic's slope could dip
/// towards zero or below, and the sound speed sqrt((K + 4G/3)/ρ) must stay real and not vanish.
pub const BULK_TANGENT_FLOOR: f32 = 0.1;

/// Pressure, paper eq. (14), physics.md §2.2 (Pa, compression-positive):
/// p = K₁μ + K₂μ² + K₃μ³ + ΓE(1 + μ) for μ ≥ 0 and p = K₁μ + ΓE(1 + μ) for μ < 0, with
/// μ = ρ/ρ₀ − 1 and E the internal energy per unit reference volume (J/m³).
pub fn pressure(eos: &PolyEos, mu: f32, e_vol: f32) -> f32 {
    // The higher-order terms only act in compression; max(μ, 0) does that without a branch.
    let mc = mu.max(0.0);
    eos.k1 * mu + (eos.k2 + eos.k3 * mc) * mc * mc + eos.gamma * e_vol * (1.0 + mu)
}

/// Cold bulk tangent dp/dμ of eq. (14) (Pa): K₁ + 2K₂μ + 3K₃μ² for μ ≥ 0, K₁ for μ < 0, floored
/// at [`BULK_TANGENT_FLOOR`]·K₁ so the sound speed stays real.
pub fn bulk_tangent(eos: &PolyEos, mu: f32) -> f32 {
    let mc = mu.max(0.0);
    (eos.k1 + (2.0 * eos.k2 + 3.0 * eos.k3 * mc) * mc).max(BULK_TANGENT_FLOOR * eos.k1)
}

/// Largest Grüneisen Γ a scene may set. Solid metals have Γ ≈ 1–3 (the paper's 4340: 1.16,
/// copper: 2.0). The element's sound speed is the cold one, sqrt((dp/dμ + 4G/3)/ρ): it leaves
/// out Γ (E/ρ₀ + p/ρ), which at Γ ≤ 5 and the pressures and heating of an impact is a few per
/// cent of c² and within the Courant number's margin; far above it the step is too long (a
/// 4340 Taylor bar with Γ = 100 loses its energy balance in 14 steps).
pub const MAX_GAMMA: f32 = 5.0;

/// Compression up to which the cold curve must rise: the steel at twice its density, beyond any
/// impact this code models.
pub const MAX_CHECKED_MU: f64 = 1.0;

/// Why the cold compression curve K₁μ + K₂μ² + K₃μ³ is not an equation of state, or `None`:
/// its slope must stay positive for 0 ≤ μ ≤ [`MAX_CHECKED_MU`] (a pressure that falls as the
/// steel is compressed has no real sound speed; [`bulk_tangent`]'s floor only keeps the step
/// finite while the slope dips between 0 and 0.1 K₁), and may not stiffen beyond any solid's
/// ([`super::stiffening_fault`]).
pub fn compression_fault(eos: &PolyEos) -> Option<String> {
    let (slope, at) =
        super::least_cubic_slope(eos.k1 as f64, eos.k2 as f64, eos.k3 as f64, MAX_CHECKED_MU);
    let rises = slope > 0.0;
    if !rises {
        return Some(format!(
            "the cold compression curve K1 μ + K2 μ² + K3 μ³ must rise up to μ = \
             {MAX_CHECKED_MU}: its slope K1 + 2 K2 μ + 3 K3 μ² is {slope:.4e} Pa at μ = {at:.4e}"
        ));
    }
    super::stiffening_fault(
        "the cold compression curve K1 μ + K2 μ² + K3 μ³",
        eos.k1 as f64,
        eos.k2 as f64,
        eos.k3 as f64,
    )
}

#[cfg(test)]
mod tests {
    use super::super::assert_rel;
    use super::*;

    /// The paper's 4340 constants (physics.md §2.2).
    fn steel() -> PolyEos {
        PolyEos {
            k1: 163.0e9,
            k2: 294.0e9,
            k3: 140.0e9,
            gamma: 1.16,
        }
    }

    /// The paper's steel passes; a K₂ of −1e30 (pressure falling at once) or a K₃ of −1e12
    /// (falling from μ ≈ 0.35) is named.
    #[test]
    fn a_falling_compression_curve_is_refused() {
        assert_eq!(compression_fault(&steel()), None);
        for eos in [
            PolyEos {
                k2: -1.0e30,
                ..steel()
            },
            PolyEos {
                k3: -1.0e12,
                ..steel()
            },
        ] {
            let why = compression_fault(&eos).expect("refused");
            assert!(why.contains("cold compression curve"), "{why}");
        }
    }

    /// A K₃ of 1e30 Pa (the steel's is 1.4e11) stiffens the curve 1.8e17 times by μ = 0.1 and
    /// is named; the paper's steel stiffens 1.39 times (226 against 163 GPa), and a K₂ that
    /// brings it just under the bound passes.
    #[test]
    fn a_curve_stiffer_than_any_solid_is_refused() {
        let why = compression_fault(&PolyEos {
            k3: 1.0e30,
            ..steel()
        })
        .expect("refused");
        assert!(
            why.contains("stiffens") && why.contains("wrong unit"),
            "{why}"
        );
        // 163e9 + 2·k2·0.1 + 3·140e9·0.01 = 100·163e9 at k2 = (16300 − 163 − 4.2)e9/0.2
        let edge = (16300.0e9 - 163.0e9 - 4.2e9) / 0.2;
        for (k2, refused) in [(0.99 * edge, false), (1.01 * edge, true)] {
            let eos = PolyEos { k2, ..steel() };
            assert_eq!(compression_fault(&eos).is_some(), refused, "K2 = {k2:e}");
        }
    }

    #[test]
    fn pressure_matches_eq_14() {
        let eos = steel();
        // μ = −0.01, E = 1e8 J/m³: K₁μ + ΓE(1+μ) = −1.63e9 + 1.16e8·0.99 = −1.63e9 + 0.11484e9
        //   = −1.51516e9 (no K₂, K₃ in tension)
        assert_rel(pressure(&eos, -0.01, 1.0e8), -1.51516e9, 1e-5);
        // μ = 0.02, E = 1e8: 3.26e9 + 294e9·4e-4 + 140e9·8e-6 + 1.16e8·1.02
        //   = 3.26e9 + 0.1176e9 + 0.00112e9 + 0.11832e9 = 3.49704e9
        assert_rel(pressure(&eos, 0.02, 1.0e8), 3.49704e9, 1e-5);
        // μ = 0.1, E = 0: 16.3e9 + 2.94e9 + 0.14e9 = 19.38e9
        assert_rel(pressure(&eos, 0.1, 0.0), 19.38e9, 1e-5);
        // μ = 0.1, E = 1e8: 19.38e9 + 1.16e8·1.1 = 19.5076e9
        assert_rel(pressure(&eos, 0.1, 1.0e8), 19.5076e9, 1e-5);
    }

    #[test]
    fn bulk_tangent_matches_derivative_and_floor() {
        let eos = steel();
        // μ < 0: K₁ = 163 GPa
        assert_rel(bulk_tangent(&eos, -0.01), 163.0e9, 1e-6);
        // μ = 0.02: 163e9 + 2·294e9·0.02 + 3·140e9·4e-4 = 163e9 + 11.76e9 + 0.168e9 = 174.928e9
        assert_rel(bulk_tangent(&eos, 0.02), 174.928e9, 1e-5);
        // μ = 0.1: 163e9 + 58.8e9 + 4.2e9 = 226e9
        assert_rel(bulk_tangent(&eos, 0.1), 226.0e9, 1e-5);
        // A softening set (K₂ < 0) is floored at 0.1 K₁: 100e9 − 2·1000e9·0.1 < 0 → 10e9.
        let soft = PolyEos {
            k1: 100.0e9,
            k2: -1000.0e9,
            k3: 0.0,
            gamma: 0.0,
        };
        assert_rel(bulk_tangent(&soft, 0.1), 10.0e9, 1e-6);
    }
}
