//! Sliding-surface correction with artificial momentum transport (physics.md §4, paper §3),
//! applied on the CPU for every hit of the step, one after another in the slaves' lattice order
//! (`Model::hit_order`).
//!
//! For a slave S inside the master triangle of segment AB (outward normal n), S moves to its
//! foot S'' on AB, weights w_A = |BS''|/|AB|, w_B = |AS''|/|AB|, and with normal velocities
//! Δ = w_A v_A + w_B v_B − v_S (closing when Δ > 0):
//!
//! ```text
//! δ = Δ / [1 + λ m_S (w_A²/m_A + w_B²/m_B) + (1 − λ) m_S n_z² / M]
//! v_S += δ n,  v_A −= λ δ m_S w_A/m_A n,  v_B −= λ δ m_S w_B/m_B n,
//! every node: v_z −= (1 − λ) δ m_S n_z / M
//! ```
//!
//! Why n_z² and a global shift along z only (physics.md writes the planar form, m_S/M along n):
//! the masses are whole rings, and a ring's radial impulse sums to zero around the ring, so the
//! projectile as a whole can only take the axial part n_z of the impulse; a uniform radial
//! velocity added to every node would be a hoop strain, not a rigid motion, and would move the
//! axis nodes off the axis. With n_z² the three equations (5), (6)+(7) and (11)+(12) hold exactly
//! together: z-momentum is conserved to round-off, the relative normal velocity after the hit is
//! zero, and λ = 0 moves the projectile rigidly (zero strain). Where n is axial (n_z = ±1) this
//! is the planar formula of physics.md to the letter.
//!
//! The positions were advanced with the velocities before the correction, so each node also
//! moves by its velocity change times the step, and the slave goes to its foot on the moved
//! segment: the step ends as if the impulse had come before the drift (the predictor-corrector
//! form of a kinematic contact). Without this, a node in lasting contact drifted a·Δt² per step
//! further than the velocity that its elements' strain rate saw, and the projectile's plastic
//! strain and damage grew in proportion to the step (docs/physics.md §4).
//!
//! With a Coulomb coefficient μ > 0 a closing hit then takes a tangential jump along the
//! segment's unit tangent t = (B − A)/|AB|, from the relative tangential velocity
//! Δ_t = (w_A v_A + w_B v_B − v_S)·t left by the normal jump, split the same way:
//!
//! ```text
//! δ_t = clamp(Δ_t / [1 + λ m_S (w_A²/m_A + w_B²/m_B) + (1 − λ) m_S t_z² / M], −μ δ, μ δ)
//! v_S += δ_t t,  v_A −= λ δ_t m_S w_A/m_A t,  v_B −= λ δ_t m_S w_B/m_B t,
//! every node: v_z −= (1 − λ) δ_t m_S t_z / M
//! ```
//!
//! Unclamped it stops the sliding (sticking); clamped, the tangential impulse m_S |δ_t| is μ
//! times the normal one m_S δ (slipping). Either way it removes kinetic energy, booked with the
//! normal step's in `dissipated`.

use crate::mesh::MasterSegment;

/// A slave particle found inside a master triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Hit {
    pub slave: u32,
    pub master: u32,
}

/// The velocities and positions the correction reads and writes.
pub struct ContactBodies<'a> {
    pub slave_r: &'a mut [f32],
    pub slave_z: &'a mut [f32],
    pub slave_vr: &'a mut [f32],
    pub slave_vz: &'a mut [f32],
    pub slave_mass: &'a [f32],
    pub node_r: &'a mut [f32],
    pub node_z: &'a mut [f32],
    pub node_vr: &'a mut [f32],
    pub node_vz: &'a mut [f32],
    pub node_mass: &'a [f32],
    pub node_on_axis: &'a [u32],
    /// The step by which the positions were just advanced (s).
    pub dt: f32,
}

/// What one step's corrections did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CorrectionStats {
    /// Kinetic energy lost in the inelastic normal collisions and to friction (J, ≥ 0 up to
    /// round-off).
    pub dissipated: f64,
    /// Hits that were closing (velocity corrected).
    pub closing: usize,
    /// Deepest slave penetration found before correction (m).
    pub max_penetration: f32,
    /// Global velocity shift added to every node along z (m/s).
    pub global_shift: f32,
    /// Axial impulse the hits gave the projectile, −Σ m_S (δ n_z + δ_t t_z) (N s; +z resists
    /// a flight along −z): the local and the global parts of each hit together, friction's
    /// included.
    pub impulse_z: f64,
    /// The part of `impulse_z` from hits on the nose's segments (N s).
    pub nose_impulse_z: f64,
}

/// Apply every hit in order (the caller passes them in `Model::hit_order`). `on_nose[k]` says
/// whether master `k` is on the nose: its hits' impulse is booked in `nose_impulse_z` too.
/// `normal_impulse[k]` gains the normal impulse m_S δ of master `k`'s closing hits (N s; the
/// load on its ring: the pressure on the nose, physics.md §4). `friction` is the Coulomb
/// coefficient μ of the sliding surface (0: frictionless).
#[allow(clippy::too_many_arguments)]
pub fn correct(
    hits: &[Hit],
    masters: &[MasterSegment],
    on_nose: &[bool],
    normal_impulse: &mut [f64],
    b: &mut ContactBodies,
    lambda: f32,
    friction: f32,
    total_mass: f64,
) -> CorrectionStats {
    let mut stats = CorrectionStats::default();
    if hits.is_empty() {
        return stats;
    }
    let dt = b.dt;
    let mut g = Global {
        lambda,
        total_mass,
        shift: 0.0,
        p_z: (0..b.node_mass.len())
            .map(|i| b.node_mass[i] as f64 * b.node_vz[i] as f64)
            .sum(),
    };
    for hit in hits {
        let seg = masters[hit.master as usize];
        let (a, bn, s) = (seg.a as usize, seg.b as usize, hit.slave as usize);
        let (ar, az) = (b.node_r[a], b.node_z[a] + g.shift * dt);
        let (br, bz) = (b.node_r[bn], b.node_z[bn] + g.shift * dt);
        let (er, ez) = (br - ar, bz - az);
        let len2 = er * er + ez * ez;
        let len = len2.sqrt();
        let n = [ez / len, -er / len];
        let t = (((b.slave_r[s] - ar) * er + (b.slave_z[s] - az) * ez) / len2).clamp(0.0, 1.0);
        let (foot_r, foot_z) = (ar + t * er, az + t * ez);
        let depth = (foot_r - b.slave_r[s]) * n[0] + (foot_z - b.slave_z[s]) * n[1];
        stats.max_penetration = stats.max_penetration.max(depth);
        b.slave_r[s] = foot_r;
        b.slave_z[s] = foot_z;

        let touch = Touch {
            s,
            a,
            b: bn,
            w_a: 1.0 - t,
            w_b: t,
            m_s: b.slave_mass[s],
            m_a: b.node_mass[a],
            m_b: b.node_mass[bn],
            nose: on_nose[hit.master as usize],
        };
        let closing = touch.relative(b, &g, n);
        if closing.is_nan() || closing <= 0.0 {
            continue;
        }
        stats.closing += 1;
        let delta = closing / touch.denominator(&g, n[1]);
        touch.kick(b, &mut g, &mut stats, n, delta);
        normal_impulse[hit.master as usize] += touch.m_s as f64 * delta as f64;

        // Coulomb friction: the tangential jump that would stop the sliding, at most μ times
        // the normal one (physics.md §4, Coulomb friction). Skipped at μ = 0 so that the
        // frictionless step stays what it was, bit for bit.
        if friction > 0.0 {
            let tan = [er / len, ez / len];
            let cap = friction * delta;
            let sliding = touch.relative(b, &g, tan);
            let delta_t = (sliding / touch.denominator(&g, tan[1])).clamp(-cap, cap);
            touch.kick(b, &mut g, &mut stats, tan, delta_t);
        }
        b.slave_r[s] = touch.w_a * b.node_r[a] + touch.w_b * b.node_r[bn];
        b.slave_z[s] = touch.w_a * b.node_z[a] + touch.w_b * b.node_z[bn] + g.shift * dt;
    }
    let shift = g.shift;
    if shift != 0.0 {
        for (v, z) in b.node_vz.iter_mut().zip(b.node_z.iter_mut()) {
            *v += shift;
            *z += shift * dt;
        }
    }
    stats.global_shift = shift;
    stats
}

/// The projectile as a whole while the step's hits are applied.
struct Global {
    lambda: f32,
    /// Total projectile mass M (kg).
    total_mass: f64,
    /// Running global shift along z: node i's velocity is (vr, vz + shift) and its position
    /// (r, z + shift Δt) until it is applied.
    shift: f32,
    /// Projectile z-momentum with the shift included (f64: it is a sum over all nodes).
    p_z: f64,
}

/// One hit: slave `s` at weights `w_a`, `w_b` between the nodes `a` and `b`.
struct Touch {
    s: usize,
    a: usize,
    b: usize,
    w_a: f32,
    w_b: f32,
    m_s: f32,
    m_a: f32,
    m_b: f32,
    /// Whether the hit's master is on the nose (`nose_impulse_z`).
    nose: bool,
}

impl Touch {
    /// Relative velocity w_A v_A + w_B v_B − v_S along the unit vector `e` (shift included).
    fn relative(&self, b: &ContactBodies, g: &Global, e: [f32; 2]) -> f32 {
        let v_a = [b.node_vr[self.a], b.node_vz[self.a] + g.shift];
        let v_b = [b.node_vr[self.b], b.node_vz[self.b] + g.shift];
        let v_s = [b.slave_vr[self.s], b.slave_vz[self.s]];
        let dot = |v: [f32; 2]| v[0] * e[0] + v[1] * e[1];
        self.w_a * dot(v_a) + self.w_b * dot(v_b) - dot(v_s)
    }

    /// The slave's effective mass ratio along a unit vector whose z part is `e_z`: a jump δ
    /// of the slave along it changes the relative velocity along it by δ times this.
    fn denominator(&self, g: &Global, e_z: f32) -> f32 {
        let (m_s, w_a, w_b) = (self.m_s, self.w_a, self.w_b);
        1.0 + g.lambda * m_s * (w_a * w_a / self.m_a + w_b * w_b / self.m_b)
            + (1.0 - g.lambda) * m_s * e_z * e_z / g.total_mass as f32
    }

    /// The slave's velocity jumps by `delta` along the unit vector `e`; the projectile takes
    /// the opposite impulse, λ of it on A and B (positions moved by the change times Δt) and
    /// the rest as the global shift along z. The kinetic energy lost and the axial impulse the
    /// projectile received are booked in `stats`.
    fn kick(
        &self,
        b: &mut ContactBodies,
        g: &mut Global,
        stats: &mut CorrectionStats,
        e: [f32; 2],
        delta: f32,
    ) {
        let (s, m_s, dt) = (self.s, self.m_s, b.dt);
        let impulse = -(m_s as f64) * delta as f64 * e[1] as f64;
        stats.impulse_z += impulse;
        if self.nose {
            stats.nose_impulse_z += impulse;
        }
        let mut d_ke = -ke(m_s, b.slave_vr[s], b.slave_vz[s]);
        b.slave_vr[s] += delta * e[0];
        b.slave_vz[s] += delta * e[1];
        d_ke += ke(m_s, b.slave_vr[s], b.slave_vz[s]);

        for (node, w, m) in [(self.a, self.w_a, self.m_a), (self.b, self.w_b, self.m_b)] {
            let dv = -g.lambda * delta * m_s * w / m;
            let before = [b.node_vr[node], b.node_vz[node] + g.shift];
            // Axis nodes keep ṙ = 0: they take only the axial part.
            if b.node_on_axis[node] == 0 {
                b.node_vr[node] += dv * e[0];
                b.node_r[node] += dv * e[0] * dt;
            }
            b.node_vz[node] += dv * e[1];
            b.node_z[node] += dv * e[1] * dt;
            let after = [b.node_vr[node], b.node_vz[node] + g.shift];
            d_ke += ke(m, after[0], after[1]) - ke(m, before[0], before[1]);
            g.p_z += m as f64 * (after[1] - before[1]) as f64;
        }

        let shift = -(1.0 - g.lambda) * delta * m_s * e[1] / g.total_mass as f32;
        d_ke += shift as f64 * g.p_z + 0.5 * g.total_mass * (shift as f64).powi(2);
        g.p_z += g.total_mass * shift as f64;
        g.shift += shift;
        stats.dissipated -= d_ke;
    }
}

/// Kinetic energy of mass `m` at velocity (vr, vz) (J).
fn ke(m: f32, vr: f32, vz: f32) -> f64 {
    0.5 * m as f64 * ((vr as f64).powi(2) + (vz as f64).powi(2))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A projectile of `extra` free nodes plus the segment A(0) → B(1) with outward normal n,
    /// and one slave just inside it. Returns (slave arrays, node arrays).
    #[derive(Clone)]
    struct Setup {
        sr: Vec<f32>,
        sz: Vec<f32>,
        svr: Vec<f32>,
        svz: Vec<f32>,
        sm: Vec<f32>,
        nr: Vec<f32>,
        nz: Vec<f32>,
        nvr: Vec<f32>,
        nvz: Vec<f32>,
        nm: Vec<f32>,
        axis: Vec<u32>,
    }

    impl Setup {
        /// Segment from A to B; the slave sits at fraction `t` along it, `depth` inside.
        fn new(a: [f32; 2], b: [f32; 2], t: f32, depth: f32) -> Setup {
            let (er, ez) = (b[0] - a[0], b[1] - a[1]);
            let len = er.hypot(ez);
            let n = [ez / len, -er / len];
            let s = [a[0] + t * er - depth * n[0], a[1] + t * ez - depth * n[1]];
            Setup {
                sr: vec![s[0]],
                sz: vec![s[1]],
                svr: vec![5.0],
                svz: vec![20.0],
                sm: vec![0.01],
                nr: vec![a[0], b[0], 0.0, 0.01],
                nz: vec![a[1], b[1], 0.05, 0.05],
                nvr: vec![1.0, -2.0, 0.0, 0.5],
                nvz: vec![-300.0, -310.0, -305.0, -300.0],
                nm: vec![0.02, 0.03, 0.5, 0.35],
                axis: vec![0, 0, 1, 0],
            }
        }

        fn bodies(&mut self) -> ContactBodies<'_> {
            ContactBodies {
                slave_r: &mut self.sr,
                slave_z: &mut self.sz,
                slave_vr: &mut self.svr,
                slave_vz: &mut self.svz,
                slave_mass: &self.sm,
                node_r: &mut self.nr,
                node_z: &mut self.nz,
                node_vr: &mut self.nvr,
                node_vz: &mut self.nvz,
                node_mass: &self.nm,
                node_on_axis: &self.axis,
                dt: DT,
            }
        }

        fn total_mass(&self) -> f64 {
            self.nm.iter().map(|&m| m as f64).sum()
        }

        fn momentum(&self) -> [f64; 2] {
            let mut p = [
                self.sm[0] as f64 * self.svr[0] as f64,
                self.sm[0] as f64 * self.svz[0] as f64,
            ];
            for i in 0..self.nm.len() {
                p[0] += self.nm[i] as f64 * self.nvr[i] as f64;
                p[1] += self.nm[i] as f64 * self.nvz[i] as f64;
            }
            p
        }

        fn kinetic(&self) -> f64 {
            let mut e = 0.5
                * self.sm[0] as f64
                * ((self.svr[0] as f64).powi(2) + (self.svz[0] as f64).powi(2));
            for i in 0..self.nm.len() {
                e += 0.5
                    * self.nm[i] as f64
                    * ((self.nvr[i] as f64).powi(2) + (self.nvz[i] as f64).powi(2));
            }
            e
        }
    }

    /// The step the positions were advanced by, large enough that its position changes show.
    const DT: f32 = 1.0e-6;

    const SEG: MasterSegment = MasterSegment {
        element: 0,
        a: 0,
        b: 1,
        c: 2,
    };

    /// Relative normal velocity w_A v_A + w_B v_B − v_S of `s` along the normal of `at`'s
    /// segment (the one the correction used, before it moved the nodes).
    fn relative_normal(s: &Setup, at: &Setup, t: f32) -> f32 {
        let (er, ez) = (at.nr[1] - at.nr[0], at.nz[1] - at.nz[0]);
        let len = er.hypot(ez);
        let n = [ez / len, -er / len];
        let dot = |vr: f32, vz: f32| vr * n[0] + vz * n[1];
        (1.0 - t) * dot(s.nvr[0], s.nvz[0]) + t * dot(s.nvr[1], s.nvz[1]) - dot(s.svr[0], s.svz[0])
    }

    /// The unit normal and the unit tangent A → B of `at`'s segment.
    fn frame(at: &Setup) -> ([f32; 2], [f32; 2]) {
        let (er, ez) = (at.nr[1] - at.nr[0], at.nz[1] - at.nz[0]);
        let len = er.hypot(ez);
        ([ez / len, -er / len], [er / len, ez / len])
    }

    /// Relative tangential velocity (w_A v_A + w_B v_B − v_S)·t of `s` on `at`'s segment.
    fn relative_tangential(s: &Setup, at: &Setup, t: f32) -> f32 {
        let e = frame(at).1;
        let dot = |vr: f32, vz: f32| vr * e[0] + vz * e[1];
        (1.0 - t) * dot(s.nvr[0], s.nvz[0]) + t * dot(s.nvr[1], s.nvz[1]) - dot(s.svr[0], s.svz[0])
    }

    /// The slave's velocity jump from `at`, split into its normal and tangential parts (δ, δ_t).
    fn slave_jump(s: &Setup, at: &Setup) -> (f32, f32) {
        let (n, e) = frame(at);
        let dv = [s.svr[0] - at.svr[0], s.svz[0] - at.svz[0]];
        (dv[0] * n[0] + dv[1] * n[1], dv[0] * e[0] + dv[1] * e[1])
    }

    /// The nose segment of the tests, inclined (outward normal ≈ (0.894, −0.447), tangent
    /// ≈ (0.447, 0.894)).
    const NOSE: ([f32; 2], [f32; 2]) = ([0.001, -0.008], [0.004, -0.002]);

    /// `correct` of the one hit of `s` at `lambda` and `friction`, on the nose.
    fn one_hit(s: &mut Setup, lambda: f32, friction: f32) -> CorrectionStats {
        let m = s.total_mass();
        correct(
            &[Hit {
                slave: 0,
                master: 0,
            }],
            &[SEG],
            &[true],
            &mut [0.0],
            &mut s.bodies(),
            lambda,
            friction,
            m,
        )
    }

    /// A slave that moves nearly with the nose along the surface while it closes on it: its
    /// relative sliding (≈ −7 m/s) is about half its closing speed (≈ 15 m/s).
    fn nearly_sticking(t: f32) -> Setup {
        let mut s = Setup::new(NOSE.0, NOSE.1, t, 1e-4);
        s.svr[0] = -10.0;
        s.svz[0] = -290.0;
        s
    }

    /// One hit on an inclined segment: z-momentum conserved to f32 round-off, eq. (5) holds after
    /// the global shift, every node moves by its velocity change times the step, the slave ends
    /// on the moved segment, and energy is lost, not made.
    #[test]
    fn one_hit_conserves_axial_momentum_and_closes_the_gap() {
        for lambda in [0.0f32, 0.2, 0.5, 1.0] {
            let (a, b) = ([0.001, -0.008], [0.004, -0.002]);
            let t = 0.3;
            let mut s = Setup::new(a, b, t, 1e-4);
            let before = Setup::new(a, b, t, 1e-4);
            let p0 = s.momentum();
            let e0 = s.kinetic();
            let m = s.total_mass();
            // The segment counts as the nose for two of the four λ, as the shank for the others.
            let on_nose = lambda < 0.4;
            let mut normal_impulse = [0.0];
            let stats = correct(
                &[Hit {
                    slave: 0,
                    master: 0,
                }],
                &[SEG],
                &[on_nose],
                &mut normal_impulse,
                &mut s.bodies(),
                lambda,
                0.0,
                m,
            );
            let p1 = s.momentum();
            let scale = 0.5 * 310.0;
            assert!(
                (p1[1] - p0[1]).abs() < 1e-6 * scale,
                "λ {lambda}: p_z {} → {}",
                p0[1],
                p1[1]
            );
            assert!(
                relative_normal(&s, &before, t).abs() < 1e-3,
                "λ {lambda}: eq. (5) residual {}",
                relative_normal(&s, &before, t)
            );
            for i in 0..4 {
                let moved = [s.nr[i] - before.nr[i], s.nz[i] - before.nz[i]];
                let kick = [s.nvr[i] - before.nvr[i], s.nvz[i] - before.nvz[i]];
                assert!(
                    (moved[0] - kick[0] * DT).abs() < 1e-8
                        && (moved[1] - kick[1] * DT).abs() < 1e-8,
                    "λ {lambda}: node {i} moved {moved:?} for a kick {kick:?}"
                );
            }
            if lambda > 0.0 {
                assert!(s.nr[0] != before.nr[0], "λ {lambda}: A keeps its place");
            }
            let foot = [
                s.nr[0] + t * (s.nr[1] - s.nr[0]),
                s.nz[0] + t * (s.nz[1] - s.nz[0]),
            ];
            assert!((s.sr[0] - foot[0]).abs() < 1e-7 && (s.sz[0] - foot[1]).abs() < 1e-7);
            assert_eq!(stats.closing, 1);
            assert!(stats.dissipated > 0.0);
            assert!(
                ((e0 - s.kinetic()) - stats.dissipated).abs() < 1e-6 * e0,
                "energy account"
            );
            assert!((stats.max_penetration - 1e-4).abs() < 1e-6);
            // The projectile's axial impulse is the slave's momentum change, reversed; on this
            // nose segment (n_z < 0) it resists the flight along −z.
            let slave_dp = s.sm[0] as f64 * (s.svz[0] - before.svz[0]) as f64;
            assert!(
                stats.impulse_z > 0.0 && (stats.impulse_z + slave_dp).abs() < 1e-5 * slave_dp.abs(),
                "λ {lambda}: impulse {} against the slave's {slave_dp}",
                stats.impulse_z
            );
            let nose = if on_nose { stats.impulse_z } else { 0.0 };
            assert_eq!(
                stats.nose_impulse_z, nose,
                "λ {lambda}: on the nose: {on_nose}"
            );
            // The segment's normal load is the slave's whole momentum change (frictionless:
            // the jump is along the normal).
            let jump = (s.svr[0] - before.svr[0]).hypot(s.svz[0] - before.svz[0]);
            let slave_dp = s.sm[0] as f64 * jump as f64;
            assert!(
                (normal_impulse[0] - slave_dp).abs() < 1e-5 * slave_dp,
                "λ {lambda}: normal impulse {} against the slave's {slave_dp}",
                normal_impulse[0]
            );
        }
    }

    /// On an axial normal (flat face, n = −z) momentum along n is conserved exactly as in the
    /// planar formula of physics.md §4.
    #[test]
    fn flat_face_conserves_momentum_along_the_normal() {
        // A → B along +r: outward normal (Δz, −Δr)/|AB| = (0, −1), a flat nose face.
        let mut s = Setup::new([0.001, -0.002], [0.004, -0.002], 0.5, 1e-4);
        let p0 = s.momentum();
        one_hit(&mut s, 0.2, 0.0);
        let p1 = s.momentum();
        assert!((p1[1] - p0[1]).abs() < 1e-6 * 300.0);
        assert!(
            (p1[0] - p0[0]).abs() < 1e-9,
            "no radial exchange on a flat face"
        );
    }

    /// λ = 0: a perfectly inelastic normal collision of the slave with the whole rigid projectile:
    /// every node gets the same velocity change, along z only, and the slave's normal velocity
    /// ends equal to the projectile's.
    #[test]
    fn lambda_zero_is_a_rigid_inelastic_collision() {
        let (a, b) = ([0.001, -0.008], [0.004, -0.002]);
        let mut s = Setup::new(a, b, 0.6, 1e-4);
        let before_r = s.nvr.clone();
        let before_z = s.nvz.clone();
        let ms = s.sm[0] as f64;
        let m = s.total_mass();
        let stats = one_hit(&mut s, 0.0, 0.0);
        assert_eq!(
            s.nvr, before_r,
            "no radial change: the projectile moves rigidly"
        );
        let dv: Vec<f32> = (0..4).map(|i| s.nvz[i] - before_z[i]).collect();
        for d in &dv {
            assert!(
                (d - dv[0]).abs() < 1e-4 * dv[0].abs(),
                "uniform shift {dv:?}"
            );
        }
        // Closed form: Δ = n_z V_z − v_S·n (V_z the common axial speed along the normal),
        // δ = Δ/(1 + m_S n_z²/M), ΔV_z = −δ m_S n_z /M.
        let (er, ez) = (b[0] - a[0], b[1] - a[1]);
        let len = (er as f64).hypot(ez as f64);
        let n = [ez as f64 / len, -er as f64 / len];
        let setup = Setup::new(a, b, 0.6, 1e-4);
        let w = [0.4f64, 0.6];
        let vn = |vr: f32, vz: f32| vr as f64 * n[0] + vz as f64 * n[1];
        let closing = w[0] * vn(setup.nvr[0], setup.nvz[0]) + w[1] * vn(setup.nvr[1], setup.nvz[1])
            - vn(setup.svr[0], setup.svz[0]);
        let delta = closing / (1.0 + ms * n[1] * n[1] / m);
        let expected = -delta * ms * n[1] / m;
        assert!(
            (dv[0] as f64 - expected).abs() < 1e-4 * expected.abs(),
            "{} vs {expected}",
            dv[0]
        );
        assert!((stats.global_shift as f64 - expected).abs() < 1e-4 * expected.abs());
    }

    /// λ = 1 reproduces the paper's eq. (9)-(10) and leaves the other nodes alone.
    #[test]
    fn lambda_one_is_paper_eq_9_10() {
        let (a, b) = ([0.001, -0.008], [0.004, -0.002]);
        let t = 0.25f64;
        let mut s = Setup::new(a, b, t as f32, 1e-4);
        let before = Setup::new(a, b, t as f32, 1e-4);
        one_hit(&mut s, 1.0, 0.0);
        let (er, ez) = ((b[0] - a[0]) as f64, (b[1] - a[1]) as f64);
        let len = er.hypot(ez);
        let n = [ez / len, -er / len];
        let vn = |vr: f32, vz: f32| vr as f64 * n[0] + vz as f64 * n[1];
        let (l_bs, l_as, l_ab) = ((1.0 - t) * len, t * len, len);
        let (ms, ma, mb) = (
            before.sm[0] as f64,
            before.nm[0] as f64,
            before.nm[1] as f64,
        );
        let (va, vb, vs) = (
            vn(before.nvr[0], before.nvz[0]),
            vn(before.nvr[1], before.nvz[1]),
            vn(before.svr[0], before.svz[0]),
        );
        let frac = ((l_bs * va + l_as * vb) / l_ab - vs)
            / (1.0 + ms * (l_bs * l_bs / ma + l_as * l_as / mb) / (l_ab * l_ab));
        let va_new = va - frac * ms / ma * l_bs / l_ab; // eq. (9)
        let vb_new = vb - frac * ms / mb * l_as / l_ab; // eq. (10)
        assert!(
            (vn(s.nvr[0], s.nvz[0]) - va_new).abs() < 1e-3,
            "{} vs {va_new}",
            vn(s.nvr[0], s.nvz[0])
        );
        assert!((vn(s.nvr[1], s.nvz[1]) - vb_new).abs() < 1e-3);
        assert_eq!(
            (s.nvr[2], s.nvz[2], s.nvr[3], s.nvz[3]),
            (before.nvr[2], before.nvz[2], before.nvr[3], before.nvz[3])
        );
    }

    /// A separating slave is only moved back to the surface.
    #[test]
    fn separating_slave_only_moves() {
        let mut s = Setup::new([0.001, -0.008], [0.004, -0.002], 0.5, 1e-4);
        // Outward normal ≈ (0.894, −0.447): this slave runs away from the surface.
        s.svr[0] = 500.0;
        s.svz[0] = -500.0;
        let (vr, vz) = (s.nvr.clone(), s.nvz.clone());
        let stats = one_hit(&mut s, 0.2, 0.0);
        assert_eq!(stats.closing, 0);
        assert_eq!(
            (s.nvr.clone(), s.nvz.clone(), s.svr[0], s.svz[0]),
            (vr, vz, 500.0, -500.0)
        );
    }

    /// μ = 0 is the frictionless correction: the slave's jump is along the normal only, and the
    /// relative sliding changes only through the global shift's tangential part.
    #[test]
    fn zero_friction_changes_no_tangential_slave_velocity() {
        let t = 0.3;
        let mut s = Setup::new(NOSE.0, NOSE.1, t, 1e-4);
        let before = Setup::new(NOSE.0, NOSE.1, t, 1e-4);
        one_hit(&mut s, 0.2, 0.0);
        let (normal, tangential) = slave_jump(&s, &before);
        assert!(normal > 0.0);
        assert!(tangential.abs() < 1e-5 * normal, "{tangential} along t");
    }

    /// With μ large enough the slave sticks: no relative sliding after the hit, and the
    /// tangential jump stays within μ times the normal one.
    #[test]
    fn large_friction_stops_the_sliding() {
        for lambda in [0.0f32, 0.2, 1.0] {
            let t = 0.3;
            let mut s = nearly_sticking(t);
            let before = nearly_sticking(t);
            let sliding = relative_tangential(&before, &before, t);
            assert!(sliding < -1.0, "the slave slides: {sliding}");
            one_hit(&mut s, lambda, 1.0);
            let after = relative_tangential(&s, &before, t);
            assert!(
                after.abs() < 1e-3,
                "λ {lambda}: still sliding at {after} m/s"
            );
            let (delta, delta_t) = slave_jump(&s, &before);
            assert!(
                delta_t.abs() < delta,
                "λ {lambda}: δ_t {delta_t} beyond μ δ {delta}"
            );
        }
    }

    /// With a small μ the slave slips: its tangential jump is μ times its normal one, against
    /// its sliding along the surface, and on the nose the friction adds axial drag.
    #[test]
    fn small_friction_slips_at_mu_times_the_normal_impulse() {
        let mu = 0.1;
        for lambda in [0.0f32, 0.2, 1.0] {
            let t = 0.3;
            let before = nearly_sticking(t);
            let mut frictionless = nearly_sticking(t);
            let drag0 = one_hit(&mut frictionless, lambda, 0.0).impulse_z;
            let mut s = nearly_sticking(t);
            let stats = one_hit(&mut s, lambda, mu);
            let (delta, delta_t) = slave_jump(&s, &before);
            assert!(
                (delta_t.abs() - mu * delta).abs() < 1e-4 * delta,
                "λ {lambda}: |δ_t| {} vs μ δ {}",
                delta_t.abs(),
                mu * delta
            );
            // The slave slides at −(w_A v_A + w_B v_B − v_S)·t relative to the surface.
            let slave_sliding = -relative_tangential(&before, &before, t);
            assert!(delta_t * slave_sliding < 0.0, "λ {lambda}: δ_t {delta_t}");
            // The normal jump is the frictionless one: friction comes after it.
            let (delta0, _) = slave_jump(&frictionless, &before);
            assert!(
                (delta - delta0).abs() < 1e-5 * delta0,
                "λ {lambda}: {delta} vs {delta0}"
            );
            let t_z = frame(&before).1[1] as f64;
            let drag = stats.impulse_z - drag0;
            let expected = -(s.sm[0] as f64) * delta_t as f64 * t_z;
            assert!(
                drag > 0.0 && (drag - expected).abs() < 1e-4 * expected,
                "λ {lambda}: friction's axial impulse {drag} vs {expected}"
            );
            assert_eq!(stats.nose_impulse_z, stats.impulse_z);
        }
    }

    /// With friction, sticking or slipping, z-momentum is still conserved to round-off, kinetic
    /// energy is lost, not made, the dissipation booked is the loss, and friction adds to the
    /// frictionless loss.
    #[test]
    fn friction_conserves_axial_momentum_and_dissipates() {
        for lambda in [0.0f32, 0.2, 0.5, 1.0] {
            // Slipping, then sticking.
            let slipping = Setup::new(NOSE.0, NOSE.1, 0.6, 1e-4);
            for (mu, start) in [(0.3, slipping), (1.0, nearly_sticking(0.6))] {
                let mut s = start.clone();
                let lost0 = one_hit(&mut start.clone(), lambda, 0.0).dissipated;
                let (p0, e0) = (s.momentum(), s.kinetic());
                let stats = one_hit(&mut s, lambda, mu);
                let (p1, e1) = (s.momentum(), s.kinetic());
                assert!(
                    (p1[1] - p0[1]).abs() < 1e-6 * 0.5 * 310.0,
                    "λ {lambda} μ {mu}: p_z {} → {}",
                    p0[1],
                    p1[1]
                );
                assert!(e1 <= e0, "λ {lambda} μ {mu}: KE {e0} → {e1}");
                assert!(
                    ((e0 - e1) - stats.dissipated).abs() < 1e-6 * e0,
                    "λ {lambda} μ {mu}: lost {} J, booked {} J",
                    e0 - e1,
                    stats.dissipated
                );
                assert!(
                    stats.dissipated > lost0,
                    "λ {lambda} μ {mu}: friction dissipated nothing ({} vs {lost0})",
                    stats.dissipated
                );
            }
        }
    }

    /// A separating slave gets no friction either, however fast it slides.
    #[test]
    fn separating_slave_gets_no_friction() {
        let mut s = Setup::new(NOSE.0, NOSE.1, 0.5, 1e-4);
        // Away from the surface along n ≈ (0.894, −0.447), and sliding along t.
        s.svr[0] = 500.0;
        s.svz[0] = 300.0;
        let (vr, vz) = (s.nvr.clone(), s.nvz.clone());
        let stats = one_hit(&mut s, 0.2, 1.0);
        assert_eq!(stats.closing, 0);
        assert_eq!(stats.impulse_z, 0.0);
        assert_eq!(
            (s.nvr.clone(), s.nvz.clone(), s.svr[0], s.svz[0]),
            (vr, vz, 500.0, 300.0)
        );
    }
}
