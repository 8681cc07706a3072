//! Taylor impact of a 4340 steel bar (Johnson & Cook 1983, `data/taylor.csv`): the FEM
//! path against a measurement, and its energy balance against a rigid frictionless wall.

use std::path::Path;

use penetrate::scene;

mod common;

/// Measured final length of the 4340 bar at 208 m/s (taylor.csv), mm.
const MEASURED_LENGTH_MM: f64 = 22.48;

/// At a coarse mesh (radius/5) the final length is within 2 % of the measurement (the project's
/// Taylor target) and the energy balance closes within 1 % of the impact energy.
#[test]
fn taylor_4340_final_length_matches_the_measurement() {
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/taylor-4340-208.toml");
    let scene = scene::load(&case, &["projectile.element_size=0.000762".to_string()]).unwrap();
    let out = std::env::temp_dir().join(format!("penetrate-test-{}-taylor", std::process::id()));
    let outcome = common::run_cpu(&scene, &out, false);
    let s = &outcome.summary;
    assert!(outcome.ok, "{}", s.status);
    let length_mm = s.final_length_m * 1e3;
    let error = (length_mm - MEASURED_LENGTH_MM) / MEASURED_LENGTH_MM;
    assert!(
        error.abs() < 0.02,
        "final length {length_mm:.3} mm vs {MEASURED_LENGTH_MM} mm measured"
    );
    assert!(
        s.max_radius_m * 1e3 > 3.81 * 1.2,
        "the foot mushroomed: radius {} mm",
        s.max_radius_m * 1e3
    );
    assert!(
        s.energy_error.abs() < 0.01,
        "energy error {}",
        s.energy_error
    );
    assert!(
        s.momentum_error < 1e-6,
        "momentum account {}",
        s.momentum_error
    );
    let _ = std::fs::remove_dir_all(&out);
}
