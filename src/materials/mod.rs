//! Material laws as small pure functions, each with its equation number from `physics.md`.

pub mod flow;
pub mod hjc;
pub mod johnson_cook;
pub mod presets;
pub mod steel_eos;
pub mod zerilli_armstrong;

/// The least slope K₁ + 2K₂x + 3K₃x² of the cubic K₁x + K₂x² + K₃x³ on [0, hi], and where it
/// is: the slope is a parabola in x, so at an end of the interval or at its vertex.
pub fn least_cubic_slope(k1: f64, k2: f64, k3: f64, hi: f64) -> (f64, f64) {
    let slope = |x: f64| k1 + (2.0 * k2 + 3.0 * k3 * x) * x;
    let vertex = if k3 > 0.0 { -k2 / (3.0 * k3) } else { 0.0 };
    let at = [0.0, hi, vertex.clamp(0.0, hi)]
        .into_iter()
        .min_by(|a, b| slope(*a).total_cmp(&slope(*b)))
        .unwrap_or(0.0);
    (slope(at), at)
}

/// Compression (μ) up to which [`stiffening_fault`] bounds a cubic pressure curve's slope: beyond
/// what the impacts this code models reach in their solids (4340 at 2500 m/s on concrete, a few
/// GPa, μ ≈ 0.02).
pub const STIFFENING_MU: f64 = 0.1;

/// Most a cubic pressure curve's slope may grow over its initial K₁ by μ = [`STIFFENING_MU`].
/// Solids stiffen far less: the paper's 4340 by 1.39×, the HJC concrete's dense curve not at
/// all (its slope falls to 0.67 K₁ by μ̄ = 0.1). The stable step shrinks as 1/√slope, ten times
/// at the bound; a K₃ typed 10⁴ times too large (259× for 4340) would run the impact on steps
/// many times shorter, a run that looks hung.
pub const MAX_STIFFENING: f64 = 100.0;

/// Why the cubic K₁x + K₂x² + K₃x³ (K₁ > 0) stiffens more than any solid: its largest slope on
/// [0, [`STIFFENING_MU`]] over K₁, beyond [`MAX_STIFFENING`], as a message naming `curve`; or
/// `None`.
pub fn stiffening_fault(curve: &str, k1: f64, k2: f64, k3: f64) -> Option<String> {
    // The largest slope of the cubic is the least of its negative's.
    let (least, at) = least_cubic_slope(-k1, -k2, -k3, STIFFENING_MU);
    let ratio = -least / k1;
    // NaN or ∞ (K₁ = 0) counts as beyond the bound.
    let within = ratio <= MAX_STIFFENING;
    (!within).then(|| {
        format!(
            "{curve} stiffens {ratio:.3e} times by μ = {at:.3}: its slope K1 + 2 K2 μ + 3 K3 μ² \
             is {:.4e} Pa against K1 = {k1:.4e} Pa, and no solid's grows more than \
             {MAX_STIFFENING} times by μ = {STIFFENING_MU} (is K2 or K3 in the wrong unit?)",
            -least
        )
    })
}

/// The material tests' check of a hand value: |got/want − 1| ≤ tol.
#[cfg(test)]
fn assert_rel(got: f32, want: f64, tol: f64) {
    let err = ((got as f64 - want) / want).abs();
    assert!(
        err <= tol,
        "got {got}, want {want}, relative error {err:e} > {tol:e}"
    );
}
