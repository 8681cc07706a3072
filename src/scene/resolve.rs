//! From what the file gives to the resolved [`Scene`]: defaults, presets, the HJC rule, each
//! key's own bounds (asked of the schema) and the checks that involve several keys.

use std::path::Path;

use toml::Value;

use super::parse::{Given, Val};
use super::schema::{self as k, DefaultValue, Key, Ty};
use super::{
    approx, num, render, Backend, CavitySpec, ContactSpec, ProjectileShape, ProjectileSpec,
    RunControl, Scene, SceneError, SurfaceKernel, TargetSpec, TensionModel, VelocityFilter,
    VelocityGradient, ViscosityJump, ViscositySwitch, WallSpec,
};
use crate::materials::hjc::Hjc;

/// Gap between a Taylor bar's lowest face and the wall at t = 0 (m): touching, not overlapping.
pub(super) const WALL_GAP: f64 = 1.0e-6;

/// Largest gap between the nose and the target's face or the wall at the start (m).
const MAX_START_GAP: f64 = 1.0;

/// The file's values for one scene, and the errors about them.
pub(super) struct Check<'a> {
    /// The scene file, for every message.
    pub file: &'a Path,
    /// What the file gives.
    pub given: &'a Given,
}

impl Check<'_> {
    /// `key = value: why`.
    pub fn non_physical(&self, key: &str, value: f64, why: impl Into<String>) -> SceneError {
        SceneError::NonPhysical {
            file: self.file.to_path_buf(),
            key: key.into(),
            value: num(value),
            why: why.into(),
        }
    }

    /// `Ok(value)` when `ok`, else a [`SceneError::NonPhysical`] saying `why`.
    pub fn require(&self, ok: bool, key: &str, value: f64, why: &str) -> Result<f64, SceneError> {
        if ok {
            Ok(value)
        } else {
            Err(self.non_physical(key, value, why))
        }
    }

    /// Keys that cannot go together, and why.
    pub fn conflict(&self, keys: &[&str], why: &str) -> SceneError {
        SceneError::Conflict {
            file: self.file.to_path_buf(),
            keys: keys.iter().map(|k| k.to_string()).collect(),
            why: why.into(),
        }
    }

    /// A key the scene must give here.
    pub fn missing(&self, key: &str, why: impl Into<String>) -> SceneError {
        SceneError::MissingKey {
            file: self.file.to_path_buf(),
            key: key.into(),
            why: why.into(),
        }
    }

    /// The number the file gives for `key`, unchecked.
    pub fn given_num(&self, key: &Key) -> Option<f64> {
        match self.given.values.get(key.path) {
            Some(Val::Number(x)) => Some(*x),
            _ => None,
        }
    }

    /// The flag the file gives for `key`.
    pub fn given_flag(&self, key: &Key) -> Option<bool> {
        match self.given.values.get(key.path) {
            Some(Val::Flag(b)) => Some(*b),
            _ => None,
        }
    }

    fn given_text(&self, key: &Key) -> Option<&str> {
        match self.given.values.get(key.path) {
            Some(Val::Text(s)) => Some(s),
            _ => None,
        }
    }

    /// Whether the file has the table at `path`.
    pub fn has_table(&self, path: &str) -> bool {
        self.given.tables.contains(path)
    }

    /// `value` checked against `key`'s own bounds.
    pub fn check(&self, key: &Key, value: f64) -> Result<f64, SceneError> {
        match key.interval() {
            Some(range) if !range.contains(value) => {
                Err(self.non_physical(key.path, value, key.bound_message()))
            }
            _ => Ok(value),
        }
    }

    /// The number for `key`: the file's, else its default; checked.
    pub fn num(&self, key: &Key) -> Result<f64, SceneError> {
        let value = match (self.given_num(key), key.default) {
            (Some(x), _) | (None, DefaultValue::Number(x)) => x,
            _ => return Err(self.missing(key.path, "add this required key")),
        };
        self.check(key, value)
    }

    /// The number for a key whose default is derived: the file's, else `derived`; checked.
    pub fn num_or(&self, key: &Key, derived: f64) -> Result<f64, SceneError> {
        self.check(key, self.given_num(key).unwrap_or(derived))
    }

    /// The count for `key`: the file's, else its default; checked.
    pub fn count(&self, key: &Key) -> Result<u64, SceneError> {
        let value = match (self.given.values.get(key.path), key.default) {
            (Some(Val::Count(n)), _) => *n,
            (None, DefaultValue::Count(n)) => n,
            _ => return Err(self.missing(key.path, "add this required key")),
        };
        self.check(key, value as f64)?;
        Ok(value)
    }

    /// The flag for `key`: the file's, else its default (`false` for a derived one).
    pub fn flag(&self, key: &Key) -> bool {
        match (self.given_flag(key), key.default) {
            (Some(b), _) | (None, DefaultValue::Flag(b)) => b,
            _ => false,
        }
    }

    /// The name chosen for a [`Ty::Choice`] key: the file's, else its default; one of the
    /// key's names.
    pub fn choice(&self, key: &Key) -> Result<&'static str, SceneError> {
        let value = match (self.given_text(key), key.default) {
            (Some(s), _) | (None, DefaultValue::Text(s)) => s,
            _ => return Err(self.missing(key.path, "add this required key")),
        };
        let Ty::Choice { names, .. } = key.ty else {
            unreachable!("{} is not a choice", key.path)
        };
        names
            .iter()
            .find(|c| **c == value)
            .copied()
            .ok_or_else(|| SceneError::BadChoice {
                file: self.file.to_path_buf(),
                key: key.path.into(),
                value: render(&Value::String(value.into())),
                choices: names.iter().map(|c| c.to_string()).collect(),
            })
    }
}

/// The resolved scene, or the first check it fails.
pub(super) fn resolve(c: &Check) -> Result<Scene, SceneError> {
    let origin = c.file;
    let name = match c.given_text(&k::NAME) {
        Some(name) if name.trim().is_empty() => {
            return Err(SceneError::NonPhysical {
                file: origin.to_path_buf(),
                key: k::NAME.path.into(),
                value: render(&Value::String(name.into())),
                why: "must not be empty; remove it to use the file name".into(),
            })
        }
        Some(name) => name.to_string(),
        None => origin
            .file_stem()
            .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned()),
    };
    let run = resolve_run(c)?;
    let contact = resolve_contact(c)?;
    let mut projectile = resolve_projectile(c)?;
    // The default nose position: a small gap, no initial overlap.
    let (target, wall, default_nose_z) = match (c.has_table("target"), c.has_table("wall")) {
        (true, true) => {
            return Err(c.conflict(
                &["target", "wall"],
                "a scene has exactly one of [target] (penetration) and [wall] (Taylor bar); \
                 remove one of the two tables",
            ))
        }
        (false, false) => {
            return Err(c.conflict(
                &["target", "wall"],
                "a scene needs one of [target] (penetration) and [wall] (Taylor bar); add one",
            ))
        }
        (true, false) => {
            let t = resolve_target(c, &projectile)?;
            let nose_z = 0.25 * t.spacing - t.start_depth(projectile.diameter);
            (Some(t), None, nose_z)
        }
        (false, true) => {
            let z = c.num(&k::WALL_Z)?;
            (None, Some(WallSpec { z }), z + WALL_GAP)
        }
    };
    let start_depth = target
        .as_ref()
        .map_or(0.0, |t| t.start_depth(projectile.diameter));
    let pilot = target
        .as_ref()
        .is_some_and(|t| t.lead_hole_depth > 0.0 && start_depth == 0.0);
    let nose_key = k::NOSE_Z.path;
    projectile.nose_z = match (c.given_num(&k::NOSE_Z), &wall) {
        (None, _) => default_nose_z,
        (Some(z), None) => c.require(
            (-start_depth..=MAX_START_GAP).contains(&z),
            nose_key,
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
            nose_key,
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

fn resolve_run(c: &Check) -> Result<RunControl, SceneError> {
    let end_time = c.num(&k::RUN_END_TIME)?;
    let cfl = c.num(&k::RUN_CFL)?;
    let output_interval = c.num(&k::RUN_OUTPUT_INTERVAL)?;
    // 500 history rows per run by default: enough for smooth plots, small files.
    let history_interval = c.num_or(&k::RUN_HISTORY_INTERVAL, end_time / 500.0)?;
    // A real GPU where there is one, the CPU reference path otherwise (never a software adapter
    // unasked: lavapipe is for tests).
    let backend = match c.choice(&k::RUN_BACKEND)? {
        "gpu" => Backend::Gpu,
        "auto" => Backend::Auto,
        _ => Backend::Cpu,
    };
    Ok(RunControl {
        end_time,
        cfl,
        output_interval,
        history_interval,
        backend,
        max_steps: c.count(&k::RUN_MAX_STEPS)?,
        stop_at_rest: c.flag(&k::RUN_STOP_AT_REST),
    })
}

fn resolve_contact(c: &Check) -> Result<ContactSpec, SceneError> {
    let lambda = c.num(&k::CONTACT_LAMBDA)?;
    let slave_radius_factor = c.num(&k::CONTACT_SLAVE_RADIUS_FACTOR)?;
    let friction = c.num(&k::CONTACT_FRICTION)?;
    let kernel = match c.choice(&k::CONTACT_KERNEL)? {
        "cut" => SurfaceKernel::Cut,
        _ => SurfaceKernel::Images,
    };
    // The images' reaction acts on the nodes at their feet, which a rigid projectile (moved
    // only by the contact's global shift) has no way to take.
    if kernel == SurfaceKernel::Images && lambda == 0.0 {
        return Err(c.conflict(
            &[k::CONTACT_KERNEL.path, k::CONTACT_LAMBDA.path],
            "the images' reaction needs a deformable projectile: set contact.lambda > 0, or \
             contact.kernel = \"cut\" for the rigid limit",
        ));
    }
    Ok(ContactSpec {
        lambda,
        slave_radius_factor,
        friction,
        kernel,
    })
}

/// Resolves `[projectile]`; `nose_z` is left at 0 for [`resolve`] to set.
fn resolve_projectile(c: &Check) -> Result<ProjectileSpec, SceneError> {
    let diameter = c.num(&k::DIAMETER)?;
    let length = c.num(&k::LENGTH)?;
    let crh = c.given_num(&k::CRH);
    let shape = match c.choice(&k::SHAPE)? {
        "ogive" => {
            let crh = crh.ok_or_else(|| {
                c.missing(
                    k::CRH.path,
                    "required for shape = \"ogive\" (calibre-radius-head, e.g. 2.0)",
                )
            })?;
            ProjectileShape::Ogive {
                crh: c.check(&k::CRH, crh)?,
            }
        }
        _ => {
            if crh.is_some() {
                return Err(c.conflict(
                    &[k::CRH.path, k::SHAPE.path],
                    "a cylinder has no crh; remove crh or set shape = \"ogive\"",
                ));
            }
            ProjectileShape::Cylinder
        }
    };
    let nose_length = shape.nose_length(diameter);
    c.require(
        length > nose_length,
        k::LENGTH.path,
        length,
        &format!(
            "must exceed the ogive nose length a·sqrt(4·crh − 1) = {} m",
            approx(nose_length)
        ),
    )?;
    let element_size = c.num(&k::ELEMENT_SIZE)?;
    c.require(
        element_size <= diameter / 4.0,
        k::ELEMENT_SIZE.path,
        element_size,
        &format!(
            "must be ≤ projectile.diameter/4 = {} m (at least two elements across the radius)",
            approx(diameter / 4.0)
        ),
    )?;
    c.require(
        length >= nose_length + element_size,
        k::LENGTH.path,
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
    let velocity = c.num(&k::VELOCITY)?;
    let material = super::material::resolve_steel(c)?;
    // The explicit step is the time a wave takes across the smallest element: a solid struck
    // faster than its waves travel would move its nodes farther than an element in one step.
    let wave = material.wave_speed();
    c.require(
        velocity < wave,
        k::VELOCITY.path,
        velocity,
        &format!(
            "must be below the projectile's elastic wave speed √((K₁ + 4G/3)/ρ) = {} m/s \
             (projectile.material: a metal's is thousands of m/s; are its moduli or its density \
             in the wrong unit?)",
            approx(wave)
        ),
    )?;
    super::material::check_strength_below_modulus(c, &material)?;
    let cavity = if c.has_table("projectile.cavity") {
        let cd = c.num(&k::CAVITY_DIAMETER)?;
        let cl = c.num(&k::CAVITY_LENGTH)?;
        let rear = c.num(&k::CAVITY_REAR_WALL)?;
        let filler = c.num(&k::CAVITY_FILLER_DENSITY)?;
        let max_d = diameter - 2.0 * element_size;
        c.require(
            cd < max_d,
            k::CAVITY_DIAMETER.path,
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
            k::CAVITY_LENGTH.path,
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
    } else {
        None
    };
    Ok(ProjectileSpec {
        shape,
        diameter,
        length,
        cavity,
        element_size,
        velocity,
        nose_z: 0.0,
        material,
        cell_pressure: c.flag(&k::CELL_PRESSURE),
    })
}

fn resolve_target(c: &Check, projectile: &ProjectileSpec) -> Result<TargetSpec, SceneError> {
    let radius = c.num(&k::TARGET_RADIUS)?;
    let thickness = c.num(&k::TARGET_THICKNESS)?;
    let spacing = c.num(&k::TARGET_SPACING)?;
    let fc = c.num(&k::TARGET_FC)?;
    let density = c.num(&k::TARGET_DENSITY)?;
    c.require(
        spacing <= projectile.diameter / 2.0,
        k::TARGET_SPACING.path,
        spacing,
        &format!(
            "must be ≤ projectile.diameter/2 = {} m (at least one particle per projectile radius)",
            approx(projectile.diameter / 2.0)
        ),
    )?;
    for (key, size) in [
        (&k::TARGET_RADIUS, radius),
        (&k::TARGET_THICKNESS, thickness),
    ] {
        c.require(
            size >= 4.0 * spacing,
            key.path,
            size,
            &format!(
                "must be ≥ 4·target.spacing = {} m (at least 4 particles across)",
                approx(4.0 * spacing)
            ),
        )?;
    }
    let smoothing_ratio = c.num(&k::SMOOTHING_RATIO)?;
    let viscosity_alpha = c.num(&k::VISCOSITY_ALPHA)?;
    let viscosity_beta = c.num(&k::VISCOSITY_BETA)?;
    let viscosity_switch = match c.choice(&k::VISCOSITY_SWITCH)? {
        "none" => ViscositySwitch::None,
        _ => ViscositySwitch::Balsara,
    };
    let viscosity_jump = match c.choice(&k::VISCOSITY_JUMP)? {
        "raw" => ViscosityJump::Raw,
        _ => ViscosityJump::Reconstructed,
    };
    let velocity_filter = match c.choice(&k::VELOCITY_FILTER)? {
        "none" => VelocityFilter::None,
        _ => VelocityFilter::Linear,
    };
    let velocity_gradient = match c.choice(&k::VELOCITY_GRADIENT)? {
        "corrected" => VelocityGradient::Corrected,
        _ => VelocityGradient::Conjugate,
    };
    let tension = match c.choice(&k::TENSION)? {
        "static" => TensionModel::Static,
        _ => TensionModel::CrackBand,
    };
    // The filter fits a linear field with the corrected gradient and moves the velocities off
    // the particles' own: the conjugate rate is the forces' only for the particles' own.
    if velocity_gradient == VelocityGradient::Conjugate && velocity_filter == VelocityFilter::Linear
    {
        return Err(c.conflict(
            &[k::VELOCITY_GRADIENT.path, k::VELOCITY_FILTER.path],
            "the conjugate gradient (the default) takes the particles' own velocities: \
             set target.velocity_filter = \"none\", or target.velocity_gradient = \
             \"corrected\" to filter",
        ));
    }
    // The reconstruction's slopes are those of the particles' own velocities, which the
    // viscosity's jump is taken between; the filter's gradient is of other velocities.
    if viscosity_jump == ViscosityJump::Reconstructed && velocity_filter == VelocityFilter::Linear {
        return Err(c.conflict(
            &[k::VISCOSITY_JUMP.path, k::VELOCITY_FILTER.path],
            "the reconstructed jump takes the particles' own velocities: set \
             target.velocity_filter = \"none\", or target.viscosity_jump = \"raw\" to filter",
        ));
    }
    let lead_hole_depth = c.num(&k::LEAD_HOLE_DEPTH)?;
    c.require(
        lead_hole_depth <= thickness - 4.0 * spacing,
        k::LEAD_HOLE_DEPTH.path,
        lead_hole_depth,
        &format!(
            "must be ≤ target.thickness − 4·target.spacing = {} m (at least 4 particles below \
             the hole)",
            approx(thickness - 4.0 * spacing)
        ),
    )?;
    let lead_hole_diameter = c.num_or(&k::LEAD_HOLE_DIAMETER, projectile.diameter)?;
    // Checked only where there is a hole. A hole narrower than the projectile is a pilot
    // hole: the nose starts at the face (resolve, `projectile.nose_z`).
    c.require(
        lead_hole_depth == 0.0 || lead_hole_diameter <= 2.0 * (radius - 4.0 * spacing),
        k::LEAD_HOLE_DIAMETER.path,
        lead_hole_diameter,
        &format!(
            "must be at most 2·(target.radius − 4·target.spacing) = {} m: the wall round the \
             hole must hold 4 particles",
            approx(2.0 * (radius - 4.0 * spacing))
        ),
    )?;
    let concrete = resolve_hjc(c, fc, density)?;
    let widest = f64::from(crate::materials::hjc::widest_crack_band(&concrete));
    c.require(
        tension == TensionModel::Static || spacing <= widest,
        k::TARGET_SPACING.path,
        spacing,
        &format!(
            "must be ≤ {} m with target.tension = \"crack-band\": a crack band one spacing \
             wide would soften faster than the concrete unloads and spend more than its \
             fracture energy (2·G_f·K_el/T_d², T_d the tensile strength at 300/s); refine, \
             or set target.tension = \"static\"",
            approx(widest)
        ),
    )?;
    Ok(TargetSpec {
        radius,
        thickness,
        spacing,
        smoothing_ratio,
        fix_rear: c.flag(&k::FIX_REAR),
        fix_lateral: c.flag(&k::FIX_LATERAL),
        artificial_stress: c.flag(&k::ARTIFICIAL_STRESS),
        viscosity_alpha,
        viscosity_beta,
        viscosity_switch,
        viscosity_jump,
        velocity_filter,
        velocity_gradient,
        lead_hole_depth,
        lead_hole_diameter,
        tension,
        concrete,
    })
}

/// HJC from the §3.1 rule, then the scene's explicit constants, then the checks.
fn resolve_hjc(c: &Check, fc: f64, density: f64) -> Result<Hjc, SceneError> {
    let mut h = Hjc::from_fc(fc as f32, density as f32);
    // Each key with the field it overrides, in schema order.
    let fields = [
        (&k::HJC_SHEAR_MODULUS, &mut h.shear_modulus),
        (&k::HJC_A, &mut h.a),
        (&k::HJC_B, &mut h.b),
        (&k::HJC_N, &mut h.n),
        (&k::HJC_C, &mut h.c),
        (&k::HJC_S_MAX, &mut h.s_max),
        (&k::HJC_T, &mut h.t),
        (&k::HJC_EPS_RATE_REF, &mut h.eps_rate_ref),
        (&k::HJC_EF_MIN, &mut h.ef_min),
        (&k::HJC_D1, &mut h.d1),
        (&k::HJC_D2, &mut h.d2),
        (&k::HJC_P_CRUSH, &mut h.p_crush),
        (&k::HJC_MU_CRUSH, &mut h.mu_crush),
        (&k::HJC_K1, &mut h.k1),
        (&k::HJC_K2, &mut h.k2),
        (&k::HJC_K3, &mut h.k3),
        (&k::HJC_P_LOCK, &mut h.p_lock),
        (&k::HJC_MU_LOCK, &mut h.mu_lock),
        (&k::HJC_FRACTURE_ENERGY, &mut h.g_f),
    ];
    for (key, field) in fields {
        if let Some(v) = c.given_num(key) {
            *field = v as f32;
        }
        c.check(key, f64::from(*field))?;
    }
    let f = f64::from;
    c.require(
        h.t > 0.0 && h.t < h.fc,
        k::HJC_T.path,
        f(h.t),
        &format!(
            "must be in (0, target.fc = {}) (Pa): concrete's tensile strength is about a tenth \
             of its compressive strength",
            num(h.fc)
        ),
    )?;
    c.require(
        h.p_lock > h.p_crush,
        k::HJC_P_LOCK.path,
        f(h.p_lock),
        &format!(
            "must be > target.concrete.p_crush = {} (Pa; f_c/3 unless set)",
            approx(f(h.p_crush))
        ),
    )?;
    c.require(
        h.mu_lock > h.mu_crush,
        k::HJC_MU_LOCK.path,
        f(h.mu_lock),
        &format!(
            "must be > target.concrete.mu_crush = {} (P_crush/K_el unless set; mu_lock is \
             {}/target.density - 1 unless set, so a target as dense as the grains needs it set)",
            approx(f(h.mu_crush)),
            crate::materials::hjc::GRAIN_DENSITY
        ),
    )?;
    if let Some(why) = crate::materials::hjc::dense_curve_fault(&h) {
        let keys = [&k::HJC_K1, &k::HJC_K2, &k::HJC_K3, &k::HJC_P_LOCK].map(|k| k.path);
        return Err(c.conflict(&keys, &why));
    }
    Ok(h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::tests::{case, smoke};
    use crate::scene::{load, ogive_nose_length};

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
        let jc = steel.strength.johnson_cook().expect("4340 is Johnson–Cook");
        let a = f64::from(jc.a);
        assert!((a / 1161.0e6 - 1.0).abs() < 0.005, "A(Rc 45) = {a}");
        assert!((f64::from(jc.b) / (0.6439 * a) - 1.0).abs() < 1e-6);
        assert_eq!(jc.n, 0.26);
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
        assert_eq!(m.strength.johnson_cook().map(|j| j.a), Some(792.0e6));
        assert_eq!(s.wall, Some(WallSpec { z: 0.0 }));
    }
}
