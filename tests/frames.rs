//! A run's binary VTK frames read back, and `penetrate plot` of what a run wrote.
//!
//! One file for both: every file in tests/ is a binary of its own, linked against the whole
//! solver, and the plots are drawn from the frames the first test reads.

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

/// Width, height and RGB bytes of a PNG.
fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
    let bytes = std::fs::read(path).unwrap();
    assert!(
        bytes.starts_with(b"\x89PNG\r\n\x1a\n"),
        "{} is not a PNG",
        path.display()
    );
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().unwrap();
    let mut rgb = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut rgb).unwrap();
    rgb.truncate(info.buffer_size());
    (info.width, info.height, rgb)
}

fn distinct_colours(rgb: &[u8]) -> usize {
    let mut colours: Vec<&[u8]> = rgb.chunks(3).collect();
    colours.sort_unstable();
    colours.dedup();
    colours.len()
}

/// Every frame of a short run reads back: the collection lists a target and a projectile file
/// for each frame, each with the summary's particles, nodes and elements, the fields by name,
/// and finite values. Frames change nothing of the run: its history is the one a run without
/// them writes, byte for byte. `penetrate plot` then draws the curves and the final fields, in
/// colour; without frames, the curves alone, saying why.
#[test]
fn a_runs_frames_read_back_and_plot() {
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

    let out = penetrate(&["plot"], &dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let pictures = [
        "depth.png",
        "velocity.png",
        "deceleration.png",
        "contact-force.png",
        "damage.png",
        "pressure.png",
    ];
    for name in pictures {
        let (width, height, rgb) = decode(&dir.join(name));
        assert!(width >= 400 && height >= 200, "{name}: {width}×{height}");
        // A chart is white, black, greys and its curves' colours, drawn along them; a field
        // map has a colour scale's worth.
        let colours = distinct_colours(&rgb);
        if name == "damage.png" || name == "pressure.png" {
            assert!(colours > 16, "{name}: {colours} colours");
        } else {
            let curve = rgb
                .chunks(3)
                .filter(|p| p[0] != p[1] || p[1] != p[2])
                .count();
            assert!(
                colours >= 4 && curve > 200,
                "{name}: {colours} colours, {curve} px of curve"
            );
        }
    }
    let out = penetrate(&["plot"], &without);
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(said.contains("field pictures need frames"), "{said}");
    for name in pictures {
        let field = name == "damage.png" || name == "pressure.png";
        assert_eq!(without.join(name).is_file(), !field, "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&without);
}

/// `penetrate plot` of a folder that is not a run's, or whose history or frames are broken,
/// names the file and exits with code 2, drawing nothing.
#[test]
fn plot_refuses_a_broken_run_folder() {
    let dir = scratch("plot-broken");
    let refused = |why: &str| {
        let out = penetrate(&["plot"], &dir);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains(why) && !err.contains("panicked"), "{err}");
        assert!(!dir.join("depth.png").exists());
    };
    refused("penetrate-test");
    std::fs::create_dir_all(&dir).unwrap();
    refused("history.csv");
    std::fs::write(dir.join("history.csv"), "time_s,depth_m\n0,0\n").unwrap();
    refused("history.csv: no column projectile_velocity_m_s");
    let header = penetrate::output::history::header().unwrap();
    let columns = header.split(',').count();
    let row = vec!["0"; columns].join(",");
    std::fs::write(dir.join("history.csv"), format!("{header}\n{row}\n")).unwrap();
    std::fs::write(dir.join("frames.pvd"), "not a collection").unwrap();
    refused("frames.pvd: not a VTK collection");
    let collection = "<VTKFile type=\"Collection\"><DataSet timestep=\"0\" file=\"t.vtu\"/>";
    std::fs::write(dir.join("frames.pvd"), collection).unwrap();
    std::fs::write(
        dir.join("t.vtu"),
        b"<VTKFile type=\"UnstructuredGrid\">\x00",
    )
    .unwrap();
    refused("t.vtu: ");
    let _ = std::fs::remove_dir_all(&dir);
}
