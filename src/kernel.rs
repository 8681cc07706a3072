//! SPH smoothing kernel: the 2-D cubic B-spline (Monaghan 1992), used in the (r, z) plane.
//!
//! `W(q) = σ/h² · {1 − 1.5q² + 0.75q³ (q < 1); 0.25(2 − q)³ (q < 2); 0}`, q = |x|/h,
//! σ = 10/(7π). Support radius 2h.

pub(crate) const SIGMA_2D: f32 = 10.0 / (7.0 * std::f32::consts::PI);

/// Support radius over h.
pub const SUPPORT: f32 = 2.0;

/// The kernel for one smoothing length, with its normalisations precomputed (the inner SPH
/// loops call it once per pair).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kernel {
    pub h: f32,
    pub inv_h: f32,
    pub norm: f32,
    pub dnorm: f32,
}

impl Kernel {
    pub fn new(h: f32) -> Kernel {
        Kernel {
            h,
            inv_h: 1.0 / h,
            norm: SIGMA_2D / (h * h),
            dnorm: SIGMA_2D / (h * h * h),
        }
    }

    /// Support radius 2h.
    pub fn support(&self) -> f32 {
        SUPPORT * self.h
    }

    /// Kernel value at distance `dist`.
    #[inline]
    pub fn w(&self, dist: f32) -> f32 {
        let q = dist * self.inv_h;
        if q < 1.0 {
            self.norm * (1.0 - 1.5 * q * q + 0.75 * q * q * q)
        } else if q < 2.0 {
            let t = 2.0 - q;
            self.norm * 0.25 * t * t * t
        } else {
            0.0
        }
    }

    /// dW/d|x| at distance `dist` (≤ 0 inside the support).
    #[inline]
    pub fn dw(&self, dist: f32) -> f32 {
        let q = dist * self.inv_h;
        if q < 1.0 {
            self.dnorm * (-3.0 * q + 2.25 * q * q)
        } else if q < 2.0 {
            let t = 2.0 - q;
            self.dnorm * (-0.75 * t * t)
        } else {
            0.0
        }
    }

    /// ∇_i W(x_i − x_j) for the separation (dr, dz) = x_i − x_j at distance `dist`.
    #[inline]
    pub fn grad(&self, dr: f32, dz: f32, dist: f32) -> [f32; 2] {
        if self.coincident(dist) {
            return [0.0, 0.0];
        }
        let f = self.dw(dist) / dist;
        [f * dr, f * dz]
    }

    /// Two particles this close have no direction between them: no gradient.
    #[inline]
    pub fn coincident(&self, dist: f32) -> bool {
        dist <= 1.0e-12 * self.h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ W dA = 1 over the plane (midpoint rule on a fine grid).
    #[test]
    fn kernel_is_normalised() {
        let k = Kernel::new(1.0);
        let n = 400;
        let d = 4.0 / n as f32;
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let x = -2.0 + (i as f32 + 0.5) * d;
                let y = -2.0 + (j as f32 + 0.5) * d;
                sum += (k.w((x * x + y * y).sqrt()) * d * d) as f64;
            }
        }
        assert!((sum - 1.0).abs() < 1e-3, "∫W = {sum}");
    }

    /// dW matches a central difference of W.
    #[test]
    fn derivative_matches_finite_difference() {
        let k = Kernel::new(0.7);
        for i in 1..27 {
            let x = 0.05 * i as f32;
            let fd = (k.w(x + 1e-3) - k.w(x - 1e-3)) / 2e-3;
            assert!(
                (fd - k.dw(x)).abs() < 2e-2 * (1.0 + fd.abs()),
                "x {x}: {fd} vs {}",
                k.dw(x)
            );
        }
    }
}
