//! The explicit coupled step (physics.md §5) and the run loop: stop conditions, energy and
//! momentum account, outputs.
//!
//! `Simulation` holds the model and its state; a [`Stepper`] advances it, on the CPU
//! reference path (`cpu_step`) or on the GPU (`gpu_step`). Building (`build`), the energy
//! account (`account`), what is measured of the state (`diagnostics`), what is written
//! (`outputs`) and the run loop (`run`) have their own modules.

mod account;
mod build;
mod cpu_step;
mod diagnostics;
mod error;
mod gpu_step;
mod outputs;
mod run;

pub use account::ENERGY_GUARD;
pub use build::build;
pub use cpu_step::MIN_STEP;
pub use error::{Entity, Instability, Moving, RunError, Unstable, When};
pub use run::{run, RunOptions, RunOutcome, SCENE_FILE};

use crate::cpu::neighbours::CellGrid;
use crate::gpu::step::{GpuStep, Sync};
use crate::pass::Pass;
use crate::scene::Scene;
use crate::state::{FemParams, Particles, Projectile, SphParams};

/// What advances a [`Simulation`] by one step: the CPU reference path or the GPU. Everything
/// else (the run loop, the studies, the outputs) drives a simulation through
/// `Simulation::step` and `Simulation::sync`, whichever stepper it has.
pub trait Stepper {
    /// One explicit step of `sim`.
    fn step(&mut self, sim: &mut Simulation) -> Result<(), RunError>;
    /// Bring the host's copy of what `what` covers up to date (nothing to do on the CPU).
    fn sync(&mut self, sim: &mut Simulation, what: Sync) -> Result<(), RunError>;
    /// "cpu" or "gpu".
    fn backend(&self) -> &'static str;
    /// The GPU step, when there is one.
    fn gpu(&mut self) -> Option<&mut GpuStep> {
        None
    }
    /// Neighbour-list builds so far, where the stepper keeps its lists across steps.
    fn builds(&self) -> Option<u64> {
        None
    }
}

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
    /// What steps the model: the CPU path until `use_gpu`.
    stepper: Box<dyn Stepper>,
    /// Elements whose centroid started behind the nose (in the shank): a shell's wall.
    shank: Vec<u32>,
    /// Per master segment: whether it started on the nose (`nose_masters`).
    on_nose: Vec<bool>,
    /// The adapter's name ("none (CPU reference path)" on the CPU).
    pub adapter: String,
}

impl Simulation {
    /// Build the meshes, the state and the pass list, and evaluate the first forces and Δt.
    pub fn new(scene: &Scene) -> Result<Simulation, RunError> {
        let mut sim = Simulation::assemble(scene)?;
        sim.start()?;
        Ok(sim)
    }

    /// The GPU step, when the run is on the GPU (bench: profiling and memory).
    pub fn gpu_step(&mut self) -> Option<&mut GpuStep> {
        self.stepper.gpu()
    }

    /// Neighbour-list builds on the GPU so far (0 on the CPU, which sorts every step).
    pub fn gpu_builds(&self) -> u64 {
        self.stepper.builds().unwrap_or(0)
    }

    /// "cpu" or "gpu": where the step runs.
    pub fn backend(&self) -> &'static str {
        self.stepper.backend()
    }

    /// Bring the CPU copy of the state up to date (GPU runs; nothing to do on the CPU).
    pub fn sync(&mut self) -> Result<(), RunError> {
        self.sync_part(Sync::Full)
    }

    /// Bring up to date what `history_row` reads (GPU runs): the rest may be stale.
    pub fn sync_history(&mut self) -> Result<(), RunError> {
        self.sync_part(Sync::History)
    }

    /// The step being taken and the time it started at, for a message.
    fn when(&self) -> When {
        When {
            step: self.step,
            time: self.time,
        }
    }

    fn has(&self, pass: Pass) -> bool {
        self.passes.contains(&pass)
    }

    /// One explicit step: velocities and positions, contact, then rates, stresses and forces at
    /// the new configuration, then the next Δt (on whichever backend steps the model).
    pub fn step(&mut self) -> Result<(), RunError> {
        self.with_stepper(|s, sim| s.step(sim))
    }

    /// Bring up to date the host's copy of the state that `what` covers (GPU runs).
    fn sync_part(&mut self, what: Sync) -> Result<(), RunError> {
        self.with_stepper(|s, sim| s.sync(sim, what))
    }

    /// Run `f` with the stepper taken out of the model it steps (a `CpuStepper`, which holds
    /// nothing, stands in meanwhile).
    fn with_stepper<T>(&mut self, f: impl FnOnce(&mut dyn Stepper, &mut Simulation) -> T) -> T {
        let mut stepper = std::mem::replace(&mut self.stepper, Box::new(cpu_step::CpuStepper));
        let out = f(stepper.as_mut(), self);
        self.stepper = stepper;
        out
    }
}
