//! Scene files (`cases/*.toml`): parse, apply `--set` overrides, validate, resolve materials.
//!
//! The types below are the resolved scene the solver consumes: every value is in SI units and
//! has been checked. [`load`] reads a file, applies `--set key.path=value` overrides to the TOML
//! tree (`overrides`), reads it against the schema (`parse`), which refuses unknown keys and
//! wrong types, then validates and resolves it (`resolve`, `material`: presets, HJC from f_c,
//! defaults). Every failure is a [`SceneError`] whose one-line message names the file and the
//! dotted key and says what to change.
//!
//! Every key is declared once, in `schema.rs`; docs/scene-reference.md, generated from it by
//! [`reference_markdown`], lists them all with type, unit, default, bounds and help, and
//! [`Scene::resolved_table`] prints every resolved value.

mod material;
mod overrides;
mod parse;
mod resolve;
mod schema;
mod table;

use std::fmt::{self, Display, LowerExp, Write as _};
use std::path::{Path, PathBuf};

use toml::{Table, Value};

use crate::materials::flow::Strength;
use crate::materials::hjc::Hjc;
use crate::materials::johnson_cook::JcDamage;
use crate::materials::steel_eos::PolyEos;

pub use table::reference_markdown;

/// Which implementation of the step runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    Cpu,
    Gpu,
    /// A real GPU if one is present, else the CPU.
    Auto,
}

impl Backend {
    /// `cpu`, `gpu` or `auto`, as the scene key `run.backend` spells it.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Cpu => "cpu",
            Backend::Gpu => "gpu",
            Backend::Auto => "auto",
        }
    }
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

impl ProjectileShape {
    /// Length of the nose ahead of the shank for a body of this `diameter` (0 for a cylinder).
    pub fn nose_length(self, diameter: f64) -> f64 {
        match self {
            ProjectileShape::Ogive { crh } => ogive_nose_length(diameter, crh),
            ProjectileShape::Cylinder => 0.0,
        }
    }
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
    /// The four triangles of a cell share one pressure (physics.md §2.4); else each its own.
    pub cell_pressure: bool,
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
    pub strength: Strength,
    pub eos: PolyEos,
    /// `None` when `damage = false`: no damage state and no damage update.
    pub damage: Option<JcDamage>,
}

impl SteelMaterial {
    /// The elastic (dilatational) wave speed at rest, √((K₁ + 4G/3)/ρ) with G = E/(2(1 + ν)),
    /// m/s: what sets the explicit step across an element.
    pub fn wave_speed(&self) -> f64 {
        let shear = self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio));
        ((f64::from(self.eos.k1) + 4.0 / 3.0 * shear) / self.density).sqrt()
    }
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
    /// What scales the viscosity down where the flow shears rather than compresses.
    pub viscosity_switch: ViscositySwitch,
    /// Which velocity jump of a pair the viscosity reads.
    pub viscosity_jump: ViscosityJump,
    /// Which velocity the concrete's strain rate is taken from.
    pub velocity_filter: VelocityFilter,
    /// Which SPH gradient of it.
    pub velocity_gradient: VelocityGradient,
    /// How the concrete fails in tension.
    pub tension: TensionModel,
    /// A hole drilled into the front face along the axis (m; 0: none): the particles whose
    /// centres lie inside it are left out, and the nose starts at its bottom by default if the
    /// projectile fits in it; a pilot hole narrower than the projectile leaves it at the face.
    pub lead_hole_depth: f64,
    pub lead_hole_diameter: f64,
    /// HJC constants: §3.1 rule from `fc` and `density`, then any explicit overrides.
    pub concrete: Hjc,
}

impl TargetSpec {
    /// How far below the front face the nose may start (m): down the lead hole if the
    /// projectile fits in it, else at the face (0).
    pub fn start_depth(&self, projectile_diameter: f64) -> f64 {
        if self.lead_hole_diameter >= projectile_diameter {
            self.lead_hole_depth
        } else {
            0.0
        }
    }
}

/// `target.viscosity_switch`: the factor on each pair's Monaghan–Gingold Π.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViscositySwitch {
    /// Π as it is: the viscosity acts on every approaching pair, in shear too.
    None,
    /// Π times the pair's mean Balsara (1995) factor `|∇·v|/(|∇·v| + |∇×v| + 10⁻⁴ c/h)`:
    /// full in a compression, none in a pure shear.
    Balsara,
}

impl ViscositySwitch {
    pub fn name(self) -> &'static str {
        match self {
            ViscositySwitch::None => "none",
            ViscositySwitch::Balsara => "balsara",
        }
    }
}

/// `target.viscosity_jump`: the velocity jump of a pair that its Monaghan–Gingold Π reads
/// (docs/physics.md §3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViscosityJump {
    /// `(v_i − v_j)·(x_i − x_j)`: every approaching pair, a smooth compression as a shock.
    Raw,
    /// What is left of it at the pair's midpoint after a limited linear reconstruction from
    /// both ends (Frontiere, Raskin & Owen 2017): none in a linear velocity field, the whole
    /// jump across a discontinuity.
    Reconstructed,
}

impl ViscosityJump {
    pub fn name(self) -> &'static str {
        match self {
            ViscosityJump::Raw => "raw",
            ViscosityJump::Reconstructed => "reconstructed",
        }
    }
}

/// `target.velocity_filter`: the velocity field whose gradient updates the concrete's stress
/// and density (`cpu::sph_rates`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VelocityFilter {
    /// The particles' own velocities.
    None,
    /// Each particle's velocity moved by the kernel-weighted mean of its neighbours' departures
    /// from the linear field fitted at it: exact for a linear field, particle-scale scatter
    /// averaged out.
    Linear,
}

impl VelocityFilter {
    pub fn name(self) -> &'static str {
        match self {
            VelocityFilter::None => "none",
            VelocityFilter::Linear => "linear",
        }
    }
}

/// `target.velocity_gradient`: the SPH estimate of the velocity gradient L that updates the
/// concrete's stress and density (`cpu::sph_rates`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VelocityGradient {
    /// `Σ_j (m̃_j/ρ_j)(v_j − v_i) ⊗ ∇W` times the inverse moment matrix: exact for a linear
    /// field, also where the kernel is cut by a free face or the projectile.
    Corrected,
    /// `Σ_j (m̃_j/ρ_i)(v_j − v_i) ⊗ ∇W`, uncorrected: the rate whose stress power is the work
    /// the pair forces (`cpu::sph_forces`) do, so the stress update books the energy the
    /// motion gives up (docs/physics.md §3).
    Conjugate,
}

impl VelocityGradient {
    pub fn name(self) -> &'static str {
        match self {
            VelocityGradient::Corrected => "corrected",
            VelocityGradient::Conjugate => "conjugate",
        }
    }
}

/// `target.tension`: how the concrete fails in tension (`materials::hjc::Tension`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TensionModel {
    /// Tensile strength raised by the strain rate, softening spent over a crack band one
    /// particle spacing wide with the fracture energy G_f.
    CrackBand,
    /// HJC as published: the static cut-off, damage at HJC's failure strain.
    Static,
}

impl TensionModel {
    pub fn name(self) -> &'static str {
        match self {
            TensionModel::CrackBand => "crack-band",
            TensionModel::Static => "static",
        }
    }
}

/// `[contact]`
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSpec {
    /// Share λ of a slave's momentum change put on the two nodes it touches (0 = rigid limit).
    pub lambda: f64,
    /// Slave preselection radius over the projectile's largest radius (k > 1).
    pub slave_radius_factor: f64,
    /// Coulomb friction coefficient μ at the sliding surface (0 = frictionless, as the paper).
    pub friction: f64,
    /// How the concrete's kernel meets the projectile's surface.
    pub kernel: SurfaceKernel,
}

/// `contact.kernel`: what the concrete particles lining the projectile have on its side of
/// their kernel (docs/physics.md §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceKernel {
    /// Nothing: the kernel is cut at the surface, as the paper has it.
    Cut,
    /// Mirror images of the particle and its neighbours across the surface's tangent, which
    /// complete it; what they exert the projectile takes back at the foot (`cpu::wall`).
    Images,
}

impl SurfaceKernel {
    pub fn name(self) -> &'static str {
        match self {
            SurfaceKernel::Cut => "cut",
            SurfaceKernel::Images => "images",
        }
    }
}

/// `[wall]`
#[derive(Clone, Debug, PartialEq)]
pub struct WallSpec {
    pub z: f64,
}

// ---------------------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------------------

/// Why a scene was rejected. Every variant carries the scene file; `Display` is one line of the
/// form `FILE: KEY ...: what is wrong; what to change`.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneError {
    /// The file could not be read (missing, a directory, not UTF-8).
    Io { file: PathBuf, why: String },
    /// The text is not valid TOML. `line` and `column` are 1-based; `text` is the offending line.
    Syntax {
        file: PathBuf,
        line: usize,
        column: usize,
        text: String,
        why: String,
    },
    /// A key the schema does not have. `expected` lists the keys that table accepts.
    UnknownKey {
        file: PathBuf,
        key: String,
        expected: Vec<String>,
    },
    /// A required key or table is absent.
    MissingKey {
        file: PathBuf,
        key: String,
        why: String,
    },
    /// The value has the wrong TOML type (`found` is the value as written).
    WrongType {
        file: PathBuf,
        key: String,
        found: String,
        expected: String,
    },
    /// A string that must be one of a fixed set of names.
    BadChoice {
        file: PathBuf,
        key: String,
        value: String,
        choices: Vec<String>,
    },
    /// A value outside its physical or numerical range (negative size, λ > 1, NaN, …).
    NonPhysical {
        file: PathBuf,
        key: String,
        value: String,
        why: String,
    },
    /// Keys that cannot go together, or a choice between tables (`[target]` vs `[wall]`).
    Conflict {
        file: PathBuf,
        keys: Vec<String>,
        why: String,
    },
    /// A `--set key.path=value` override that cannot be applied or whose value was rejected.
    BadOverride {
        file: PathBuf,
        set: String,
        why: String,
    },
}

impl SceneError {
    fn file(&self) -> &Path {
        match self {
            SceneError::Io { file, .. }
            | SceneError::Syntax { file, .. }
            | SceneError::UnknownKey { file, .. }
            | SceneError::MissingKey { file, .. }
            | SceneError::WrongType { file, .. }
            | SceneError::BadChoice { file, .. }
            | SceneError::NonPhysical { file, .. }
            | SceneError::Conflict { file, .. }
            | SceneError::BadOverride { file, .. } => file,
        }
    }

    /// The dotted keys the error is about.
    fn keys(&self) -> Vec<&str> {
        match self {
            SceneError::UnknownKey { key, .. }
            | SceneError::MissingKey { key, .. }
            | SceneError::WrongType { key, .. }
            | SceneError::BadChoice { key, .. }
            | SceneError::NonPhysical { key, .. } => vec![key],
            SceneError::Conflict { keys, .. } => keys.iter().map(String::as_str).collect(),
            SceneError::Io { .. } | SceneError::Syntax { .. } | SceneError::BadOverride { .. } => {
                vec![]
            }
        }
    }

    /// The message without the leading file name.
    fn detail(&self) -> String {
        match self {
            SceneError::Io { why, .. } => why.clone(),
            SceneError::Syntax {
                line,
                column,
                text,
                why,
                ..
            } => format!(
                "line {line}, column {column}: TOML syntax error: {why} (in `{}`); fix the syntax",
                truncate(text.trim(), 60)
            ),
            SceneError::UnknownKey { key, expected, .. } => {
                let table = key.rsplit_once('.').map_or("the top level", |(t, _)| t);
                format!(
                    "{key}: unknown key; remove it or use one of the keys of {table}: {}",
                    expected.join(", ")
                )
            }
            SceneError::MissingKey { key, why, .. } => format!("{key}: missing; {why}"),
            SceneError::WrongType {
                key,
                found,
                expected,
                ..
            } => format!("{key} = {found}: wrong type; write {expected}"),
            SceneError::BadChoice {
                key,
                value,
                choices,
                ..
            } => {
                let quoted: Vec<String> = choices.iter().map(|c| format!("\"{c}\"")).collect();
                format!("{key} = {value}: must be one of {}", quoted.join(", "))
            }
            SceneError::NonPhysical {
                key, value, why, ..
            } => format!("{key} = {value}: {why}"),
            SceneError::Conflict { keys, why, .. } => format!("{}: {why}", keys.join(", ")),
            SceneError::BadOverride { set, why, .. } => format!("--set {set}: {why}"),
        }
    }
}

impl Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // One line, whatever a key, value or path contains.
        let line = format!("{}: {}", self.file().display(), self.detail());
        for c in line.chars() {
            if c.is_control() {
                write!(f, "{}", c.escape_default())?;
            } else {
                f.write_char(c)?;
            }
        }
        Ok(())
    }
}

impl std::error::Error for SceneError {}

fn truncate(s: &str, max_chars: usize) -> String {
    if s.chars().count() <= max_chars {
        s.to_string()
    } else {
        let head: String = s.chars().take(max_chars).collect();
        format!("{head}…")
    }
}

// ---------------------------------------------------------------------------------------------
// Loading and overrides
// ---------------------------------------------------------------------------------------------

/// Reads, overrides, validates and resolves the scene file at `path`.
///
/// `overrides` are `key.path=value` strings (the command line's `--set`), applied in order on
/// top of the file; the value is a TOML literal (`499`, `33.5e6`, `true`, `"ogive"`) or a bare
/// word, read as a string (`ogive`).
pub fn load(path: &Path, overrides: &[String]) -> Result<Scene, SceneError> {
    let io = |why: String| SceneError::Io {
        file: path.to_path_buf(),
        why,
    };
    let bytes = read_capped(path, SCENE_FILE_LIMIT)
        .map_err(|e| io(format!("cannot read the scene file ({e}); check the path")))?
        .ok_or_else(|| {
            io(format!(
                "larger than {} MiB, not a scene file (a scene is a few kB of TOML); check \
                 the path",
                SCENE_FILE_LIMIT >> 20
            ))
        })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        io(format!(
            "not UTF-8 text (invalid byte at offset {}); save the file as UTF-8",
            e.utf8_error().valid_up_to()
        ))
    })?;
    parse_str(&text, path, overrides)
}

/// The most bytes a scene file may have: shipped scenes have 2–4 kB.
pub const SCENE_FILE_LIMIT: u64 = 1 << 20;

/// The bytes of the file at `path`, or `None` when it has more than `limit` (read no further:
/// a path such as /dev/zero never ends).
pub fn read_capped(path: &Path, limit: u64) -> std::io::Result<Option<Vec<u8>>> {
    use std::io::Read as _;
    let mut bytes = Vec::new();
    std::fs::File::open(path)?
        .take(limit + 1)
        .read_to_end(&mut bytes)?;
    Ok((bytes.len() as u64 <= limit).then_some(bytes))
}

/// A shipped case (`cases/<name>`) with `--set` overrides, for unit tests.
#[cfg(test)]
pub(crate) fn shipped_case(name: &str, overrides: &[&str]) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name);
    let sets: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    load(&path, &sets).unwrap()
}

/// [`load`] on text already read; `origin` names the file in messages and gives the default
/// scene name (its stem).
pub fn parse_str(text: &str, origin: &Path, overrides: &[String]) -> Result<Scene, SceneError> {
    let mut doc: Table = text
        .parse()
        .map_err(|e: toml::de::Error| syntax_error(origin, text, &e))?;
    let mut set_keys = Vec::with_capacity(overrides.len());
    for set in overrides {
        let key =
            overrides::apply_override(&mut doc, set).map_err(|why| SceneError::BadOverride {
                file: origin.to_path_buf(),
                set: set.clone(),
                why,
            })?;
        set_keys.push((key, set));
    }
    let scene = parse::read(&doc, origin).and_then(|given| {
        resolve::resolve(&resolve::Check {
            file: origin,
            given: &given,
        })
    });
    // An error about a key an override set is the override's fault: say so.
    scene.map_err(|err| {
        let blamed = set_keys.iter().rev().find(|(key, _)| {
            err.keys().iter().any(|k| {
                k == key
                    || (matches!(err, SceneError::UnknownKey { .. })
                        && key.starts_with(&format!("{k}.")))
            })
        });
        match blamed {
            Some((_, set)) => SceneError::BadOverride {
                file: origin.to_path_buf(),
                set: (*set).clone(),
                why: err.detail(),
            },
            None => err,
        }
    })
}

fn syntax_error(origin: &Path, text: &str, e: &toml::de::Error) -> SceneError {
    let start = e.span().map_or(0, |s| s.start).min(text.len());
    // The span is a byte offset; step back to a char boundary before slicing.
    let start = (0..=start)
        .rev()
        .find(|&i| text.is_char_boundary(i))
        .unwrap_or(0);
    let before = &text[..start];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    let text_line = text[line_start..].lines().next().unwrap_or("");
    let why: Vec<&str> = e
        .message()
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    SceneError::Syntax {
        file: origin.to_path_buf(),
        line,
        column,
        text: text_line.to_string(),
        why: why.join("; "),
    }
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

/// A value as it would be written in the file, shortened.
fn render(value: &Value) -> String {
    match value {
        Value::Table(_) => "a table".into(),
        Value::Float(x) => truncate(&number_text(*x), 40),
        other => truncate(&other.to_string(), 40),
    }
}

/// `x` as messages and sweeps write it: in decimals for ordinary magnitudes (`300`, `0.003`),
/// in exponent form beyond them (`1e308`, not 309 digits). Read back, it is `x` again.
pub fn number_text(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-6..1e15).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        x.to_string()
    }
}

/// Length of a tangent ogive nose of shank radius `a`: `a·sqrt(4·crh − 1)`.
pub fn ogive_nose_length(diameter: f64, crh: f64) -> f64 {
    0.5 * diameter * (4.0 * crh - 1.0).sqrt()
}

/// A number as a TOML literal that reads back to the same value: plain in [1e-3, 1e6),
/// exponent form outside.
fn num<T: Copy + Into<f64> + Display + LowerExp>(x: T) -> String {
    let magnitude = x.into().abs();
    if magnitude == 0.0 || (1.0e-3..1.0e6).contains(&magnitude) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A derived number for a message, to 4 significant digits.
fn approx(x: f64) -> String {
    num(format!("{x:.3e}").parse::<f64>().unwrap_or(x))
}

impl Scene {
    /// World z of the model's z = 0: a Taylor scene's wall, else the target's face (0). The
    /// solver builds the scene with that at z = 0, where f32 positions resolve a step's
    /// motion, and adds it back in what it writes.
    pub fn origin_z(&self) -> f64 {
        self.wall.as_ref().map_or(0.0, |w| w.z)
    }

    /// The projectile placed in the model's coordinates (see [`Scene::origin_z`]).
    pub fn model_projectile(&self) -> ProjectileSpec {
        ProjectileSpec {
            nose_z: self.projectile.nose_z - self.origin_z(),
            ..self.projectile.clone()
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A shipped case by file name.
    pub(crate) fn case(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("cases")
            .join(name)
    }

    /// The smoke case with `overrides`.
    pub(crate) fn smoke(overrides: &[&str]) -> Result<Scene, SceneError> {
        let sets: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        load(&case("smoke.toml"), &sets)
    }

    /// Every shipped case, in name order.
    pub(crate) fn shipped_cases() -> Vec<PathBuf> {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
        let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
            .expect("cases/ exists")
            .map(|e| e.expect("readable entry").path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        paths.sort();
        paths
    }

    #[test]
    fn every_shipped_case_loads() {
        let paths = shipped_cases();
        assert!(
            paths.len() >= 7,
            "expected the shipped cases, found {paths:?}"
        );
        for path in paths {
            let scene = load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(scene.target.is_some(), scene.wall.is_none(), "{path:?}");
        }
    }

    #[test]
    fn overrides_change_exactly_their_value() {
        let base = smoke(&[]).unwrap();

        let mut expected = base.clone();
        expected.projectile.velocity = 499.0;
        assert_eq!(smoke(&["projectile.velocity=499"]).unwrap(), expected);

        let mut expected = base.clone();
        expected.target.as_mut().unwrap().concrete = Hjc::from_fc(33.5e6, 2370.0);
        assert_eq!(smoke(&["target.fc=33.5e6"]).unwrap(), expected);

        let mut expected = base.clone();
        let law = &mut expected.projectile.material.strength.law;
        let crate::materials::flow::FlowLaw::JohnsonCook(jc) = law else {
            panic!("the smoke preset is Johnson–Cook: {law:?}")
        };
        jc.a = 1.0e9;
        assert_eq!(smoke(&["projectile.material.jc_a=1e9"]).unwrap(), expected);

        let mut expected = base.clone();
        expected.contact.lambda = 0.0;
        assert_eq!(smoke(&["contact.lambda=0"]).unwrap(), expected);

        let mut expected = base.clone();
        expected.target.as_mut().unwrap().concrete.p_lock = 1.0e9;
        assert_eq!(smoke(&["target.concrete.p_lock = 1e9"]).unwrap(), expected);

        let mut expected = base.clone();
        expected.run.backend = Backend::Cpu;
        expected.name = "renamed".into();
        assert_eq!(
            smoke(&["run.backend=cpu", "name=\"renamed\""]).unwrap(),
            expected
        );
    }

    #[test]
    fn later_override_wins() {
        let s = smoke(&["projectile.velocity=400", "projectile.velocity=350.5"]).unwrap();
        assert_eq!(s.projectile.velocity, 350.5);
    }
}
