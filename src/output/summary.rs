//! `summary.json`: what a run produced and how it ended.

use serde::Serialize;

#[derive(Clone, Debug, Default, Serialize)]
pub struct Summary {
    pub scene: String,
    /// `completed`, or the reason the run stopped.
    pub status: String,
    /// Why a completed run ended: end time, projectile at rest, projectile left the target.
    pub stop_reason: String,
    pub backend: String,
    pub adapter: String,
    pub depth_m: f64,
    pub projectile_velocity_m_s: f64,
    pub max_damage: f64,
    pub max_plastic_strain: f64,
    pub final_length_m: f64,
    pub max_radius_m: f64,
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
    pub max_slave_penetration_m: f64,
    /// GPU runs: how many steps built the SPH neighbour lists (the rest reused them).
    pub neighbour_list_builds: u64,
}

/// Energy account at the end of the run (J).
#[derive(Clone, Debug, Default, Serialize)]
pub struct EnergySummary {
    pub initial_kinetic: f64,
    pub kinetic: f64,
    pub internal_projectile: f64,
    pub internal_target: f64,
    pub plastic_work_projectile: f64,
    pub contact_dissipated: f64,
    pub wall_dissipated: f64,
}
