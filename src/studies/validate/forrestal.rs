//! Forrestal's penetration equation for a rigid ogive-nosed projectile into concrete
//! (Forrestal, Altman, Cargile & Hanchak 1994; physics.md §8). It was fitted to the same family
//! of tests as the shots it is compared with: a cross-check, not truth.

/// The equation's inputs besides the striking speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inputs {
    /// Projectile mass m (kg).
    pub mass: f64,
    /// Shank radius a (m).
    pub shank_radius: f64,
    /// Calibre-radius-head ψ of the ogive nose.
    pub crh: f64,
    /// Target density ρ (kg/m³).
    pub density: f64,
    /// Unconfined compressive strength f_c (Pa).
    pub fc: f64,
}

impl Inputs {
    /// Nose factor `N = (8ψ − 1)/(24ψ²)`.
    pub fn nose_factor(&self) -> f64 {
        (8.0 * self.crh - 1.0) / (24.0 * self.crh * self.crh)
    }

    /// Empirical strength factor `S = 82.6 f_c^−0.544`, f_c in MPa.
    pub fn strength_factor(&self) -> f64 {
        82.6 * (self.fc * 1e-6).powf(-0.544)
    }

    /// The stress the equation assumes on the buried nose at speed `v`, `S f_c + N ρ v²` (Pa).
    pub fn tunnel_stress(&self, v: f64) -> f64 {
        self.strength_factor() * self.fc + self.nose_factor() * self.density * v * v
    }

    /// Final depth (m) at striking speed `vs` (m/s) with the 4a crater:
    /// `P = (m/(2πa²ρN)) ln(1 + NρV₁²/(S f_c)) + 4a`,
    /// `V₁² = (mV_s² − 4πa³S f_c)/(m + 4πa³ρN)` (the speed left after the 4a-deep crater).
    /// `None` when V₁² ≤ 0: the projectile stops inside the crater, outside the tunnel law.
    pub fn depth(&self, vs: f64) -> Option<f64> {
        self.depth_with_crater(vs, Crater::FourRadii)
    }

    /// The ogive's length `H = a √(4ψ − 1)` (m), as the mesh has it.
    pub fn nose_length(&self) -> f64 {
        crate::scene::ogive_nose_length(2.0 * self.shank_radius, self.crh)
    }

    /// Final depth (m) at striking speed `vs` with the entry crater `crater`, c deep: the force
    /// grows linearly over the crater to the tunnel's `πa²(S f_c + NρV₁²)`, so
    /// `V₁² = (mV_s² − πa²c S f_c)/(m + πa²c ρN)` and `P = (m/(2πa²ρN)) ln(1 + NρV₁²/(S f_c)) + c`
    /// (with c = 4a, Forrestal's). `None` when V₁² ≤ 0.
    pub fn depth_with_crater(&self, vs: f64, crater: Crater) -> Option<f64> {
        let (m, a, rho) = (self.mass, self.shank_radius, self.density);
        let c = match crater {
            Crater::FourRadii => 4.0 * a,
            Crater::LiChen => 0.707 * 2.0 * a + self.nose_length(),
        };
        let n = self.nose_factor();
        let resistance = self.strength_factor() * self.fc;
        let k = std::f64::consts::PI * a * a * c;
        let v1_sq = (m * vs * vs - k * resistance) / (m + k * rho * n);
        if v1_sq <= 0.0 {
            return None;
        }
        let scale = m / (2.0 * std::f64::consts::PI * a * a * rho * n);
        Some(scale * (n * rho * v1_sq / resistance).ln_1p() + c)
    }
}

/// How deep the entry crater of Forrestal's equation is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Crater {
    /// Four shank radii (Forrestal, Altman, Cargile & Hanchak 1994).
    FourRadii,
    /// `(0.707 + H/d) d`, H the nose's length (Li & Chen 2003, Int. J. Impact Engng 28:93).
    LiChen,
}

/// The axial stress resisting the projectile, `σ = −m (dv/dt)/(πa²)`, along a run's history
/// (time, depth, speed), where the nose is buried (depth ≥ `nose_length`) and the projectile
/// still moves: one `(speed, σ)` per history row, the deceleration the least-squares slope of
/// the speed over the rows within `half_window` of it. Forrestal's equation assumes
/// `σ = S f_c + N ρ v²` there, the same law at every depth.
pub fn tunnel_resistance(
    time: &[f64],
    depth: &[f64],
    speed: &[f64],
    mass: f64,
    shank_radius: f64,
    nose_length: f64,
    half_window: usize,
) -> Vec<(f64, f64)> {
    let n = time.len().min(depth.len()).min(speed.len());
    let area = std::f64::consts::PI * shank_radius * shank_radius;
    (half_window..n.saturating_sub(half_window))
        .filter(|&i| depth[i] >= nose_length && speed[i] > 0.0)
        .filter_map(|i| {
            let rows = i - half_window..=i + half_window;
            let k = rows.clone().count() as f64;
            let t_mean = rows.clone().map(|j| time[j]).sum::<f64>() / k;
            let v_mean = rows.clone().map(|j| speed[j]).sum::<f64>() / k;
            let (mut stt, mut stv) = (0.0, 0.0);
            for j in rows {
                stt += (time[j] - t_mean).powi(2);
                stv += (time[j] - t_mean) * (speed[j] - v_mean);
            }
            (stt > 0.0).then(|| (speed[i], -mass * (stv / stt) / area))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A history integrated from m dv/dt = −πa²(R + Nρv²) gives back R + Nρv² along the tunnel
    /// (to the window's curvature error), and nothing while the nose is not yet buried.
    #[test]
    fn tunnel_resistance_recovers_the_law_it_was_made_from() {
        let (m, a, rho, n, r) = (0.9, 0.01345, 2370.0, 0.156, 4.2e8);
        let area = std::f64::consts::PI * a * a;
        let (mut t, mut z, mut v) = (0.0, 0.0, 600.0);
        let dt = 2e-6;
        let decel = |v: f64| area * (r + n * rho * v * v) / m;
        let (mut time, mut depth, mut speed) = (vec![], vec![], vec![]);
        while v > 0.0 {
            time.push(t);
            depth.push(z);
            speed.push(v);
            // Midpoint step: ample for a smooth ODE at this step.
            let vm = v - 0.5 * dt * decel(v);
            z += dt * vm;
            v -= dt * decel(vm);
            t += dt;
        }
        let nose = 0.0356;
        let points = tunnel_resistance(&time, &depth, &speed, m, a, nose, 5);
        assert!(points.len() > 100, "{}", points.len());
        let first_buried = depth.iter().position(|&d| d >= nose).unwrap();
        assert_eq!(points[0].0, speed[first_buried.max(5)]);
        for &(v, sigma) in &points {
            let law = r + n * rho * v * v;
            assert!(
                (sigma / law - 1.0).abs() < 1e-3,
                "v {v}: {sigma} against {law}"
            );
        }
    }

    /// The 277 m/s shot's inputs (forrestal1994.csv: m = 0.906 kg, f_c = 35.2 MPa; a = 13.45 mm,
    /// ψ = 2, ρ = 2370 kg/m³).
    fn shot_277() -> Inputs {
        Inputs {
            mass: 0.906,
            shank_radius: 0.01345,
            crh: 2.0,
            density: 2370.0,
            fc: 35.2e6,
        }
    }

    /// The 277 m/s shot by hand:
    ///   N = (16 − 1)/96 = 0.15625
    ///   S = 82.6 · 35.2^−0.544 = 82.6 · exp(−0.544 · 3.56105) = 82.6 · 0.144106 = 11.9031
    ///   S f_c = 4.18990e8 Pa;  4πa³ = 4π · 2.43314e-6 = 3.05757e-5 m³
    ///   V₁² = (0.906 · 277² − 3.05757e-5 · 4.18990e8) / (0.906 + 3.05757e-5 · 2370 · 0.15625)
    ///       = (69516.47 − 12810.92) / (0.906 + 0.0113226) = 56705.56 / 0.9173226 = 61816.4 m²/s²
    ///   m/(2πa²ρN) = 0.906 / (2π · 1.80903e-4 · 2370 · 0.15625) = 0.906 / 0.420912 = 2.15246 m
    ///   NρV₁²/(S f_c) = 370.3125 · 61816.4 / 4.18990e8 = 0.0546347
    ///   P = 2.15246 · ln(1.0546347) + 4 · 0.01345 = 2.15246 · 0.0531946 + 0.0538 = 0.16830 m
    /// (measured: 0.173 m).
    #[test]
    fn depth_matches_the_hand_calculation() {
        let shot = shot_277();
        assert_eq!(shot.nose_factor(), 0.15625);
        assert!((shot.strength_factor() - 11.9031).abs() < 1e-4);
        let p = shot.depth(277.0).unwrap();
        assert!((p - 0.16830).abs() < 2e-5, "{p}");
        // Deeper when faster; none below the crater's threshold speed (V₁² = 0 at
        // sqrt(12810.92/0.906) = 118.9 m/s).
        assert!(shot.depth(499.0).unwrap() > p);
        assert!(shot.depth(118.0).is_none());
        assert!(shot.depth(120.0).unwrap() > 4.0 * 0.01345);
    }

    /// The same shot with Li and Chen's crater, by hand:
    ///   H = a √7 = 0.0355854 m;  c = 0.707 · 0.0269 + H = 0.0546037 m
    ///   πa²c = π · 1.80903e-4 · 0.0546037 = 3.10325e-5 m³
    ///   V₁² = (69516.47 − 3.10325e-5 · 4.18990e8) / (0.906 + 3.10325e-5 · 2370 · 0.15625)
    ///       = 56514.3 / 0.917492 = 61596.4 m²/s²
    ///   P = 2.15246 · ln(1 + 370.3125 · 61596.4 / 4.18990e8) + c
    ///     = 2.15246 · ln(1.0544403) + 0.0546037 = 0.16871 m
    /// and with c = 4a it is `depth`.
    #[test]
    fn the_li_chen_crater_matches_the_hand_calculation() {
        let shot = shot_277();
        assert!((shot.nose_length() - 0.0355854).abs() < 1e-7);
        let p = shot.depth_with_crater(277.0, Crater::LiChen).unwrap();
        assert!((p - 0.16871).abs() < 2e-5, "{p}");
        assert_eq!(
            shot.depth_with_crater(277.0, Crater::FourRadii),
            shot.depth(277.0)
        );
        // A longer nose digs a deeper crater: the same speed is used up sooner in it.
        let slender = Inputs { crh: 6.0, ..shot };
        assert!(slender.nose_length() > shot.nose_length());
    }
}
