//! Scene files (`cases/*.toml`): parse, apply `--set` overrides, validate, resolve materials.
//!
//! The types below are the resolved scene the solver consumes: every value is in SI units and
//! has been checked. [`load`] reads a file, applies `--set key.path=value` overrides to the TOML
//! tree, deserializes it into private raw structs that reject unknown keys, then validates and
//! resolves it (material presets, HJC from f_c, defaults). Every failure is a [`SceneError`]
//! whose one-line message names the file and the dotted key and says what to change.
//!
//! Keys (SI units; `*` required; `Scene::resolved_table` prints every resolved value):
//!
//! - `name` (default: the file stem)
//! - `[run]` `end_time`*, `cfl` (0.5), `output_interval` (0: first and last frame),
//!   `history_interval` (end_time/500), `backend` ("auto"), `max_steps` (5e6), `stop_at_rest`
//!   (true)
//! - `[projectile]` `shape`* ("ogive" | "cylinder"), `diameter`*, `length`*, `crh` (ogive only,
//!   required there), `element_size`*, `velocity`*, `nose_z` (0.25·target.spacing, or
//!   wall.z + 1 µm)
//! - `[projectile.cavity]` (optional) `diameter`*, `length`*, `rear_wall`*, `filler_density` (0)
//! - `[projectile.material]` `preset`* ("4340-rc30" | "4340-rc45" | "copper-ofhc" |
//!   "copper-ofhc-za"), then any constant: `density`, `youngs_modulus`, `poisson_ratio`,
//!   `specific_heat`, `taylor_quinney`, `t_room`, `t_melt`, `eps_rate_ref`, `eos_k1`,
//!   `eos_k2`, `eos_k3`, `eos_gamma`, `damage`, `d1`…`d5`, `spall_stress`, `eps_f_min`; the
//!   Johnson–Cook presets' `jc_a`, `jc_b`, `jc_n`, `jc_c`, `jc_m`, or the Zerilli–Armstrong
//!   preset's `za_c0`, `za_c2`, `za_c3`, `za_c4` (the other law's keys are refused)
//! - `[target]` (penetration scenes) `radius`*, `thickness`*, `spacing`*, `fc`*, `density`*,
//!   `smoothing_ratio` (1.5), `fix_rear`, `fix_lateral`, `artificial_stress` (false),
//!   `viscosity_alpha` (1), `viscosity_beta` (2), `viscosity_switch` ("none" | "balsara"),
//!   `velocity_filter` ("none" | "linear"; "linear" needs `velocity_gradient = "corrected"`),
//!   `velocity_gradient` ("conjugate" | "corrected"),
//!   `lead_hole_depth` (0), `lead_hole_diameter` (projectile.diameter; narrower: a pilot hole,
//!   the nose starts at the face)
//! - `[target.concrete]` (optional) any [`Hjc`] field but `density` and `fc`, over
//!   [`Hjc::from_fc`]
//! - `[contact]` (optional) `lambda` (0.2), `slave_radius_factor` (1.5)
//! - `[wall]` (Taylor-bar scenes, instead of `[target]`) `z`*

use std::fmt::{self, Display, LowerExp, Write as _};
use std::path::{Path, PathBuf};

use serde::de::{
    self, DeserializeSeed, Expected, IntoDeserializer, MapAccess, Unexpected, Visitor,
};
use serde::Deserialize;
use toml::{Table, Value};

use crate::materials::hjc::Hjc;
use crate::materials::johnson_cook::{FlowLaw, JcDamage, JcStrength};
use crate::materials::presets::{self, DamageConstants, ZaConstants, PRESETS};
use crate::materials::steel_eos::PolyEos;
use crate::materials::zerilli_armstrong::ZaFcc;

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
    /// Which velocity the concrete's strain rate is taken from.
    pub velocity_filter: VelocityFilter,
    /// Which SPH gradient of it.
    pub velocity_gradient: VelocityGradient,
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
    /// motion gives up (docs/validation.md,
    /// "The stress update sees more strain than the forces pay for").
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
        let key = apply_override(&mut doc, set).map_err(|why| SceneError::BadOverride {
            file: origin.to_path_buf(),
            set: set.clone(),
            why,
        })?;
        set_keys.push((key, set));
    }
    let scene = RawScene::deserialize(ValueDe {
        value: &Value::Table(doc),
        path: String::new(),
    })
    .map_err(|e| e.into_scene_error(origin))
    .and_then(|raw| resolve(raw, origin));
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

/// Tables whose presence means something (a wall scene, a hollow projectile): an override may
/// set keys inside them only when the file has them.
const PRESENCE_TABLES: [&str; 3] = ["target", "wall", "projectile.cavity"];

/// Sets `key.path=value` in `doc`; returns the dotted key.
fn apply_override(doc: &mut Table, set: &str) -> Result<String, String> {
    let (key, value) = set
        .split_once('=')
        .ok_or("expected key.path=value, e.g. projectile.velocity=499")?;
    let segments: Vec<&str> = key.split('.').map(str::trim).collect();
    if segments.iter().any(|s| s.is_empty()) {
        return Err(format!(
            "`{}` is not a dotted key like projectile.velocity",
            key.trim()
        ));
    }
    let key = segments.join(".");
    // The deepest scene key has three parts; the cap also bounds the tables an override creates.
    if segments.len() > 8 {
        return Err(format!("{key} is not a scene key (too many parts)"));
    }
    let value = parse_literal(value.trim())?;
    let (last, parents) = segments.split_last().ok_or("empty key")?;
    let mut table = doc;
    for (i, segment) in parents.iter().enumerate() {
        let path = segments[..=i].join(".");
        if !table.contains_key(*segment) {
            if PRESENCE_TABLES.contains(&path.as_str()) {
                return Err(format!(
                    "the file has no [{path}] table; add the table to the file to set {key}"
                ));
            }
            table.insert(segment.to_string(), Value::Table(Table::new()));
        }
        table = match table.get_mut(*segment) {
            Some(Value::Table(t)) => t,
            _ => return Err(format!("{path} is a value, not a table; cannot set {key}")),
        };
    }
    table.insert(last.to_string(), value);
    Ok(key)
}

/// A TOML literal, or a bare word read as a string. A decimal integer too large for TOML's
/// 64 bits (`--set projectile.velocity=100000000000000000000`) is read as the float it is, so
/// that the key's own range check answers, not "wrong type".
fn parse_literal(text: &str) -> Result<Value, String> {
    if text.is_empty() {
        return Err("no value after `=`".into());
    }
    if let Ok(mut t) = format!("v = {text}").parse::<Table>() {
        if t.len() == 1 {
            if let Some(v) = t.remove("v") {
                return Ok(v);
            }
        }
    }
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) {
        if let Ok(x) = text.parse::<f64>() {
            return Ok(Value::Float(x));
        }
    }
    let bare = text
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || "-_.+".contains(c));
    if bare {
        Ok(Value::String(text.to_string()))
    } else {
        Err(format!(
            "cannot read `{text}` as a value; write a number, true/false or a \"string\""
        ))
    }
}

// ---------------------------------------------------------------------------------------------
// Deserializing a TOML tree with the dotted key of every error
// ---------------------------------------------------------------------------------------------

/// What went wrong while deserializing, before the file name is known.
#[derive(Debug)]
enum DeKind {
    Unknown {
        field: String,
        expected: &'static [&'static str],
    },
    Missing {
        field: &'static str,
    },
    Type {
        expected: String,
    },
    NonFinite,
    TooLarge,
    TooSmall,
}

#[derive(Debug)]
struct DeError {
    kind: DeKind,
    /// Dotted key, set by the innermost deserializer that sees the error.
    key: Option<String>,
    /// The offending value as written.
    found: Option<String>,
}

impl DeError {
    fn new(kind: DeKind) -> DeError {
        DeError {
            kind,
            key: None,
            found: None,
        }
    }

    /// Attaches the key path of the table or value being deserialized (innermost wins).
    fn at(mut self, path: &str, value: Option<&Value>) -> DeError {
        if self.key.is_none() {
            self.key = Some(match &self.kind {
                DeKind::Unknown { field, .. } => join(path, field),
                DeKind::Missing { field } => join(path, field),
                _ => path.to_string(),
            });
        }
        if self.found.is_none() {
            self.found = value.map(render);
        }
        self
    }

    fn into_scene_error(self, origin: &Path) -> SceneError {
        let file = origin.to_path_buf();
        let key = self.key.unwrap_or_else(|| "(top level)".into());
        let value = self.found.unwrap_or_default();
        let non_physical = |why: &str| SceneError::NonPhysical {
            file: file.clone(),
            key: key.clone(),
            value: value.clone(),
            why: why.into(),
        };
        match self.kind {
            DeKind::Unknown { expected, .. } => SceneError::UnknownKey {
                file,
                key,
                expected: expected.iter().map(|s| s.to_string()).collect(),
            },
            DeKind::Missing { .. } => {
                let why = if TABLES.contains(&key.as_str()) {
                    format!("add a [{key}] table")
                } else {
                    "add this required key".into()
                };
                SceneError::MissingKey { file, key, why }
            }
            DeKind::Type { expected } => SceneError::WrongType {
                file,
                key,
                found: value,
                expected: describe_expected(&expected),
            },
            DeKind::NonFinite => non_physical("must be a finite number"),
            DeKind::TooLarge => non_physical(
                "magnitude beyond the f32 range (3.4e38) the solver computes in; use a smaller value",
            ),
            DeKind::TooSmall => non_physical(
                "nonzero magnitude below f32's smallest normal number (1.2e-38), it would flush \
                 to zero; use 0 or a larger value",
            ),
        }
    }
}

/// Required tables (a missing one gets "add a [table]" rather than "add this key").
const TABLES: [&str; 3] = ["run", "projectile", "projectile.material"];

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

/// serde's name of the expected type, in the words of a scene file.
fn describe_expected(serde_expected: &str) -> String {
    match serde_expected {
        "f64" => "a number".into(),
        "u64" => "a whole number ≥ 0 (written as a float, at most 2⁵³)".into(),
        "a boolean" => "true or false".into(),
        "a string" => "a \"string\" in quotes".into(),
        s if s.starts_with("struct ") => "a table".into(),
        s => s.into(),
    }
}

impl Display for DeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?} at {:?}", self.kind, self.key)
    }
}

impl std::error::Error for DeError {}

impl de::Error for DeError {
    fn custom<T: Display>(msg: T) -> Self {
        DeError::new(DeKind::Type {
            expected: msg.to_string(),
        })
    }

    fn invalid_type(_: Unexpected, expected: &dyn Expected) -> Self {
        DeError::new(DeKind::Type {
            expected: expected.to_string(),
        })
    }

    fn invalid_value(_: Unexpected, expected: &dyn Expected) -> Self {
        DeError::new(DeKind::Type {
            expected: expected.to_string(),
        })
    }

    fn unknown_field(field: &str, expected: &'static [&'static str]) -> Self {
        DeError::new(DeKind::Unknown {
            field: field.to_string(),
            expected,
        })
    }

    fn missing_field(field: &'static str) -> Self {
        DeError::new(DeKind::Missing { field })
    }
}

/// A deserializer over a borrowed TOML value that knows its dotted key, so every error names
/// the full key (`target.fcc`), and that refuses non-finite and out-of-f32-range floats.
struct ValueDe<'a> {
    value: &'a Value,
    path: String,
}

impl<'de> de::Deserializer<'de> for ValueDe<'_> {
    type Error = DeError;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, DeError> {
        let result = match self.value {
            Value::String(s) => visitor.visit_str(s),
            Value::Integer(i) => visitor.visit_i64(*i),
            Value::Float(x) if !x.is_finite() => Err(DeError::new(DeKind::NonFinite)),
            Value::Float(x) if x.abs() > f64::from(f32::MAX) => Err(DeError::new(DeKind::TooLarge)),
            Value::Float(x) if *x != 0.0 && x.abs() < f64::from(f32::MIN_POSITIVE) => {
                Err(DeError::new(DeKind::TooSmall))
            }
            Value::Float(x) => visitor.visit_f64(*x),
            Value::Boolean(b) => visitor.visit_bool(*b),
            Value::Datetime(_) => Err(de::Error::invalid_type(
                Unexpected::Other("a date"),
                &visitor,
            )),
            // No scene key is an array; refusing here also stops serde from filling a struct
            // from a sequence.
            Value::Array(_) => Err(de::Error::invalid_type(Unexpected::Seq, &visitor)),
            Value::Table(table) => visitor.visit_map(TableAccess {
                iter: table.iter(),
                path: &self.path,
                pending: None,
            }),
        };
        result.map_err(|e| e.at(&self.path, Some(self.value)))
    }

    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, DeError> {
        visitor.visit_some(self)
    }

    /// A count may be written as a float when it is a whole number (`max_steps = 5e6`), up to
    /// 2⁵³, where every whole number is still a float.
    fn deserialize_u64<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, DeError> {
        match self.value {
            Value::Float(x) if *x >= 0.0 && x.fract() == 0.0 && *x <= 2f64.powi(53) => visitor
                .visit_u64(*x as u64)
                .map_err(|e: DeError| e.at(&self.path, Some(self.value))),
            _ => self.deserialize_any(visitor),
        }
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u128 f32 f64 char str string bytes byte_buf unit
        unit_struct newtype_struct seq tuple tuple_struct map struct enum identifier ignored_any
    }
}

struct TableAccess<'a> {
    iter: toml::map::Iter<'a>,
    path: &'a str,
    pending: Option<(&'a String, &'a Value)>,
}

impl<'de> MapAccess<'de> for TableAccess<'_> {
    type Error = DeError;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, DeError> {
        let Some((key, value)) = self.iter.next() else {
            return Ok(None);
        };
        self.pending = Some((key, value));
        let key_de: de::value::StrDeserializer<'_, DeError> = key.as_str().into_deserializer();
        seed.deserialize(key_de)
            .map(Some)
            .map_err(|e| e.at(self.path, None))
    }

    fn next_value_seed<V: DeserializeSeed<'de>>(&mut self, seed: V) -> Result<V::Value, DeError> {
        let (key, value) = self
            .pending
            .take()
            .ok_or_else(|| de::Error::custom("value requested before its key"))?;
        seed.deserialize(ValueDe {
            value,
            path: join(self.path, key),
        })
    }
}

// ---------------------------------------------------------------------------------------------
// Raw scene: the file's shape, every optional key an Option
// ---------------------------------------------------------------------------------------------

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    name: Option<String>,
    run: RawRun,
    projectile: RawProjectile,
    target: Option<RawTarget>,
    contact: Option<RawContact>,
    wall: Option<RawWall>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRun {
    end_time: f64,
    cfl: Option<f64>,
    output_interval: Option<f64>,
    history_interval: Option<f64>,
    backend: Option<String>,
    max_steps: Option<u64>,
    stop_at_rest: Option<bool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProjectile {
    shape: String,
    diameter: f64,
    length: f64,
    crh: Option<f64>,
    element_size: f64,
    velocity: f64,
    nose_z: Option<f64>,
    cavity: Option<RawCavity>,
    material: RawSteel,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCavity {
    diameter: f64,
    length: f64,
    rear_wall: f64,
    filler_density: Option<f64>,
}

/// `[projectile.material]`: a preset name and an optional override of each constant.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSteel {
    preset: String,
    density: Option<f64>,
    youngs_modulus: Option<f64>,
    poisson_ratio: Option<f64>,
    specific_heat: Option<f64>,
    taylor_quinney: Option<f64>,
    t_room: Option<f64>,
    t_melt: Option<f64>,
    jc_a: Option<f64>,
    jc_b: Option<f64>,
    jc_n: Option<f64>,
    jc_c: Option<f64>,
    jc_m: Option<f64>,
    eps_rate_ref: Option<f64>,
    za_c0: Option<f64>,
    za_c2: Option<f64>,
    za_c3: Option<f64>,
    za_c4: Option<f64>,
    eos_k1: Option<f64>,
    eos_k2: Option<f64>,
    eos_k3: Option<f64>,
    eos_gamma: Option<f64>,
    damage: Option<bool>,
    d1: Option<f64>,
    d2: Option<f64>,
    d3: Option<f64>,
    d4: Option<f64>,
    d5: Option<f64>,
    spall_stress: Option<f64>,
    eps_f_min: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTarget {
    radius: f64,
    thickness: f64,
    spacing: f64,
    fc: f64,
    density: f64,
    smoothing_ratio: Option<f64>,
    fix_rear: Option<bool>,
    fix_lateral: Option<bool>,
    artificial_stress: Option<bool>,
    viscosity_alpha: Option<f64>,
    viscosity_beta: Option<f64>,
    viscosity_switch: Option<String>,
    velocity_filter: Option<String>,
    velocity_gradient: Option<String>,
    lead_hole_depth: Option<f64>,
    lead_hole_diameter: Option<f64>,
    concrete: Option<RawHjc>,
}

/// `[target.concrete]`: overrides of the HJC constants that [`Hjc::from_fc`] produced.
#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawHjc {
    shear_modulus: Option<f64>,
    a: Option<f64>,
    b: Option<f64>,
    n: Option<f64>,
    c: Option<f64>,
    s_max: Option<f64>,
    t: Option<f64>,
    eps_rate_ref: Option<f64>,
    ef_min: Option<f64>,
    d1: Option<f64>,
    d2: Option<f64>,
    p_crush: Option<f64>,
    mu_crush: Option<f64>,
    k1: Option<f64>,
    k2: Option<f64>,
    k3: Option<f64>,
    p_lock: Option<f64>,
    mu_lock: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawContact {
    lambda: Option<f64>,
    slave_radius_factor: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWall {
    z: f64,
}

// ---------------------------------------------------------------------------------------------
// Validation and resolution
// ---------------------------------------------------------------------------------------------

/// Default particle preselection radius factor k (physics.md §4).
const DEFAULT_SLAVE_RADIUS_FACTOR: f64 = 1.5;
/// The paper's λ (physics.md §4).
const DEFAULT_LAMBDA: f64 = 0.2;
/// Gap between a Taylor bar's lowest face and the wall at t = 0 (m): touching, not overlapping.
const WALL_GAP: f64 = 1.0e-6;

/// Makes validation errors for one file.
struct Check<'a> {
    file: &'a Path,
}

impl Check<'_> {
    fn non_physical(&self, key: &str, value: f64, why: impl Into<String>) -> SceneError {
        SceneError::NonPhysical {
            file: self.file.to_path_buf(),
            key: key.into(),
            value: num(value),
            why: why.into(),
        }
    }

    /// `Ok(value)` when `ok`, else a [`SceneError::NonPhysical`] saying `why`.
    fn require(&self, ok: bool, key: &str, value: f64, why: &str) -> Result<f64, SceneError> {
        if ok {
            Ok(value)
        } else {
            Err(self.non_physical(key, value, why))
        }
    }

    fn positive(&self, key: &str, value: f64, unit: &str) -> Result<f64, SceneError> {
        self.require(value > 0.0, key, value, &format!("must be > 0 ({unit})"))
    }

    fn non_negative(&self, key: &str, value: f64, unit: &str) -> Result<f64, SceneError> {
        self.require(value >= 0.0, key, value, &format!("must be ≥ 0 ({unit})"))
    }

    fn choice<'c>(
        &self,
        key: &str,
        value: &str,
        choices: &[&'c str],
    ) -> Result<&'c str, SceneError> {
        choices
            .iter()
            .find(|c| **c == value)
            .copied()
            .ok_or_else(|| SceneError::BadChoice {
                file: self.file.to_path_buf(),
                key: key.into(),
                value: render(&Value::String(value.into())),
                choices: choices.iter().map(|c| c.to_string()).collect(),
            })
    }

    fn conflict(&self, keys: &[&str], why: &str) -> SceneError {
        SceneError::Conflict {
            file: self.file.to_path_buf(),
            keys: keys.iter().map(|k| k.to_string()).collect(),
            why: why.into(),
        }
    }

    fn missing(&self, key: &str, why: impl Into<String>) -> SceneError {
        SceneError::MissingKey {
            file: self.file.to_path_buf(),
            key: key.into(),
            why: why.into(),
        }
    }
}

fn resolve(raw: RawScene, origin: &Path) -> Result<Scene, SceneError> {
    let c = Check { file: origin };
    let name = match raw.name {
        Some(name) if name.trim().is_empty() => {
            return Err(SceneError::NonPhysical {
                file: origin.to_path_buf(),
                key: "name".into(),
                value: render(&Value::String(name)),
                why: "must not be empty; remove it to use the file name".into(),
            })
        }
        Some(name) => name,
        None => origin
            .file_stem()
            .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned()),
    };
    let run = resolve_run(&c, &raw.run)?;
    let contact = resolve_contact(&c, raw.contact.as_ref())?;
    let mut projectile = resolve_projectile(&c, &raw.projectile)?;
    // The default nose position: a small gap, no initial overlap.
    let (target, wall, default_nose_z) = match (raw.target, raw.wall) {
        (Some(_), Some(_)) => {
            return Err(c.conflict(
                &["target", "wall"],
                "a scene has exactly one of [target] (penetration) and [wall] (Taylor bar); \
                 remove one of the two tables",
            ))
        }
        (None, None) => {
            return Err(c.conflict(
                &["target", "wall"],
                "a scene needs one of [target] (penetration) and [wall] (Taylor bar); add one",
            ))
        }
        (Some(t), None) => {
            let t = resolve_target(&c, &t, &projectile)?;
            let nose_z = 0.25 * t.spacing - t.start_depth(projectile.diameter);
            (Some(t), None, nose_z)
        }
        (None, Some(w)) => (None, Some(WallSpec { z: w.z }), w.z + WALL_GAP),
    };
    let start_depth = target
        .as_ref()
        .map_or(0.0, |t| t.start_depth(projectile.diameter));
    let pilot = target
        .as_ref()
        .is_some_and(|t| t.lead_hole_depth > 0.0 && start_depth == 0.0);
    projectile.nose_z = match (raw.projectile.nose_z, &wall) {
        (None, _) => default_nose_z,
        (Some(z), None) => c.require(
            (-start_depth..=MAX_START_GAP).contains(&z),
            "projectile.nose_z",
            z,
            &if pilot {
                format!(
                    "must be in [0, {MAX_START_GAP}] (m): the lead hole is narrower than the \
                     projectile (target.lead_hole_diameter < projectile.diameter), so the nose \
                     starts at or above the front face z = 0"
                )
            } else {
                format!(
                    "must be in [−target.lead_hole_depth, {MAX_START_GAP}] = [{}, \
                     {MAX_START_GAP}] (m): the target's front face is z = 0, the nose may not \
                     start inside the concrete (only down a lead hole), and f32 positions lose \
                     resolution far from it",
                    num(if start_depth > 0.0 { -start_depth } else { 0.0 })
                )
            },
        )?,
        (Some(z), Some(w)) => c.require(
            z >= w.z && z - w.z <= MAX_START_GAP,
            "projectile.nose_z",
            z,
            &format!(
                "must be in [wall.z, wall.z + {MAX_START_GAP}] = [{}, {}] (m): the bar may not \
                 start inside the wall, nor far from it",
                num(w.z),
                num(w.z + MAX_START_GAP)
            ),
        )?,
    };
    Ok(Scene {
        name,
        path: origin.to_path_buf(),
        run,
        projectile,
        target,
        contact,
        wall,
    })
}

fn resolve_run(c: &Check, r: &RawRun) -> Result<RunControl, SceneError> {
    let end_time = c.positive("run.end_time", r.end_time, "s")?;
    let cfl = r.cfl.unwrap_or(0.5);
    c.require(
        cfl > 0.0 && cfl <= 1.0,
        "run.cfl",
        cfl,
        "must be in (0, 1]: the Courant number of an explicit step",
    )?;
    let output_interval = c.non_negative(
        "run.output_interval",
        r.output_interval.unwrap_or(0.0),
        "s; 0 writes the first and last frame only",
    )?;
    // 500 history rows per run by default: enough for smooth plots, small files.
    let history_interval = c.positive(
        "run.history_interval",
        r.history_interval.unwrap_or(end_time / 500.0),
        "s",
    )?;
    // A real GPU where there is one, the CPU reference path otherwise (never a software adapter
    // unasked: lavapipe is for tests).
    let backend = match r.backend.as_deref() {
        None => Backend::Auto,
        Some(b) => match c.choice("run.backend", b, &["cpu", "gpu", "auto"])? {
            "gpu" => Backend::Gpu,
            "auto" => Backend::Auto,
            _ => Backend::Cpu,
        },
    };
    let max_steps = r.max_steps.unwrap_or(5_000_000);
    if max_steps == 0 {
        return Err(c.non_physical("run.max_steps", 0.0, "must be ≥ 1"));
    }
    Ok(RunControl {
        end_time,
        cfl,
        output_interval,
        history_interval,
        backend,
        max_steps,
        stop_at_rest: r.stop_at_rest.unwrap_or(true),
    })
}

fn resolve_contact(c: &Check, raw: Option<&RawContact>) -> Result<ContactSpec, SceneError> {
    let lambda = raw.and_then(|r| r.lambda).unwrap_or(DEFAULT_LAMBDA);
    c.require(
        (0.0..=1.0).contains(&lambda),
        "contact.lambda",
        lambda,
        "must be in [0, 1]: the local share of the momentum transport (0 = rigid projectile)",
    )?;
    let factor = raw
        .and_then(|r| r.slave_radius_factor)
        .unwrap_or(DEFAULT_SLAVE_RADIUS_FACTOR);
    c.require(
        factor > 1.0,
        "contact.slave_radius_factor",
        factor,
        "must be > 1: slaves are preselected beyond the projectile's largest radius",
    )?;
    Ok(ContactSpec {
        lambda,
        slave_radius_factor: factor,
    })
}

/// Length of a tangent ogive nose of shank radius `a`: `a·sqrt(4·crh − 1)`.
pub fn ogive_nose_length(diameter: f64, crh: f64) -> f64 {
    0.5 * diameter * (4.0 * crh - 1.0).sqrt()
}

/// Largest gap between the nose and the target's face or the wall at the start (m).
const MAX_START_GAP: f64 = 1.0;

/// Resolves `[projectile]`; `nose_z` is left at 0 for [`resolve`] to set.
fn resolve_projectile(c: &Check, p: &RawProjectile) -> Result<ProjectileSpec, SceneError> {
    let diameter = c.positive("projectile.diameter", p.diameter, "m")?;
    let length = c.positive("projectile.length", p.length, "m")?;
    let shape = match c.choice("projectile.shape", &p.shape, &["ogive", "cylinder"])? {
        "ogive" => {
            let crh = p.crh.ok_or_else(|| {
                c.missing(
                    "projectile.crh",
                    "required for shape = \"ogive\" (calibre-radius-head, e.g. 2.0)",
                )
            })?;
            c.require(
                crh >= 0.5,
                "projectile.crh",
                crh,
                "must be ≥ 0.5 (0.5 is a hemispherical nose)",
            )?;
            ProjectileShape::Ogive { crh }
        }
        _ => {
            if p.crh.is_some() {
                return Err(c.conflict(
                    &["projectile.crh", "projectile.shape"],
                    "a cylinder has no crh; remove crh or set shape = \"ogive\"",
                ));
            }
            ProjectileShape::Cylinder
        }
    };
    let nose_length = shape.nose_length(diameter);
    c.require(
        length > nose_length,
        "projectile.length",
        length,
        &format!(
            "must exceed the ogive nose length a·sqrt(4·crh − 1) = {} m",
            approx(nose_length)
        ),
    )?;
    let element_size = c.positive("projectile.element_size", p.element_size, "m")?;
    c.require(
        element_size <= diameter / 4.0,
        "projectile.element_size",
        element_size,
        &format!(
            "must be ≤ projectile.diameter/4 = {} m (at least two elements across the radius)",
            approx(diameter / 4.0)
        ),
    )?;
    c.require(
        length >= nose_length + element_size,
        "projectile.length",
        length,
        &if nose_length > 0.0 {
            format!(
                "must be ≥ the nose length plus projectile.element_size = {} m (at least one \
                 element along the shank)",
                approx(nose_length + element_size)
            )
        } else {
            format!(
                "must be ≥ projectile.element_size = {} m (at least one element along the bar)",
                approx(element_size)
            )
        },
    )?;
    c.require(
        p.velocity >= 0.0 && p.velocity <= 5000.0,
        "projectile.velocity",
        p.velocity,
        "must be in [0, 5000] (m/s): the striking speed, not negative (flight is along −z); \
         the material models are not meant beyond 5 km/s",
    )?;
    let material = resolve_steel(c, &p.material)?;
    // The explicit step is the time a wave takes across the smallest element: a solid struck
    // faster than its waves travel would move its nodes farther than an element in one step.
    let wave = material.wave_speed();
    c.require(
        p.velocity < wave,
        "projectile.velocity",
        p.velocity,
        &format!(
            "must be below the projectile's elastic wave speed √((K₁ + 4G/3)/ρ) = {} m/s \
             (projectile.material: a metal's is thousands of m/s; are its moduli or its density \
             in the wrong unit?)",
            approx(wave)
        ),
    )?;
    check_strength_below_modulus(c, &material)?;
    let cavity = match &p.cavity {
        None => None,
        Some(cav) => {
            let cd = c.positive("projectile.cavity.diameter", cav.diameter, "m")?;
            let cl = c.positive("projectile.cavity.length", cav.length, "m")?;
            let rear = c.positive("projectile.cavity.rear_wall", cav.rear_wall, "m")?;
            let filler = cav.filler_density.unwrap_or(0.0);
            c.require(
                (0.0..=23_000.0).contains(&filler),
                "projectile.cavity.filler_density",
                filler,
                "must be in [0, 23000] (kg/m³; 0 = empty): no solid is denser than osmium's 22590",
            )?;
            let max_d = diameter - 2.0 * element_size;
            c.require(
                cd < max_d,
                "projectile.cavity.diameter",
                cd,
                &format!(
                    "must be < projectile.diameter − 2·element_size = {} m (the wall needs at \
                     least one element); make the cavity narrower",
                    approx(max_d)
                ),
            )?;
            let shank = length - nose_length;
            c.require(
                cl + rear < shank,
                "projectile.cavity.length",
                cl,
                &format!(
                    "cavity length + rear_wall = {} m must be < the shank length {} m (length \
                     minus the nose); make the cavity shorter",
                    approx(cl + rear),
                    approx(shank)
                ),
            )?;
            Some(CavitySpec {
                diameter: cd,
                length: cl,
                rear_wall: rear,
                filler_density: filler,
            })
        }
    };
    Ok(ProjectileSpec {
        shape,
        diameter,
        length,
        cavity,
        element_size,
        velocity: p.velocity,
        nose_z: 0.0,
        material,
    })
}

/// Copies every `Some` field of a raw override struct over the same field of `dst`.
macro_rules! override_fields {
    ($dst:expr, $src:expr, $convert:expr; $($field:ident),+ $(,)?) => {
        $(if let Some(v) = $src.$field { $dst.$field = $convert(v); })+
    };
}

/// A metal yields, and hardens, at stresses far below its modulus (4340: A/E = 0.004): a
/// Johnson–Cook A or B at or above E is in another unit. Checked once E itself has passed the
/// checks that name it (its range, K₁, the wave speed).
fn check_strength_below_modulus(c: &Check, m: &SteelMaterial) -> Result<(), SceneError> {
    let e = m.youngs_modulus;
    let strengths = match &m.strength.law {
        FlowLaw::JohnsonCook => [("jc_a", m.strength.a), ("jc_b", m.strength.b)],
        FlowLaw::ZerilliArmstrongFcc(z) => [("za_c0", z.c0), ("za_c2", z.c2)],
    };
    for (field, value) in strengths {
        c.require(
            f64::from(value) < e,
            &format!("projectile.material.{field}"),
            f64::from(value),
            &format!(
                "must be below projectile.material.youngs_modulus = {} (Pa): a metal yields at \
                 stresses far below its modulus (4340: A/E = 0.004)",
                num(e)
            ),
        )?;
    }
    Ok(())
}

fn resolve_steel(c: &Check, m: &RawSteel) -> Result<SteelMaterial, SceneError> {
    let name = c.choice("projectile.material.preset", &m.preset, &PRESETS)?;
    let mut k = presets::preset(name).expect("every preset name has constants");
    override_fields!(k, m, |v| v;
        density, youngs_modulus, poisson_ratio, specific_heat, taylor_quinney, t_room, t_melt,
        jc_a, jc_b, jc_n, jc_c, jc_m, eps_rate_ref, eos_k2, eos_k3, eos_gamma);
    let key = |field: &str| format!("projectile.material.{field}");
    c.require(
        (500.0..=23_000.0).contains(&k.density),
        &key("density"),
        k.density,
        "must be in [500, 23000] (kg/m³): solid metals lie between lithium's 534 and osmium's \
         22590",
    )?;
    c.require(
        k.youngs_modulus > 0.0 && k.youngs_modulus <= 1.2e12,
        &key("youngs_modulus"),
        k.youngs_modulus,
        "must be in (0, 1.2e12] (Pa): no solid is stiffer than diamond (about 1.1e12 Pa; the \
         stiffest metal, iridium, has 5.3e11)",
    )?;
    c.require(
        k.poisson_ratio > 0.0 && k.poisson_ratio < 0.5,
        &key("poisson_ratio"),
        k.poisson_ratio,
        "must be in (0, 0.5)",
    )?;
    c.require(
        (100.0..=4_000.0).contains(&k.specific_heat),
        &key("specific_heat"),
        k.specific_heat,
        "must be in [100, 4000] (J/(kg K)): solid metals lie between about 130 (lead, gold, \
         tungsten) and 3600 (lithium)",
    )?;
    c.require(
        (0.0..=1.0).contains(&k.taylor_quinney),
        &key("taylor_quinney"),
        k.taylor_quinney,
        "must be in [0, 1]: the share of plastic work turned into heat",
    )?;
    c.positive(&key("t_room"), k.t_room, "K")?;
    c.require(
        k.t_melt > k.t_room && k.t_melt <= 4000.0,
        &key("t_melt"),
        k.t_melt,
        &format!(
            "must be > t_room = {} and ≤ 4000 (K): no metal melts above tungsten's 3695",
            num(k.t_room)
        ),
    )?;
    // First, so that a Johnson–Cook key given to a Zerilli–Armstrong preset is named as
    // belonging to the other law rather than checked against its range.
    let law = resolve_flow_law(c, m, k.za, &key)?;
    c.positive(&key("jc_a"), k.jc_a, "Pa")?;
    c.non_negative(&key("jc_b"), k.jc_b, "Pa")?;
    c.require(
        k.jc_n > 0.0 && k.jc_n <= 1.0,
        &key("jc_n"),
        k.jc_n,
        "must be in (0, 1]",
    )?;
    c.require(
        (0.0..=1.0).contains(&k.jc_c),
        &key("jc_c"),
        k.jc_c,
        "must be in [0, 1]: the strain-rate sensitivity of metals is about 0.001 to 0.1 (1 \
         would raise the flow stress twelvefold at 10⁵/s)",
    )?;
    c.positive(&key("jc_m"), k.jc_m, "-")?;
    c.positive(&key("eps_rate_ref"), k.eps_rate_ref, "1/s")?;
    // Copper's K₁ is the elastic bulk modulus of the final E and ν.
    let bulk = k.youngs_modulus / (3.0 * (1.0 - 2.0 * k.poisson_ratio));
    let eos_k1 = m.eos_k1.or(k.eos_k1).unwrap_or(bulk);
    c.require(
        eos_k1 > 0.0 && (eos_k1 as f32).is_finite(),
        &key("eos_k1"),
        eos_k1,
        "must be > 0 (Pa) and within the f32 range",
    )?;
    c.require(
        (0.0..=crate::materials::steel_eos::MAX_GAMMA as f64).contains(&k.eos_gamma),
        &key("eos_gamma"),
        k.eos_gamma,
        &format!(
            "must be in [0, {}]: the Grüneisen Γ of solid metals is about 1 to 3, and the \
             stable step leaves out the energy term Γ (E/ρ₀ + p/ρ) of the sound speed",
            crate::materials::steel_eos::MAX_GAMMA
        ),
    )?;
    let eos = PolyEos {
        k1: eos_k1 as f32,
        k2: k.eos_k2 as f32,
        k3: k.eos_k3 as f32,
        gamma: k.eos_gamma as f32,
    };
    // The EOS's K₁ and the elastic E, ν describe one solid: the stress update takes its
    // shear modulus from E and ν and its pressure from K₁, so a K₁ far from E/(3(1 − 2ν)) runs
    // another Poisson's ratio than the one given (or one of them is in the wrong unit).
    let ratio = eos_k1 / bulk;
    if !(0.5..=2.0).contains(&ratio) {
        return Err(c.conflict(
            &[
                &key("eos_k1"),
                &key("youngs_modulus"),
                &key("poisson_ratio"),
            ],
            &format!(
                "K₁ = {} Pa is {} times the elastic bulk modulus E/(3(1 − 2ν)) = {} Pa; \
                 both are the solid's bulk modulus and must agree within a factor of 2 (is \
                 one of them in the wrong unit?)",
                approx(eos_k1),
                approx(ratio),
                approx(bulk)
            ),
        ));
    }
    if let Some(why) = crate::materials::steel_eos::compression_fault(&eos) {
        return Err(c.conflict(&[&key("eos_k1"), &key("eos_k2"), &key("eos_k3")], &why));
    }
    let damage = resolve_damage(c, m, k.damage, &key)?;
    Ok(SteelMaterial {
        preset: m.preset.clone(),
        density: k.density,
        youngs_modulus: k.youngs_modulus,
        poisson_ratio: k.poisson_ratio,
        specific_heat: k.specific_heat,
        taylor_quinney: k.taylor_quinney,
        strength: JcStrength {
            law,
            a: k.jc_a as f32,
            b: k.jc_b as f32,
            n: k.jc_n as f32,
            c: k.jc_c as f32,
            m: k.jc_m as f32,
            eps_rate_ref: k.eps_rate_ref as f32,
            t_room: k.t_room as f32,
            t_melt: k.t_melt as f32,
        },
        eos,
        damage,
    })
}

/// The flow-stress law: Johnson–Cook's, or, for a preset with Zerilli–Armstrong constants,
/// those with the scene's `za_*` overrides. A key of the other law is refused, not ignored.
fn resolve_flow_law(
    c: &Check,
    m: &RawSteel,
    preset: Option<ZaConstants>,
    key: &dyn Fn(&str) -> String,
) -> Result<FlowLaw, SceneError> {
    let jc_given = [
        ("jc_a", m.jc_a),
        ("jc_b", m.jc_b),
        ("jc_n", m.jc_n),
        ("jc_c", m.jc_c),
        ("jc_m", m.jc_m),
    ];
    let za_given = [
        ("za_c0", m.za_c0),
        ("za_c2", m.za_c2),
        ("za_c3", m.za_c3),
        ("za_c4", m.za_c4),
    ];
    let first = |given: &[(&'static str, Option<f64>)]| {
        given.iter().find(|(_, v)| v.is_some()).map(|(f, _)| *f)
    };
    let Some(mut z) = preset else {
        if let Some(field) = first(&za_given) {
            return Err(c.conflict(
                &[&key(field), &key("preset")],
                &format!(
                    "preset \"{}\" takes the Johnson–Cook law (jc_a … jc_m); the \
                     Zerilli–Armstrong constants are for preset \"copper-ofhc-za\"",
                    m.preset
                ),
            ));
        }
        return Ok(FlowLaw::JohnsonCook);
    };
    if let Some(field) = first(&jc_given) {
        return Err(c.conflict(
            &[&key(field), &key("preset")],
            &format!(
                "preset \"{}\" takes the Zerilli–Armstrong law (za_c0 … za_c4); the \
                 Johnson–Cook constants would be unused",
                m.preset
            ),
        ));
    }
    for (dst, given) in [
        (&mut z.c0, m.za_c0),
        (&mut z.c2, m.za_c2),
        (&mut z.c3, m.za_c3),
        (&mut z.c4, m.za_c4),
    ] {
        *dst = given.unwrap_or(*dst);
    }
    c.positive(&key("za_c0"), z.c0, "Pa")?;
    c.non_negative(&key("za_c2"), z.c2, "Pa")?;
    for (field, value) in [("za_c3", z.c3), ("za_c4", z.c4)] {
        c.require(
            (0.0..=0.1).contains(&value),
            &key(field),
            value,
            "must be in [0, 0.1] (1/K): copper's are 0.0028 and 0.000115 per kelvin",
        )?;
    }
    Ok(FlowLaw::ZerilliArmstrongFcc(ZaFcc {
        c0: z.c0 as f32,
        c2: z.c2 as f32,
        c3: z.c3 as f32,
        c4: z.c4 as f32,
    }))
}

fn resolve_damage(
    c: &Check,
    m: &RawSteel,
    preset: Option<DamageConstants>,
    key: &dyn Fn(&str) -> String,
) -> Result<Option<JcDamage>, SceneError> {
    let given = [
        ("d1", m.d1),
        ("d2", m.d2),
        ("d3", m.d3),
        ("d4", m.d4),
        ("d5", m.d5),
        ("spall_stress", m.spall_stress),
        ("eps_f_min", m.eps_f_min),
    ];
    if !m.damage.unwrap_or(preset.is_some()) {
        if let Some((field, _)) = given.iter().find(|(_, v)| v.is_some()) {
            let why = if m.damage.is_some() {
                "damage constants given with damage = false; remove them or set damage = true"
            } else {
                "this preset has no damage model; set damage = true to use the constants"
            };
            return Err(c.conflict(&[&key(field), &key("damage")], why));
        }
        return Ok(None);
    }
    let from_preset = preset.map(|d| [d.d1, d.d2, d.d3, d.d4, d.d5, d.spall_stress, d.eps_f_min]);
    let mut v = [0.0; 7];
    for (i, (field, value)) in given.iter().enumerate() {
        v[i] = value.or(from_preset.map(|p| p[i])).ok_or_else(|| {
            c.missing(
                &key(field),
                format!(
                    "required with damage = true: preset \"{}\" has no damage constants",
                    m.preset
                ),
            )
        })?;
    }
    let [d1, d2, d3, d4, d5, spall_stress, eps_f_min] = v;
    c.positive(
        &key("spall_stress"),
        spall_stress,
        "Pa, tensile mean stress",
    )?;
    c.positive(&key("eps_f_min"), eps_f_min, "-")?;
    Ok(Some(JcDamage {
        d1: d1 as f32,
        d2: d2 as f32,
        d3: d3 as f32,
        d4: d4 as f32,
        d5: d5 as f32,
        spall_stress: spall_stress as f32,
        eps_f_min: eps_f_min as f32,
    }))
}

fn resolve_target(
    c: &Check,
    t: &RawTarget,
    projectile: &ProjectileSpec,
) -> Result<TargetSpec, SceneError> {
    let radius = c.positive("target.radius", t.radius, "m")?;
    let thickness = c.positive("target.thickness", t.thickness, "m")?;
    let spacing = c.positive("target.spacing", t.spacing, "m")?;
    let fc = c.positive("target.fc", t.fc, "Pa")?;
    let density = c.require(
        (1000.0..=5000.0).contains(&t.density),
        "target.density",
        t.density,
        "must be in [1000, 5000] (kg/m³): concrete lies between lightweight concrete's ≈ 1400 \
         and heavyweight concrete's ≈ 4000",
    )?;
    c.require(
        spacing <= projectile.diameter / 2.0,
        "target.spacing",
        spacing,
        &format!(
            "must be ≤ projectile.diameter/2 = {} m (at least one particle per projectile radius)",
            approx(projectile.diameter / 2.0)
        ),
    )?;
    for (key, size) in [("target.radius", radius), ("target.thickness", thickness)] {
        c.require(
            size >= 4.0 * spacing,
            key,
            size,
            &format!(
                "must be ≥ 4·target.spacing = {} m (at least 4 particles across)",
                approx(4.0 * spacing)
            ),
        )?;
    }
    let smoothing_ratio = t.smoothing_ratio.unwrap_or(1.5);
    c.require(
        (1.0..=3.0).contains(&smoothing_ratio),
        "target.smoothing_ratio",
        smoothing_ratio,
        "must be in [1, 3]: h/Δ (physics.md §3 suggests 1.2-2)",
    )?;
    // Monaghan–Gingold defaults α = 1, β = 2 (physics.md §3).
    let viscosity_alpha = c.non_negative(
        "target.viscosity_alpha",
        t.viscosity_alpha.unwrap_or(1.0),
        "-",
    )?;
    let viscosity_beta = c.non_negative(
        "target.viscosity_beta",
        t.viscosity_beta.unwrap_or(2.0),
        "-",
    )?;
    let viscosity_switch = match t.viscosity_switch.as_deref() {
        None => ViscositySwitch::None,
        Some(name) => match c.choice("target.viscosity_switch", name, &["none", "balsara"])? {
            "none" => ViscositySwitch::None,
            _ => ViscositySwitch::Balsara,
        },
    };
    let velocity_filter = match t.velocity_filter.as_deref() {
        None => VelocityFilter::None,
        Some(name) => match c.choice("target.velocity_filter", name, &["none", "linear"])? {
            "none" => VelocityFilter::None,
            _ => VelocityFilter::Linear,
        },
    };
    let velocity_gradient = match t.velocity_gradient.as_deref() {
        None => VelocityGradient::Conjugate,
        Some(name) => match c.choice(
            "target.velocity_gradient",
            name,
            &["corrected", "conjugate"],
        )? {
            "corrected" => VelocityGradient::Corrected,
            _ => VelocityGradient::Conjugate,
        },
    };
    // The filter fits a linear field with the corrected gradient and moves the velocities off
    // the particles' own: the conjugate rate is the forces' only for the particles' own.
    if velocity_gradient == VelocityGradient::Conjugate && velocity_filter == VelocityFilter::Linear
    {
        return Err(c.conflict(
            &["target.velocity_gradient", "target.velocity_filter"],
            "the conjugate gradient (the default) takes the particles' own velocities: \
             set target.velocity_filter = \"none\", or target.velocity_gradient = \
             \"corrected\" to filter",
        ));
    }
    c.require(
        (5.0e6..=200.0e6).contains(&fc),
        "target.fc",
        fc,
        "must be in [5e6, 200e6] (Pa): the f_c rule of physics.md §3.1 is for normal to \
         high-strength concrete",
    )?;
    let lead_hole_depth = c.non_negative(
        "target.lead_hole_depth",
        t.lead_hole_depth.unwrap_or(0.0),
        "m",
    )?;
    c.require(
        lead_hole_depth <= thickness - 4.0 * spacing,
        "target.lead_hole_depth",
        lead_hole_depth,
        &format!(
            "must be ≤ target.thickness − 4·target.spacing = {} m (at least 4 particles below \
             the hole)",
            approx(thickness - 4.0 * spacing)
        ),
    )?;
    let lead_hole_diameter = c.positive(
        "target.lead_hole_diameter",
        t.lead_hole_diameter.unwrap_or(projectile.diameter),
        "m",
    )?;
    // Checked only where there is a hole. A hole narrower than the projectile is a pilot
    // hole: the nose starts at the face (resolve, `projectile.nose_z`).
    c.require(
        lead_hole_depth == 0.0 || lead_hole_diameter <= 2.0 * (radius - 4.0 * spacing),
        "target.lead_hole_diameter",
        lead_hole_diameter,
        &format!(
            "must be at most 2·(target.radius − 4·target.spacing) = {} m: the wall round the \
             hole must hold 4 particles",
            approx(2.0 * (radius - 4.0 * spacing))
        ),
    )?;
    Ok(TargetSpec {
        radius,
        thickness,
        spacing,
        smoothing_ratio,
        fix_rear: t.fix_rear.unwrap_or(false),
        fix_lateral: t.fix_lateral.unwrap_or(false),
        artificial_stress: t.artificial_stress.unwrap_or(false),
        viscosity_alpha,
        viscosity_beta,
        viscosity_switch,
        velocity_filter,
        velocity_gradient,
        lead_hole_depth,
        lead_hole_diameter,
        concrete: resolve_hjc(c, fc, density, t.concrete.as_ref())?,
    })
}

/// HJC from the §3.1 rule, then the scene's explicit constants, then the checks.
fn resolve_hjc(c: &Check, fc: f64, density: f64, raw: Option<&RawHjc>) -> Result<Hjc, SceneError> {
    let mut h = Hjc::from_fc(fc as f32, density as f32);
    let none = RawHjc::default();
    let raw = raw.unwrap_or(&none);
    override_fields!(h, raw, |v: f64| v as f32;
        shear_modulus, a, b, n, c, s_max, t, eps_rate_ref, ef_min, d1, d2, p_crush, mu_crush,
        k1, k2, k3, p_lock, mu_lock);
    let key = |field: &str| format!("target.concrete.{field}");
    let f = f64::from;
    c.positive(&key("shear_modulus"), f(h.shear_modulus), "Pa")?;
    c.non_negative(&key("a"), f(h.a), "-")?;
    c.non_negative(&key("b"), f(h.b), "-")?;
    c.positive(&key("n"), f(h.n), "-")?;
    c.non_negative(&key("c"), f(h.c), "-")?;
    c.positive(&key("s_max"), f(h.s_max), "-, normalised by f_c")?;
    c.require(
        h.t > 0.0 && h.t < h.fc,
        &key("t"),
        f(h.t),
        &format!(
            "must be in (0, target.fc = {}) (Pa): concrete's tensile strength is about a tenth \
             of its compressive strength",
            num(h.fc)
        ),
    )?;
    c.positive(&key("eps_rate_ref"), f(h.eps_rate_ref), "1/s")?;
    c.positive(&key("ef_min"), f(h.ef_min), "-")?;
    c.non_negative(&key("d1"), f(h.d1), "-")?;
    c.positive(&key("k1"), f(h.k1), "Pa")?;
    c.positive(&key("p_crush"), f(h.p_crush), "Pa")?;
    c.positive(&key("mu_crush"), f(h.mu_crush), "-")?;
    c.require(
        h.p_lock > h.p_crush,
        &key("p_lock"),
        f(h.p_lock),
        &format!(
            "must be > target.concrete.p_crush = {} (Pa; f_c/3 unless set)",
            approx(f(h.p_crush))
        ),
    )?;
    c.require(
        h.mu_lock > h.mu_crush,
        &key("mu_lock"),
        f(h.mu_lock),
        &format!(
            "must be > target.concrete.mu_crush = {} (P_crush/K_el unless set; mu_lock is \
             {}/target.density - 1 unless set, so a target as dense as the grains needs it set)",
            approx(f(h.mu_crush)),
            crate::materials::hjc::GRAIN_DENSITY
        ),
    )?;
    if let Some(why) = crate::materials::hjc::dense_curve_fault(&h) {
        return Err(c.conflict(&[&key("k1"), &key("k2"), &key("k3"), &key("p_lock")], &why));
    }
    Ok(h)
}

// ---------------------------------------------------------------------------------------------
// The resolved table (`penetrate check`)
// ---------------------------------------------------------------------------------------------

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

/// Collects `key = value  # unit` lines.
struct Lines(String);

impl Lines {
    fn line(&mut self, key: &str, value: impl Display, unit: &str) {
        // Writing to a String cannot fail.
        let _ = writeln!(self.0, "{key} = {value}  # {unit}");
    }

    fn text(&mut self, key: &str, value: &str, unit: &str) {
        self.line(key, Value::String(value.into()), unit);
    }
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

    /// Every resolved value, one `dotted.key = value  # unit` line each, under the same dotted
    /// names `--set` takes; passing the lines back as overrides reproduces the scene.
    pub fn resolved_table(&self) -> String {
        let mut out = Lines(String::new());
        out.text("name", &self.name, "-");

        let r = &self.run;
        out.line("run.end_time", num(r.end_time), "s");
        out.line("run.cfl", num(r.cfl), "-");
        out.line("run.output_interval", num(r.output_interval), "s");
        out.line("run.history_interval", num(r.history_interval), "s");
        out.text(
            "run.backend",
            r.backend.name(),
            "\"cpu\" | \"gpu\" | \"auto\"",
        );
        out.line("run.max_steps", r.max_steps, "steps");
        out.line("run.stop_at_rest", r.stop_at_rest, "true | false");

        let p = &self.projectile;
        match p.shape {
            ProjectileShape::Ogive { crh } => {
                out.text("projectile.shape", "ogive", "\"ogive\" | \"cylinder\"");
                out.line("projectile.crh", num(crh), "calibres");
            }
            ProjectileShape::Cylinder => {
                out.text("projectile.shape", "cylinder", "\"ogive\" | \"cylinder\"")
            }
        }
        out.line("projectile.diameter", num(p.diameter), "m");
        out.line("projectile.length", num(p.length), "m");
        out.line("projectile.element_size", num(p.element_size), "m");
        out.line("projectile.velocity", num(p.velocity), "m/s");
        out.line("projectile.nose_z", num(p.nose_z), "m");
        if let Some(cav) = &p.cavity {
            out.line("projectile.cavity.diameter", num(cav.diameter), "m");
            out.line("projectile.cavity.length", num(cav.length), "m");
            out.line("projectile.cavity.rear_wall", num(cav.rear_wall), "m");
            let filler = num(cav.filler_density);
            out.line("projectile.cavity.filler_density", filler, "kg/m³");
        }

        let m = &p.material;
        let mat = |field: &str| format!("projectile.material.{field}");
        out.text(&mat("preset"), &m.preset, &PRESETS.join(" | "));
        out.line(&mat("density"), num(m.density), "kg/m³");
        out.line(&mat("youngs_modulus"), num(m.youngs_modulus), "Pa");
        out.line(&mat("poisson_ratio"), num(m.poisson_ratio), "-");
        out.line(&mat("specific_heat"), num(m.specific_heat), "J/(kg K)");
        out.line(&mat("taylor_quinney"), num(m.taylor_quinney), "-");
        let s = &m.strength;
        out.line(&mat("t_room"), num(s.t_room), "K");
        out.line(&mat("t_melt"), num(s.t_melt), "K");
        match &s.law {
            FlowLaw::JohnsonCook => {
                out.line(&mat("jc_a"), num(s.a), "Pa");
                out.line(&mat("jc_b"), num(s.b), "Pa");
                out.line(&mat("jc_n"), num(s.n), "-");
                out.line(&mat("jc_c"), num(s.c), "-");
                out.line(&mat("jc_m"), num(s.m), "-");
            }
            FlowLaw::ZerilliArmstrongFcc(z) => {
                out.line(&mat("za_c0"), num(z.c0), "Pa");
                out.line(&mat("za_c2"), num(z.c2), "Pa");
                out.line(&mat("za_c3"), num(z.c3), "1/K");
                out.line(&mat("za_c4"), num(z.c4), "1/K");
            }
        }
        out.line(&mat("eps_rate_ref"), num(s.eps_rate_ref), "1/s");
        out.line(&mat("eos_k1"), num(m.eos.k1), "Pa");
        out.line(&mat("eos_k2"), num(m.eos.k2), "Pa");
        out.line(&mat("eos_k3"), num(m.eos.k3), "Pa");
        out.line(&mat("eos_gamma"), num(m.eos.gamma), "-");
        out.line(&mat("damage"), m.damage.is_some(), "true | false");
        if let Some(d) = &m.damage {
            for (field, value) in [
                ("d1", d.d1),
                ("d2", d.d2),
                ("d3", d.d3),
                ("d4", d.d4),
                ("d5", d.d5),
            ] {
                out.line(&mat(field), num(value), "-");
            }
            out.line(&mat("spall_stress"), num(d.spall_stress), "Pa");
            out.line(&mat("eps_f_min"), num(d.eps_f_min), "-");
        }

        if let Some(t) = &self.target {
            out.line("target.radius", num(t.radius), "m");
            out.line("target.thickness", num(t.thickness), "m");
            out.line("target.spacing", num(t.spacing), "m");
            out.line("target.fc", num(t.concrete.fc), "Pa");
            out.line("target.density", num(t.concrete.density), "kg/m³");
            out.line(
                "target.smoothing_ratio",
                num(t.smoothing_ratio),
                "h/spacing",
            );
            out.line("target.fix_rear", t.fix_rear, "true | false");
            out.line("target.fix_lateral", t.fix_lateral, "true | false");
            out.line(
                "target.artificial_stress",
                t.artificial_stress,
                "true | false",
            );
            out.line("target.viscosity_alpha", num(t.viscosity_alpha), "-");
            out.line("target.viscosity_beta", num(t.viscosity_beta), "-");
            out.text(
                "target.viscosity_switch",
                t.viscosity_switch.name(),
                "\"none\" | \"balsara\"",
            );
            out.text(
                "target.velocity_filter",
                t.velocity_filter.name(),
                "\"none\" | \"linear\"",
            );
            out.text(
                "target.velocity_gradient",
                t.velocity_gradient.name(),
                "\"corrected\" | \"conjugate\"",
            );
            out.line("target.lead_hole_depth", num(t.lead_hole_depth), "m");
            out.line("target.lead_hole_diameter", num(t.lead_hole_diameter), "m");
            let h = &t.concrete;
            for (field, value, unit) in [
                ("shear_modulus", h.shear_modulus, "Pa"),
                ("a", h.a, "-"),
                ("b", h.b, "-"),
                ("n", h.n, "-"),
                ("c", h.c, "-"),
                ("s_max", h.s_max, "-"),
                ("t", h.t, "Pa"),
                ("eps_rate_ref", h.eps_rate_ref, "1/s"),
                ("ef_min", h.ef_min, "-"),
                ("d1", h.d1, "-"),
                ("d2", h.d2, "-"),
                ("p_crush", h.p_crush, "Pa"),
                ("mu_crush", h.mu_crush, "-"),
                ("k1", h.k1, "Pa"),
                ("k2", h.k2, "Pa"),
                ("k3", h.k3, "Pa"),
                ("p_lock", h.p_lock, "Pa"),
                ("mu_lock", h.mu_lock, "-"),
            ] {
                out.line(&format!("target.concrete.{field}"), num(value), unit);
            }
        }

        out.line("contact.lambda", num(self.contact.lambda), "-");
        let k = num(self.contact.slave_radius_factor);
        out.line("contact.slave_radius_factor", k, "-");
        if let Some(w) = &self.wall {
            out.line("wall.z", num(w.z), "m");
        }
        out.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("cases")
            .join(name)
    }

    fn smoke(overrides: &[&str]) -> Result<Scene, SceneError> {
        let sets: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        load(&case("smoke.toml"), &sets)
    }

    fn shipped_cases() -> Vec<PathBuf> {
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
    fn forrestal_cases_follow_the_csv() {
        for (v, fc, thickness) in [
            (277.0, 35.2e6, 0.76),
            (499.0, 33.5e6, 0.76),
            (642.0, 34.7e6, 1.83),
            (800.0, 32.4e6, 1.83),
        ] {
            let s = load(&case(&format!("forrestal1994-{v}.toml")), &[]).unwrap();
            let t = s.target.as_ref().unwrap();
            assert_eq!(s.projectile.velocity, v);
            assert_eq!(t.concrete, Hjc::from_fc(fc as f32, 2370.0));
            assert_eq!(t.thickness, thickness);
            assert_eq!(s.projectile.shape, ProjectileShape::Ogive { crh: 2.0 });
            // Modelled mass: solid outline minus the cavity's steel, plus filler (see the case).
            let cav = s.projectile.cavity.unwrap();
            let cavity_volume = std::f64::consts::PI * 0.25 * cav.diameter.powi(2) * cav.length;
            let mass = 1.004_278_7 - cavity_volume * (7800.0 - cav.filler_density);
            assert!((0.903..0.913).contains(&mass), "{v} m/s: mass {mass}");
        }
    }

    #[test]
    fn ogive_outline_weighs_what_the_cases_assume() {
        // Tangent ogive r(x) = sqrt(R² − (L_n − x)²) − (R − a), x from the tip, then the shank.
        let (d, crh, length, density) = (0.0269_f64, 2.0, 0.2424, 7800.0);
        let (a, big_r) = (0.5 * d, crh * d);
        let nose = ogive_nose_length(d, crh);
        let n = 20_000;
        let nose_volume: f64 = (0..n)
            .map(|i| {
                let x = (i as f64 + 0.5) * nose / n as f64;
                let r = (big_r * big_r - (nose - x).powi(2)).sqrt() - (big_r - a);
                std::f64::consts::PI * r * r * nose / n as f64
            })
            .sum();
        let mass = density * (nose_volume + std::f64::consts::PI * a * a * (length - nose));
        assert!((mass - 1.004_278_7).abs() < 1e-5, "{mass}");
    }

    #[test]
    fn smoke_resolves_presets_and_defaults() {
        let s = smoke(&[]).unwrap();
        assert_eq!(s.name, "smoke");
        let t = s.target.as_ref().unwrap();
        assert_eq!(t.concrete, Hjc::from_fc(35.0e6, 2370.0));
        assert_eq!(s.projectile.nose_z, 0.25 * t.spacing);
        assert_eq!(s.run.history_interval, 2e-5 / 500.0);
        assert_eq!(s.run.backend, Backend::Auto);
        assert_eq!(s.contact.lambda, 0.2);
        assert_eq!(s.contact.slave_radius_factor, 1.5);
        assert_eq!(t.velocity_gradient, VelocityGradient::Conjugate);
        assert_eq!(t.velocity_filter, VelocityFilter::None);
        let steel = &s.projectile.material;
        let a = f64::from(steel.strength.a);
        assert!((a / 1161.0e6 - 1.0).abs() < 0.005, "A(Rc 45) = {a}");
        assert!((f64::from(steel.strength.b) / (0.6439 * a) - 1.0).abs() < 1e-6);
        assert_eq!(steel.strength.n, 0.26);
        assert!(steel.damage.is_some());
    }

    #[test]
    fn lead_hole_moves_the_default_nose_to_its_bottom() {
        let s = smoke(&["target.lead_hole_depth=0.02"]).unwrap();
        let t = s.target.as_ref().unwrap();
        assert_eq!((t.lead_hole_depth, t.lead_hole_diameter), (0.02, 0.02));
        assert_eq!(s.projectile.nose_z, 0.25 * t.spacing - 0.02);
        let s = smoke(&[
            "target.lead_hole_depth=0.02",
            "target.lead_hole_diameter=0.03",
        ])
        .unwrap();
        assert_eq!(s.target.as_ref().unwrap().lead_hole_diameter, 0.03);
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
        expected.projectile.material.strength.a = 1.0e9;
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

    #[test]
    fn resolved_table_read_back_as_overrides_reproduces_every_case() {
        for path in shipped_cases() {
            let scene = load(&path, &[]).unwrap();
            let table = scene.resolved_table();
            let sets: Vec<String> = table
                .lines()
                .map(|line| {
                    let (assignment, _unit) = line.split_once("  # ").expect("unit comment");
                    assignment.replacen(" = ", "=", 1)
                })
                .collect();
            assert!(sets.len() > 30, "{table}");
            let again = load(&path, &sets).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(again, scene, "{path:?}\n{table}");
        }
    }

    #[test]
    fn copper_has_no_damage_and_a_bulk_modulus_eos() {
        let s = load(&case("taylor-copper-190.toml"), &[]).unwrap();
        let cu = &s.projectile.material;
        assert!(cu.damage.is_none());
        assert_eq!(cu.eos.k1, (124.0e9 / (3.0 * (1.0 - 2.0 * 0.34))) as f32);
        assert_eq!(s.projectile.nose_z, WALL_GAP);
        assert_eq!(s.projectile.shape, ProjectileShape::Cylinder);

        let sets: Vec<String> = [
            "damage=true",
            "d1=0.54",
            "d2=4.89",
            "d3=-3.03",
            "d4=0.014",
            "d5=1.12",
            "spall_stress=1.5e9",
            "eps_f_min=0.1",
        ]
        .iter()
        .map(|s| format!("projectile.material.{s}"))
        .collect();
        let with = load(&case("taylor-copper-190.toml"), &sets).unwrap();
        assert_eq!(with.projectile.material.damage.unwrap().d2, 4.89);
    }

    #[test]
    fn taylor_4340_overrides_density_and_room_temperature() {
        let s = load(&case("taylor-4340-208.toml"), &[]).unwrap();
        let m = &s.projectile.material;
        assert_eq!(m.density, 7830.0);
        assert_eq!(m.strength.t_room, 295.0);
        assert_eq!(m.strength.a, 792.0e6);
        assert_eq!(s.wall, Some(WallSpec { z: 0.0 }));
    }
}
