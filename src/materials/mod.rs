//! Material laws as small pure functions, each with its equation number from `physics.md`.

pub mod hjc;
pub mod johnson_cook;
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

/// The material tests' check of a hand value: |got/want − 1| ≤ tol.
#[cfg(test)]
fn assert_rel(got: f32, want: f64, tol: f64) {
    let err = ((got as f64 - want) / want).abs();
    assert!(
        err <= tol,
        "got {got}, want {want}, relative error {err:e} > {tol:e}"
    );
}
