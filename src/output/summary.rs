//! `summary.json`: what a run produced and how it ended.

use std::sync::OnceLock;

use serde::{Deserialize, Serialize};

/// `penetrate <version> <fingerprint>`: the fingerprint is the 64-bit FNV-1a hash of the running
/// executable's bytes, so any rebuild that changes the binary changes it; `unknown` where the
/// executable cannot be read (such a build never matches, see [`same_build`]).
pub fn build_id() -> &'static str {
    static ID: OnceLock<String> = OnceLock::new();
    ID.get_or_init(|| {
        let fingerprint = std::env::current_exe().and_then(std::fs::read).map_or_else(
            |_| "unknown".to_string(),
            |bytes| format!("{:016x}", fnv1a(&bytes)),
        );
        format!("penetrate {} {fingerprint}", env!("CARGO_PKG_VERSION"))
    })
}

/// Whether a run recorded as made by `recorded` came from this very build (an unreadable
/// executable matches nothing).
pub fn same_build(recorded: &str) -> bool {
    recorded == build_id() && !recorded.ends_with(" unknown")
}

/// The fingerprint of a `solver_build` string (its last word), if it has one.
pub fn fingerprint(build: &str) -> Option<&str> {
    build
        .rsplit(' ')
        .next()
        .filter(|f| f.len() == 16 && f.bytes().all(|b| b.is_ascii_hexdigit()))
}

fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The stop reason of a run that reached its end time (`Summary::stop_reason`).
pub const END_TIME_REACHED: &str = "end time reached";

/// The stop reason of a run whose projectile went through the target: all of it is behind
/// the rear face.
pub const PERFORATED: &str = "projectile left the target (perforation)";

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Summary {
    pub scene: String,
    /// `completed`, or the reason the run stopped.
    pub status: String,
    /// Why a completed run ended: end time, projectile at rest, projectile left the target.
    pub stop_reason: String,
    pub backend: String,
    pub adapter: String,
    /// Which build of the solver made the run: `penetrate <version> <fingerprint>`
    /// ([`build_id`]). `--resume` takes a run only from the same build. Empty in summaries
    /// written before it existed.
    #[serde(default)]
    pub solver_build: String,
    pub depth_m: f64,
    pub projectile_velocity_m_s: f64,
    pub max_damage: f64,
    /// Largest damage over the elements that started behind the nose (the shank; a shell's
    /// wall). 0 in summaries written before it existed.
    #[serde(default)]
    pub max_damage_shank: f64,
    pub max_plastic_strain: f64,
    /// Largest plastic strain over the elements that started behind the nose. 0 in summaries
    /// written before it existed.
    #[serde(default)]
    pub max_plastic_strain_shank: f64,
    /// Largest pressure checkerboard in a crossed-triangle cell at the end (Pa,
    /// `Elements::max_checkerboard`). 0 in summaries written before it existed.
    #[serde(default)]
    pub checkerboard_pa: f64,
    /// Largest alternation of the triangles' relative volumes in a cell at the end
    /// (`Elements::max_volume_checkerboard`). 0 in summaries written before it existed.
    #[serde(default)]
    pub volume_checkerboard: f64,
    /// Largest pressure checkerboard in a cell at the end as a fraction of the cell's
    /// quasi-static flow stress (`Elements::max_checkerboard_over_flow`). Absent from
    /// summaries written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checkerboard_over_flow_stress: Option<f64>,
    pub final_length_m: f64,
    pub max_radius_m: f64,
    /// Axial impulse the contact gave the projectile over the run (N s, +z against a flight
    /// along −z; `history.csv`'s `contact_impulse_Ns`). 0 in summaries written before it
    /// existed.
    #[serde(default)]
    pub contact_impulse_n_s: f64,
    /// The part of `contact_impulse_n_s` given through the nose's segments (N s; the rest
    /// went through the shank and the tail). 0 in summaries written before it existed.
    #[serde(default)]
    pub nose_impulse_n_s: f64,
    pub time_s: f64,
    pub steps: u64,
    pub particles: usize,
    pub elements: usize,
    pub nodes: usize,
    pub projectile_mass_kg: f64,
    pub wall_s: f64,
    /// (E_kin + E_int + E_dissipated − E₀)/E₀ with E₀ the initial kinetic energy.
    pub energy_error: f64,
    /// |P_z − P_z0 − boundary impulse| / |P_z0|.
    pub momentum_error: f64,
    pub energy: EnergySummary,
    pub passes: Vec<String>,
    pub min_dt_s: f64,
    pub max_dt_s: f64,
    /// Deepest slave penetration the contact detected and corrected (m).
    pub max_slave_penetration_m: f64,
    /// Most slaves left inside the projectile after a step's correction (checked at every
    /// history row and at the end; it should be 0), and how deep the deepest was (m).
    pub slaves_inside: usize,
    pub max_residual_penetration_m: f64,
    /// Non-finite values in the final state (`Simulation::nonfinite_values`).
    pub nonfinite_values: usize,
    /// Particles held at the density floor at the end (`cpu::concrete::MIN_DENSITY_RATIO`):
    /// debris that separated from its neighbours.
    #[serde(default)]
    pub particles_at_density_floor: usize,
    /// Concrete thrown off the front face (the entry crater's spall) and off the rear face
    /// (scabbing) at the end: the mass of the particles lying more than one spacing outside
    /// the slab's original faces (kg; `Model::ejecta`).
    #[serde(default)]
    pub front_ejecta_kg: f64,
    #[serde(default)]
    pub rear_ejecta_kg: f64,
    /// Largest speed of a particle or node at the end (m/s).
    pub max_speed_m_s: f64,
    /// How many steps built the SPH neighbour lists (the rest reused them).
    pub neighbour_list_builds: u64,
    /// GPU runs: blocking waits, bytes read back and bytes written, by what asked for them
    /// (the steps, the history rows, the full reads, the summary's own included).
    /// Absent on the CPU and in summaries written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_transfers: Option<crate::gpu::traffic::Traffic>,
    /// Steps whose Δt the projectile's elements set (their least stable step no larger than
    /// the particles'), and those the target's particles set.
    #[serde(default)]
    pub fem_limited_steps: u64,
    #[serde(default)]
    pub sph_limited_steps: u64,
    /// The element or particle whose own stable step is the least at the end: which, where,
    /// and its state.
    #[serde(default)]
    pub smallest_step_at_end: String,
}

impl Summary {
    /// The projectile's forward speed (m/s) when a penetration ran out of time before it came
    /// to rest: its depth is then not final. `None` when it stopped, or was still moving at no
    /// more than 1 % of `striking` m/s.
    pub fn unfinished_penetration(&self, striking: f64) -> Option<f64> {
        (self.stop_reason == END_TIME_REACHED && self.projectile_velocity_m_s > 0.01 * striking)
            .then_some(self.projectile_velocity_m_s)
    }

    /// Whether the numbers could have come from a run: all finite, lengths, mass and times
    /// positive, damage in [0, 1]. A `summary.json` edited or damaged after the run fails it,
    /// and `--resume` runs again rather than report its numbers.
    pub fn is_plausible(&self) -> bool {
        let e = &self.energy;
        let all_finite = [
            self.depth_m,
            self.projectile_velocity_m_s,
            self.energy_error,
            self.momentum_error,
            self.contact_impulse_n_s,
            self.nose_impulse_n_s,
            e.initial_kinetic,
            e.kinetic,
            e.internal_projectile,
            e.internal_target,
            e.strain_energy_target,
            e.plastic_work_projectile,
            e.contact_dissipated,
            e.wall_dissipated,
        ]
        .iter()
        .all(|x| x.is_finite());
        let positive = |x: f64| x.is_finite() && x > 0.0;
        let not_negative = |x: f64| x.is_finite() && x >= 0.0;
        let damage = |d: f64| (0.0..=1.0).contains(&d);
        all_finite
            && [
                self.final_length_m,
                self.max_radius_m,
                self.projectile_mass_kg,
            ]
            .into_iter()
            .all(positive)
            && [
                self.time_s,
                self.wall_s,
                self.max_plastic_strain,
                self.max_plastic_strain_shank,
                self.checkerboard_pa,
                self.volume_checkerboard,
                self.min_dt_s,
                self.max_slave_penetration_m,
                self.max_residual_penetration_m,
                self.max_speed_m_s,
            ]
            .into_iter()
            .all(not_negative)
            && self.max_dt_s.is_finite()
            && self.min_dt_s <= self.max_dt_s
            && damage(self.max_damage)
            && damage(self.max_damage_shank)
            && self.checkerboard_over_flow_stress.is_none_or(not_negative)
    }
}

/// Energy account at the end of the run (J).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct EnergySummary {
    pub initial_kinetic: f64,
    pub kinetic: f64,
    pub internal_projectile: f64,
    /// The work the particle forces did, split pairwise (the account's term).
    pub internal_target: f64,
    /// The same as the integrated strain power σ:ε̇ of the corrected velocity gradient, with
    /// viscous heating: not in the account; its distance from `internal_target` is the SPH
    /// discretisation's mismatch between strain rate and force.
    pub strain_energy_target: f64,
    pub plastic_work_projectile: f64,
    pub contact_dissipated: f64,
    pub wall_dissipated: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Only a run cut off by its end time with the projectile still going forward faster than
    /// 1 % of its striking speed has an unfinished depth.
    #[test]
    fn an_unfinished_penetration_is_one_cut_off_while_moving() {
        let at = |reason: &str, v: f64| Summary {
            stop_reason: reason.into(),
            projectile_velocity_m_s: v,
            ..Summary::default()
        };
        assert_eq!(
            at(END_TIME_REACHED, 19.7).unfinished_penetration(445.0),
            Some(19.7)
        );
        assert_eq!(
            at(END_TIME_REACHED, 4.0).unfinished_penetration(445.0),
            None
        );
        assert_eq!(
            at(END_TIME_REACHED, -3.0).unfinished_penetration(445.0),
            None
        );
        assert_eq!(
            at("projectile at rest", 19.7).unfinished_penetration(445.0),
            None
        );
    }
}
