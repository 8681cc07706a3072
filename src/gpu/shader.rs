//! The WGSL programs of the GPU path, each assembled in one place from `shaders/` after a
//! prelude that Rust writes (the uniform blocks of `params.rs` and the constants the shaders
//! share with the CPU path), so neither can drift from its Rust definition.
//!
//! naga parses a program without an adapter: a kernel's bind-group layout is read from the
//! shader's own `@binding` declarations and the host binds buffers by their WGSL names, and the
//! tests below validate every program on any machine, so a WGSL error fails `cargo test`
//! without a GPU.

use std::sync::OnceLock;

use super::Slot;

/// One file of `shaders/`: its name (for error messages) and its text.
#[derive(Clone, Copy, Debug)]
pub struct Part {
    pub file: &'static str,
    pub text: &'static str,
}

macro_rules! part {
    ($file:literal) => {
        Part {
            file: $file,
            text: include_str!(concat!("../../shaders/", $file)),
        }
    };
}

const COMMON: Part = part!("common.wgsl");
const PARAMS: Part = part!("params.wgsl");
const STEP: Part = part!("step.wgsl");
const GRID: Part = part!("grid.wgsl");
const GATHER_BINDINGS: Part = part!("gather_bindings.wgsl");
const NEIGHBOUR_LOOP: Part = part!("neighbour_loop.wgsl");
const DEVIATOR: Part = part!("deviator.wgsl");
const HJC: Part = part!("hjc.wgsl");
const JOHNSON_COOK: Part = part!("johnson_cook.wgsl");
const STEEL_EOS: Part = part!("steel_eos.wgsl");
const WALL: Part = part!("wall.wgsl");
const WALL_IMAGES: Part = part!("wall_images.wgsl");

/// The programs the solver builds: one per pass (or per pass stage), named as the pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Program {
    Neighbours,
    NeighbourList,
    Scan,
    SphRates,
    SphFilter,
    SphForces,
    Concrete,
    FemStress,
    Integrate,
    ContactDetect,
    History,
    Walls,
}

impl Program {
    pub const ALL: [Program; 12] = [
        Program::Neighbours,
        Program::NeighbourList,
        Program::Scan,
        Program::SphRates,
        Program::SphFilter,
        Program::SphForces,
        Program::Concrete,
        Program::FemStress,
        Program::Integrate,
        Program::ContactDetect,
        Program::History,
        Program::Walls,
    ];

    /// The pass's name, as its kernels are labelled.
    pub fn name(self) -> &'static str {
        match self {
            Program::Neighbours => "neighbours",
            Program::NeighbourList => "neighbour_list",
            Program::Scan => "scan",
            Program::SphRates => "sph_rates",
            Program::SphFilter => "sph_filter",
            Program::SphForces => "sph_forces",
            Program::Concrete => "concrete",
            Program::FemStress => "fem_stress",
            Program::Integrate => "integrate",
            Program::ContactDetect => "contact_detect",
            Program::History => "history",
            Program::Walls => "walls",
        }
    }

    /// The entry points the host dispatches.
    pub fn entries(self) -> &'static [&'static str] {
        match self {
            Program::Neighbours => &[
                "bounds",
                "setup",
                "clear",
                "count",
                "scatter",
                "sort_cells",
                "pack",
            ],
            Program::NeighbourList => &["list"],
            Program::Scan => &["scan_block", "scan_add"],
            Program::SphRates => &["gradient"],
            Program::SphFilter => &["filter_velocity"],
            Program::SphForces => &["forces"],
            Program::Concrete | Program::FemStress => &["main"],
            Program::Integrate => &["main"],
            Program::ContactDetect => &["detect", "apply"],
            Program::History => &["reduce"],
            Program::Walls => &["find", "sums"],
        }
    }

    /// The pipeline-overridable constants the host sets (what a scene does not need is then
    /// compiled out).
    pub fn overrides(self) -> &'static [&'static str] {
        match self {
            Program::SphRates => &["BALSARA", "CONJUGATE", "RECONSTRUCT", "IMAGES"],
            Program::SphForces => &["ART_STRESS", "BALSARA", "RECONSTRUCT", "IMAGES"],
            Program::Concrete => &["CONJUGATE", "ART_STRESS"],
            Program::FemStress => &["DAMAGE"],
            _ => &[],
        }
    }

    /// The program's files after the prelude and common.wgsl, in order.
    pub fn parts(self) -> Vec<Part> {
        match self {
            Program::Neighbours => vec![PARAMS, GRID, part!("neighbours.wgsl")],
            Program::NeighbourList => {
                vec![PARAMS, GRID, NEIGHBOUR_LOOP, part!("neighbour_list.wgsl")]
            }
            Program::Scan => vec![part!("scan.wgsl")],
            Program::SphRates => {
                vec![
                    PARAMS,
                    GRID,
                    GATHER_BINDINGS,
                    NEIGHBOUR_LOOP,
                    WALL,
                    WALL_IMAGES,
                    part!("sph_rates.wgsl"),
                ]
            }
            Program::SphFilter => gather_parts(part!("sph_filter.wgsl")),
            Program::SphForces => {
                vec![
                    PARAMS,
                    STEP,
                    GRID,
                    GATHER_BINDINGS,
                    NEIGHBOUR_LOOP,
                    WALL,
                    WALL_IMAGES,
                    part!("sph_forces.wgsl"),
                ]
            }
            Program::Concrete => hjc_parts(part!("concrete.wgsl")),
            Program::FemStress => fem_stress_parts(part!("fem_stress.wgsl")),
            Program::Integrate => step_parts(part!("integrate.wgsl")),
            Program::ContactDetect => step_parts(part!("contact_detect.wgsl")),
            Program::History => vec![part!("history.wgsl")],
            Program::Walls => vec![PARAMS, GRID, WALL, part!("walls.wgsl")],
        }
    }

    /// The WGSL the adapter compiles.
    pub fn source(self) -> String {
        source(&self.parts())
    }
}

/// A pass that gathers over the neighbour lists: the parameters, the grid, the shared bindings
/// 0–6 (`GpuGrid::walk_bindings`), the neighbour loop, then `pass`.
fn gather_parts(pass: Part) -> Vec<Part> {
    vec![PARAMS, GRID, GATHER_BINDINGS, NEIGHBOUR_LOOP, pass]
}

/// The step's own passes: the shared blocks (Clock, StepUniform's atomics, status words), then
/// `pass`.
pub(crate) fn step_parts(pass: Part) -> Vec<Part> {
    vec![PARAMS, STEP, pass]
}

/// The concrete pass and its law tests: the deviatoric helpers shared with `fem_stress`, the
/// HJC law, then `pass`.
pub(crate) fn hjc_parts(pass: Part) -> Vec<Part> {
    vec![PARAMS, DEVIATOR, HJC, pass]
}

/// The stress pass and its law tests: the step's shared blocks, the deviatoric helpers, the
/// flow laws and the steel EOS, then `pass`.
pub(crate) fn fem_stress_parts(pass: Part) -> Vec<Part> {
    vec![PARAMS, STEP, DEVIATOR, JOHNSON_COOK, STEEL_EOS, pass]
}

/// The text Rust declares for every program: uniform blocks and shared constants.
pub fn prelude() -> &'static str {
    static PRELUDE: OnceLock<String> = OnceLock::new();
    PRELUDE.get_or_init(|| {
        let mut s = String::from("// Written by src/gpu/shader.rs from its Rust definitions.\n");
        for block in super::params::BLOCKS {
            s.push_str(block);
        }
        for (name, value) in shared_constants() {
            s.push_str(&match value {
                Value::F32(v) => format!("const {name}: f32 = {v:?}f;\n"),
                Value::U32(v) => format!("const {name}: u32 = {v}u;\n"),
            });
        }
        s
    })
}

/// A constant's value in the type WGSL declares it with.
#[derive(Clone, Copy, Debug)]
enum Value {
    F32(f32),
    U32(u32),
}

/// Constants the shaders take from their CPU twins' definitions, under their WGSL names.
fn shared_constants() -> Vec<(&'static str, Value)> {
    use crate::materials::{flow, hjc, johnson_cook, steel_eos};
    use Value::{F32, U32};
    let status = |i: usize| U32(i as u32);
    vec![
        ("WG", U32(super::WORKGROUP)),
        ("HISTORY_CHUNK", U32(super::history::CHUNK)),
        ("SIGMA_2D", F32(crate::kernel::SIGMA_2D)),
        ("GRID_REACH", U32(crate::cpu::neighbours::REACH)),
        (
            "MAX_CELLS_PER_AXIS",
            U32(crate::cpu::neighbours::MAX_CELLS_PER_AXIS),
        ),
        ("NBR_MAX", U32(super::neighbours::NBR_MAX as u32)),
        ("SCAN_BLOCK", U32(super::scan::SCAN_BLOCK)),
        (
            "SCAN_ITEMS",
            U32(super::scan::SCAN_BLOCK / super::WORKGROUP),
        ),
        ("HJC_POW_BASE_FLOOR", F32(hjc::POW_BASE_FLOOR)),
        ("HJC_FAILURE_STRAIN_FLOOR", F32(hjc::FAILURE_STRAIN_FLOOR)),
        ("HJC_TENSILE_RATE_REF", F32(hjc::TENSILE_RATE_REF)),
        ("HJC_TENSILE_RATE_KNEE", F32(hjc::TENSILE_RATE_KNEE)),
        ("HJC_TENSILE_RATE_LIMIT", F32(hjc::TENSILE_RATE_LIMIT)),
        ("HJC_TENSILE_RATE_EXPONENT", F32(hjc::TENSILE_RATE_EXPONENT)),
        (
            "HJC_TENSILE_RATE_COEFFICIENT",
            F32(hjc::TENSILE_RATE_COEFFICIENT),
        ),
        ("JC_POW_BASE_FLOOR", F32(johnson_cook::POW_BASE_FLOOR)),
        ("JC_HARDENING_EPS_FLOOR", F32(flow::HARDENING_EPS_FLOOR)),
        (
            "JC_FAILURE_STRAIN_FLOOR",
            F32(johnson_cook::FAILURE_STRAIN_FLOOR),
        ),
        ("JC_DAMAGE_EXP_CAP", F32(johnson_cook::DAMAGE_EXP_CAP)),
        ("JC_RETURN_TOLERANCE", F32(flow::RETURN_TOLERANCE)),
        ("MIN_POSITIVE", F32(f32::MIN_POSITIVE)),
        ("EOS_BULK_TANGENT_FLOOR", F32(steel_eos::BULK_TANGENT_FLOOR)),
        (
            "MIN_DENSITY_RATIO",
            F32(crate::cpu::concrete::MIN_DENSITY_RATIO),
        ),
        (
            "OPEN_RELATIVE_VOLUME",
            F32(crate::cpu::fem_stress::OPEN_RELATIVE_VOLUME),
        ),
        (
            "CELL_MODE_STIFFNESS",
            F32(crate::cpu::fem_stress::CELL_MODE_STIFFNESS),
        ),
        ("ETA2", F32(crate::cpu::sph_forces::ETA2)),
        ("NO_WALL", U32(crate::cpu::wall::NO_WALL)),
        (
            "MIN_CORRECTION_DET",
            F32(crate::cpu::sph_rates::MIN_CORRECTION_DET),
        ),
        ("BALSARA_FLOOR", F32(crate::cpu::sph_rates::BALSARA_FLOOR)),
        ("PI", F32(std::f32::consts::PI)),
        (
            "STATUS_INVERTED_ELEMENT",
            status(super::integrate::STATUS_INVERTED_ELEMENT),
        ),
        (
            "STATUS_PARTICLE_NONFINITE",
            status(super::integrate::STATUS_PARTICLE_NONFINITE),
        ),
        (
            "STATUS_PARTICLE_ESCAPED",
            status(super::integrate::STATUS_PARTICLE_ESCAPED),
        ),
        (
            "STATUS_NODE_NONFINITE",
            status(super::integrate::STATUS_NODE_NONFINITE),
        ),
        (
            "STATUS_NODE_ESCAPED",
            status(super::integrate::STATUS_NODE_ESCAPED),
        ),
        ("STATUS_WORDS", status(super::integrate::STATUS_WORDS)),
        ("F32_MAX_BITS", U32(f32::MAX.to_bits())),
        ("DT_FROM_CLOCK", U32(super::timestep::DT_FROM_CLOCK)),
        (
            "MOVED2_WORD",
            U32((super::neighbours::MOVED2_OFFSET / 4) as u32),
        ),
    ]
}

/// The WGSL of a program made of `parts`: the prelude, common.wgsl, then the parts.
pub fn source(parts: &[Part]) -> String {
    let mut s = String::from(prelude());
    for p in std::iter::once(&COMMON).chain(parts) {
        s.push('\n');
        s.push_str(p.text);
    }
    s
}

/// Where line `line` (1-based) of `source(parts)` comes from: "file:line".
fn locate(parts: &[Part], line: usize) -> String {
    let mut start = 1;
    let files = std::iter::once(("(prelude)", prelude())).chain(
        std::iter::once(&COMMON)
            .chain(parts)
            .map(|p| (p.file, p.text)),
    );
    for (file, text) in files {
        // Each part follows a newline of its own (`source`).
        let lines = text.lines().count() + 1;
        if line < start + lines {
            return format!("shaders/{file}:{}", line + 1 - start);
        }
        start += lines;
    }
    format!("line {line}")
}

/// A resource binding of a parsed shader (group 0).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Binding {
    pub index: u32,
    pub name: String,
    pub slot: Slot,
}

/// The bindings `source` declares, in binding order, read by naga.
pub fn bindings(source: &str) -> Result<Vec<Binding>, String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    let mut out = Vec::new();
    for (_, var) in module.global_variables.iter() {
        let Some(binding) = &var.binding else {
            continue;
        };
        if binding.group != 0 {
            return Err(format!(
                "{:?} is in bind group {}; the passes use group 0 only",
                var.name, binding.group
            ));
        }
        let slot = match var.space {
            naga::AddressSpace::Uniform => Slot::Uniform,
            naga::AddressSpace::Storage { access } => {
                if access.contains(naga::StorageAccess::STORE) {
                    Slot::ReadWrite
                } else {
                    Slot::Read
                }
            }
            other => return Err(format!("{:?}: a binding in {other:?}", var.name)),
        };
        out.push(Binding {
            index: binding.binding,
            name: var.name.clone().unwrap_or_default(),
            slot,
        });
    }
    out.sort_by_key(|b| b.index);
    Ok(out)
}

/// Storage buffers the widest program binds: the adapter must allow this many per stage.
pub fn storage_buffers_needed() -> u32 {
    static NEEDED: OnceLock<u32> = OnceLock::new();
    *NEEDED.get_or_init(|| {
        Program::ALL
            .iter()
            .filter_map(|p| bindings(&p.source()).ok())
            .map(|b| b.iter().filter(|b| b.slot != Slot::Uniform).count() as u32)
            .max()
            .unwrap_or(0)
    })
}

/// Parse and validate the program made of `parts`, naming the file and line of an error.
pub fn validate(parts: &[Part]) -> Result<naga::Module, String> {
    let src = source(parts);
    let module = naga::front::wgsl::parse_str(&src).map_err(|e| {
        let at = e
            .location(&src)
            .map_or(String::new(), |l| locate(parts, l.line_number as usize));
        format!("{at}: {}", e.emit_to_string(&src))
    })?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .map_err(|e| {
        let at = e
            .location(&src)
            .map_or(String::new(), |l| locate(parts, l.line_number as usize));
        format!("{at}: {}", e.emit_to_string(&src))
    })?;
    Ok(module)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every program parses and validates (no adapter needed), declares the entry points and
    /// override constants the host uses, and binds within group 0.
    #[test]
    fn every_program_validates_without_an_adapter() {
        for program in Program::ALL {
            let module =
                validate(&program.parts()).unwrap_or_else(|e| panic!("{}: {e}", program.name()));
            for entry in program.entries() {
                let found = module.entry_points.iter().find(|e| e.name == *entry);
                assert!(
                    found.is_some_and(|e| e.stage == naga::ShaderStage::Compute),
                    "{} has no compute entry point {entry}",
                    program.name()
                );
            }
            // The host dispatches WORKGROUP threads a group (one for a single-thread entry).
            for e in &module.entry_points {
                assert!(
                    [[super::super::WORKGROUP, 1, 1], [1, 1, 1]].contains(&e.workgroup_size),
                    "{}.{}: workgroup size {:?}",
                    program.name(),
                    e.name,
                    e.workgroup_size
                );
            }
            let mut overrides: Vec<&str> = module
                .overrides
                .iter()
                .filter_map(|(_, o)| o.name.as_deref())
                .collect();
            let mut listed = program.overrides().to_vec();
            overrides.sort_unstable();
            listed.sort_unstable();
            assert_eq!(overrides, listed, "{}", program.name());
            bindings(&program.source()).unwrap();
        }
    }

    /// A type error in a pass's file fails validation, and the message names the file and line.
    #[test]
    fn a_wgsl_type_error_is_named_by_file_and_line() {
        let bad = Part {
            file: "bad.wgsl",
            text:
                "// a pass\n@compute @workgroup_size(64)\nfn main() {\n    let x: u32 = 1.5;\n}\n",
        };
        let e = validate(&step_parts(bad)).unwrap_err();
        assert!(e.contains("shaders/bad.wgsl:4"), "{e}");
    }

    /// Each uniform block's WGSL layout (naga's) is the size encase writes from the Rust struct.
    #[test]
    fn uniform_blocks_have_the_rust_layout() {
        use crate::gpu::params::{
            DtSlot, FemUniform, KernelUniform, ScanLevel, SphUniform, StepUniform,
        };
        use encase::ShaderType;
        let module = validate(&[]).unwrap();
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let size = |name: &str| {
            let (ty, _) = module
                .types
                .iter()
                .find(|(_, t)| t.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("no struct {name} in the prelude"));
            u64::from(layouter[ty].size)
        };
        assert_eq!(size("KernelUniform"), KernelUniform::min_size().get());
        assert_eq!(size("SphUniform"), SphUniform::min_size().get());
        assert_eq!(size("FemUniform"), FemUniform::min_size().get());
        assert_eq!(size("StepUniform"), StepUniform::min_size().get());
        assert_eq!(size("DtSlot"), DtSlot::min_size().get());
        assert_eq!(size("ScanLevel"), ScanLevel::min_size().get());
    }

    /// The prelude's constants are the CPU path's values, bit for bit.
    #[test]
    fn shared_constants_round_trip() {
        let module = validate(&[]).unwrap();
        for (name, value) in shared_constants() {
            let (_, c) = module
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("no const {name}"));
            let got = &module.global_expressions[c.init];
            let ok = match (value, got) {
                (Value::F32(v), naga::Expression::Literal(naga::Literal::F32(g))) => {
                    v.to_bits() == g.to_bits()
                }
                (Value::U32(v), naga::Expression::Literal(naga::Literal::U32(g))) => v == *g,
                _ => false,
            };
            assert!(ok, "{name}: {value:?} became {got:?}");
        }
    }
}
