//! The validated scope of a penetration: what the shipped validation covers (the Forrestal et
//! al. 1994 shots of `data/forrestal1994.csv`, in the README's accuracy table), so that `run`
//! can say in one line when a scene lies outside it. Accuracy is only known inside.

use crate::scene::{ProjectileShape, Scene};

/// Where a user reads what was validated and how well.
pub const VALIDATION_SUMMARY: &str = "README.md, \"Accuracy at a glance\"";

/// The validated shots' nose: a tangent ogive of this calibre-radius-head
/// (forrestal1994.csv's header: ogive radius 53.8 mm on a 26.9 mm shank).
pub const NOSE_CRH: f64 = 2.0;
/// Their shank diameter (m), the scale the validation holds at.
pub const DIAMETER: f64 = 0.0269;
/// Their striking speeds (m/s), least and greatest.
pub const VELOCITY: [f64; 2] = [277.0, 800.0];
/// Their concrete's unconfined strength f_c (Pa), least and greatest.
pub const FC: [f64; 2] = [32.4e6, 35.2e6];

/// Relative difference within which a nose or a diameter counts as the validated one.
const SAME: f64 = 0.01;

/// One line saying how a penetration `scene` lies outside the validated scope (nose CRH,
/// velocity, f_c, scale), or `None` inside it or for a scene without a target (a Taylor bar).
pub fn outside(scene: &Scene) -> Option<String> {
    let target = scene.target.as_ref()?;
    let p = &scene.projectile;
    let mut out = Vec::new();
    match p.shape {
        ProjectileShape::Ogive { crh } if (crh / NOSE_CRH - 1.0).abs() <= SAME => {}
        ProjectileShape::Ogive { crh } => out.push(format!("nose CRH {crh}")),
        ProjectileShape::Cylinder => out.push("a flat nose".to_string()),
    }
    let v = p.velocity.abs();
    if !(VELOCITY[0]..=VELOCITY[1]).contains(&v) {
        out.push(format!("{v} m/s"));
    }
    let fc = target.concrete.fc as f64;
    if !(FC[0]..=FC[1]).contains(&fc) {
        out.push(format!("f_c {:.1} MPa", fc / 1e6));
    }
    if (p.diameter / DIAMETER - 1.0).abs() > SAME {
        out.push(format!("diameter {} mm", p.diameter * 1e3));
    }
    (!out.is_empty()).then(|| {
        format!(
            "outside the validated scope ({}; validated: CRH {NOSE_CRH} ogive, {} mm, {}–{} m/s, \
             f_c {}–{} MPa): accuracy unknown, see {VALIDATION_SUMMARY}",
            out.join(", "),
            DIAMETER * 1e3,
            VELOCITY[0],
            VELOCITY[1],
            FC[0] / 1e6,
            FC[1] / 1e6
        )
    })
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    fn root() -> &'static Path {
        Path::new(env!("CARGO_MANIFEST_DIR"))
    }

    /// The scope's speeds and strengths are the measured shots' own range, and the shipped
    /// Forrestal cases (one per shot) are inside it; so the constants follow the data.
    #[test]
    fn the_scope_is_the_validated_shots() {
        let shots = crate::studies::validate::data::forrestal(&root().join("data")).unwrap();
        let range = |f: fn(&crate::studies::validate::data::Shot) -> f64| {
            let v: Vec<f64> = shots.iter().map(f).collect();
            [
                v.iter().copied().fold(f64::MAX, f64::min),
                v.iter().copied().fold(f64::MIN, f64::max),
            ]
        };
        let same = |a: [f64; 2], b: [f64; 2]| (0..2).all(|k| (a[k] / b[k] - 1.0).abs() < 1e-12);
        assert!(same(range(|s| s.velocity), VELOCITY));
        assert!(same(range(|s| s.fc), FC), "{:?}", range(|s| s.fc));
        for v in ["277", "499", "642", "800"] {
            let case = root().join(format!("cases/forrestal1994-{v}.toml"));
            let scene = crate::scene::load(&case, &[]).unwrap();
            assert_eq!(outside(&scene), None, "{v} m/s");
        }
    }

    /// Each of the four ways out is named, and a Taylor bar has no penetration scope.
    #[test]
    fn a_scene_outside_is_named_by_what_lies_outside() {
        let case = root().join("cases/forrestal1994-277.toml");
        let load = |set: &[&str]| {
            let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
            crate::scene::load(&case, &set).unwrap()
        };
        let line = outside(&load(&[
            "projectile.crh=3",
            "projectile.velocity=1000",
            "target.fc=58.4e6",
        ]))
        .unwrap();
        assert!(
            line.contains("nose CRH 3")
                && line.contains("1000 m/s")
                && line.contains("f_c 58.4 MPa")
                && !line.contains("diameter 26.9")
                && line.contains(VALIDATION_SUMMARY),
            "{line}"
        );
        let small = outside(&load(&[
            "projectile.diameter=0.02",
            "projectile.cavity.diameter=0.005",
        ]))
        .unwrap();
        assert!(small.contains("diameter 20 mm"), "{small}");
        let bar = crate::scene::load(&root().join("cases/taylor-4340-208.toml"), &[]).unwrap();
        assert_eq!(outside(&bar), None);
    }
}
