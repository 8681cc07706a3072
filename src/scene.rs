//! Scene files (`cases/*.toml`): parse, apply `--set` overrides, validate, resolve materials.
//!
//! The types below are the resolved scene the solver consumes: every value is in SI units and
//! has been checked. (Loader, overrides, validation and presets: to be written.)

use std::path::PathBuf;

use crate::materials::hjc::Hjc;
use crate::materials::johnson_cook::{JcDamage, JcStrength};
use crate::materials::steel_eos::PolyEos;

/// Which implementation of the step runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    Cpu,
    Gpu,
    /// A real GPU if one is present, else the CPU.
    Auto,
}

/// A fully resolved, validated scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// From the `name` key, or the file stem.
    pub name: String,
    pub path: PathBuf,
    pub run: RunControl,
    pub projectile: ProjectileSpec,
    /// `None` for Taylor-bar scenes (projectile against a rigid wall only).
    pub target: Option<TargetSpec>,
    pub contact: ContactSpec,
    /// Rigid wall, the plane z = `wall.z`, for Taylor-bar scenes.
    pub wall: Option<WallSpec>,
}

/// `[run]`
#[derive(Clone, Debug, PartialEq)]
pub struct RunControl {
    /// Simulated time at which the run stops (s).
    pub end_time: f64,
    /// Courant number applied to the smallest element and particle step.
    pub cfl: f64,
    /// Interval between VTK frames (s); 0 writes only the first and last frame.
    pub output_interval: f64,
    /// Interval between `history.csv` rows (s).
    pub history_interval: f64,
    pub backend: Backend,
    /// Hard cap on the number of steps (a guard against a collapsing time step).
    pub max_steps: u64,
    /// Stop when the projectile has come to rest (centre-of-mass velocity turned non-negative
    /// along the flight direction) or has left the target.
    pub stop_at_rest: bool,
}

/// Projectile outline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ProjectileShape {
    /// Tangent ogive nose of the given calibre-radius-head on a cylindrical shank.
    Ogive { crh: f64 },
    /// Flat-ended cylinder (Taylor bar).
    Cylinder,
}

/// A coaxial cavity in the shank with an inert filler.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CavitySpec {
    pub diameter: f64,
    pub length: f64,
    /// Thickness of the steel plug between the cavity and the tail face (m).
    pub rear_wall: f64,
    /// Filler density (kg/m³): its mass is lumped on the cavity wall nodes; 0 = empty.
    pub filler_density: f64,
}

/// `[projectile]`
#[derive(Clone, Debug, PartialEq)]
pub struct ProjectileSpec {
    pub shape: ProjectileShape,
    pub diameter: f64,
    /// Overall length, nose tip to tail (m).
    pub length: f64,
    pub cavity: Option<CavitySpec>,
    /// Target element size (m).
    pub element_size: f64,
    /// Striking speed (m/s, positive); the projectile flies along −z.
    pub velocity: f64,
    /// Initial z of the nose tip (m); the target's front face is z = 0.
    pub nose_z: f64,
    pub material: SteelMaterial,
}

/// Elastic-plastic metal of the projectile (physics.md §2).
#[derive(Clone, Debug, PartialEq)]
pub struct SteelMaterial {
    /// Name of the preset the constants started from.
    pub preset: String,
    pub density: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    /// J/(kg K)
    pub specific_heat: f64,
    /// Fraction β of plastic work that heats the metal.
    pub taylor_quinney: f64,
    pub strength: JcStrength,
    pub eos: PolyEos,
    /// `None` when `damage = false`: no damage state and no damage update.
    pub damage: Option<JcDamage>,
}

/// `[target]`: a concrete cylinder, axis on r = 0, front face z = 0, rear face z = −thickness.
#[derive(Clone, Debug, PartialEq)]
pub struct TargetSpec {
    pub radius: f64,
    pub thickness: f64,
    /// Particle spacing Δ (m).
    pub spacing: f64,
    /// Smoothing length over spacing, h/Δ.
    pub smoothing_ratio: f64,
    /// Fixed (zero-velocity) rear face.
    pub fix_rear: bool,
    /// Fixed (zero-velocity) lateral surface.
    pub fix_lateral: bool,
    /// Gray–Monaghan artificial stress against the tensile instability.
    pub artificial_stress: bool,
    /// Monaghan–Gingold viscosity coefficients.
    pub viscosity_alpha: f64,
    pub viscosity_beta: f64,
    /// HJC constants: §3.1 rule from `fc` and `density`, then any explicit overrides.
    pub concrete: Hjc,
}

/// `[contact]`
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSpec {
    /// Share λ of a slave's momentum change put on the two nodes it touches (0 = rigid limit).
    pub lambda: f64,
    /// Slave preselection radius over the projectile's largest radius (k > 1).
    pub slave_radius_factor: f64,
}

/// `[wall]`
#[derive(Clone, Debug, PartialEq)]
pub struct WallSpec {
    pub z: f64,
}
