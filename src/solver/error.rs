//! Why a run stopped early or went wrong, by kind: what happened, to which entity, where, at
//! which step and time. `Display` gives the message a run's status and the command line carry.

use std::fmt;

use super::MIN_STEP;
use crate::gpu::GpuError;

/// Why a run stopped early or went wrong.
#[derive(Clone, Debug, PartialEq)]
pub enum RunError {
    /// Bad input caught while building the model.
    Setup(String),
    /// The GPU could not take the scene (`when` None), or failed while stepping it.
    Gpu { error: GpuError, when: Option<When> },
    /// The run went unstable: what, where and when.
    Unstable(Instability),
    /// Output could not be written.
    Io(String),
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
            RunError::Io(m) => write!(f, "output: {m}"),
        }
    }
}

impl std::error::Error for RunError {}

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
