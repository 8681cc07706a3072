//! The explicit coupled step (physics.md §5) and the run loop: stop conditions, energy and
//! momentum account, outputs.
//!
//! A [`Simulation`] is a [`Model`] (the meshes, the state, the pass list) and the [`Stepper`]
//! that advances it, on the CPU reference path (`cpu_step`) or on the GPU (`gpu_step`). The
//! model is reached only through [`Simulation::model`], which brings the host's copy up to
//! date first, so what a caller reads is never stale. Building (`build`), the energy account
//! (`account`), what is measured of the state (`diagnostics`), what is written (`outputs`), the
//! run loop (`run`) and its checkpoints (`checkpoint`) have their own modules.

mod account;
mod build;
mod checkpoint;
mod cpu_step;
mod diagnostics;
mod error;
mod gpu_step;
mod outputs;
mod run;

pub use account::ENERGY_GUARD;
pub use build::{auto_gpu, build, resolve};
pub use checkpoint::{Checkpoint, Counters, FrameEntry, Refusal, RestartError, State, VERSION};
pub use cpu_step::{MIN_STEP, RECENTRE_STEP};
pub use error::{
    Entity, Instability, Kept, Moving, Output, OutputError, OutputFailure, RunError, Unstable, When,
};
pub use run::{run, RunOptions, RunOutcome, SCENE_FILE};

use crate::cpu::neighbours::CellGrid;
use crate::gpu::step::{GpuStep, Sync};
use crate::pass::Pass;
use crate::scene::Scene;
use crate::state::{FemParams, Particles, Projectile, SphParams};

/// What advances a [`Model`] by one step: the CPU reference path or the GPU.
pub trait Stepper {
    /// One explicit step of `model`.
    fn step(&mut self, model: &mut Model) -> Result<(), RunError>;
    /// Bring the host's copy of what `what` covers up to date (nothing to do on the CPU).
    fn sync(&mut self, model: &mut Model, what: Sync) -> Result<(), RunError>;
    /// "cpu" or "gpu".
    fn backend(&self) -> &'static str;
    /// Whether a step leaves the host's copy of the state current (the CPU's, which is the
    /// state itself).
    fn keeps_host_current(&self) -> bool;
    /// The GPU step, when there is one.
    fn gpu(&mut self) -> Option<&mut GpuStep> {
        None
    }
    /// Neighbour-list builds so far, where the stepper keeps its lists across steps.
    fn builds(&self) -> Option<u64> {
        None
    }
    /// What crossed between the host and the GPU so far, where there is a GPU.
    fn traffic(&self) -> Option<crate::gpu::traffic::Traffic> {
        None
    }
}

/// Running energy and impulse account (f64).
#[derive(Clone, Debug, Default)]
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
    /// Per master segment, the normal impulse its closing hits gave it (N s): the load on its
    /// ring, whose rate over the ring's area is the contact pressure there.
    pub segment_impulse: Vec<f64>,
    pub plastic_work: f64,
    /// Deepest slave penetration the contact found (before correcting it), m.
    pub max_penetration: f32,
    /// Most slaves found inside the projectile after a step's correction, and the deepest of
    /// them (m), over the checks at history rows and the end (`check_slaves_inside`).
    pub slaves_inside: usize,
    pub max_residual_penetration: f32,
    pub min_dt: f64,
    pub max_dt: f64,
    /// Steps whose Δt the elements set (their least stable step no larger than the
    /// particles'), and those the particles set: which side to refine or coarsen for speed.
    pub fem_limited_steps: u64,
    pub sph_limited_steps: u64,
}

impl Account {
    /// Books one step as set by the elements or by the particles.
    pub fn count_limit(&mut self, fem_limited: bool) {
        if fem_limited {
            self.fem_limited_steps += 1;
        } else {
            self.sph_limited_steps += 1;
        }
    }
}

/// How much of the host's copy of a GPU run's state is current, least first. A GPU step
/// leaves every node's z and v_z current and the nodes its hits touched whole (what the λ
/// correction and the stop test read; gpu::step), `Sync::History` what a history row reads,
/// `Sync::Full` everything.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Fresh {
    Nodes,
    History,
    Full,
}

/// What the wall images of a step leave (`cpu::wall`): empty without them.
#[derive(Clone, Debug, Default)]
pub struct Walls {
    pub walls: Vec<crate::cpu::wall::Wall>,
    pub reaction: Vec<[f32; 2]>,
    pub sums: Vec<[f32; 4]>,
    /// The mirror line's depth inside the surface (m): `wall::OFFSET_SPACINGS` spacings.
    pub offset: f32,
}

impl Walls {
    /// The walls, once the `walls` pass has found them (it runs exactly in scenes with images,
    /// before the gathers).
    pub fn found(&self) -> Option<&[crate::cpu::wall::Wall]> {
        (!self.walls.is_empty()).then_some(&self.walls[..])
    }
}

/// The meshes, the state and the pass list: what a [`Stepper`] advances and the outputs read.
pub struct Model {
    pub scene: Scene,
    pub particles: Particles,
    pub sph: Option<SphParams>,
    pub grid: CellGrid,
    pub projectile: Projectile,
    pub fem: FemParams,
    /// Slave particles (preselected once, physics.md §4), in `hit_order`.
    pub slaves: Vec<u32>,
    /// Each particle's place in the order the λ correction applies a step's hits (its lattice
    /// site, row by row from the face: `TargetLattice::site`). The correction is sequential,
    /// so this order is part of the model; the particles' storage order is not.
    pub hit_order: Vec<u32>,
    /// With `contact.kernel = "images"`: each particle's wall, the ring force its images exert
    /// on it, and those forces' sums per master segment (`cpu::wall`), the step's last.
    pub walls: Walls,
    pub passes: Vec<Pass>,
    pub time: f64,
    pub step: u64,
    pub dt: f32,
    /// Whether the elements set `dt` (`stable_dt`).
    pub fem_limited: bool,
    pub account: Account,
    pub last_hits: usize,
    /// World z of the model's z = 0: the scene's origin ([`Scene::origin_z`]) at the start,
    /// then moved with the projectile in a target ([`Model::recentre`]).
    origin: f64,
    /// The wall, a Taylor scene's: the model's z = 0 ([`Scene::origin_z`]).
    wall_z: Option<f32>,
    escape: f32,
    /// Elements whose centroid started behind the nose (in the shank): a shell's wall.
    shank: Vec<u32>,
    /// Per master segment: whether it started on the nose (`nose_masters`).
    on_nose: Vec<bool>,
    /// The adapter's name ("none (CPU reference path)" on the CPU).
    pub adapter: String,
    /// The particles' sums as the GPU reduced them for a history row, standing in for the
    /// host's particle velocities and energies, which that read leaves stale; `None` where
    /// the host's particles are current (the CPU path, after a full read).
    reduced: Option<crate::gpu::history::ParticleTotals>,
}

impl Model {
    /// Per master segment of [`Projectile::masters`]: whether it started on the nose.
    pub fn on_nose(&self) -> &[bool] {
        &self.on_nose
    }
}

/// A model and what steps it: the CPU reference path until [`Simulation::use_gpu`].
pub struct Simulation {
    model: Model,
    stepper: Box<dyn Stepper>,
    /// What of `model` is current on the host.
    fresh: Fresh,
}

impl Simulation {
    /// Build the meshes, the state and the pass list, and evaluate the first forces and Δt.
    pub fn new(scene: &Scene) -> Result<Simulation, RunError> {
        let mut model = Model::assemble(scene)?;
        model.start()?;
        Ok(Simulation::on_cpu(model))
    }

    /// A started model on the CPU reference path.
    fn on_cpu(model: Model) -> Simulation {
        Simulation {
            model,
            stepper: Box::new(cpu_step::CpuStepper),
            fresh: Fresh::Full,
        }
    }

    /// The model, its host copy brought up to date first (GPU runs: a read-back).
    pub fn model(&mut self) -> Result<&Model, RunError> {
        self.current(Fresh::Full).map(|m| &*m)
    }

    /// The model, to edit its state before it steps on: on the CPU path only, since the GPU
    /// steps its own copy of the state and would not see the edit.
    pub fn model_mut(&mut self) -> Result<&mut Model, RunError> {
        if !self.stepper.keeps_host_current() {
            return Err(RunError::Setup(format!(
                "the state of a run on the {} cannot be edited: it steps its own copy",
                self.stepper.backend()
            )));
        }
        Ok(&mut self.model)
    }

    /// The model, its host copy brought up to date, without what stepped it.
    pub fn into_model(mut self) -> Result<Model, RunError> {
        self.current(Fresh::Full)?;
        Ok(self.model)
    }

    /// Simulated time at the start of the next step (s); current on every backend.
    pub fn time(&self) -> f64 {
        self.model.time
    }

    /// Steps taken; current on every backend.
    pub fn steps(&self) -> u64 {
        self.model.step
    }

    /// The GPU step, when the run is on the GPU (bench: profiling and memory).
    pub fn gpu_step(&mut self) -> Option<&mut GpuStep> {
        self.stepper.gpu()
    }

    /// Steps that built the neighbour lists so far, on either backend.
    pub fn list_builds(&self) -> u64 {
        self.stepper.builds().unwrap_or(self.model.grid.builds)
    }

    /// Build the neighbour lists in the next step whatever the particles did (`bench`).
    pub fn force_list_build(&mut self) {
        match self.stepper.gpu() {
            Some(g) => g.force_list_build(),
            None => self.model.grid.invalidate(),
        }
    }

    /// "cpu" or "gpu": where the step runs.
    pub fn backend(&self) -> &'static str {
        self.stepper.backend()
    }

    /// One explicit step: velocities and positions, contact, then rates, stresses and forces at
    /// the new configuration, then the next Δt (on whichever backend steps the model).
    pub fn step(&mut self) -> Result<(), RunError> {
        let stepped = self.stepper.step(&mut self.model);
        if !self.stepper.keeps_host_current() {
            self.fresh = Fresh::Nodes;
        }
        stepped
    }

    /// The model with at least `need` of its host copy current.
    fn current(&mut self, need: Fresh) -> Result<&mut Model, RunError> {
        if self.fresh < need {
            let what = match need {
                Fresh::Full => Sync::Full,
                Fresh::History | Fresh::Nodes => Sync::History,
            };
            self.stepper.sync(&mut self.model, what)?;
            self.fresh = need;
        }
        Ok(&mut self.model)
    }
}

impl Model {
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
}
