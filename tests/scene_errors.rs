//! Bad scene files and overrides: each must be refused with one line that names the file and the
//! dotted key, and no input may make the loader panic.
//!
//! One file past 800 lines on purpose: it is a table of bad inputs, one case each, and every
//! file in tests/ is a binary of its own (a link per piece in the fast tier).

use std::path::{Path, PathBuf};

use penetrate::scene::{load, parse_str, SceneError};

const ORIGIN: &str = "cases/bad-scene.toml";

fn smoke_text() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/smoke.toml");
    std::fs::read_to_string(path).expect("cases/smoke.toml")
}

/// The smoke case with `from` replaced by `to` (which must occur).
fn smoke_with(from: &str, to: &str) -> String {
    let text = smoke_text();
    assert!(text.contains(from), "smoke.toml has no `{from}`");
    text.replacen(from, to, 1)
}

/// Parses `text` expecting an error; checks the one-line message names the file and every
/// `needles` entry, and returns the error.
fn refused(text: &str, overrides: &[&str], needles: &[&str]) -> SceneError {
    let sets: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let err = parse_str(text, Path::new(ORIGIN), &sets).expect_err("the scene must be refused");
    let msg = err.to_string();
    assert!(!msg.contains('\n'), "not one line: {msg}");
    assert!(msg.starts_with(ORIGIN), "no file name: {msg}");
    for needle in needles {
        assert!(msg.contains(needle), "`{needle}` missing from: {msg}");
    }
    err
}

#[test]
fn smoke_case_is_valid() {
    parse_str(&smoke_text(), Path::new(ORIGIN), &[]).unwrap();
}

#[test]
fn unknown_top_level_key() {
    let text = format!("colour = \"red\"\n{}", smoke_text());
    let err = refused(&text, &[], &["colour", "unknown key"]);
    assert!(matches!(err, SceneError::UnknownKey { .. }));
}

#[test]
fn unknown_nested_key() {
    let err = refused(
        &smoke_with("fc = 35e6", "fcc = 35e6"),
        &[],
        &["target.fcc", "unknown key", "fc"],
    );
    assert!(matches!(err, SceneError::UnknownKey { .. }));
    refused(
        &format!("{}\n[target.concrete]\nmu_lok = 0.1\n", smoke_text()),
        &[],
        &["target.concrete.mu_lok"],
    );
}

#[test]
fn missing_key() {
    let err = refused(
        &smoke_with("velocity = 300.0", ""),
        &[],
        &["projectile.velocity", "missing"],
    );
    assert!(matches!(err, SceneError::MissingKey { .. }));
    refused(
        &smoke_with("crh = 2.0", ""),
        &[],
        &["projectile.crh", "ogive"],
    );
}

#[test]
fn wrong_type() {
    let err = refused(
        &smoke_with("velocity = 300.0", "velocity = \"fast\""),
        &[],
        &["projectile.velocity", "\"fast\"", "number"],
    );
    assert!(matches!(err, SceneError::WrongType { .. }));
    refused(
        &smoke_with("velocity = 300.0", "velocity = [300.0]"),
        &[],
        &["projectile.velocity"],
    );
    refused(&smoke_with("[run]", "run = 5\n[runs]"), &[], &["run"]);
}

#[test]
fn negative_size() {
    let err = refused(
        &smoke_with("diameter = 0.02", "diameter = -0.02"),
        &[],
        &["projectile.diameter = -0.02", "> 0"],
    );
    assert!(matches!(err, SceneError::NonPhysical { .. }));
}

/// A bar shorter than one element, or an ogive whose shank is, is refused (a 1e-5 m Taylor bar
/// used to mesh one flat row and stop at step 0 with a node "escaped", 1e-30 m as a "folded"
/// mesh to be cured by smaller elements).
#[test]
fn shorter_than_one_element() {
    // smoke: diameter 0.02 m, crh 2 (nose 0.02646 m), element_size 0.0025 m.
    refused(
        &smoke_text(),
        &["projectile.length=0.027"],
        &["projectile.length = 0.027", "0.02896", "along the shank"],
    );
    refused(
        &smoke_with("crh = 2.0", ""),
        &["projectile.shape=\"cylinder\"", "projectile.length=1e-30"],
        &["projectile.length = 1e-30", "0.0025 m", "along the bar"],
    );
}

#[test]
fn lambda_outside_unit_interval() {
    let text = format!("{}\n[contact]\nlambda = 1.5\n", smoke_text());
    refused(&text, &[], &["contact.lambda = 1.5", "[0, 1]"]);
}

/// Friction is a Coulomb coefficient in [0, 1]: a negative, non-finite or larger value is
/// refused naming the key, from the file and from `--set` alike; 0.3 is taken.
#[test]
fn friction_outside_unit_interval() {
    for (bad, shown) in [("-0.1", "-0.1"), ("2.0", "2")] {
        let err = refused(
            &smoke_text(),
            &[&format!("contact.friction={bad}")],
            &["contact.friction", "[0, 1]"],
        );
        assert!(matches!(err, SceneError::BadOverride { .. }), "{err}");
        let text = format!("{}\n[contact]\nfriction = {bad}\n", smoke_text());
        let err = refused(
            &text,
            &[],
            &[&format!("contact.friction = {shown}"), "must be in [0, 1]"],
        );
        assert!(matches!(err, SceneError::NonPhysical { .. }), "{err}");
    }
    for bad in ["nan", "inf"] {
        refused(
            &smoke_text(),
            &[&format!("contact.friction={bad}")],
            &["contact.friction", "finite"],
        );
        let text = format!("{}\n[contact]\nfriction = {bad}\n", smoke_text());
        refused(&text, &[], &["contact.friction", "finite"]);
    }
    for (set, mu) in [("contact.friction=0.3", 0.3), ("contact.friction=0", 0.0)] {
        let scene = parse_str(&smoke_text(), Path::new(ORIGIN), &[set.into()]);
        assert_eq!(scene.unwrap().contact.friction, mu);
    }
    let text = format!("{}\n[contact]\nfriction = 0.3\n", smoke_text());
    let scene = parse_str(&text, Path::new(ORIGIN), &[]).unwrap();
    assert_eq!(scene.contact.friction, 0.3);
}

/// A target narrower than the projectile is an edge impact, not an error (the stability
/// suite's grazing scene): every particle is then a slave.
#[test]
fn target_narrower_than_projectile_is_accepted() {
    let text = smoke_with("radius = 0.04", "radius = 0.01");
    parse_str(&text, Path::new(ORIGIN), &[]).expect("an edge impact is a valid scene");
}

#[test]
fn nan_and_inf() {
    refused(
        &smoke_with("velocity = 300.0", "velocity = nan"),
        &[],
        &["projectile.velocity", "finite"],
    );
    refused(
        &smoke_with("fc = 35e6", "fc = inf"),
        &[],
        &["target.fc", "finite"],
    );
    refused(
        &smoke_with("fc = 35e6", "fc = -inf"),
        &[],
        &["target.fc", "finite"],
    );
}

#[test]
fn beyond_f32() {
    refused(
        &smoke_with("density = 2370.0", "density = 1e39"),
        &[],
        &["target.density = 1e39", "f32"],
    );
    refused(
        &smoke_with("density = 2370.0", "density = 1e-300"),
        &[],
        &["target.density = 1e-300", "f32"],
    );
}

#[test]
fn bad_override_key() {
    let err = refused(
        &smoke_text(),
        &["projectile.velcity=499"],
        &[
            "--set projectile.velcity=499",
            "projectile.velcity",
            "unknown key",
        ],
    );
    assert!(matches!(err, SceneError::BadOverride { .. }));
    refused(
        &smoke_text(),
        &["nothing.here=1"],
        &["nothing.here", "nothing"],
    );
    refused(
        &smoke_text(),
        &["projectile.velocity.x=1"],
        &["projectile.velocity", "not a table"],
    );
    refused(&smoke_text(), &["wall.z=0"], &["wall.z", "no [wall] table"]);
    refused(
        &smoke_text(),
        &["velocity"],
        &["velocity", "key.path=value"],
    );
    refused(
        &smoke_text(),
        &["projectile..velocity=1"],
        &["projectile..velocity"],
    );
}

#[test]
fn bad_override_value() {
    let err = refused(
        &smoke_text(),
        &["projectile.velocity=fast"],
        &[
            "--set projectile.velocity=fast",
            "projectile.velocity",
            "number",
        ],
    );
    assert!(matches!(err, SceneError::BadOverride { .. }));
    refused(
        &smoke_text(),
        &["projectile.velocity=-5"],
        &["projectile.velocity = -5", "[0, 5000]"],
    );
    refused(
        &smoke_text(),
        &["projectile.velocity=[1"],
        &["projectile.velocity", "cannot read"],
    );
    refused(
        &smoke_text(),
        &["contact.lambda="],
        &["contact.lambda", "no value"],
    );
    // A count may be written as a float when it is a whole number.
    let sets = ["run.max_steps=5e6".to_string()];
    let scene = parse_str(&smoke_text(), Path::new(ORIGIN), &sets).unwrap();
    assert_eq!(scene.run.max_steps, 5_000_000);
    for bad in [
        "run.max_steps=2.5",
        "run.max_steps=-1e3",
        "run.max_steps=1e20",
        "run.max_steps=100000000000000000000",
    ] {
        refused(&smoke_text(), &[bad], &[bad, "whole number"]);
    }
    // An integer beyond TOML's 64 bits (a sweep writes 1e20 so) is a number out of range, not
    // a word.
    for set in [
        "projectile.velocity=100000000000000000000",
        "projectile.velocity=-100000000000000000000",
    ] {
        let err = refused(&smoke_text(), &[set], &[set, "[0, 5000]"]);
        assert!(!err.to_string().contains("wrong type"), "{err}");
    }
    // A key set twice takes the last value, and the message names that `--set`, not the first.
    let err = refused(
        &smoke_text(),
        &["run.end_time=3e-6", "run.end_time=0"],
        &["--set run.end_time=0:", "run.end_time = 0"],
    );
    assert!(!err.to_string().contains("3e-6"), "{err}");
}

#[test]
fn empty_file() {
    let err = refused("", &[], &["run", "missing", "[run]"]);
    assert!(matches!(err, SceneError::MissingKey { .. }));
    refused("# only a comment\n", &[], &["run"]);
}

#[test]
fn syntax_error() {
    let err = refused(
        &smoke_with("velocity = 300.0", "velocity = 300..0"),
        &[],
        &["velocity = 300..0", "line 14", "syntax"],
    );
    assert!(matches!(err, SceneError::Syntax { .. }));
    refused(
        &smoke_with("velocity = 300.0", "velocity = 300.0\nvelocity = 200.0"),
        &[],
        &["velocity", "duplicate"],
    );
}

#[test]
fn both_target_and_wall() {
    let err = refused(
        &format!("{}\n[wall]\nz = 0.0\n", smoke_text()),
        &[],
        &["target, wall", "exactly one"],
    );
    assert!(matches!(err, SceneError::Conflict { .. }));
}

#[test]
fn neither_target_nor_wall() {
    let text = smoke_text();
    let without_target = &text[..text.find("[target]").unwrap()];
    refused(without_target, &[], &["target, wall", "needs one"]);
}

#[test]
fn cavity_too_big() {
    let wide = format!(
        "{}\n[projectile.cavity]\ndiameter = 0.018\nlength = 0.02\nrear_wall = 0.005\n",
        smoke_text()
    );
    refused(
        &wide,
        &[],
        &["projectile.cavity.diameter = 0.018", "narrower"],
    );
    let long = format!(
        "{}\n[projectile.cavity]\ndiameter = 0.01\nlength = 0.03\nrear_wall = 0.005\n",
        smoke_text()
    );
    refused(&long, &[], &["projectile.cavity.length = 0.03", "shorter"]);
    let partial = format!("{}\n[projectile.cavity]\ndiameter = 0.01\n", smoke_text());
    refused(&partial, &[], &["projectile.cavity.length", "missing"]);
}

#[test]
fn bad_choices_and_conflicting_keys() {
    let err = refused(
        &smoke_with("shape = \"ogive\"", "shape = \"sphere\""),
        &[],
        &["projectile.shape = \"sphere\"", "\"ogive\", \"cylinder\""],
    );
    assert!(matches!(err, SceneError::BadChoice { .. }));
    refused(
        &smoke_text(),
        &["run.backend=tpu"],
        &["run.backend", "\"auto\""],
    );
    refused(
        &smoke_text(),
        &["projectile.material.preset=mild-steel"],
        &["projectile.material.preset", "4340-rc45"],
    );
    refused(
        &smoke_text(),
        &["target.viscosity_switch=\"morris\""],
        &["target.viscosity_switch", "\"none\", \"balsara\""],
    );
    refused(
        &smoke_text(),
        &["target.velocity_filter=\"xsph\""],
        &["target.velocity_filter", "\"none\", \"linear\""],
    );
    refused(
        &smoke_text(),
        &["target.velocity_gradient=\"dual\""],
        &["target.velocity_gradient", "\"corrected\", \"conjugate\""],
    );
    refused(
        &smoke_text(),
        &[
            "target.velocity_gradient=\"conjugate\"",
            "target.velocity_filter=\"linear\"",
        ],
        &[
            "target.velocity_gradient",
            "target.velocity_filter",
            "particles' own velocities",
        ],
    );
    // The conjugate gradient is the default: the filter alone is refused too, and the message
    // names the way to filter.
    refused(
        &smoke_text(),
        &["target.velocity_filter=\"linear\""],
        &[
            "target.velocity_gradient",
            "target.velocity_filter",
            "(the default)",
            "\"corrected\" to filter",
        ],
    );
    // The reconstructed viscosity takes the particles' own velocities too.
    refused(
        &smoke_text(),
        &[
            "target.velocity_gradient=\"corrected\"",
            "target.velocity_filter=\"linear\"",
            "target.viscosity_jump=\"reconstructed\"",
        ],
        &[
            "target.viscosity_jump",
            "target.velocity_filter",
            "particles' own velocities",
        ],
    );
    refused(
        &smoke_with("shape = \"ogive\"", "shape = \"cylinder\""),
        &[],
        &["projectile.crh", "cylinder has no crh"],
    );
    refused(
        &smoke_text(),
        &["contact.kernel=\"ghosts\""],
        &["contact.kernel", "\"cut\", \"images\""],
    );
    // The images' reaction needs nodes that move by it.
    refused(
        &smoke_text(),
        &["contact.kernel=\"images\"", "contact.lambda=0"],
        &["contact.kernel", "contact.lambda", "deformable projectile"],
    );
}

#[test]
fn lead_hole_must_fit_target_and_projectile() {
    // smoke: thickness 0.05 m, spacing 2.5 mm, radius 0.04 m, projectile diameter 0.02 m.
    refused(
        &smoke_text(),
        &["target.lead_hole_depth=0.045"],
        &["target.lead_hole_depth", "0.04"],
    );
    refused(
        &smoke_text(),
        &["target.lead_hole_depth=-0.01"],
        &["target.lead_hole_depth"],
    );
    // A pilot hole narrower than the projectile: the nose cannot start down it.
    refused(
        &smoke_text(),
        &[
            "target.lead_hole_depth=0.02",
            "target.lead_hole_diameter=0.015",
            "projectile.nose_z=-0.01",
        ],
        &[
            "projectile.nose_z",
            "target.lead_hole_diameter < projectile.diameter",
        ],
    );
    let pilot = parse_str(
        &smoke_text(),
        Path::new(ORIGIN),
        &[
            "target.lead_hole_depth=0.02".into(),
            "target.lead_hole_diameter=0.015".into(),
        ],
    )
    .unwrap();
    // It starts at the face, as without a hole (a quarter spacing above it).
    assert_eq!(pilot.projectile.nose_z, 0.25 * 0.0025);
    refused(
        &smoke_text(),
        &[
            "target.lead_hole_depth=0.02",
            "target.lead_hole_diameter=0.07",
        ],
        &["target.lead_hole_diameter", "0.06"],
    );
    // The nose may start down the hole, not below its bottom.
    refused(
        &smoke_text(),
        &["target.lead_hole_depth=0.02", "projectile.nose_z=-0.021"],
        &["projectile.nose_z", "lead_hole_depth"],
    );
    parse_str(
        &smoke_text(),
        Path::new(ORIGIN),
        &[
            "target.lead_hole_depth=0.02".into(),
            "projectile.nose_z=-0.02".into(),
        ],
    )
    .unwrap();
}

/// E and ν give the solid's elastic bulk modulus, which the EOS's K₁ must match: a unit slip in
/// E (211 Pa for 211 GPa), or a Poisson's ratio the EOS does not share, is refused.
#[test]
fn elastic_moduli_must_match_the_eos() {
    let text = smoke_text();
    let conflict = [
        "projectile.material.eos_k1",
        "projectile.material.youngs_modulus",
    ];
    refused(
        &text,
        &["projectile.material.youngs_modulus=211"],
        &[&conflict[..], &["E/(3(1 − 2ν)) = 167.5 Pa"]].concat(),
    );
    let err = refused(
        &smoke_with(
            "preset = \"4340-rc45\"",
            "preset = \"4340-rc45\"\neos_k1 = 163",
        ),
        &[],
        &conflict,
    );
    assert!(matches!(err, SceneError::Conflict { .. }));
    refused(
        &text,
        &["projectile.material.poisson_ratio=0.499"],
        &[&conflict[..], &["projectile.material.poisson_ratio"]].concat(),
    );
    // Within a factor of 2 either way: the preset's K₁ is 0.97 of E/(3(1 − 2ν)).
    let sets = |k1: &str| vec![format!("projectile.material.eos_k1={k1}")];
    parse_str(&text, Path::new(ORIGIN), &sets("3.3e11")).unwrap();
    parse_str(&text, Path::new(ORIGIN), &sets("0.85e11")).unwrap();
    refused(&text, &["projectile.material.eos_k1=3.4e11"], &conflict);
    refused(&text, &["projectile.material.eos_k1=0.83e11"], &conflict);
}

/// A projectile struck faster than its own elastic waves travel (moduli or density in the
/// wrong unit) is refused: each step would carry its nodes across an element.
#[test]
fn projectile_slower_than_its_waves() {
    // Copper's K₁ follows E, so E = 3 Pa keeps the two consistent and the waves at 2 cm/s.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/taylor-copper-190.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    refused(
        &text,
        &["projectile.material.youngs_modulus=3"],
        &["projectile.velocity = 190", "0.0227 m/s"],
    );
    // Copper's waves travel at 4615 m/s.
    parse_str(
        &text,
        Path::new(ORIGIN),
        &["projectile.velocity=4600".into()],
    )
    .unwrap();
    refused(&text, &["projectile.velocity=4650"], &["4615 m/s"]);
}

/// Densities, a specific heat, a stiffness, a melting point, strengths and a rate sensitivity no
/// metal or concrete has (another unit, another material) are refused, naming the key and the
/// range; the ends of each range are accepted.
#[test]
fn material_constants_of_real_materials() {
    for (set, needles) in [
        (
            "projectile.material.density=8.96e9",
            ["projectile.material.density", "[500, 23000]"],
        ),
        (
            "projectile.material.density=1e-30",
            ["projectile.material.density", "[500, 23000]"],
        ),
        (
            "projectile.material.specific_heat=1",
            ["projectile.material.specific_heat", "[100, 4000]"],
        ),
        ("target.density=1", ["target.density = 1:", "[1000, 5000]"]),
        (
            "target.density=5001",
            ["target.density = 5001", "[1000, 5000]"],
        ),
        (
            "projectile.material.youngs_modulus=2.11e14",
            ["projectile.material.youngs_modulus", "(0, 1.2e12]"],
        ),
        (
            "projectile.material.t_melt=1e30",
            ["projectile.material.t_melt", "≤ 4000"],
        ),
        // Strengths in another unit (GPa read as MPa, MPa as Pa).
        (
            "projectile.material.jc_a=1.1e12",
            ["projectile.material.jc_a", "youngs_modulus = 2.11e11"],
        ),
        (
            "projectile.material.jc_b=510e9",
            ["projectile.material.jc_b", "youngs_modulus = 2.11e11"],
        ),
        (
            "projectile.material.jc_c=1.4",
            ["projectile.material.jc_c", "[0, 1]"],
        ),
        (
            "target.concrete.t=3.7e12",
            ["target.concrete.t", "target.fc = 3.5e7"],
        ),
        // Pressure curves in another unit: stiffer than any solid by μ = 0.1 (the run would
        // crawl on steps many times shorter).
        (
            "projectile.material.eos_k3=1e30",
            ["projectile.material.eos_k3", "stiffens"],
        ),
        (
            "target.concrete.k3=1e30",
            ["target.concrete.k3", "stiffens"],
        ),
    ] {
        refused(&smoke_text(), &[set], &needles);
    }
    let shell = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/shell-projectile.toml");
    let shell = std::fs::read_to_string(shell).unwrap();
    refused(
        &shell,
        &["projectile.cavity.filler_density=1580e3"],
        &["projectile.cavity.filler_density", "[0, 23000]"],
    );
    parse_str(
        &shell,
        Path::new(ORIGIN),
        &["projectile.cavity.filler_density=23000".to_string()],
    )
    .unwrap();
    for set in [
        "projectile.material.density=500",
        "projectile.material.density=23000",
        "projectile.material.specific_heat=100",
        "projectile.material.specific_heat=4000",
        "target.density=1000",
        "projectile.material.t_melt=4000",
        "projectile.material.jc_a=1e11",
        "projectile.material.jc_b=0",
        "projectile.material.jc_c=1",
    ] {
        parse_str(&smoke_text(), Path::new(ORIGIN), &[set.to_string()])
            .unwrap_or_else(|e| panic!("{set}: {e}"));
    }
    // A tensile strength near f_c is a valid HJC constant, but a crack band as wide as the
    // spacing would snap back at that strength: refused with the crack band, run without.
    let strong = "target.concrete.t=3.4e7".to_string();
    refused(
        &smoke_text(),
        &[strong.as_str()],
        &[
            "target.spacing",
            "crack-band",
            "target.tension = \"static\"",
        ],
    );
    parse_str(
        &smoke_text(),
        Path::new(ORIGIN),
        &[strong, "target.tension=\"static\"".to_string()],
    )
    .unwrap();
    // The stiffest allowed, with the K₁ that goes with it.
    let stiff = [
        "projectile.material.youngs_modulus=1.2e12".to_string(),
        "projectile.material.eos_k1=9e11".to_string(),
    ];
    parse_str(&smoke_text(), Path::new(ORIGIN), &stiff).unwrap();
}

#[test]
fn copper_damage_needs_constants() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/taylor-copper-190.toml");
    let err = load(&path, &["projectile.material.damage=true".into()]).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("taylor-copper-190.toml"), "{msg}");
    assert!(msg.contains("projectile.material.d1"), "{msg}");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replace(
        "preset = \"copper-ofhc-za\"",
        "preset = \"copper-ofhc-za\"\ndamage = true\nd2 = 4.89",
    );
    refused(&text, &[], &["projectile.material.d1", "damage = true"]);
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replace(
        "preset = \"copper-ofhc-za\"",
        "preset = \"copper-ofhc-za\"\nd1 = 0.5",
    );
    refused(&text, &[], &["projectile.material.d1", "damage = true"]);
}

/// A constant of the other flow-stress law is refused, naming both keys, rather than ignored;
/// the Zerilli–Armstrong constants are bounded like the Johnson–Cook ones.
#[test]
fn flow_law_keys_are_the_presets() {
    let copper = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/taylor-copper-190.toml");
    let copper = std::fs::read_to_string(copper).unwrap();
    refused(
        &copper,
        &["projectile.material.jc_c=0.02"],
        &[
            "projectile.material.jc_c",
            "projectile.material.preset",
            "Zerilli–Armstrong",
        ],
    );
    // Even out of Johnson–Cook's range, the key is named as the other law's.
    refused(
        &copper,
        &["projectile.material.jc_c=5"],
        &[
            "projectile.material.jc_c",
            "preset \"copper-ofhc-za\" takes",
        ],
    );
    refused(
        &smoke_text(),
        &["projectile.material.za_c0=4e7"],
        &[
            "projectile.material.za_c0",
            "projectile.material.preset",
            "Johnson–Cook",
        ],
    );
    refused(
        &copper,
        &["projectile.material.za_c4=0.5"],
        &["projectile.material.za_c4 = 0.5", "[0, 0.1]"],
    );
    refused(
        &copper,
        &["projectile.material.za_c0=-1"],
        &["projectile.material.za_c0 = -1"],
    );
    refused(
        &copper,
        &["projectile.material.za_c2=890e9"],
        &["projectile.material.za_c2", "youngs_modulus"],
    );
    // The Johnson–Cook copper of the taylor.csv header takes its own constants.
    parse_str(
        &copper,
        Path::new(ORIGIN),
        &[
            "projectile.material.preset=copper-ofhc".into(),
            "projectile.material.jc_c=0.02".into(),
        ],
    )
    .unwrap();
}

#[test]
fn concrete_constants_are_checked() {
    let text = format!("{}\n[target.concrete]\nmu_lock = 1e-4\n", smoke_text());
    refused(&text, &[], &["target.concrete.mu_lock", "mu_crush"]);
    // The rule's lock strain, ρ_grain/ρ₀ − 1, is ≤ 0 for a target as dense as the grains.
    refused(
        &smoke_text(),
        &["target.density=2700"],
        &["target.concrete.mu_lock", "target.density - 1 unless set"],
    );
    parse_str(
        &format!("{}\n[target.concrete]\nmu_lock = 0.05\n", smoke_text()),
        Path::new(ORIGIN),
        &["target.density=2700".to_string()],
    )
    .expect("a dense target with its own mu_lock is accepted");
    refused(
        &smoke_with("fc = 35e6", "fc = 2e6"),
        &[],
        &["target.fc = 2e6", "[5e6, 200e6]"],
    );
    refused(
        &smoke_text(),
        &["projectile.material.poisson_ratio=0.5"],
        &["projectile.material.poisson_ratio", "(0, 0.5)"],
    );
    // A Grüneisen Γ far above any solid's, which the stable step is not made for.
    refused(
        &smoke_text(),
        &["projectile.material.eos_gamma=100"],
        &["projectile.material.eos_gamma", "[0, 5]"],
    );
}

#[test]
fn unreadable_paths() {
    let missing = Path::new("cases/does-not-exist.toml");
    let msg = load(missing, &[]).unwrap_err().to_string();
    assert!(msg.starts_with("cases/does-not-exist.toml: "), "{msg}");
    assert!(!msg.contains('\n'));

    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let msg = load(&dir, &[]).unwrap_err().to_string();
    assert!(msg.contains("cases"), "{msg}");

    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("not-utf8.toml");
    std::fs::write(&tmp, b"name = \"\xff\xfe\"\n").unwrap();
    let msg = load(&tmp, &[]).unwrap_err().to_string();
    assert!(
        msg.contains("not-utf8.toml") && msg.contains("UTF-8"),
        "{msg}"
    );

    // A file that never ends is refused once it passes the limit, not read until memory runs
    // out; so is a file just over the limit, and one at it is read.
    let msg = load(Path::new("/dev/zero"), &[]).unwrap_err().to_string();
    assert!(
        msg.starts_with("/dev/zero: ") && msg.contains("larger than 1 MiB"),
        "{msg}"
    );
    let big = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("big.toml");
    let limit = penetrate::scene::SCENE_FILE_LIMIT as usize;
    let mut text = smoke_text().into_bytes();
    text.resize(limit, b'\n');
    std::fs::write(&big, &text).unwrap();
    load(&big, &[]).expect("a scene of exactly the limit is read");
    text.push(b'\n');
    std::fs::write(&big, &text).unwrap();
    let msg = load(&big, &[]).unwrap_err().to_string();
    assert!(
        msg.contains("big.toml") && msg.contains("larger than 1 MiB"),
        "{msg}"
    );
    let _ = std::fs::remove_file(&big);
}

#[test]
fn deep_nesting_is_refused() {
    let deep = vec!["a"; 10_000].join(".");
    refused(&format!("[{deep}]\nx = 1\n"), &[], &["recursion limit"]);
    refused(
        &format!("x = {}{}\n", "[".repeat(10_000), "]".repeat(10_000)),
        &[],
        &["line 1"],
    );
    refused(&smoke_text(), &[&format!("{deep}=1")], &["too many parts"]);
}

/// xorshift64: deterministic pseudo-random numbers without a dependency.
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// A few hundred random mutations of the smoke case never make the loader panic, and every
/// refusal is one line naming the file.
#[test]
fn mutations_never_panic() {
    const EXTREMES: [&str; 16] = [
        "-1e300",
        "0",
        "1e-300",
        "\"x\"",
        "x",
        "1e39",
        "-0.0",
        "nan",
        "inf",
        "-1",
        "true",
        "9223372036854775807",
        "1e-45",
        "[]",
        "{}",
        "0.5",
    ];
    let base: Vec<String> = smoke_text().lines().map(str::to_string).collect();
    let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
    let mut refusals = 0;
    for _ in 0..400 {
        let mut lines = base.clone();
        let mut overrides = Vec::new();
        for _ in 0..1 + rng.below(3) {
            let i = rng.below(lines.len());
            match rng.below(5) {
                0 => {
                    lines.remove(i);
                }
                1 | 2 => {
                    if let Some((key, _)) = lines[i].split_once('=') {
                        let value = EXTREMES[rng.below(EXTREMES.len())];
                        lines[i] = format!("{key}= {value}");
                    }
                }
                3 => {
                    let line = lines[i].clone();
                    let cut = rng.below(line.len() + 1);
                    let cut = (0..=cut).rev().find(|&c| line.is_char_boundary(c)).unwrap();
                    lines[i] = line[..cut].to_string();
                }
                _ => {
                    let keys = [
                        "projectile.velocity",
                        "target.spacing",
                        "contact.lambda",
                        "projectile.material.jc_n",
                        "target.concrete.p_lock",
                        "run.max_steps",
                        "projectile.cavity.length",
                    ];
                    let key = keys[rng.below(keys.len())];
                    let value = EXTREMES[rng.below(EXTREMES.len())];
                    overrides.push(format!("{key}={value}"));
                }
            }
        }
        let text = lines.join("\n");
        let outcome = std::panic::catch_unwind(|| parse_str(&text, Path::new(ORIGIN), &overrides));
        let result = outcome.unwrap_or_else(|_| panic!("panicked on\n{text}\n{overrides:?}"));
        if let Err(e) = result {
            refusals += 1;
            let msg = e.to_string();
            assert!(msg.starts_with(ORIGIN) && !msg.contains('\n'), "{msg}");
        }
    }
    assert!(
        refusals > 100,
        "the mutations should mostly be refused ({refusals})"
    );
}

/// Every key `check` lists for the smoke (penetration) and Taylor (wall) cases, set to each
/// extreme value: the loader refuses it with one line or accepts it, and an accepted scene then
/// either builds (meshes, target, memory estimate, first forces) or is refused with a message,
/// never a panic or a hang. This is the validator's property: what it lets through, the solver
/// can set up.
#[test]
fn extreme_values_of_every_key_never_panic() {
    const EXTREMES: [&str; 15] = [
        "-1e300", "0", "1e-300", "1e300", "-0.0", "nan", "inf", "-inf", "-1", "1e-45", "1e38",
        "0.999999", "2", "\"\"", "1e-30",
    ];
    let taylor = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/taylor-4340-208.toml");
    let (mut tried, mut accepted, mut built) = (0, 0, 0);
    for base in [smoke_text(), std::fs::read_to_string(taylor).unwrap()] {
        let scene = parse_str(&base, Path::new(ORIGIN), &[]).unwrap();
        let keys: Vec<String> = scene
            .resolved_table()
            .lines()
            .filter_map(|l| l.split_once(" = ").map(|(k, _)| k.to_string()))
            .filter(|k| k != "name")
            .collect();
        assert!(keys.len() > 40, "too few keys: {keys:?}");
        for key in &keys {
            for value in EXTREMES {
                tried += 1;
                let sets = vec![format!("{key}={value}")];
                let outcome = std::panic::catch_unwind(|| {
                    let scene = parse_str(&base, Path::new(ORIGIN), &sets)?;
                    Ok::<_, SceneError>(penetrate::solver::Simulation::new(&scene).map(|_| ()))
                });
                match outcome {
                    Err(_) => panic!("panicked on --set {key}={value}"),
                    Ok(Err(e)) => {
                        let msg = e.to_string();
                        assert!(msg.starts_with(ORIGIN) && !msg.contains('\n'), "{msg}");
                    }
                    Ok(Ok(build)) => {
                        accepted += 1;
                        match build {
                            Ok(()) => built += 1,
                            Err(e) => {
                                let msg = e.to_string();
                                assert!(!msg.is_empty() && !msg.contains('\n'), "{msg}");
                            }
                        }
                    }
                }
            }
        }
    }
    eprintln!("{tried} overrides: {accepted} accepted, {built} built");
    assert!(
        built > 100,
        "too few scenes built ({built}) to exercise the solver's set-up"
    );
}

/// Random token soup, random bytes and truncations of the smoke case: refused with one line
/// naming the file, never a panic.
#[test]
fn random_text_never_panics() {
    const TOKENS: [&str; 24] = [
        "[",
        "]",
        "[[",
        "]]",
        "=",
        "\"",
        "'",
        "\n",
        " ",
        ".",
        ",",
        "{",
        "}",
        "#",
        "projectile",
        "target",
        "velocity",
        "1e400",
        "-",
        "0x1f",
        "true",
        "nan",
        "\\u0000",
        "é",
    ];
    let smoke = smoke_text();
    let mut rng = XorShift(0xD1B5_4A32_D192_ED03);
    for round in 0..600 {
        let text: String = match round % 3 {
            0 => (0..rng.below(80))
                .map(|_| TOKENS[rng.below(TOKENS.len())])
                .collect(),
            1 => {
                let bytes: Vec<u8> = (0..rng.below(200)).map(|_| rng.next() as u8).collect();
                String::from_utf8_lossy(&bytes).into_owned()
            }
            _ => {
                let cut = rng.below(smoke.len());
                let cut = (0..=cut)
                    .rev()
                    .find(|&c| smoke.is_char_boundary(c))
                    .unwrap();
                smoke[..cut].to_string()
            }
        };
        let outcome = std::panic::catch_unwind(|| parse_str(&text, Path::new(ORIGIN), &[]));
        let result = outcome.unwrap_or_else(|_| panic!("panicked on {text:?}"));
        if let Err(e) = result {
            let msg = e.to_string();
            assert!(msg.starts_with(ORIGIN) && !msg.contains('\n'), "{msg}");
        }
    }
}
