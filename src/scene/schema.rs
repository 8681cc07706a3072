//! The scene schema: one declaration per key. Parsing (`parse.rs`), the single-key bounds
//! checks (`resolve.rs` through [`Key::check`]), the lines of `Scene::resolved_table` and
//! docs/scene-reference.md all come from the [`KEYS`] below; checks that involve several keys
//! stay code in `resolve.rs`.

use crate::materials::flow::{FlowLaw, Strength};
use crate::materials::hjc::Hjc;
use crate::materials::johnson_cook::{JcDamage, JcFlow};
use crate::materials::presets::PRESETS;
use crate::materials::zerilli_armstrong::ZaFcc;

use super::{CavitySpec, ProjectileShape, Scene, SteelMaterial, TargetSpec};

/// What a key's value is written as.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ty {
    /// A finite number within f32's range (an integer is read as the float it is).
    Number,
    /// A whole number ≥ 0, also written as a float up to 2⁵³ (`5e6`).
    Count,
    /// `true` or `false`.
    Flag,
    /// Any string.
    Text,
    /// One of `names`; `quoted`: the resolved table's comment quotes them (the preset names
    /// have always been listed bare there).
    Choice {
        names: &'static [&'static str],
        quoted: bool,
    },
}

/// The value a key takes when the scene leaves it out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DefaultValue {
    /// No default: the scene must give it (when its table is there).
    Required,
    /// This number.
    Number(f64),
    /// This count.
    Count(u64),
    /// This flag.
    Flag(bool),
    /// This name.
    Text(&'static str),
    /// Derived from other keys or a preset, as the words say (resolve computes it).
    Derived(&'static str),
}

/// The values a key accepts on its own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bounds {
    /// Any value of its type.
    None,
    /// An interval the schema checks: `> 0`, `≥ 1`, `(0, 1]`, `[5e6, 200e6]`.
    Range(&'static str),
    /// A rule involving other keys, in words: resolve checks it.
    Rule(&'static str),
}

/// How a key's resolved value is written in the resolved table.
#[derive(Clone, Debug, PartialEq)]
pub enum Shown {
    /// An f64, in [`super::num`]'s form.
    Number(f64),
    /// An f32 the solver holds, in its own shortest form.
    Single(f32),
    /// A count.
    Count(u64),
    /// A flag.
    Flag(bool),
    /// A string, TOML-quoted.
    Text(String),
}

/// One scene key.
pub struct Key {
    /// The dotted path, as `--set` and the resolved table write it.
    pub path: &'static str,
    /// What the value is written as.
    pub ty: Ty,
    /// SI unit (`-`: dimensionless).
    pub unit: &'static str,
    /// Its value when left out.
    pub default: DefaultValue,
    /// The values it accepts on its own.
    pub bounds: Bounds,
    /// The rest of the out-of-bounds message after `must be in [a, b]`; empty on a bound at 0
    /// (`> 0`, `≥ 0`) means ` (unit)`.
    pub why: &'static str,
    /// One line for the reference.
    pub help: &'static str,
    /// The resolved value read back from a scene; `None` where the scene has no such value (a
    /// cylinder's crh, the other flow law's constants, a table the scene lacks).
    pub show: fn(&Scene) -> Option<Shown>,
}

impl Key {
    /// What every declaration starts from.
    const BASE: Key = Key {
        path: "",
        ty: Ty::Number,
        unit: "-",
        default: DefaultValue::Required,
        bounds: Bounds::None,
        why: "",
        help: "",
        show: |_| None,
    };

    /// The interval of [`Bounds::Range`], parsed.
    pub fn interval(&self) -> Option<Interval> {
        match self.bounds {
            Bounds::Range(text) => Interval::parse(text),
            _ => None,
        }
    }

    /// The message for a value outside [`Bounds::Range`]: `must be in (0, 1]: why`.
    pub fn bound_message(&self) -> String {
        let text = match self.bounds {
            Bounds::Range(t) | Bounds::Rule(t) => t,
            Bounds::None => "",
        };
        let lead = if text.starts_with(['[', '(']) {
            "in "
        } else {
            ""
        };
        let why = if self.why.is_empty() && matches!(text, "> 0" | "≥ 0") {
            format!(" ({})", self.unit)
        } else {
            self.why.to_string()
        };
        format!("must be {lead}{text}{why}")
    }

    /// The comment of its line in the resolved table: the unit, or the values a flag or a
    /// choice takes.
    pub fn table_unit(&self) -> String {
        match self.ty {
            Ty::Flag => "true | false".into(),
            Ty::Choice { names, quoted } => {
                let names: Vec<String> = names
                    .iter()
                    .map(|n| {
                        if quoted {
                            format!("\"{n}\"")
                        } else {
                            n.to_string()
                        }
                    })
                    .collect();
                names.join(" | ")
            }
            _ => self.unit.into(),
        }
    }

    /// The table the key is in (`""`: the top level).
    pub fn table(&self) -> &'static str {
        self.path.rsplit_once('.').map_or("", |(t, _)| t)
    }
}

/// A bound parsed from its text: `> 0`, `≥ 1`, `(0, 1]`, `[5e6, 200e6]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    lo: f64,
    lo_closed: bool,
    hi: f64,
    hi_closed: bool,
}

impl Interval {
    fn parse(text: &str) -> Option<Interval> {
        let number = |s: &str| s.trim().parse::<f64>().ok();
        if let Some(lo) = text.strip_prefix("> ") {
            return Some(Interval::above(number(lo)?, false));
        }
        if let Some(lo) = text.strip_prefix("≥ ") {
            return Some(Interval::above(number(lo)?, true));
        }
        let lo_closed = match text.chars().next()? {
            '[' => true,
            '(' => false,
            _ => return None,
        };
        let hi_closed = match text.chars().last()? {
            ']' => true,
            ')' => false,
            _ => return None,
        };
        let (lo, hi) = text[1..text.len() - 1].split_once(',')?;
        Some(Interval {
            lo: number(lo)?,
            lo_closed,
            hi: number(hi)?,
            hi_closed,
        })
    }

    fn above(lo: f64, lo_closed: bool) -> Interval {
        Interval {
            lo,
            lo_closed,
            hi: f64::INFINITY,
            hi_closed: true,
        }
    }

    /// Whether `x` lies in the interval.
    pub fn contains(&self, x: f64) -> bool {
        let above = if self.lo_closed {
            x >= self.lo
        } else {
            x > self.lo
        };
        let below = if self.hi_closed {
            x <= self.hi
        } else {
            x < self.hi
        };
        above && below
    }
}

/// Whether a table must be there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Need {
    /// The scene must have it.
    Required,
    /// Left out, its keys take their defaults.
    Optional,
    /// Its presence makes the scene what it is (a wall scene, a hollow projectile): `--set`
    /// may set keys in it only when the file has it.
    Selects,
}

/// One table of the scene file.
pub struct TableDecl {
    /// Dotted path (`""`: the top level).
    pub path: &'static str,
    /// Whether the scene must have it.
    pub need: Need,
    /// One line for the reference.
    pub help: &'static str,
}

/// Every table, in the order of [`KEYS`].
pub static TABLES: &[TableDecl] = &[
    TableDecl {
        path: "",
        need: Need::Required,
        help: "The top level of the file.",
    },
    TableDecl {
        path: "run",
        need: Need::Required,
        help: "Run control.",
    },
    TableDecl {
        path: "projectile",
        need: Need::Required,
        help: "The projectile's outline, mesh and striking speed.",
    },
    TableDecl {
        path: "projectile.cavity",
        need: Need::Selects,
        help: "A coaxial cavity in the shank with an inert filler (a hollow projectile).",
    },
    TableDecl {
        path: "projectile.material",
        need: Need::Required,
        help: "The projectile's metal: a preset, then any of its constants.",
    },
    TableDecl {
        path: "target",
        need: Need::Selects,
        help: "A concrete cylinder, axis r = 0, front face z = 0 (penetration scenes; a scene \
               has exactly one of [target] and [wall]).",
    },
    TableDecl {
        path: "target.concrete",
        need: Need::Optional,
        help: "Overrides of the HJC constants that the rule of physics.md §3.1 derives from \
               target.fc and target.density.",
    },
    TableDecl {
        path: "contact",
        need: Need::Optional,
        help: "The FEM–SPH contact.",
    },
    TableDecl {
        path: "wall",
        need: Need::Selects,
        help: "A rigid wall, the plane z = wall.z (Taylor-bar scenes, instead of [target]).",
    },
];

/// The key at `path`.
pub fn key(path: &str) -> Option<&'static Key> {
    KEYS.iter().copied().find(|k| k.path == path)
}

/// The table at `path`.
pub fn table(path: &str) -> Option<&'static TableDecl> {
    TABLES.iter().find(|t| t.path == path)
}

/// The names a table holds, keys and tables, in schema order.
pub fn members(table: &str) -> Vec<&'static str> {
    let mut names: Vec<&'static str> = Vec::new();
    for k in KEYS {
        let rest = if table.is_empty() {
            Some(k.path)
        } else {
            k.path.strip_prefix(table).and_then(|r| r.strip_prefix('.'))
        };
        if let Some(name) = rest.map(|r| r.split('.').next().unwrap_or(r)) {
            if !names.contains(&name) {
                names.push(name);
            }
        }
    }
    names
}

// Readers of a resolved scene for `show`.

fn steel(s: &Scene) -> &SteelMaterial {
    &s.projectile.material
}

fn strength(s: &Scene, f: fn(&Strength) -> f32) -> Option<Shown> {
    Some(Shown::Single(f(&steel(s).strength)))
}

fn jc(s: &Scene, f: fn(&JcFlow) -> f32) -> Option<Shown> {
    steel(s)
        .strength
        .johnson_cook()
        .map(|j| Shown::Single(f(j)))
}

fn za(s: &Scene, f: fn(&ZaFcc) -> f32) -> Option<Shown> {
    match &steel(s).strength.law {
        FlowLaw::ZerilliArmstrongFcc(z) => Some(Shown::Single(f(z))),
        FlowLaw::JohnsonCook(_) => None,
    }
}

fn damage(s: &Scene, f: fn(&JcDamage) -> f32) -> Option<Shown> {
    steel(s).damage.as_ref().map(|d| Shown::Single(f(d)))
}

fn cavity(s: &Scene, f: fn(&CavitySpec) -> f64) -> Option<Shown> {
    s.projectile.cavity.as_ref().map(|c| Shown::Number(f(c)))
}

fn target(s: &Scene, f: fn(&TargetSpec) -> Shown) -> Option<Shown> {
    s.target.as_ref().map(f)
}

fn concrete(s: &Scene, f: fn(&Hjc) -> f32) -> Option<Shown> {
    s.target.as_ref().map(|t| Shown::Single(f(&t.concrete)))
}

fn number(x: f64) -> Option<Shown> {
    Some(Shown::Number(x))
}

/// Declares each key as a `const` and lists them all in [`KEYS`]; a field left out takes
/// [`Key::BASE`]'s value.
macro_rules! schema {
    ($($name:ident = $path:literal { $($field:ident: $value:expr),+ $(,)? })+) => {
        $(
            #[doc = concat!("`", $path, "`")]
            pub const $name: Key = Key { path: $path, $($field: $value,)+ ..Key::BASE };
        )+
        /// Every key, in the order the resolved table lists them.
        pub static KEYS: &[&Key] = &[$(&$name),+];
    };
}

use Bounds::{Range, Rule};
use DefaultValue::Derived;
use Shown::{Single, Text};

const FLAG: Ty = Ty::Flag;
const PRESET: &str = "the preset's";
const HJC_RULE: &str = "from target.fc by the HJC rule";

schema! {
    NAME = "name" { ty: Ty::Text, default: Derived("the file stem"),
        help: "Scene name, in the outputs and reports", show: |s| Some(Text(s.name.clone())) }

    RUN_END_TIME = "run.end_time" { unit: "s", bounds: Range("> 0"),
        help: "Simulated time at which the run stops", show: |s| number(s.run.end_time) }
    RUN_CFL = "run.cfl" { default: DefaultValue::Number(0.5), bounds: Range("(0, 1]"),
        why: ": the Courant number of an explicit step",
        help: "Courant number applied to the smallest element and particle step",
        show: |s| number(s.run.cfl) }
    RUN_OUTPUT_INTERVAL = "run.output_interval" { unit: "s", default: DefaultValue::Number(0.0),
        bounds: Range("≥ 0"), why: " (s; 0 writes the first and last frame only)",
        help: "Interval between VTK frames; 0 writes only the first and last frame",
        show: |s| number(s.run.output_interval) }
    RUN_HISTORY_INTERVAL = "run.history_interval" { unit: "s",
        default: Derived("run.end_time / 500"), bounds: Range("> 0"),
        help: "Interval between history.csv rows", show: |s| number(s.run.history_interval) }
    RUN_BACKEND = "run.backend" {
        ty: Ty::Choice { names: &["cpu", "gpu", "auto"], quoted: true },
        default: DefaultValue::Text("auto"),
        help: "Which implementation runs the step; \"auto\": a real GPU if there is one, else \
               the CPU",
        show: |s| Some(Text(s.run.backend.name().into())) }
    RUN_MAX_STEPS = "run.max_steps" { ty: Ty::Count, unit: "steps",
        default: DefaultValue::Count(5_000_000), bounds: Range("≥ 1"),
        help: "Hard cap on the number of steps (a guard against a collapsing time step)",
        show: |s| Some(Shown::Count(s.run.max_steps)) }
    RUN_STOP_AT_REST = "run.stop_at_rest" { ty: FLAG, default: DefaultValue::Flag(true),
        help: "Stop when the projectile has come to rest or has left the target",
        show: |s| Some(Shown::Flag(s.run.stop_at_rest)) }

    SHAPE = "projectile.shape" {
        ty: Ty::Choice { names: &["ogive", "cylinder"], quoted: true },
        help: "Outline: a tangent-ogive nose on a cylindrical shank, or a flat-ended cylinder \
               (Taylor bar)",
        show: |s| Some(Text(match s.projectile.shape {
            ProjectileShape::Ogive { .. } => "ogive".into(),
            ProjectileShape::Cylinder => "cylinder".into(),
        })) }
    CRH = "projectile.crh" { unit: "calibres",
        default: Derived("required for shape = \"ogive\", refused for a cylinder"),
        bounds: Range("≥ 0.5"), why: " (0.5 is a hemispherical nose)",
        help: "Calibre-radius-head of the ogive nose",
        show: |s| match s.projectile.shape {
            ProjectileShape::Ogive { crh } => number(crh),
            ProjectileShape::Cylinder => None,
        } }
    DIAMETER = "projectile.diameter" { unit: "m", bounds: Range("> 0"),
        help: "Shank diameter", show: |s| number(s.projectile.diameter) }
    LENGTH = "projectile.length" { unit: "m", bounds: Range("> 0"),
        help: "Overall length, nose tip to tail; at least the nose plus one element",
        show: |s| number(s.projectile.length) }
    ELEMENT_SIZE = "projectile.element_size" { unit: "m", bounds: Range("> 0"),
        help: "Target element size of the projectile mesh; at most diameter/4",
        show: |s| number(s.projectile.element_size) }
    CELL_PRESSURE = "projectile.cell_pressure" { ty: FLAG, default: DefaultValue::Flag(true),
        help: "One pressure for the four triangles of each mesh cell (physics.md §2.4); \
               false: each triangle the pressure of its own volume, which checkerboards",
        show: |s| Some(Shown::Flag(s.projectile.cell_pressure)) }
    VELOCITY = "projectile.velocity" { unit: "m/s", bounds: Range("[0, 5000]"),
        why: " (m/s): the striking speed, not negative (flight is along −z); the material models \
              are not meant beyond 5 km/s",
        help: "Striking speed (the projectile flies along −z); below its elastic wave speed",
        show: |s| number(s.projectile.velocity) }
    NOSE_Z = "projectile.nose_z" { unit: "m",
        default: Derived("target.spacing/4 above the face or the lead hole's bottom; \
                          wall.z + 1 µm"),
        bounds: Rule("[−target.lead_hole_depth, 1] (the face at 0), or [wall.z, wall.z + 1]"),
        help: "Initial z of the nose tip; the target's front face is z = 0",
        show: |s| number(s.projectile.nose_z) }

    CAVITY_DIAMETER = "projectile.cavity.diameter" { unit: "m", bounds: Range("> 0"),
        help: "Cavity diameter; the wall round it keeps at least one element",
        show: |s| cavity(s, |c| c.diameter) }
    CAVITY_LENGTH = "projectile.cavity.length" { unit: "m", bounds: Range("> 0"),
        help: "Cavity length; with rear_wall, shorter than the shank",
        show: |s| cavity(s, |c| c.length) }
    CAVITY_REAR_WALL = "projectile.cavity.rear_wall" { unit: "m", bounds: Range("> 0"),
        help: "Thickness of the steel plug between the cavity and the tail face",
        show: |s| cavity(s, |c| c.rear_wall) }
    CAVITY_FILLER_DENSITY = "projectile.cavity.filler_density" { unit: "kg/m³",
        default: DefaultValue::Number(0.0), bounds: Range("[0, 23000]"),
        why: " (kg/m³; 0 = empty): no solid is denser than osmium's 22590",
        help: "Filler density, its mass lumped on the cavity wall nodes; 0 = empty",
        show: |s| cavity(s, |c| c.filler_density) }

    PRESET_NAME = "projectile.material.preset" {
        ty: Ty::Choice { names: &PRESETS, quoted: false },
        help: "The preset the constants start from (src/materials/presets.rs)",
        show: |s| Some(Text(steel(s).preset.clone())) }
    DENSITY = "projectile.material.density" { unit: "kg/m³", default: Derived(PRESET),
        bounds: Range("[500, 23000]"),
        why: " (kg/m³): solid metals lie between lithium's 534 and osmium's 22590",
        help: "Density", show: |s| number(steel(s).density) }
    YOUNGS_MODULUS = "projectile.material.youngs_modulus" { unit: "Pa", default: Derived(PRESET),
        bounds: Range("(0, 1.2e12]"),
        why: " (Pa): no solid is stiffer than diamond (about 1.1e12 Pa; the stiffest metal, \
              iridium, has 5.3e11)",
        help: "Young's modulus E", show: |s| number(steel(s).youngs_modulus) }
    POISSON_RATIO = "projectile.material.poisson_ratio" { default: Derived(PRESET),
        bounds: Range("(0, 0.5)"), help: "Poisson's ratio ν",
        show: |s| number(steel(s).poisson_ratio) }
    SPECIFIC_HEAT = "projectile.material.specific_heat" { unit: "J/(kg K)",
        default: Derived(PRESET), bounds: Range("[100, 4000]"),
        why: " (J/(kg K)): solid metals lie between about 130 (lead, gold, tungsten) and 3600 \
              (lithium)",
        help: "Specific heat", show: |s| number(steel(s).specific_heat) }
    TAYLOR_QUINNEY = "projectile.material.taylor_quinney" { default: Derived(PRESET),
        bounds: Range("[0, 1]"), why: ": the share of plastic work turned into heat",
        help: "Taylor–Quinney β: the share of plastic work that heats the metal",
        show: |s| number(steel(s).taylor_quinney) }
    T_ROOM = "projectile.material.t_room" { unit: "K", default: Derived(PRESET),
        bounds: Range("> 0"), help: "Room (initial) temperature",
        show: |s| strength(s, |st| st.t_room) }
    T_MELT = "projectile.material.t_melt" { unit: "K", default: Derived(PRESET),
        bounds: Rule("> t_room, ≤ 4000"), help: "Melting temperature",
        show: |s| strength(s, |st| st.t_melt) }
    JC_A = "projectile.material.jc_a" { unit: "Pa",
        default: Derived("the preset's (Johnson–Cook presets only)"), bounds: Range("> 0"),
        help: "Johnson–Cook yield stress A; below youngs_modulus", show: |s| jc(s, |st| st.a) }
    JC_B = "projectile.material.jc_b" { unit: "Pa",
        default: Derived("the preset's (Johnson–Cook presets only)"), bounds: Range("≥ 0"),
        help: "Johnson–Cook hardening modulus B; below youngs_modulus",
        show: |s| jc(s, |st| st.b) }
    JC_N = "projectile.material.jc_n" {
        default: Derived("the preset's (Johnson–Cook presets only)"), bounds: Range("(0, 1]"),
        help: "Johnson–Cook hardening exponent n", show: |s| jc(s, |st| st.n) }
    JC_C = "projectile.material.jc_c" {
        default: Derived("the preset's (Johnson–Cook presets only)"), bounds: Range("[0, 1]"),
        why: ": the strain-rate sensitivity of metals is about 0.001 to 0.1 (1 would raise the \
              flow stress twelvefold at 10⁵/s)",
        help: "Johnson–Cook strain-rate sensitivity C", show: |s| jc(s, |st| st.c) }
    JC_M = "projectile.material.jc_m" {
        default: Derived("the preset's (Johnson–Cook presets only)"), bounds: Range("> 0"),
        help: "Johnson–Cook thermal-softening exponent m", show: |s| jc(s, |st| st.m) }
    ZA_C0 = "projectile.material.za_c0" { unit: "Pa",
        default: Derived("the preset's (Zerilli–Armstrong presets only)"), bounds: Range("> 0"),
        help: "Zerilli–Armstrong athermal stress C₀; below youngs_modulus",
        show: |s| za(s, |z| z.c0) }
    ZA_C2 = "projectile.material.za_c2" { unit: "Pa",
        default: Derived("the preset's (Zerilli–Armstrong presets only)"), bounds: Range("≥ 0"),
        help: "Zerilli–Armstrong C₂; below youngs_modulus", show: |s| za(s, |z| z.c2) }
    ZA_C3 = "projectile.material.za_c3" { unit: "1/K",
        default: Derived("the preset's (Zerilli–Armstrong presets only)"),
        bounds: Range("[0, 0.1]"),
        why: " (1/K): copper's are 0.0028 and 0.000115 per kelvin",
        help: "Zerilli–Armstrong C₃", show: |s| za(s, |z| z.c3) }
    ZA_C4 = "projectile.material.za_c4" { unit: "1/K",
        default: Derived("the preset's (Zerilli–Armstrong presets only)"),
        bounds: Range("[0, 0.1]"),
        why: " (1/K): copper's are 0.0028 and 0.000115 per kelvin",
        help: "Zerilli–Armstrong C₄", show: |s| za(s, |z| z.c4) }
    EPS_RATE_REF = "projectile.material.eps_rate_ref" { unit: "1/s", default: Derived(PRESET),
        bounds: Range("> 0"), help: "Reference strain rate of the flow law",
        show: |s| strength(s, |st| st.eps_rate_ref) }
    EOS_K1 = "projectile.material.eos_k1" { unit: "Pa",
        default: Derived("the preset's, or E/(3(1 − 2ν)) (copper)"), bounds: Range("> 0"),
        why: " (Pa) and within the f32 range",
        help: "EOS bulk modulus K₁; within a factor 2 of E/(3(1 − 2ν))",
        show: |s| Some(Single(steel(s).eos.k1)) }
    EOS_K2 = "projectile.material.eos_k2" { unit: "Pa", default: Derived(PRESET),
        help: "EOS K₂ (with K₃, stiffening by at most 100× at μ = 0.1)",
        show: |s| Some(Single(steel(s).eos.k2)) }
    EOS_K3 = "projectile.material.eos_k3" { unit: "Pa", default: Derived(PRESET),
        help: "EOS K₃", show: |s| Some(Single(steel(s).eos.k3)) }
    EOS_GAMMA = "projectile.material.eos_gamma" { default: Derived(PRESET),
        bounds: Range("[0, 5]"),
        why: ": the Grüneisen Γ of solid metals is about 1 to 3, and the stable step leaves out \
              the energy term Γ (E/ρ₀ + p/ρ) of the sound speed",
        help: "Grüneisen Γ", show: |s| Some(Single(steel(s).eos.gamma)) }
    DAMAGE = "projectile.material.damage" { ty: FLAG,
        default: Derived("true if the preset has damage constants"),
        help: "Johnson–Cook damage and spall on or off",
        show: |s| Some(Shown::Flag(steel(s).damage.is_some())) }
    D1 = "projectile.material.d1" { default: Derived(DAMAGE_DEFAULT),
        help: "Johnson–Cook damage D₁", show: |s| damage(s, |d| d.d1) }
    D2 = "projectile.material.d2" { default: Derived(DAMAGE_DEFAULT),
        help: "Johnson–Cook damage D₂", show: |s| damage(s, |d| d.d2) }
    D3 = "projectile.material.d3" { default: Derived(DAMAGE_DEFAULT),
        help: "Johnson–Cook damage D₃", show: |s| damage(s, |d| d.d3) }
    D4 = "projectile.material.d4" { default: Derived(DAMAGE_DEFAULT),
        help: "Johnson–Cook damage D₄", show: |s| damage(s, |d| d.d4) }
    D5 = "projectile.material.d5" { default: Derived(DAMAGE_DEFAULT),
        help: "Johnson–Cook damage D₅", show: |s| damage(s, |d| d.d5) }
    SPALL_STRESS = "projectile.material.spall_stress" { unit: "Pa",
        default: Derived(DAMAGE_DEFAULT), bounds: Range("> 0"),
        why: " (Pa, tensile mean stress)", help: "Tensile mean stress that spalls the metal",
        show: |s| damage(s, |d| d.spall_stress) }
    EPS_F_MIN = "projectile.material.eps_f_min" { default: Derived(DAMAGE_DEFAULT),
        bounds: Range("> 0"), help: "Least failure strain",
        show: |s| damage(s, |d| d.eps_f_min) }

    TARGET_RADIUS = "target.radius" { unit: "m", bounds: Range("> 0"),
        help: "Target radius; at least 4 spacings",
        show: |s| target(s, |t| Shown::Number(t.radius)) }
    TARGET_THICKNESS = "target.thickness" { unit: "m", bounds: Range("> 0"),
        help: "Target thickness; at least 4 spacings",
        show: |s| target(s, |t| Shown::Number(t.thickness)) }
    TARGET_SPACING = "target.spacing" { unit: "m", bounds: Range("> 0"),
        help: "Particle spacing Δ; at most projectile.diameter/2",
        show: |s| target(s, |t| Shown::Number(t.spacing)) }
    TARGET_FC = "target.fc" { unit: "Pa", bounds: Range("[5e6, 200e6]"),
        why: " (Pa): the f_c rule of physics.md §3.1 is for normal to high-strength concrete",
        help: "Unconfined compressive strength f_c, from which the HJC constants follow",
        show: |s| concrete(s, |h| h.fc) }
    TARGET_DENSITY = "target.density" { unit: "kg/m³", bounds: Range("[1000, 5000]"),
        why: " (kg/m³): concrete lies between lightweight concrete's ≈ 1400 and heavyweight \
              concrete's ≈ 4000",
        help: "Concrete density", show: |s| concrete(s, |h| h.density) }
    SMOOTHING_RATIO = "target.smoothing_ratio" { unit: "h/spacing",
        default: DefaultValue::Number(1.5), bounds: Range("[1, 3]"),
        why: ": h/Δ (physics.md §3 suggests 1.2-2)", help: "Smoothing length over spacing, h/Δ",
        show: |s| target(s, |t| Shown::Number(t.smoothing_ratio)) }
    FIX_REAR = "target.fix_rear" { ty: FLAG, default: DefaultValue::Flag(false),
        help: "Fixed (zero-velocity) rear face", show: |s| target(s, |t| Shown::Flag(t.fix_rear)) }
    FIX_LATERAL = "target.fix_lateral" { ty: FLAG, default: DefaultValue::Flag(false),
        help: "Fixed (zero-velocity) lateral surface",
        show: |s| target(s, |t| Shown::Flag(t.fix_lateral)) }
    ARTIFICIAL_STRESS = "target.artificial_stress" { ty: FLAG, default: DefaultValue::Flag(false),
        help: "Gray–Monaghan artificial stress against the tensile instability",
        show: |s| target(s, |t| Shown::Flag(t.artificial_stress)) }
    VISCOSITY_ALPHA = "target.viscosity_alpha" { default: DefaultValue::Number(1.0),
        bounds: Range("≥ 0"), help: "Monaghan–Gingold viscosity α",
        show: |s| target(s, |t| Shown::Number(t.viscosity_alpha)) }
    VISCOSITY_BETA = "target.viscosity_beta" { default: DefaultValue::Number(2.0),
        bounds: Range("≥ 0"), help: "Monaghan–Gingold viscosity β",
        show: |s| target(s, |t| Shown::Number(t.viscosity_beta)) }
    VISCOSITY_SWITCH = "target.viscosity_switch" {
        ty: Ty::Choice { names: &["none", "balsara"], quoted: true },
        default: DefaultValue::Text("none"),
        help: "What scales the viscosity down where the flow shears rather than compresses",
        show: |s| target(s, |t| Text(t.viscosity_switch.name().into())) }
    VISCOSITY_JUMP = "target.viscosity_jump" {
        ty: Ty::Choice { names: &["raw", "reconstructed"], quoted: true },
        default: DefaultValue::Text("raw"),
        help: "Which velocity jump of a pair the viscosity reads: \"raw\" (the pair's own) or \
               \"reconstructed\" (what a limited linear reconstruction leaves at the pair's \
               midpoint: none in a smooth compression); \"reconstructed\" needs \
               velocity_filter = \"none\"",
        show: |s| target(s, |t| Text(t.viscosity_jump.name().into())) }
    VELOCITY_FILTER = "target.velocity_filter" {
        ty: Ty::Choice { names: &["none", "linear"], quoted: true },
        default: DefaultValue::Text("none"),
        help: "Which velocity the concrete's strain rate is taken from; \"linear\" needs \
               velocity_gradient = \"corrected\"",
        show: |s| target(s, |t| Text(t.velocity_filter.name().into())) }
    VELOCITY_GRADIENT = "target.velocity_gradient" {
        ty: Ty::Choice { names: &["corrected", "conjugate"], quoted: true },
        default: DefaultValue::Text("conjugate"),
        help: "Which SPH estimate of the velocity gradient updates the concrete's stress",
        show: |s| target(s, |t| Text(t.velocity_gradient.name().into())) }
    TENSION = "target.tension" {
        ty: Ty::Choice { names: &["crack-band", "static"], quoted: true },
        default: DefaultValue::Text("crack-band"),
        help: "How the concrete fails in tension: \"crack-band\" (rate-dependent strength, \
               softening that spends target.concrete.fracture_energy per crack area) or \
               \"static\" (HJC's cut-off as published)",
        show: |s| target(s, |t| Text(t.tension.name().into())) }
    LEAD_HOLE_DEPTH = "target.lead_hole_depth" { unit: "m", default: DefaultValue::Number(0.0),
        bounds: Range("≥ 0"),
        help: "Depth of a hole drilled along the axis (0: none); leaves 4 spacings below it",
        show: |s| target(s, |t| Shown::Number(t.lead_hole_depth)) }
    LEAD_HOLE_DIAMETER = "target.lead_hole_diameter" { unit: "m",
        default: Derived("projectile.diameter"), bounds: Range("> 0"),
        help: "Diameter of the lead hole; narrower than the projectile: a pilot hole, the nose \
               starts at the face",
        show: |s| target(s, |t| Shown::Number(t.lead_hole_diameter)) }

    HJC_SHEAR_MODULUS = "target.concrete.shear_modulus" { unit: "Pa", default: Derived(HJC_RULE),
        bounds: Range("> 0"), help: "Shear modulus", show: |s| concrete(s, |h| h.shear_modulus) }
    HJC_A = "target.concrete.a" { default: Derived(HJC_RULE), bounds: Range("≥ 0"),
        help: "Normalised cohesive strength A", show: |s| concrete(s, |h| h.a) }
    HJC_B = "target.concrete.b" { default: Derived(HJC_RULE), bounds: Range("≥ 0"),
        help: "Normalised pressure hardening B", show: |s| concrete(s, |h| h.b) }
    HJC_N = "target.concrete.n" { default: Derived(HJC_RULE), bounds: Range("> 0"),
        help: "Pressure hardening exponent N", show: |s| concrete(s, |h| h.n) }
    HJC_C = "target.concrete.c" { default: Derived(HJC_RULE), bounds: Range("≥ 0"),
        help: "Strain-rate coefficient C", show: |s| concrete(s, |h| h.c) }
    HJC_S_MAX = "target.concrete.s_max" { default: Derived(HJC_RULE), bounds: Range("> 0"),
        why: " (-, normalised by f_c)", help: "Normalised maximum strength S_max",
        show: |s| concrete(s, |h| h.s_max) }
    HJC_T = "target.concrete.t" { unit: "Pa", default: Derived(HJC_RULE),
        bounds: Rule("(0, target.fc)"), help: "Tensile strength T",
        show: |s| concrete(s, |h| h.t) }
    HJC_EPS_RATE_REF = "target.concrete.eps_rate_ref" { unit: "1/s", default: Derived(HJC_RULE),
        bounds: Range("> 0"), help: "Reference strain rate",
        show: |s| concrete(s, |h| h.eps_rate_ref) }
    HJC_EF_MIN = "target.concrete.ef_min" { default: Derived(HJC_RULE), bounds: Range("> 0"),
        help: "Least plastic strain to fracture", show: |s| concrete(s, |h| h.ef_min) }
    HJC_D1 = "target.concrete.d1" { default: Derived(HJC_RULE), bounds: Range("≥ 0"),
        help: "Damage constant D₁", show: |s| concrete(s, |h| h.d1) }
    HJC_D2 = "target.concrete.d2" { default: Derived(HJC_RULE),
        help: "Damage constant D₂", show: |s| concrete(s, |h| h.d2) }
    HJC_P_CRUSH = "target.concrete.p_crush" { unit: "Pa", default: Derived(HJC_RULE),
        bounds: Range("> 0"), help: "Crushing pressure (f_c/3 by the rule)",
        show: |s| concrete(s, |h| h.p_crush) }
    HJC_MU_CRUSH = "target.concrete.mu_crush" { default: Derived(HJC_RULE),
        bounds: Range("> 0"), help: "Crushing volumetric strain",
        show: |s| concrete(s, |h| h.mu_crush) }
    HJC_K1 = "target.concrete.k1" { unit: "Pa", default: Derived(HJC_RULE),
        bounds: Range("> 0"), help: "Dense-curve K₁", show: |s| concrete(s, |h| h.k1) }
    HJC_K2 = "target.concrete.k2" { unit: "Pa", default: Derived(HJC_RULE),
        help: "Dense-curve K₂", show: |s| concrete(s, |h| h.k2) }
    HJC_K3 = "target.concrete.k3" { unit: "Pa", default: Derived(HJC_RULE),
        help: "Dense-curve K₃", show: |s| concrete(s, |h| h.k3) }
    HJC_P_LOCK = "target.concrete.p_lock" { unit: "Pa", default: Derived(HJC_RULE),
        bounds: Rule("> target.concrete.p_crush"), help: "Locking pressure",
        show: |s| concrete(s, |h| h.p_lock) }
    HJC_MU_LOCK = "target.concrete.mu_lock" { default: Derived(HJC_RULE),
        bounds: Rule("> target.concrete.mu_crush"),
        help: "Locking volumetric strain (grain density/target.density − 1 by the rule)",
        show: |s| concrete(s, |h| h.mu_lock) }
    HJC_FRACTURE_ENERGY = "target.concrete.fracture_energy" { unit: "J/m²",
        default: Derived("73·f_c[MPa]^0.18 (fib Model Code 2010)"), bounds: Range("> 0"),
        help: "Fracture energy G_f spent per crack area (target.tension = \"crack-band\")",
        show: |s| concrete(s, |h| h.g_f) }

    CONTACT_LAMBDA = "contact.lambda" { default: DefaultValue::Number(0.2), bounds: Range("[0, 1]"),
        why: ": the local share of the momentum transport (0 = rigid projectile)",
        help: "Share λ of a slave's momentum change put on the two nodes it touches \
               (0 = rigid limit)",
        show: |s| number(s.contact.lambda) }
    CONTACT_SLAVE_RADIUS_FACTOR = "contact.slave_radius_factor" {
        default: DefaultValue::Number(1.5), bounds: Range("> 1"),
        why: ": slaves are preselected beyond the projectile's largest radius",
        help: "Slave preselection radius over the projectile's largest radius",
        show: |s| number(s.contact.slave_radius_factor) }
    CONTACT_FRICTION = "contact.friction" { default: DefaultValue::Number(0.0),
        bounds: Range("[0, 1]"), why: ": a Coulomb coefficient (0 = frictionless)",
        help: "Coulomb friction coefficient μ at the sliding surface: a slave's tangential \
               impulse is at most μ times its normal one (0 = frictionless, as the paper)",
        show: |s| number(s.contact.friction) }
    CONTACT_KERNEL = "contact.kernel" {
        ty: Ty::Choice { names: &["cut", "images"], quoted: true },
        default: DefaultValue::Text("cut"),
        help: "What completes the kernel of the concrete lining the projectile: \"cut\" \
               (nothing, as the paper) or \"images\" (mirror images across the surface, whose \
               reaction the projectile takes); \"images\" needs contact.lambda > 0",
        show: |s| Some(Text(s.contact.kernel.name().into())) }

    WALL_Z = "wall.z" { unit: "m", help: "The wall's plane z = wall.z",
        show: |s| s.wall.as_ref().and_then(|w| number(w.z)) }
}

const DAMAGE_DEFAULT: &str = "the preset's; required with damage = true if it has none";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_is_declared_once_with_its_table_and_help() {
        for (i, k) in KEYS.iter().enumerate() {
            assert!(!k.help.is_empty() && !k.unit.is_empty(), "{}", k.path);
            assert!(table(k.table()).is_some(), "{}: no table", k.path);
            assert!(
                KEYS[..i].iter().all(|other| other.path != k.path),
                "{} twice",
                k.path
            );
        }
    }

    #[test]
    fn every_range_parses() {
        for k in KEYS {
            if let Bounds::Range(text) = k.bounds {
                assert!(k.interval().is_some(), "{}: `{text}`", k.path);
            }
        }
        let gamma = EOS_GAMMA.interval().unwrap();
        let max = f64::from(crate::materials::steel_eos::MAX_GAMMA);
        assert!(gamma.contains(max) && !gamma.contains(max * 1.0001));
    }

    #[test]
    fn bound_messages_read_as_before() {
        assert_eq!(RUN_END_TIME.bound_message(), "must be > 0 (s)");
        assert_eq!(JC_M.bound_message(), "must be > 0 (-)");
        assert_eq!(POISSON_RATIO.bound_message(), "must be in (0, 0.5)");
        assert_eq!(RUN_MAX_STEPS.bound_message(), "must be ≥ 1");
        assert!(RUN_CFL
            .bound_message()
            .starts_with("must be in (0, 1]: the Courant"));
    }

    #[test]
    fn members_list_keys_and_tables() {
        assert_eq!(
            members(""),
            ["name", "run", "projectile", "target", "contact", "wall"]
        );
        let projectile = members("projectile");
        assert!(projectile.ends_with(&["nose_z", "cavity", "material"]));
    }
}
