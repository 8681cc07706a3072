//! Why a run stopped early or went wrong, by kind: what happened, to which entity, where, at
//! which step and time. `Display` gives the message a run's status and the command line carry.

use std::fmt;
use std::path::PathBuf;

use super::{RestartError, MIN_STEP};
use crate::gpu::GpuError;
use crate::output::frames::Refused;

/// Why a run stopped early or went wrong.
#[derive(Clone, Debug, PartialEq)]
pub enum RunError {
    /// Bad input caught while building the model.
    Setup(String),
    /// The GPU could not take the scene (`when` None), or failed while stepping it.
    Gpu { error: GpuError, when: Option<When> },
    /// The run went unstable: what, where and when.
    Unstable(Instability),
    /// A restart file that cannot be read or does not go on with this run (boxed, as `Output`).
    Restart(Box<RestartError>),
    /// An output could not be written (boxed: the other kinds are small, and every step
    /// returns this type).
    Output(Box<OutputError>),
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RunError::Setup(m) => write!(f, "setup: {m}"),
            RunError::Gpu { error, when: None } => write!(f, "setup: {error}"),
            RunError::Gpu {
                error,
                when: Some(w),
            } => write!(f, "GPU failed {w}: {error}"),
            RunError::Unstable(i) => write!(f, "unstable: {i}"),
            RunError::Restart(e) => write!(f, "{e}"),
            RunError::Output(e) => write!(f, "output: {e}"),
        }
    }
}

impl std::error::Error for RunError {}

impl From<OutputError> for RunError {
    fn from(e: OutputError) -> RunError {
        RunError::Output(Box::new(e))
    }
}

impl From<Instability> for RunError {
    fn from(i: Instability) -> RunError {
        RunError::Unstable(i)
    }
}

/// The step a run was taking and the time it started at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct When {
    pub step: u64,
    /// s
    pub time: f64,
}

impl fmt::Display for When {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "at step {}, t {:.4e} s", self.step, self.time)
    }
}

/// One entity of the model, by its index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Entity {
    Particle(usize),
    Node(usize),
    Element(usize),
}

impl Entity {
    /// The entity `index` of the kind named "particle", "node" or "element".
    pub fn named(kind: &str, index: usize) -> Entity {
        match kind {
            "particle" => Entity::Particle(index),
            "node" => Entity::Node(index),
            _ => Entity::Element(index),
        }
    }
}

impl fmt::Display for Entity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Entity::Particle(i) => write!(f, "particle {i}"),
            Entity::Node(i) => write!(f, "node {i}"),
            Entity::Element(i) => write!(f, "element {i}"),
        }
    }
}

/// A run gone unstable: what happened, and when.
#[derive(Clone, Debug, PartialEq)]
pub struct Instability {
    pub what: Unstable,
    pub when: When,
}

/// What made a run unstable.
#[derive(Clone, Debug, PartialEq)]
pub enum Unstable {
    /// An entity went wrong (a non-finite value, an escape, an inversion) at (r, z), m, in the
    /// world's coordinates.
    Entity {
        entity: Entity,
        reason: &'static str,
        r: f64,
        z: f64,
    },
    /// The next Δt fell below [`MIN_STEP`] (or is not a number); `site` says where the stable
    /// step is smallest and why.
    StepCollapsed { dt: f32, cfl: f64, site: String },
    /// Nothing bounds the next Δt (it would exceed 1 s), and why.
    StepUnbounded { dt: f32, why: String },
    /// The energy account is off by `error` of the impact energy (or not a number).
    EnergyLost { error: f64, fastest: Moving },
    /// The target's forces did `share` of the impact energy more work than was done on it.
    EnergyMade { share: f64, fastest: Moving },
}

/// The fastest entity when the energy account came apart: which, where (m, world) and how
/// fast (m/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moving {
    pub entity: Entity,
    pub r: f64,
    pub z: f64,
    pub speed: f64,
}

impl fmt::Display for Instability {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let when = self.when;
        match &self.what {
            Unstable::Entity {
                entity,
                reason,
                r,
                z,
            } => write!(
                f,
                "{entity} {reason} at (r {r:.4e}, z {z:.4e}) m, step {}, t {:.4e} s",
                when.step, when.time
            ),
            Unstable::StepCollapsed { dt, cfl, site } => write!(
                f,
                "time step collapsed to {dt:e} s (the least stable step × run.cfl = {}; a step \
                 under {MIN_STEP:e} s is taken as a collapse) {when}: {site}",
                crate::scene::number_text(*cfl)
            ),
            Unstable::StepUnbounded { dt, why } => write!(
                f,
                "nothing limits the time step {when}: it would be {dt:e} s, more than 1 s: {why}"
            ),
            Unstable::EnergyLost { error, fastest } => write!(
                f,
                "energy balance lost: the account is off by {:+.1} % of the impact energy \
                 {when}; fastest: {fastest}",
                100.0 * error
            ),
            Unstable::EnergyMade { share, fastest } => write!(
                f,
                "energy made in the target: its forces have done {:.1} % of the impact energy \
                 more work on the motion than the motion did on it {when}; fastest: {fastest}",
                100.0 * share
            ),
        }
    }
}

impl fmt::Display for Moving {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} at (r {:.4e}, z {:.4e}) m, {:.3e} m/s",
            self.entity, self.r, self.z, self.speed
        )
    }
}

/// Which output the disk refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// The output folder itself.
    Folder,
    /// What an earlier run left in the folder, cleared before this run writes.
    Previous,
    /// The resolved scene, `scene.toml`.
    Scene,
    /// `history.csv`.
    History,
    /// The VTK frame of this number, or `frames.pvd` as it lists it.
    Frame(usize),
    /// `summary.json`.
    Summary,
    /// The checkpoint, `restart.bin`.
    Checkpoint,
}

/// An output the disk refused: which, the system's reason (naming the file), and when.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputFailure {
    pub what: Output,
    pub kind: std::io::ErrorKind,
    pub reason: String,
    /// The step the run had reached; `None` before it started stepping.
    pub when: Option<When>,
}

impl OutputFailure {
    /// `what` refused with `e`, at `when`.
    pub fn new(what: Output, e: &std::io::Error, when: Option<When>) -> OutputFailure {
        OutputFailure {
            what,
            kind: e.kind(),
            reason: e.to_string(),
            when,
        }
    }
}

impl From<Refused> for OutputFailure {
    /// A frame the writer's thread could not write, when the frame was taken.
    fn from(r: Refused) -> OutputFailure {
        let when = When {
            step: r.step,
            time: r.time,
        };
        OutputFailure::new(Output::Frame(r.frame), &r.error, Some(when))
    }
}

impl fmt::Display for OutputFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.when {
            Some(w) => write!(f, "output failed {w}: {}", self.reason),
            None => write!(f, "{}", self.reason),
        }
    }
}

/// What a run the disk stopped kept of its outputs.
#[derive(Clone, Debug, PartialEq)]
pub struct Kept {
    /// The run's status: why it stopped, the refused write included.
    pub status: String,
    /// Its output folder, where what was written stays.
    pub folder: PathBuf,
    /// Whether `summary.json` was written too, or why not.
    pub summary: Result<(), String>,
}

/// An output failure, and what the run kept when it had started.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputError {
    pub failure: OutputFailure,
    pub kept: Option<Kept>,
}

impl From<OutputFailure> for OutputError {
    fn from(failure: OutputFailure) -> OutputError {
        OutputError {
            failure,
            kept: None,
        }
    }
}

impl fmt::Display for OutputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Some(k) = &self.kept else {
            return write!(f, "{}", self.failure);
        };
        write!(
            f,
            "{}; what was written is kept in {}",
            k.status,
            k.folder.display()
        )?;
        match &k.summary {
            Ok(()) => write!(f, ", with summary.json"),
            Err(e) => write!(f, "; summary.json could not be written: {e}"),
        }
    }
}
