//! Polynomial equation of state of the steel, paper eq. (14), physics.md §2.2.

/// `p = K₁μ + K₂μ² + K₃μ³ + Γ E (1 + μ)` (Pa), linear term only for μ < 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolyEos {
    pub k1: f32,
    pub k2: f32,
    pub k3: f32,
    pub gamma: f32,
}
