//! What a simulation writes: history rows, VTK frames and the summary.

use super::{Fresh, Model, Pass, RunError, Simulation, Stepper};
use crate::cpu;
use crate::output::frames::{Frame, Part};
use crate::output::history::Row;
use crate::output::summary::{EnergySummary, Summary};
use crate::output::vtk::Vtu;

impl Model {
    pub(super) fn history_row(&self) -> Row {
        let body = self.body_bounds();
        Row {
            time: self.time,
            step: self.step,
            dt: self.dt as f64,
            depth: body.depth,
            velocity: self.projectile_velocity(),
            kinetic: self.kinetic_energy(),
            internal: self.internal_target() + self.internal_projectile(),
            contact_dissipated: self.account.contact_dissipated,
            contact_impulse: self.account.contact_impulse,
            nose_impulse: self.account.nose_impulse,
            energy_error: self.energy_error(),
            max_damage: self.max_damage(),
            max_plastic_strain: self.max_plastic_strain(),
            hits: self.last_hits,
            damage_area: self.damage_area(),
            plastic_work: self.account.plastic_work,
            checkerboard: self.projectile.elements.max_checkerboard() as f64,
            length: body.length,
            radius: body.radius,
        }
    }

    /// VTK frame `number` of the target (when it has particles) and the projectile: owned
    /// copies of their arrays, for the frame writer's thread.
    pub fn frame(&self, number: usize) -> Frame {
        let world = |z: &[f32]| -> Vec<f32> { z.iter().map(|&z| self.world_z(z) as f32).collect() };
        let fields = |fields: &[(&str, &[f32])]| -> Vec<(String, Vec<f32>)> {
            fields
                .iter()
                .map(|(name, values)| (name.to_string(), values.to_vec()))
                .collect()
        };
        let mut parts = Vec::with_capacity(2);
        let p = &self.particles;
        if !p.is_empty() {
            let speed: Vec<f32> = (0..p.len()).map(|i| p.vr[i].hypot(p.vz[i])).collect();
            let grid = Vtu {
                r: p.r.clone(),
                z: world(&p.z),
                triangles: None,
                point_data: fields(&[
                    ("pressure", &p.p),
                    ("density", &p.rho),
                    ("damage", &p.damage),
                    ("plastic_strain", &p.eps_p),
                    ("speed", &speed),
                    ("v_r", &p.vr),
                    ("v_z", &p.vz),
                    ("energy", &p.energy),
                    ("strain_energy", &p.strain_energy),
                    ("mass", &p.mass),
                ]),
                cell_data: Vec::new(),
            };
            parts.push(Part {
                file: format!("target_{number:05}.vtu"),
                index: 0,
                grid,
            });
        }
        let n = &self.projectile.nodes;
        let e = &self.projectile.elements;
        let seq: Vec<f32> = (0..e.len())
            .map(|k| cpu::deviator::von_mises(&[e.s_rr[k], e.s_zz[k], e.s_rz[k], e.s_tt[k]]))
            .collect();
        let failed: Vec<f32> = e.failed.iter().map(|&f| f as f32).collect();
        let grid = Vtu {
            r: n.r.clone(),
            z: world(&n.z),
            triangles: Some(e.nodes.clone()),
            point_data: fields(&[("v_r", &n.vr), ("v_z", &n.vz)]),
            cell_data: fields(&[
                ("damage", &e.damage),
                ("failed", &failed),
                ("plastic_strain", &e.eps_p),
                ("pressure", &e.p),
                ("von_mises", &seq),
                ("temperature", &e.temperature),
            ]),
        };
        parts.push(Part {
            file: format!("projectile_{number:05}.vtu"),
            index: 1,
            grid,
        });
        Frame {
            number,
            step: self.step,
            time: self.time,
            parts,
        }
    }

    /// World z of a model position ([`Model::recentre`]).
    pub(super) fn world_z(&self, z: f32) -> f64 {
        z as f64 + self.origin
    }

    /// Passes that ran, with the side they ran on.
    pub fn pass_names(&self, backend: &str) -> Vec<String> {
        self.passes
            .iter()
            .map(|p| {
                format!(
                    "{}:{}",
                    p.name(),
                    if *p == Pass::ContactCorrect {
                        "cpu"
                    } else {
                        backend
                    }
                )
            })
            .collect()
    }

    /// The run's summary, with where it stepped (`stepper`).
    pub(super) fn summary(
        &self,
        status: &str,
        stop_reason: &str,
        wall_s: f64,
        stepper: &dyn Stepper,
    ) -> Summary {
        let body = self.body_bounds();
        let a = &self.account;
        let ejecta = self.ejecta();
        Summary {
            scene: self.scene.name.clone(),
            status: status.to_string(),
            stop_reason: stop_reason.to_string(),
            backend: stepper.backend().into(),
            adapter: self.adapter.clone(),
            solver_build: crate::output::summary::build_id().into(),
            depth_m: body.depth,
            projectile_velocity_m_s: self.projectile_velocity(),
            max_damage: self.max_damage(),
            max_damage_shank: self.max_damage_shank(),
            max_plastic_strain: self.max_plastic_strain(),
            max_plastic_strain_shank: self.max_plastic_strain_shank(),
            checkerboard_pa: self.projectile.elements.max_checkerboard() as f64,
            volume_checkerboard: self
                .projectile
                .elements
                .max_volume_checkerboard(&self.projectile.nodes)
                as f64,
            checkerboard_over_flow_stress: Some(
                self.projectile
                    .elements
                    .max_checkerboard_over_flow(&self.fem.strength) as f64,
            ),
            final_length_m: body.length,
            max_radius_m: body.radius,
            contact_impulse_n_s: a.contact_impulse,
            nose_impulse_n_s: a.nose_impulse,
            time_s: self.time,
            steps: self.step,
            particles: self.particles.len(),
            elements: self.projectile.elements.len(),
            nodes: self.projectile.nodes.len(),
            projectile_mass_kg: self.projectile.total_mass,
            wall_s,
            energy_error: self.energy_error(),
            momentum_error: self.momentum_error(),
            energy: EnergySummary {
                initial_kinetic: a.initial_kinetic,
                kinetic: self.kinetic_energy(),
                internal_projectile: self.internal_projectile(),
                internal_target: self.internal_target(),
                strain_energy_target: self.strain_energy_target(),
                plastic_work_projectile: a.plastic_work,
                contact_dissipated: a.contact_dissipated,
                wall_dissipated: a.wall_dissipated,
            },
            passes: self.pass_names(stepper.backend()),
            min_dt_s: if a.min_dt == f64::MAX { 0.0 } else { a.min_dt },
            max_dt_s: a.max_dt,
            max_slave_penetration_m: a.max_penetration as f64,
            slaves_inside: a.slaves_inside,
            nonfinite_values: self.nonfinite_values(),
            particles_at_density_floor: self.particles_at_density_floor(),
            front_ejecta_kg: ejecta[0],
            rear_ejecta_kg: ejecta[1],
            max_speed_m_s: self.max_speed(),
            max_residual_penetration_m: a.max_residual_penetration as f64,
            neighbour_list_builds: stepper.builds().unwrap_or(self.grid.builds),
            gpu_transfers: stepper.traffic(),
            fem_limited_steps: a.fem_limited_steps,
            sph_limited_steps: a.sph_limited_steps,
            smallest_step_at_end: self.smallest_step_site(),
        }
    }
}

impl Simulation {
    /// The history row of the state as it stands (what it reads brought up to date first).
    pub(super) fn history_row(&mut self) -> Result<Row, RunError> {
        Ok(self.current(Fresh::History)?.history_row())
    }

    /// VTK frame `number` of the state brought up to date first.
    pub(super) fn frame(&mut self, number: usize) -> Result<Frame, RunError> {
        Ok(self.current(Fresh::Full)?.frame(number))
    }

    /// The run's summary, the host's copy of the state brought up to date first; where that
    /// read-back fails, of the copy as it stands (`status` says what failed).
    pub(super) fn summary(&mut self, status: &str, stop_reason: &str, wall_s: f64) -> Summary {
        let _ = self.current(Fresh::Full);
        self.model
            .summary(status, stop_reason, wall_s, self.stepper.as_ref())
    }
}
