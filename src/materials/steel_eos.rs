//! Polynomial equation of state of the steel, paper eq. (14), physics.md §2.2.

/// `p = K₁μ + K₂μ² + K₃μ³ + Γ E (1 + μ)` (Pa), linear term only for μ < 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolyEos {
    pub k1: f32,
    pub k2: f32,
    pub k3: f32,
    pub gamma: f32,
}
/// Pressure, paper eq. (14): p = K₁μ + K₂μ² + K₃μ³ + Γ E (1 + μ) for μ ≥ 0 and
/// p = K₁μ + Γ E (1 + μ) for μ < 0 (physics.md §2.2); μ = ρ/ρ₀ − 1, E internal energy per unit
/// reference volume (J/m³).
pub fn pressure(eos: &PolyEos, mu: f32, e_vol: f32) -> f32 {
    let cold = if mu >= 0.0 {
        mu * (eos.k1 + mu * (eos.k2 + mu * eos.k3))
    } else {
        eos.k1 * mu
    };
    cold + eos.gamma * e_vol * (1.0 + mu)
}

/// dp/dμ of the cold curve, for the sound speed: K₁ + 2K₂μ + 3K₃μ² (μ ≥ 0), K₁ below; floored
/// at 0.1 K₁ so the sound speed stays real however the polynomial bends.
pub fn bulk_tangent(eos: &PolyEos, mu: f32) -> f32 {
    if mu >= 0.0 {
        (eos.k1 + mu * (2.0 * eos.k2 + 3.0 * eos.k3 * mu)).max(0.1 * eos.k1)
    } else {
        eos.k1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const EOS: PolyEos = PolyEos {
        k1: 163e9,
        k2: 294e9,
        k3: 140e9,
        gamma: 1.16,
    };

    /// By hand, with the paper's 4340 constants:
    /// μ = 0.02, E = 0: 163e9·0.02 + 294e9·4e-4 + 140e9·8e-6 = 3.26e9 + 0.1176e9 + 0.00112e9 = 3.37872e9;
    /// μ = 0.1, E = 1e8: 16.3e9 + 2.94e9 + 0.14e9 + 1.16·1e8·1.1 = 19.38e9 + 0.1276e9 = 19.5076e9;
    /// μ = −0.01, E = 0: −1.63e9.
    #[test]
    fn pressure_by_hand() {
        let close = |a: f32, b: f64| ((a as f64 - b) / b).abs() < 1e-5;
        assert!(close(pressure(&EOS, 0.02, 0.0), 3.37872e9));
        assert!(close(pressure(&EOS, 0.1, 1e8), 19.5076e9));
        assert!(close(pressure(&EOS, -0.01, 0.0), -1.63e9));
        assert!(close(
            bulk_tangent(&EOS, 0.1),
            163e9 + 2.0 * 294e9 * 0.1 + 3.0 * 140e9 * 0.01
        ));
        assert_eq!(bulk_tangent(&EOS, -0.05), 163e9);
    }
}
