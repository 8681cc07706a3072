//! The explicit coupled step (physics.md §5) and the run loop: stop conditions, energy and
//! momentum account, outputs.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::contact::{self, ContactBodies, Hit};
use crate::cpu::{self, neighbours::CellGrid};
use crate::gpu::step::{GpuStep, StepSetup, Sync};
use crate::mesh;
use crate::output;
use crate::output::history::{History, Row};
use crate::output::progress::Progress;
use crate::output::summary::{EnergySummary, Summary};
use crate::output::vtk;
use crate::scene::{Backend, Scene};
use crate::state::{FemParams, Particles, Projectile, SphParams};

/// One pass of the step. A scene's pass list holds only what it needs (architecture.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    Integrate,
    ContactDetect,
    ContactCorrect,
    Neighbours,
    SphRates,
    Concrete,
    SphForces,
    FemStress,
    FemForces,
}

impl Pass {
    pub fn name(&self) -> &'static str {
        match self {
            Pass::Integrate => "integrate",
            Pass::ContactDetect => "contact_detect",
            Pass::ContactCorrect => "contact_correct",
            Pass::Neighbours => "neighbours",
            Pass::SphRates => "sph_rates",
            Pass::Concrete => "concrete",
            Pass::SphForces => "sph_forces",
            Pass::FemStress => "fem_stress",
            Pass::FemForces => "fem_forces",
        }
    }
}

/// Why a run stopped early or went wrong.
#[derive(Clone, Debug, PartialEq)]
pub enum RunError {
    /// Bad input caught while building the model.
    Setup(String),
    /// The run went unstable: what, where and when.
    Unstable(String),
    /// Output could not be written.
    Io(String),
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RunError::Setup(m) => write!(f, "setup: {m}"),
            RunError::Unstable(m) => write!(f, "unstable: {m}"),
            RunError::Io(m) => write!(f, "output: {m}"),
        }
    }
}

impl std::error::Error for RunError {}

/// Running energy and impulse account (f64).
#[derive(Clone, Copy, Debug, Default)]
pub struct Account {
    pub initial_kinetic: f64,
    pub initial_momentum: f64,
    pub contact_dissipated: f64,
    pub wall_dissipated: f64,
    /// z-impulse exerted on the model by fixed boundaries and the wall (N s).
    pub boundary_impulse: f64,
    /// z-impulse the contact gave the projectile (N s; +z resists a flight along −z).
    pub contact_impulse: f64,
    /// The part of `contact_impulse` given through the nose's master segments (N s).
    pub nose_impulse: f64,
    pub plastic_work: f64,
    /// Deepest slave penetration the contact found (before correcting it), m.
    pub max_penetration: f32,
    /// Most slaves found inside the projectile after a step's correction, and the deepest of
    /// them (m), over the checks at history rows and the end (`check_slaves_inside`).
    pub slaves_inside: usize,
    pub max_residual_penetration: f32,
    pub min_dt: f64,
    pub max_dt: f64,
}

/// The whole model and its state.
pub struct Simulation {
    pub scene: Scene,
    pub particles: Particles,
    pub sph: Option<SphParams>,
    pub grid: CellGrid,
    pub projectile: Projectile,
    pub fem: FemParams,
    /// Slave particles (preselected once, physics.md §4).
    pub slaves: Vec<u32>,
    pub passes: Vec<Pass>,
    pub time: f64,
    pub step: u64,
    pub dt: f32,
    pub account: Account,
    pub last_hits: usize,
    /// The wall, a Taylor scene's: the model's z = 0 ([`Scene::origin_z`]).
    wall_z: Option<f32>,
    escape: f32,
    /// The GPU step when the run is on the GPU; the CPU state is then refreshed by `sync`.
    gpu: Option<Box<GpuStep>>,
    /// The account when the GPU took over (its accumulators add to it).
    gpu_base: Account,
    /// Elements whose centroid started behind the nose (in the shank): a shell's wall.
    shank: Vec<u32>,
    /// Per master segment: whether it started on the nose (`nose_masters`).
    on_nose: Vec<bool>,
    /// "cpu" or "gpu", and the adapter's name.
    pub backend: &'static str,
    pub adapter: String,
}

impl Simulation {
    /// Build the meshes, the state and the pass list, and evaluate the first forces and Δt.
    pub fn new(scene: &Scene) -> Result<Simulation, RunError> {
        let mut sim = Simulation::assemble(scene)?;
        sim.start()?;
        Ok(sim)
    }

    /// Build the meshes, the state and the pass list, at rest before the first forces.
    fn assemble(scene: &Scene) -> Result<Simulation, RunError> {
        crate::estimate::check_fits(scene).map_err(RunError::Setup)?;
        // Built with the world's `origin_z` at z = 0, added back in frames and messages
        // (`world_z`): f32 positions resolve a step's motion only near the origin (a Taylor bar
        // placed at z = 100 m would not move at all).
        let spec = &scene.model_projectile();
        let pmesh = mesh::projectile::build(spec).map_err(|e| RunError::Setup(e.to_string()))?;
        let projectile =
            Projectile::from_mesh(&pmesh, spec.velocity as f32, spec.material.strength.t_room);
        let fem = FemParams::new(&spec.material);
        let (particles, sph) = match &scene.target {
            Some(t) => {
                let mut lattice = mesh::target::lattice(
                    t.radius,
                    t.thickness,
                    t.spacing,
                    t.concrete.density as f64,
                )
                .map_err(|e| RunError::Setup(e.to_string()))?;
                mesh::target::drill(&mut lattice, t.lead_hole_depth, t.lead_hole_diameter);
                (
                    Particles::from_lattice(&lattice, t),
                    Some(SphParams::new(t)),
                )
            }
            None => (Particles::default(), None),
        };
        let shank_from = (spec.nose_z + spec.shape.nose_length(spec.diameter)) as f32;
        let shank = (0..pmesh.elements.len() as u32)
            .filter(|&e| {
                let n = pmesh.elements[e as usize];
                n.iter().map(|&i| pmesh.node_z[i as usize]).sum::<f32>() / 3.0 > shank_from
            })
            .collect();
        let on_nose = nose_masters(&pmesh, shank_from);
        let r_max = pmesh.node_r.iter().copied().fold(0.0f32, f32::max);
        let k = scene.contact.slave_radius_factor as f32;
        let slaves = (0..particles.len() as u32)
            .filter(|&i| particles.r[i as usize] <= k * r_max)
            .collect();
        let rigid = scene.contact.lambda == 0.0 && scene.wall.is_none();
        let mut passes = vec![Pass::Integrate];
        if sph.is_some() {
            passes.extend([
                Pass::ContactDetect,
                Pass::ContactCorrect,
                Pass::Neighbours,
                Pass::SphRates,
                Pass::Concrete,
                Pass::SphForces,
            ]);
        }
        if !rigid {
            passes.extend([Pass::FemStress, Pass::FemForces]);
        }
        let extent = scene
            .target
            .as_ref()
            .map_or(0.0, |t| t.radius.max(t.thickness))
            + spec.length
            + 0.5 * spec.diameter
            + spec.nose_z.abs();
        let mut sim = Simulation {
            scene: scene.clone(),
            particles,
            sph,
            grid: CellGrid::default(),
            projectile,
            fem,
            slaves,
            passes,
            time: 0.0,
            step: 0,
            dt: 0.0,
            account: Account::default(),
            last_hits: 0,
            wall_z: scene.wall.as_ref().map(|_| 0.0),
            escape: (20.0 * extent) as f32,
            gpu: None,
            gpu_base: Account::default(),
            shank,
            on_nose,
            backend: "cpu",
            adapter: "none (CPU reference path)".into(),
        };
        sim.account.initial_kinetic = sim.kinetic_energy();
        sim.account.initial_momentum = sim.momentum_z();
        sim.account.min_dt = f64::MAX;
        Ok(sim)
    }

    /// The first forces and Δt: unstable when the scene as built cannot take a step.
    fn start(&mut self) -> Result<(), RunError> {
        self.forces(0.0)?;
        self.dt = self.stable_dt()?;
        Ok(())
    }

    /// Move the step onto a GPU adapter (`name`: part of its name, or the best one). The
    /// state built by `new` is uploaded; from here on `step` runs there.
    pub fn use_gpu(&mut self, gpu: crate::gpu::Gpu) -> Result<(), RunError> {
        let adapter = gpu.adapter_name();
        let setup = StepSetup {
            particles: self.sph.as_ref().map(|sp| (&self.particles, sp)),
            projectile: &self.projectile,
            fem: &self.fem,
            deformable: self.has(Pass::FemStress),
            slaves: &self.slaves,
            contact: self.has(Pass::ContactDetect),
            wall_z: self.wall_z,
            escape: self.escape,
            cfl: self.scene.run.cfl as f32,
            dt: self.dt,
            list_skin: crate::gpu::step::LIST_SKIN,
        };
        let step = GpuStep::new(gpu, &setup).map_err(RunError::Setup)?;
        self.gpu = Some(Box::new(step));
        self.gpu_base = self.account;
        self.backend = "gpu";
        self.adapter = adapter;
        Ok(())
    }

    /// The GPU step, when the run is on the GPU (bench: profiling and memory).
    pub fn gpu_step(&mut self) -> Option<&mut GpuStep> {
        self.gpu.as_deref_mut()
    }

    /// Bring the CPU copy of the state up to date (GPU runs; nothing to do on the CPU).
    pub fn sync(&mut self) -> Result<(), RunError> {
        self.sync_part(Sync::Full)
    }

    /// Bring up to date what `history_row` reads (GPU runs): the rest may be stale.
    pub fn sync_history(&mut self) -> Result<(), RunError> {
        self.sync_part(Sync::History)
    }

    fn sync_part(&mut self, what: Sync) -> Result<(), RunError> {
        let Some(g) = self.gpu.as_mut() else {
            return Ok(());
        };
        let t = g
            .download(&mut self.particles, &mut self.projectile, what)
            .map_err(|e| RunError::Unstable(format!("GPU: {e}")))?;
        let base = self.gpu_base;
        self.account.boundary_impulse = base.boundary_impulse + t.boundary_impulse;
        self.account.wall_dissipated = base.wall_dissipated + t.wall_lost;
        self.account.plastic_work = base.plastic_work + t.plastic_work;
        self.dt = t.next_dt;
        Ok(())
    }

    /// One step on the GPU: up to contact detection there, the correction here, and the rest
    /// there in the next submission (gpu::step).
    fn step_gpu(&mut self, g: &mut GpuStep) -> Result<(), RunError> {
        let gpu_err = |e: String| RunError::Unstable(format!("GPU: {e}"));
        let rb = g.advance().map_err(gpu_err)?;
        let dt = rb.dt;
        if collapsed(dt) || dt > 1.0 {
            // The site of the collapse is read from the state: bring it back first.
            g.download(&mut self.particles, &mut self.projectile, Sync::Full)
                .map_err(gpu_err)?;
        }
        self.check_dt(dt)?;
        {
            let n = &mut self.projectile.nodes;
            n.r = rb.node_r;
            n.z = rb.node_z;
            n.vr = rb.node_vr;
            n.vz = rb.node_vz;
        }
        if let Some((what, index, reason)) = GpuStep::status_problem(&rb.status) {
            let (r, z) = self.locate(g, what, index as usize);
            return Err(RunError::Unstable(format!(
                "{what} {index} {reason} at (r {r:.4e}, z {:.4e}) m, step {}, t {:.4e} s",
                self.world_z(z),
                self.step,
                self.time
            )));
        }
        if self.has(Pass::ContactDetect) {
            self.last_hits = rb.hits.len();
            if !rb.hits.is_empty() {
                let mut order: Vec<usize> = (0..rb.hits.len()).collect();
                order.sort_by_key(|&k| rb.hits[k].0);
                let slave = |k: usize| rb.hits[order[k]].0;
                let data = |k: usize| rb.hit_data[order[k]];
                let m = order.len();
                let mut sr: Vec<f32> = (0..m).map(|k| data(k)[0]).collect();
                let mut sz: Vec<f32> = (0..m).map(|k| data(k)[1]).collect();
                let mut svr: Vec<f32> = (0..m).map(|k| data(k)[2]).collect();
                let mut svz: Vec<f32> = (0..m).map(|k| data(k)[3]).collect();
                let sm: Vec<f32> = (0..m)
                    .map(|k| self.particles.mass[slave(k) as usize])
                    .collect();
                let hits: Vec<Hit> = (0..m)
                    .map(|k| Hit {
                        slave: k as u32,
                        master: rb.hits[order[k]].1,
                    })
                    .collect();
                correct_contact(
                    &hits,
                    Slaves {
                        r: &mut sr,
                        z: &mut sz,
                        vr: &mut svr,
                        vz: &mut svz,
                        mass: &sm,
                    },
                    &mut self.projectile,
                    &self.on_nose,
                    self.scene.contact.lambda as f32,
                    dt,
                    &mut self.account,
                );
                let fixes: Vec<(u32, [f32; 4])> = (0..m)
                    .map(|k| (slave(k), [sr[k], sz[k], svr[k], svz[k]]))
                    .collect();
                // How far the correction moved a slave (the neighbour lists' watch).
                let moved = (0..m)
                    .map(|k| (sr[k] - data(k)[0]).hypot(sz[k] - data(k)[1]))
                    .fold(0.0f32, f32::max);
                let n = &self.projectile.nodes;
                g.correct(&fixes, moved, n);
            }
        }
        self.time += dt as f64;
        self.step += 1;
        self.dt = dt;
        self.account.min_dt = self.account.min_dt.min(dt as f64);
        self.account.max_dt = self.account.max_dt.max(dt as f64);
        Ok(())
    }

    /// Position of an entity the GPU flagged (the state is read back for it).
    fn locate(&mut self, g: &mut GpuStep, what: &str, index: usize) -> (f32, f32) {
        if g.download(&mut self.particles, &mut self.projectile, Sync::Full)
            .is_err()
        {
            return (f32::NAN, f32::NAN);
        }
        let n = &self.projectile.nodes;
        match what {
            "particle" => (self.particles.r[index], self.particles.z[index]),
            "node" => (n.r[index], n.z[index]),
            _ => {
                let el = self.projectile.elements.nodes[index];
                let c = |v: &[f32]| el.iter().map(|&k| v[k as usize]).sum::<f32>() / 3.0;
                (c(&n.r), c(&n.z))
            }
        }
    }

    fn has(&self, pass: Pass) -> bool {
        self.passes.contains(&pass)
    }

    /// Rates, stresses and forces at the current configuration, advancing the material state by
    /// `dt` (0 at start-up).
    fn forces(&mut self, dt: f32) -> Result<(), RunError> {
        if let Some(sph) = &self.sph {
            cpu::neighbours::run(
                &mut self.grid,
                &self.particles.r,
                &self.particles.z,
                cpu::integrate::support(sph),
            );
            cpu::sph_rates::run(&mut self.particles, &self.grid, sph);
            cpu::concrete::run(&mut self.particles, sph, dt);
            cpu::sph_forces::run(&mut self.particles, &self.grid, sph);
        }
        if self.has(Pass::FemStress) {
            let p = &mut self.projectile;
            let origin = self.scene.origin_z();
            cpu::fem_stress::run(&mut p.elements, &p.nodes, &self.fem, dt).map_err(|inv| {
                RunError::Unstable(format!(
                    "element {} inverted at (r {:.4e}, z {:.4e}) m, step {}, t {:.4e} s",
                    inv.element,
                    inv.r,
                    inv.z as f64 + origin,
                    self.step,
                    self.time
                ))
            })?;
            cpu::fem_forces::run(&mut p.nodes, &p.elements);
            self.account.plastic_work += p
                .elements
                .plastic_work
                .iter()
                .map(|&w| w as f64)
                .sum::<f64>();
        }
        Ok(())
    }

    fn stable_dt(&mut self) -> Result<f32, RunError> {
        let mut dt = f32::MAX;
        if let Some(sph) = &self.sph {
            dt = dt.min(cpu::timestep::particle_dt(&self.particles, sph));
        }
        if self.has(Pass::FemStress) {
            dt = dt.min(cpu::timestep::element_dt(&self.projectile.elements));
        }
        let dt = dt * self.scene.run.cfl as f32;
        self.check_dt(dt)?;
        Ok(dt)
    }

    /// The next step must be positive, finite and bounded: it collapses when the mesh or the
    /// lattice does, and nothing bounds it when every element has failed and opened
    /// (`cpu::fem_stress::OPEN_RELATIVE_VOLUME`) and there is no target, or when the
    /// projectile's waves are absurdly slow (a bar at rest with E = 1e-9 Pa).
    fn check_dt(&self, dt: f32) -> Result<(), RunError> {
        if collapsed(dt) {
            return Err(RunError::Unstable(format!(
                "time step collapsed to {dt:e} s (the least stable step × run.cfl = {}; a step \
                 under {MIN_STEP:e} s is taken as a collapse) at step {}, t {:.4e} s: {}",
                crate::scene::number_text(self.scene.run.cfl),
                self.step,
                self.time,
                self.smallest_step_site()
            )));
        }
        if dt > 1.0 {
            let e = &self.projectile.elements;
            let why = if self.sph.is_none() && e.failed.iter().all(|&f| f != 0) {
                "every element of the projectile has failed and opened, and there is no target"
                    .to_string()
            } else {
                // Waves that slow: the site says which element, and its state.
                self.smallest_step_site()
            };
            return Err(RunError::Unstable(format!(
                "nothing limits the time step at step {}, t {:.4e} s: it would be {dt:e} s, \
                 more than 1 s: {why}",
                self.step, self.time
            )));
        }
        Ok(())
    }

    /// Where the step is smallest: the element or particle whose own stable step is the least,
    /// where it is and the state that made it so (a crushed element, a compressed particle).
    /// Reads the CPU copy of the state, which a GPU run must have downloaded.
    fn smallest_step_site(&self) -> String {
        let mut site: Option<(f32, String)> = None;
        let mut offer = |dt: f32, what: &dyn Fn() -> String| {
            if site.as_ref().is_none_or(|s| dt < s.0) {
                site = Some((dt, what()));
            }
        };
        if self.has(Pass::FemStress) {
            let e = &self.projectile.elements;
            let n = &self.projectile.nodes;
            if let Some(k) = (0..e.len()).min_by(|&a, &b| e.dt[a].total_cmp(&e.dt[b])) {
                offer(e.dt[k], &|| {
                    let el = e.nodes[k];
                    let c = |v: &[f32]| el.iter().map(|&i| v[i as usize]).sum::<f32>() / 3.0;
                    let volume = crate::mesh::geometry::Geometry::new(&el, &n.r, &n.z).volume();
                    format!(
                        "element {k} has the smallest stable step, {:e} s, at (r {:.4e}, \
                         z {:.4e}) m: {:.3e} of its initial volume, plastic strain {:.3}, \
                         damage {:.2}{}",
                        e.dt[k],
                        c(&n.r),
                        self.world_z(c(&n.z)),
                        volume / e.volume0[k],
                        e.eps_p[k],
                        e.damage[k],
                        if e.failed[k] != 0 { ", failed" } else { "" }
                    )
                });
            }
        }
        if let Some(sph) = &self.sph {
            let p = &self.particles;
            let step = |i: usize| cpu::timestep::particle_step(p, sph, i);
            if let Some(i) = (0..p.len()).min_by(|&a, &b| step(a).total_cmp(&step(b))) {
                offer(step(i), &|| {
                    format!(
                        "particle {i} has the smallest stable step, {:e} s, at (r {:.4e}, \
                         z {:.4e}) m: density {:.4e} kg/m³, sound speed {:.0} m/s, speed {:.0} \
                         m/s",
                        step(i),
                        p.r[i],
                        self.world_z(p.z[i]),
                        p.rho[i],
                        p.sound[i],
                        p.vr[i].hypot(p.vz[i])
                    )
                });
            }
        }
        site.map_or_else(|| "nothing sets it".into(), |s| s.1)
    }

    /// One explicit step: velocities and positions, contact, then rates, stresses and forces at
    /// the new configuration, then the next Δt.
    pub fn step(&mut self) -> Result<(), RunError> {
        if let Some(mut g) = self.gpu.take() {
            let result = self.step_gpu(&mut g);
            self.gpu = Some(g);
            return result;
        }
        let dt = self.dt;
        let origin = self.scene.origin_z();
        let blowup = |b: cpu::integrate::Blowup, step: u64, time: f64| {
            RunError::Unstable(format!(
                "{} {} {} at (r {:.4e}, z {:.4e}) m, step {step}, t {time:.4e} s",
                b.what,
                b.index,
                b.reason,
                b.r,
                b.z as f64 + origin
            ))
        };
        if let Some(sph) = &self.sph {
            // Impulse the fixed boundary exerts on the rest: minus what its particles would
            // have gained from their neighbours.
            let p = &self.particles;
            self.account.boundary_impulse -= (0..p.len())
                .filter(|&i| p.fixed[i] != 0)
                .map(|i| p.mass[i] as f64 * p.az[i] as f64 * dt as f64)
                .sum::<f64>();
            cpu::integrate::particles(&mut self.particles, sph, dt, self.escape)
                .map_err(|b| blowup(b, self.step, self.time))?;
        }
        let p_before = self.projectile_momentum();
        let lost = cpu::integrate::nodes(&mut self.projectile.nodes, dt, self.wall_z, self.escape)
            .map_err(|b| blowup(b, self.step, self.time))?;
        if self.wall_z.is_some() {
            self.account.wall_dissipated += lost;
            let forces: f64 = self.projectile.nodes.fz.iter().map(|&f| f as f64).sum();
            self.account.boundary_impulse +=
                self.projectile_momentum() - p_before - forces * dt as f64;
        }
        if self.has(Pass::ContactDetect) {
            let hits = self.detect();
            self.last_hits = hits.len();
            let p = &mut self.particles;
            correct_contact(
                &hits,
                Slaves {
                    r: &mut p.r,
                    z: &mut p.z,
                    vr: &mut p.vr,
                    vz: &mut p.vz,
                    mass: &p.mass,
                },
                &mut self.projectile,
                &self.on_nose,
                self.scene.contact.lambda as f32,
                dt,
                &mut self.account,
            );
        }
        self.forces(dt)?;
        self.time += dt as f64;
        self.step += 1;
        self.account.min_dt = self.account.min_dt.min(dt as f64);
        self.account.max_dt = self.account.max_dt.max(dt as f64);
        self.dt = self.stable_dt()?;
        Ok(())
    }

    fn detect(&self) -> Vec<Hit> {
        cpu::contact_detect::run(
            &self.slaves,
            &self.particles,
            &self.projectile.nodes,
            &self.projectile.masters,
        )
    }

    pub fn kinetic_energy(&self) -> f64 {
        let p = &self.particles;
        let n = &self.projectile.nodes;
        let ke = |m: &[f32], vr: &[f32], vz: &[f32]| -> f64 {
            (0..m.len())
                .map(|i| 0.5 * m[i] as f64 * ((vr[i] as f64).powi(2) + (vz[i] as f64).powi(2)))
                .sum()
        };
        ke(&p.mass, &p.vr, &p.vz) + ke(&n.mass, &n.vr, &n.vz)
    }

    fn projectile_momentum(&self) -> f64 {
        let n = &self.projectile.nodes;
        (0..n.len())
            .map(|i| n.mass[i] as f64 * n.vz[i] as f64)
            .sum()
    }

    /// Total z-momentum of projectile and target.
    pub fn momentum_z(&self) -> f64 {
        let p = &self.particles;
        self.projectile_momentum()
            + (0..p.len())
                .map(|i| p.mass[i] as f64 * p.vz[i] as f64)
                .sum::<f64>()
    }

    pub fn internal_target(&self) -> f64 {
        let p = &self.particles;
        (0..p.len())
            .map(|i| p.mass[i] as f64 * p.energy[i] as f64)
            .sum()
    }

    /// The target's energy as the integrated strain power (`Particles::strain_energy`), J.
    pub fn strain_energy_target(&self) -> f64 {
        let p = &self.particles;
        (0..p.len())
            .map(|i| p.mass[i] as f64 * p.strain_energy[i] as f64)
            .sum()
    }

    pub fn internal_projectile(&self) -> f64 {
        let e = &self.projectile.elements;
        (0..e.len())
            .map(|i| e.volume0[i] as f64 * e.energy[i] as f64)
            .sum()
    }

    /// (E_kin + E_int + dissipated − E₀)/E₀.
    pub fn energy_error(&self) -> f64 {
        let a = &self.account;
        let total = self.kinetic_energy()
            + self.internal_target()
            + self.internal_projectile()
            + a.contact_dissipated
            + a.wall_dissipated;
        (total - a.initial_kinetic) / a.initial_kinetic.max(f64::MIN_POSITIVE)
    }

    pub fn momentum_error(&self) -> f64 {
        let a = &self.account;
        (self.momentum_z() - a.initial_momentum - a.boundary_impulse).abs()
            / a.initial_momentum.abs().max(f64::MIN_POSITIVE)
    }

    /// Penetration depth: how far the nose tip is beyond the original front face z = 0 (m).
    /// The tip is the deepest node of the body ([`Simulation::attached_nodes`]): debris, free
    /// to run ahead of the body, is not the nose.
    pub fn depth(&self) -> f64 {
        self.body_bounds().depth
    }

    /// Centre-of-mass speed along the flight direction (−z), m/s.
    pub fn projectile_velocity(&self) -> f64 {
        -self.projectile_momentum() / self.projectile.total_mass
    }

    /// (length along z, largest radius) of the projectile, over its attached nodes (as
    /// [`Simulation::depth`]).
    pub fn projectile_extent(&self) -> (f64, f64) {
        let b = self.body_bounds();
        (b.length, b.radius)
    }

    /// The depth and extent of the body, from one pass over its nodes (the body is found once).
    fn body_bounds(&self) -> BodyBounds {
        let n = &self.projectile.nodes;
        let (mut z_min, mut z_max, mut r_max) = (f32::MAX, f32::MIN, 0.0f32);
        for i in self.attached_nodes() {
            z_min = z_min.min(n.z[i]);
            z_max = z_max.max(n.z[i]);
            r_max = r_max.max(n.r[i]);
        }
        BodyBounds {
            depth: match self.scene.target {
                Some(_) => (-(z_min as f64)).max(0.0),
                None => 0.0,
            },
            length: (z_max - z_min) as f64,
            radius: r_max as f64,
        }
    }

    /// The nodes of the projectile's body: the largest set (by reference volume) of elements
    /// that have not failed, joined through shared nodes. A node whose elements have all failed
    /// is debris, and so is a piece still intact but held to the body only by failed elements
    /// (a broken-off tip). Every node if every element has failed (nothing is left to tell the
    /// body from its debris).
    fn attached_nodes(&self) -> impl Iterator<Item = usize> + '_ {
        let body = body_nodes(
            &self.projectile.elements.nodes,
            &self.projectile.elements.failed,
            &self.projectile.elements.volume0,
            self.projectile.nodes.len(),
        );
        (0..self.projectile.nodes.len()).filter(move |&i| body[i])
    }

    pub fn max_damage(&self) -> f64 {
        self.projectile
            .elements
            .damage
            .iter()
            .copied()
            .fold(0.0f32, f32::max) as f64
    }

    /// Largest damage over the elements that started behind the nose (the shank; for a shell,
    /// its wall): the nose's surface elements, which fail at any speed here, left out.
    pub fn max_damage_shank(&self) -> f64 {
        self.shank_max(&self.projectile.elements.damage)
    }

    /// Largest plastic strain over the same elements: the body's deformation, the failed nose
    /// elements' strain left out.
    pub fn max_plastic_strain_shank(&self) -> f64 {
        self.shank_max(&self.projectile.elements.eps_p)
    }

    fn shank_max(&self, values: &[f32]) -> f64 {
        self.shank
            .iter()
            .map(|&e| values[e as usize])
            .fold(0.0f32, f32::max) as f64
    }

    /// Σ damage × r–z area over the projectile's elements in the current configuration (m²):
    /// the failed part of its section, partial damage counted by its share (the shell study's
    /// damaged area, paper Fig. 9).
    pub fn damage_area(&self) -> f64 {
        let n = &self.projectile.nodes;
        let e = &self.projectile.elements;
        let at = |k: u32| (n.r[k as usize] as f64, n.z[k as usize] as f64);
        e.nodes
            .iter()
            .zip(&e.damage)
            .filter(|(_, &d)| d > 0.0)
            .map(|(&[i, j, m], &d)| {
                let ((ri, zi), (rj, zj), (rm, zm)) = (at(i), at(j), at(m));
                let area = 0.5 * ((rj - ri) * (zm - zi) - (rm - ri) * (zj - zi));
                d as f64 * area.abs()
            })
            // Not `sum`, whose empty total is −0, which the history would print as "-0e0".
            .fold(0.0, |total, a| total + a)
    }

    pub fn max_plastic_strain(&self) -> f64 {
        self.projectile
            .elements
            .eps_p
            .iter()
            .copied()
            .fold(0.0f32, f32::max) as f64
    }

    /// Why the run should stop now, if it should.
    fn stop_reason(&self) -> Option<&'static str> {
        if self.time >= self.scene.run.end_time {
            return Some("end time reached");
        }
        if self.scene.run.stop_at_rest {
            if let Some(t) = &self.scene.target {
                let v = self.projectile_velocity();
                if self.step > 10 && v <= 0.0 {
                    return Some("projectile at rest");
                }
                let z_max = self
                    .projectile
                    .nodes
                    .z
                    .iter()
                    .copied()
                    .fold(f32::MIN, f32::max) as f64;
                if z_max < -t.thickness {
                    return Some("projectile left the target (perforation)");
                }
            }
        }
        None
    }

    /// Non-finite values in the state: positions, velocities, density, energy, pressure and
    /// deviator of the particles; positions and velocities of the nodes; stresses and energy
    /// of the elements.
    pub fn nonfinite_values(&self) -> usize {
        let p = &self.particles;
        let n = &self.projectile.nodes;
        let e = &self.projectile.elements;
        let fields: [&[f32]; 20] = [
            &p.r, &p.z, &p.vr, &p.vz, &p.rho, &p.energy, &p.p, &p.s_rr, &p.s_zz, &p.s_rz, &p.s_tt,
            &n.r, &n.z, &n.vr, &n.vz, &e.s_rr, &e.s_zz, &e.s_rz, &e.p, &e.energy,
        ];
        fields
            .iter()
            .map(|f| f.iter().filter(|x| !x.is_finite()).count())
            .sum()
    }

    /// Particles whose density is at the floor the continuity update holds it to.
    pub fn particles_at_density_floor(&self) -> usize {
        self.sph.as_ref().map_or(0, |sph| {
            let floor = crate::cpu::concrete::density_floor(&sph.concrete);
            self.particles
                .rho
                .iter()
                .filter(|&&rho| rho <= floor)
                .count()
        })
    }

    /// Largest speed of a particle or node (m/s).
    pub fn max_speed(&self) -> f64 {
        self.fastest().speed as f64
    }

    /// The fastest particle or node.
    fn fastest(&self) -> Fastest {
        let p = &self.particles;
        let n = &self.projectile.nodes;
        let find = |what, r: &[f32], z: &[f32], vr: &[f32], vz: &[f32]| {
            (0..vr.len()).fold(
                Fastest {
                    what,
                    index: 0,
                    r: f32::NAN,
                    z: f32::NAN,
                    speed: 0.0,
                },
                |f, i| {
                    let speed = vr[i].hypot(vz[i]);
                    if speed > f.speed {
                        Fastest {
                            what,
                            index: i,
                            r: r[i],
                            z: z[i],
                            speed,
                        }
                    } else {
                        f
                    }
                },
            )
        };
        let a = find("particle", &p.r, &p.z, &p.vr, &p.vz);
        let b = find("node", &n.r, &n.z, &n.vr, &n.vz);
        if b.speed > a.speed {
            b
        } else {
            a
        }
    }

    /// An error when the energy account has come apart (off by more than [`ENERGY_GUARD`] of
    /// the impact energy, or not a number), or when the target has given back more than that
    /// share of the impact energy beyond what was done on it (its internal energy, the work its
    /// forces did, below −[`ENERGY_GUARD`]: a target that starts at rest and unstressed can
    /// only return what it stored, so its forces are making energy even though the account
    /// books it): the run has blown up somewhere, and the message says when and names the
    /// fastest particle or node. A scene with nothing moving at the start has no impact energy
    /// to measure against and is not checked.
    pub fn check_energy(&self) -> Result<(), RunError> {
        self.energy_guard(self.energy_error())
    }

    /// [`Self::check_energy`] on an energy error already computed (a history row's).
    fn energy_guard(&self, error: f64) -> Result<(), RunError> {
        let impact = self.account.initial_kinetic;
        if impact <= 0.0 {
            return Ok(());
        }
        let made = -self.internal_target() / impact;
        let what = if error.is_nan() || error.abs() > ENERGY_GUARD {
            format!(
                "energy balance lost: the account is off by {:+.1} % of the impact energy",
                100.0 * error
            )
        } else if made > ENERGY_GUARD {
            format!(
                "energy made in the target: its forces have done {:.1} % of the impact energy \
                 more work on the motion than the motion did on it",
                100.0 * made
            )
        } else {
            return Ok(());
        };
        let f = self.fastest();
        Err(RunError::Unstable(format!(
            "{what} at step {}, t {:.4e} s; fastest: {} {} at (r {:.4e}, z {:.4e}) m, {:.3e} m/s",
            self.step,
            self.time,
            f.what,
            f.index,
            f.r,
            self.world_z(f.z),
            f.speed
        )))
    }

    /// Count the slaves left inside the projectile (beyond 10⁻⁴ of an element: round-off of
    /// the correction's projection) and book the worst in the account.
    pub fn check_slaves_inside(&mut self) {
        if self.slaves.is_empty() {
            return;
        }
        let tol = 1.0e-4 * self.scene.projectile.element_size as f32;
        let (n, depth) = cpu::contact_detect::inside(
            &self.slaves,
            &self.particles,
            &self.projectile.nodes,
            &self.projectile.masters,
            tol,
        );
        let a = &mut self.account;
        a.slaves_inside = a.slaves_inside.max(n);
        a.max_residual_penetration = a.max_residual_penetration.max(depth);
    }

    fn history_row(&self) -> Row {
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

    /// Write one VTK frame of the target and the projectile.
    pub fn write_frame(
        &self,
        dir: &Path,
        frame: usize,
        pvd: &mut vtk::Collection,
    ) -> std::io::Result<()> {
        let p = &self.particles;
        let world = |z: &[f32]| -> Vec<f32> { z.iter().map(|&z| self.world_z(z) as f32).collect() };
        if !p.is_empty() {
            let name = format!("target_{frame:05}.vtu");
            let speed: Vec<f32> = (0..p.len()).map(|i| p.vr[i].hypot(p.vz[i])).collect();
            vtk::write_vtu(
                &dir.join(&name),
                &p.r,
                &world(&p.z),
                None,
                &[
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
                ],
                &[],
            )?;
            pvd.add(self.time, 0, &name)?;
        }
        let n = &self.projectile.nodes;
        let e = &self.projectile.elements;
        let name = format!("projectile_{frame:05}.vtu");
        let seq: Vec<f32> = (0..e.len())
            .map(|k| cpu::deviator::von_mises(&[e.s_rr[k], e.s_zz[k], e.s_rz[k], e.s_tt[k]]))
            .collect();
        let failed: Vec<f32> = e.failed.iter().map(|&f| f as f32).collect();
        vtk::write_vtu(
            &dir.join(&name),
            &n.r,
            &world(&n.z),
            Some(&e.nodes),
            &[("v_r", &n.vr), ("v_z", &n.vz)],
            &[
                ("damage", &e.damage),
                ("failed", &failed),
                ("plastic_strain", &e.eps_p),
                ("pressure", &e.p),
                ("von_mises", &seq),
                ("temperature", &e.temperature),
            ],
        )?;
        pvd.add(self.time, 1, &name)
    }

    /// World z of a model position ([`Scene::origin_z`]).
    fn world_z(&self, z: f32) -> f64 {
        z as f64 + self.scene.origin_z()
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

    pub fn summary(&self, status: &str, stop_reason: &str, wall_s: f64) -> Summary {
        let body = self.body_bounds();
        let a = &self.account;
        Summary {
            scene: self.scene.name.clone(),
            status: status.to_string(),
            stop_reason: stop_reason.to_string(),
            backend: self.backend.into(),
            adapter: self.adapter.clone(),
            solver_build: crate::output::summary::build_id().into(),
            depth_m: body.depth,
            projectile_velocity_m_s: self.projectile_velocity(),
            max_damage: self.max_damage(),
            max_damage_shank: self.max_damage_shank(),
            max_plastic_strain: self.max_plastic_strain(),
            max_plastic_strain_shank: self.max_plastic_strain_shank(),
            checkerboard_pa: self.projectile.elements.max_checkerboard() as f64,
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
            passes: self.pass_names(self.backend),
            min_dt_s: if a.min_dt == f64::MAX { 0.0 } else { a.min_dt },
            max_dt_s: a.max_dt,
            max_slave_penetration_m: a.max_penetration as f64,
            slaves_inside: a.slaves_inside,
            nonfinite_values: self.nonfinite_values(),
            particles_at_density_floor: self.particles_at_density_floor(),
            max_speed_m_s: self.max_speed(),
            max_residual_penetration_m: a.max_residual_penetration as f64,
            neighbour_list_builds: self.gpu.as_ref().map_or(0, |g| g.builds),
        }
    }
}

/// The slaves' kinematics the λ correction moves: the particles' own arrays on the CPU path,
/// the hits' slaves read back from the GPU on the GPU path (a hit's `slave` indexes them).
struct Slaves<'a> {
    r: &'a mut [f32],
    z: &'a mut [f32],
    vr: &'a mut [f32],
    vz: &'a mut [f32],
    mass: &'a [f32],
}

/// Per master segment of `mesh`: whether it lies on the nose, its midpoint ahead of the
/// nose–shank junction at `shank_from` (a flat end's face counts, its midpoint on the
/// junction; a shell's cavity wall carries no masters).
fn nose_masters(mesh: &mesh::ProjectileMesh, shank_from: f32) -> Vec<bool> {
    let z = &mesh.node_z;
    mesh.masters
        .iter()
        .map(|m| 0.5 * (z[m.a as usize] + z[m.b as usize]) <= shank_from)
        .collect()
}

/// The body's depth beyond the target's face and its extent (m, [`Simulation::body_bounds`]).
struct BodyBounds {
    depth: f64,
    length: f64,
    radius: f64,
}

/// The smallest step a run goes on with (s): below it the run has collapsed.
pub const MIN_STEP: f32 = 1.0e-13;

/// A step too small to go on with (or not a number): the run has collapsed.
fn collapsed(dt: f32) -> bool {
    !(dt.is_finite() && dt > MIN_STEP)
}

/// The λ correction of `hits` (physics.md §4) on `slaves` and the projectile's nodes; its
/// dissipation and deepest penetration are booked in `account`.
fn correct_contact(
    hits: &[Hit],
    slaves: Slaves<'_>,
    projectile: &mut Projectile,
    on_nose: &[bool],
    lambda: f32,
    dt: f32,
    account: &mut Account,
) {
    let Projectile {
        nodes: n,
        masters,
        total_mass,
        ..
    } = projectile;
    let mut bodies = ContactBodies {
        slave_r: slaves.r,
        slave_z: slaves.z,
        slave_vr: slaves.vr,
        slave_vz: slaves.vz,
        slave_mass: slaves.mass,
        node_r: &mut n.r,
        node_z: &mut n.z,
        node_vr: &mut n.vr,
        node_vz: &mut n.vz,
        node_mass: &n.mass,
        node_on_axis: &n.on_axis,
        dt,
    };
    let stats = contact::correct(hits, masters, on_nose, &mut bodies, lambda, *total_mass);
    account.contact_dissipated += stats.dissipated;
    account.contact_impulse += stats.impulse_z;
    account.nose_impulse += stats.nose_impulse_z;
    account.max_penetration = account.max_penetration.max(stats.max_penetration);
}

/// Options of `penetrate run`.
#[derive(Clone, Debug)]
pub struct RunOptions {
    pub out: PathBuf,
    pub quiet: bool,
    /// Write VTK frames (tests turn them off).
    pub vtk: bool,
    /// Overrides the scene's `run.backend`.
    pub backend: Option<Backend>,
    /// Part of the GPU adapter's name (`--adapter`).
    pub adapter: Option<String>,
}

impl RunOptions {
    /// CPU or scene backend, progress shown, VTK frames on.
    pub fn new(out: PathBuf) -> RunOptions {
        RunOptions {
            out,
            quiet: false,
            vtk: true,
            backend: None,
            adapter: None,
        }
    }
}

/// Build the model on the backend asked for: `gpu` fails without a usable adapter; `auto` takes
/// a real GPU if there is one and the CPU otherwise.
pub fn build(
    scene: &Scene,
    backend: Backend,
    adapter: Option<&str>,
) -> Result<Simulation, RunError> {
    let mut sim = Simulation::new(scene)?;
    attach(&mut sim, backend, adapter)?;
    Ok(sim)
}

/// Move a started model onto the backend asked for (see [`build`]).
fn attach(sim: &mut Simulation, backend: Backend, adapter: Option<&str>) -> Result<(), RunError> {
    match backend {
        Backend::Cpu => {}
        Backend::Gpu => {
            let gpu = crate::gpu::Gpu::new(adapter)
                .map_err(|e| RunError::Setup(format!("--backend gpu: {e}")))?;
            sim.use_gpu(gpu)?;
        }
        Backend::Auto => {
            if let Ok(gpu) = crate::gpu::Gpu::new(adapter) {
                if crate::gpu::is_hardware(&gpu.info) || adapter.is_some() {
                    sim.use_gpu(gpu)?;
                }
            }
        }
    }
    Ok(())
}

/// The resolved scene a run writes into its output folder.
pub const SCENE_FILE: &str = "scene.toml";

/// The result of a run: its summary, and whether it ended normally.
pub struct RunOutcome {
    pub summary: Summary,
    pub ok: bool,
}

/// Share of the impact energy by which the energy account may be off before a run is stopped
/// as unstable. Every run of the validation and of the stability suite closes it to 0.7 % or
/// better (README, "Stability"), so this catches a blow-up, not an inaccuracy.
pub const ENERGY_GUARD: f64 = 0.05;

/// The fastest particle or node, for the message of a run that blew up.
#[derive(Clone, Copy)]
struct Fastest {
    what: &'static str,
    index: usize,
    r: f32,
    z: f32,
    speed: f32,
}

/// Run a scene to its end, writing the outputs as it goes. An unstable run stops, says what and
/// where in `status`, and keeps what it had written. So does a run whose outputs the disk stops
/// taking, as far as the disk lets it: its files end whole, `summary.json` is written where it
/// fits, and it returns [`RunError::Io`] saying where, when and what was kept.
pub fn run(scene: &Scene, opts: &RunOptions) -> Result<RunOutcome, RunError> {
    let io = |e: std::io::Error| RunError::Io(e.to_string());
    output::create_folder(&opts.out).map_err(RunError::Io)?;
    output::clear_previous_run(&opts.out).map_err(|e| io(output::named(&opts.out, e)))?;
    // What exactly ran, every default resolved (`penetrate validate --resume` compares it).
    let resolved = scene.resolved_table();
    output::write_whole(&opts.out.join(SCENE_FILE), resolved.as_bytes()).map_err(io)?;
    let started = Instant::now();
    let backend = opts.backend.unwrap_or(scene.run.backend);
    let history_file = opts.out.join("history.csv");
    let mut sim = Simulation::assemble(scene)?;
    if let Err(e) = sim.start() {
        // The scene as built cannot take a step (its first forces or Δt, on the CPU): the
        // state at rest and why, as any unstable run leaves them.
        let mut history = History::create(&history_file).map_err(io)?;
        history.write(&sim.history_row()).map_err(io)?;
        history.flush().map_err(io)?;
        let status = format!("{e} (before the first step, evaluated on the CPU)");
        let summary = sim.summary(&status, "", started.elapsed().as_secs_f64());
        write_summary(&opts.out, &summary).map_err(io)?;
        return Ok(RunOutcome { summary, ok: false });
    }
    attach(&mut sim, backend, opts.adapter.as_deref())?;
    warn_from_estimate(scene, &opts.out, opts.vtk);
    let mut history = History::create(&history_file).map_err(io)?;
    let mut pvd = vtk::Collection::new(opts.out.join("frames.pvd"));
    let mut frame = 0;
    // The step of the last frame written: the last frame is not written twice.
    let mut frame_step = None;
    if opts.vtk {
        sim.write_frame(&opts.out, frame, &mut pvd).map_err(io)?;
        frame += 1;
        frame_step = Some(sim.step);
    }
    history.write(&sim.history_row()).map_err(io)?;
    // The step of the last row written: the last row is not written twice.
    let mut history_step = sim.step;
    // Set once the disk refused an output: the run stops there.
    let mut write_failed = false;
    let mut next_history = scene.run.history_interval;
    let mut next_frame = if scene.run.output_interval > 0.0 {
        scene.run.output_interval
    } else {
        f64::MAX
    };
    let mut progress = Progress::new(scene.run.end_time, opts.quiet);
    let (status, reason, ok) = loop {
        if crate::interrupt::requested() {
            break (
                format!(
                    "interrupted (Ctrl-C or SIGTERM) at step {}, t {:.4e} s",
                    sim.step, sim.time
                ),
                String::new(),
                false,
            );
        }
        if let Some(reason) = sim.stop_reason() {
            break ("completed".to_string(), reason.to_string(), true);
        }
        if sim.step >= scene.run.max_steps {
            break (
                format!(
                    "stopped: max_steps = {} reached at t {:.4e} s",
                    scene.run.max_steps, sim.time
                ),
                String::new(),
                false,
            );
        }
        if let Err(e) = sim.step() {
            break (e.to_string(), String::new(), false);
        }
        let frame_due = opts.vtk && sim.time >= next_frame;
        let synced = if frame_due {
            sim.sync()
        } else if sim.time >= next_history {
            sim.sync_history()
        } else {
            Ok(())
        };
        if let Err(e) = synced {
            break (e.to_string(), String::new(), false);
        }
        if sim.time >= next_history {
            sim.check_slaves_inside();
            let row = sim.history_row();
            if let Err(e) = history.write(&row) {
                write_failed = true;
                break (output_failed(&sim, &e), String::new(), false);
            }
            history_step = sim.step;
            next_history += scene.run.history_interval;
            progress.update(sim.time, sim.step, row.depth, row.velocity);
            if let Err(e) = sim.energy_guard(row.energy_error) {
                break (e.to_string(), String::new(), false);
            }
        }
        if frame_due {
            if let Err(e) = sim.write_frame(&opts.out, frame, &mut pvd) {
                write_failed = true;
                break (output_failed(&sim, &e), String::new(), false);
            }
            frame += 1;
            frame_step = Some(sim.step);
            next_frame += scene.run.output_interval;
        }
    };
    progress.finish();
    // A run that stopped for another reason keeps that reason alone.
    let checked = sim
        .sync()
        .and_then(|()| if ok { sim.check_energy() } else { Ok(()) });
    let (status, reason, ok) = match checked {
        Ok(()) => (status, reason, ok),
        Err(e) if ok => (e.to_string(), String::new(), false),
        // Keep what stopped the run first.
        Err(e) => (format!("{status}; then {e}"), reason, false),
    };
    sim.check_slaves_inside();
    let mut status = status;
    if !write_failed {
        // The last row and frame; after a refused write the disk has had its say.
        let last = match history_step != sim.step {
            true => history.write(&sim.history_row()),
            false => Ok(()),
        }
        .and_then(|()| history.flush())
        .and_then(|()| match opts.vtk && frame_step != Some(sim.step) {
            true => sim.write_frame(&opts.out, frame, &mut pvd),
            false => Ok(()),
        });
        if let Err(e) = last {
            write_failed = true;
            status = format!("{status}; then {}", output_failed(&sim, &e));
        }
    }
    let summary = sim.summary(&status, &reason, started.elapsed().as_secs_f64());
    let saved = write_summary(&opts.out, &summary);
    if write_failed {
        let kept = match saved {
            Ok(()) => ", with summary.json".to_string(),
            Err(e) => format!("; summary.json could not be written: {e}"),
        };
        return Err(RunError::Io(format!(
            "{status}; what was written is kept in {}{kept}",
            opts.out.display()
        )));
    }
    saved.map_err(io)?;
    Ok(RunOutcome { summary, ok })
}

/// The status of a run the disk stopped: when, and the write refused.
fn output_failed(sim: &Simulation, e: &std::io::Error) -> String {
    format!(
        "output failed at step {}, t {:.4e} s: {e}",
        sim.step, sim.time
    )
}

fn write_summary(out: &Path, summary: &Summary) -> std::io::Result<()> {
    let json = serde_json::to_string_pretty(summary).map_err(std::io::Error::other)?;
    output::write_whole(&out.join("summary.json"), (json + "\n").as_bytes())
}

/// Says on stderr what `check`'s estimate foresees going wrong before the run starts: more
/// steps than `run.max_steps` to `run.end_time`, and outputs that overfill the disk.
fn warn_from_estimate(scene: &Scene, out: &Path, vtk: bool) {
    let Ok(mesh) = mesh::projectile::build(&scene.model_projectile()) else {
        return;
    };
    let e = crate::estimate::estimate(scene, &mesh);
    if let Some(line) = steps_warning(scene, &e) {
        eprintln!("{line}");
    }
    if let Some(free) = output::free_bytes(out) {
        warn_if_outputs_overfill(&e, out, vtk, free);
    }
}

/// The warning for a run whose estimated steps to `run.end_time` exceed `run.max_steps` (a
/// sliver in the projectile's mesh, from a feature far smaller than its elements, can ask for
/// billions), naming what sets the step; `None` when the cap is not in reach. The estimate
/// takes the concrete at its stiffest, so a run may take fewer steps than it says.
fn steps_warning(scene: &Scene, e: &crate::estimate::Estimate) -> Option<String> {
    if e.steps <= scene.run.max_steps {
        return None;
    }
    let by = if e.dt_fem <= e.dt_sph {
        format!(
            "the projectile mesh's smallest element, {:.3e} m high ({:.2e} of projectile.element_size)",
            e.fem_altitude,
            e.fem_altitude / scene.projectile.element_size
        )
    } else {
        "the concrete's particles (target.spacing and its stiffness)".to_string()
    };
    Some(format!(
        "penetrate: warning: this run needs {} steps to run.end_time = {} s at check's estimated step of {:.3e} s, set by {by}; run.max_steps = {} would stop it near t ≈ {:.3e} s",
        e.steps_text(),
        crate::scene::number_text(scene.run.end_time),
        e.dt,
        scene.run.max_steps,
        scene.run.max_steps as f64 * e.dt
    ))
}

/// Says on stderr when the frames (unless `--no-vtk`) and the history rows a run writes, by
/// `check`'s estimate, need more than the `free` bytes where they go: such a run stops when
/// the disk is full (exit code 3).
fn warn_if_outputs_overfill(e: &crate::estimate::Estimate, out: &Path, vtk: bool, free: u64) {
    let frame_bytes = if vtk { e.frames_bytes() } else { 0.0 };
    if frame_bytes + e.history_bytes() > free as f64 {
        use crate::estimate::MIB;
        let rows = format!(
            "{} history rows, ≈ {:.1} MiB,",
            e.history_rows,
            e.history_bytes() / MIB
        );
        let what = if vtk {
            format!(
                "{} frames, ≈ {:.1} MiB of ASCII VTU, and {rows}",
                e.frames,
                frame_bytes / MIB
            )
        } else {
            rows
        };
        let remedy = if vtk {
            "raise run.output_interval or run.history_interval, or pass --no-vtk"
        } else {
            "raise run.history_interval"
        };
        eprintln!(
            "penetrate: warning: this run may write {what} and {} has {:.1} MiB free: the run stops (exit code 3) when the disk is full; {remedy}",
            out.display(),
            free as f64 / MIB
        );
    }
}

/// Which nodes belong to the body: the largest set, by reference volume, of elements that have
/// not failed and are joined through shared nodes (union–find over the nodes). Every node when
/// every element has failed.
fn body_nodes(conn: &[[u32; 3]], failed: &[u32], volume0: &[f32], n_nodes: usize) -> Vec<bool> {
    if !failed.contains(&0) {
        return vec![true; n_nodes];
    }
    let mut parent: Vec<usize> = (0..n_nodes).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let intact = || (0..conn.len()).filter(|&e| failed[e] == 0);
    for e in intact() {
        let a = root(&mut parent, conn[e][0] as usize);
        for &n in &conn[e][1..] {
            let b = root(&mut parent, n as usize);
            parent[b] = a;
        }
    }
    let mut volume = vec![0.0f64; n_nodes];
    for e in intact() {
        let a = root(&mut parent, conn[e][0] as usize);
        volume[a] += volume0[e] as f64;
    }
    let body = (0..n_nodes)
        .max_by(|&a, &b| volume[a].total_cmp(&volume[b]))
        .unwrap_or(0);
    let mut held = vec![false; n_nodes];
    for e in intact() {
        for &n in &conn[e] {
            held[n as usize] = true;
        }
    }
    (0..n_nodes)
        .map(|i| held[i] && root(&mut parent, i) == body)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The smoke scene's ogive: the nose's masters run from the tip to the junction and no
    /// further, and their lengths add up to the tangent ogive's arc s φ_tip (s = crh d, cos
    /// φ_tip = (s − a)/s) within the chords' shortfall; the shank and the tail face are not
    /// the nose. A Taylor bar's flat end is.
    #[test]
    fn nose_masters_are_the_ogive_arc() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let scene = crate::scene::load(&root.join("cases/smoke.toml"), &[]).unwrap();
        let spec = scene.model_projectile();
        let mesh = mesh::projectile::build(&spec).unwrap();
        let junction = (spec.nose_z + spec.shape.nose_length(spec.diameter)) as f32;
        let nose = nose_masters(&mesh, junction);
        let (z, r) = (&mesh.node_z, &mesh.node_r);
        let mut arc = 0.0f64;
        for (m, &on) in mesh.masters.iter().zip(&nose) {
            let (a, b) = (m.a as usize, m.b as usize);
            if on {
                assert!(
                    z[a] <= junction && z[b] <= junction,
                    "{m:?} behind the junction"
                );
                arc += ((r[a] - r[b]) as f64).hypot((z[a] - z[b]) as f64);
            } else {
                assert!(
                    z[a] >= junction && z[b] >= junction,
                    "{m:?} ahead of the junction"
                );
            }
        }
        let crate::scene::ProjectileShape::Ogive { crh } = spec.shape else {
            panic!("the smoke projectile is an ogive")
        };
        let d = spec.diameter;
        let s = crh * d;
        let expected = s * ((s - 0.5 * d) / s).acos();
        assert!(
            arc < expected && arc > 0.99 * expected,
            "the nose's masters are {arc} m long against the arc's {expected} m"
        );
        assert!(nose.iter().any(|&on| !on), "the shank has masters");

        let bar = crate::scene::load(&root.join("cases/taylor-4340-208.toml"), &[]).unwrap();
        let spec = bar.model_projectile();
        let mesh = mesh::projectile::build(&spec).unwrap();
        let nose = nose_masters(&mesh, spec.nose_z as f32);
        for (m, &on) in mesh.masters.iter().zip(&nose) {
            let face = mesh.node_z[m.a as usize] == spec.nose_z as f32
                && mesh.node_z[m.b as usize] == spec.nose_z as f32;
            assert_eq!(on, face, "{m:?}");
        }
        assert!(nose.iter().any(|&on| on), "the bar's end face has masters");
    }
}
