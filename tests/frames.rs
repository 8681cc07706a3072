//! A run's binary VTK frames read back.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use penetrate::output::vtk;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("penetrate-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn penetrate(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_penetrate"))
        .args(args)
        .arg(dir)
        .output()
        .unwrap()
}

/// The smoke case for 4 µs with a frame every µs, on the CPU, into `dir` (`extra` added).
fn short_smoke_run(dir: &Path, extra: &[&str]) {
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/smoke.toml");
    let mut args = vec!["run", case.to_str().unwrap(), "--backend", "cpu", "--quiet"];
    args.extend([
        "--set",
        "run.end_time=4e-6",
        "--set",
        "run.output_interval=1e-6",
    ]);
    args.extend(extra);
    args.push("--out");
    let out = penetrate(&args, dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Every frame of a short run reads back: the collection lists a target and a projectile file
/// for each frame, each with the summary's particles, nodes and elements, the fields by name,
/// and finite values. Frames change nothing of the run: its history is the one a run without
/// them writes, byte for byte.
#[test]
fn a_runs_frames_read_back() {
    let dir = scratch("frames");
    short_smoke_run(&dir, &[]);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let count = |key: &str| summary[key].as_u64().unwrap() as usize;
    let (particles, nodes, elements) = (count("particles"), count("nodes"), count("elements"));
    let listed = vtk::read_pvd(&dir.join("frames.pvd")).unwrap();
    // At t = 0, every µs and at the end.
    assert_eq!(listed.len(), 2 * 5, "{listed:?}");
    for set in &listed {
        let grid = vtk::read_vtu(&dir.join(&set.file)).unwrap();
        let (points, names, cells, cell_names): (usize, &[&str], usize, &[&str]) = match set.part {
            0 => (
                particles,
                &[
                    "pressure",
                    "density",
                    "damage",
                    "plastic_strain",
                    "speed",
                    "v_r",
                    "v_z",
                    "energy",
                    "strain_energy",
                    "mass",
                ],
                particles,
                &[],
            ),
            _ => (
                nodes,
                &["v_r", "v_z"],
                elements,
                &[
                    "damage",
                    "failed",
                    "plastic_strain",
                    "pressure",
                    "von_mises",
                    "temperature",
                ],
            ),
        };
        assert!(set
            .file
            .starts_with(["target_", "projectile_"][set.part.min(1)]));
        assert_eq!(grid.triangles.is_some(), set.part == 1, "{}", set.file);
        assert_eq!(
            (grid.r.len(), grid.z.len()),
            (points, points),
            "{}",
            set.file
        );
        assert_eq!(grid.cells(), cells, "{}", set.file);
        for (fields, expected, len) in [
            (&grid.point_data, names, points),
            (&grid.cell_data, cell_names, cells),
        ] {
            let read: Vec<&str> = fields.iter().map(|(n, _)| n.as_str()).collect();
            assert_eq!(read, expected, "{}", set.file);
            for (name, values) in fields {
                assert_eq!(values.len(), len, "{} {name}", set.file);
                assert!(values.iter().all(|v| v.is_finite()), "{} {name}", set.file);
            }
        }
        assert!(grid.r.iter().chain(&grid.z).all(|v| v.is_finite()));
    }
    let without = scratch("no-frames");
    short_smoke_run(&without, &["--no-vtk"]);
    let history = |d: &Path| std::fs::read(d.join("history.csv")).unwrap();
    assert_eq!(history(&dir), history(&without), "frames changed the run");

    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&without);
}
