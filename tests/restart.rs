//! `penetrate run --checkpoint-every` and `--restart`: a run killed outright and restarted
//! from its checkpoint ends as the run that was never stopped, bit for bit on the CPU path, and
//! a restart file that is damaged or of another run is refused (exit code 2), saying why.

use std::os::unix::process::ExitStatusExt as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use penetrate::solver::Checkpoint;

fn case(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name)
}

/// An empty folder of this test process.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("penetrate-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `penetrate run` of the smoke scene on the CPU, quiet, with `set` and `args`.
fn smoke(set: &[&str], args: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_penetrate"));
    command
        .arg("run")
        .arg(case("smoke.toml"))
        .args(["--backend", "cpu", "--quiet"]);
    for s in set {
        command.args(["--set", s]);
    }
    command.args(args);
    command
}

fn arg(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The files of `dir` by name, with their bytes.
fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let name = e.file_name().into_string().unwrap();
            (name, std::fs::read(e.path()).unwrap())
        })
        .collect();
    out.sort();
    out
}

/// `summary.json` of `dir` without what differs between any two runs (wall time, build).
fn physics(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    let mut summary: serde_json::Value = serde_json::from_str(&text).unwrap();
    let fields = summary.as_object_mut().unwrap();
    fields.remove("wall_s").unwrap();
    fields.remove("solver_build").unwrap();
    summary
}

/// Killed (SIGKILL) after its first checkpoint and restarted from it, a run ends with the
/// summary, history and frames of the same run never stopped; the restart writes into the
/// checkpoint's folder by default and cuts back what the killed run wrote after it.
#[test]
fn a_killed_run_restarted_ends_as_if_never_stopped() {
    killed_and_restarted("plain", &[]);
}

/// The same with wall images, whose last reaction on the projectile the checkpoint carries.
#[test]
fn a_killed_run_with_wall_images_restarted_ends_as_if_never_stopped() {
    killed_and_restarted("images", &["contact.kernel=\"images\""]);
}

/// The same from 33 mm in front of the face: the model's origin, moved with the projectile at
/// the start (`solver::RECENTRE_STEP`), comes with the checkpoint, and moves again after it as
/// the nose enters.
#[test]
fn a_killed_run_with_a_moving_origin_restarted_ends_as_if_never_stopped() {
    killed_and_restarted("origin", &["projectile.nose_z=0.033"]);
}

/// Runs the smoke scene with `extra` whole, and killed after its first checkpoint and
/// restarted, and checks that the two end with the same outputs.
fn killed_and_restarted(name: &str, extra: &[&str]) {
    let mut set = vec!["run.end_time=2e-4", "run.output_interval=2e-5"];
    set.extend_from_slice(extra);
    let whole = scratch(&format!("restart-whole-{name}"));
    let run = smoke(&set, &["--out", arg(&whole)]).output().unwrap();
    assert!(run.status.success(), "{run:?}");

    let killed = scratch(&format!("restart-killed-{name}"));
    let checkpoint = killed.join("restart.bin");
    let every = ["--checkpoint-every", "1e-5"];
    let mut child = smoke(&set, &every)
        .args(["--out", arg(&killed)])
        .spawn()
        .unwrap();
    let start = Instant::now();
    while !checkpoint.exists() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before its first checkpoint"
        );
        assert!(start.elapsed() < Duration::from_secs(120), "no checkpoint");
        std::thread::sleep(Duration::from_millis(5));
    }
    // Rows past the checkpoint in the file, so that there is something to cut back.
    let counted = Checkpoint::read(&checkpoint).unwrap().history.bytes;
    let history = killed.join("history.csv");
    while std::fs::metadata(&history).unwrap().len() <= counted {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended too soon"
        );
        assert!(start.elapsed() < Duration::from_secs(120), "no rows");
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap();
    let status = child.wait().unwrap();
    assert_eq!(
        status.signal(),
        Some(9),
        "the run ended before it was killed"
    );
    assert!(!killed.join("summary.json").exists());

    let restarted = smoke(&set, &every)
        .args(["--restart", arg(&checkpoint)])
        .output()
        .unwrap();
    assert!(restarted.status.success(), "{restarted:?}");
    assert_eq!(physics(&killed), physics(&whole));
    let outputs = |dir: &Path| -> Vec<(String, Vec<u8>)> {
        files(dir)
            .into_iter()
            .filter(|(name, _)| name != "summary.json" && name != "restart.bin")
            .collect()
    };
    let (a, b) = (outputs(&killed), outputs(&whole));
    let names = |f: &[(String, Vec<u8>)]| f.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
    assert_eq!(names(&a), names(&b));
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(x == y, "{name} differs from the uninterrupted run's");
    }
    let _ = std::fs::remove_dir_all(&whole);
    let _ = std::fs::remove_dir_all(&killed);
}

/// Every kind of restart file that cannot go on with the run is refused with exit code 2 and
/// a message naming the file and what is wrong, and leaves the output folder as it was.
#[test]
fn a_restart_file_that_does_not_fit_is_refused() {
    let dir = scratch("restart-refused");
    let set = ["run.end_time=1e-5"];
    let first = smoke(&set, &["--no-vtk", "--checkpoint-every", "5e-6"])
        .args(["--out", arg(&dir)])
        .output()
        .unwrap();
    assert!(first.status.success(), "{first:?}");
    let good = std::fs::read(dir.join("restart.bin")).unwrap();

    let refused = |file: &Path, set: &[&str], args: &[&str], says: &[&str]| {
        let before = files(&dir);
        let out: Output = smoke(set, args)
            .args(["--restart", arg(file)])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{says:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(
            stderr.contains(arg(file)),
            "the file is not named: {stderr}"
        );
        for s in says {
            assert!(stderr.contains(s), "not `{s}`: {stderr}");
        }
        assert!(files(&dir) == before, "{says:?}: the output folder changed");
    };
    let damaged = scratch("restart-damaged");
    let bad = |name: &str, bytes: &[u8]| {
        let path = damaged.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    };
    let no_vtk = ["--no-vtk"];

    refused(
        &damaged.join("none.bin"),
        &set,
        &no_vtk,
        &["cannot be read"],
    );
    let truncated = bad("truncated.bin", &good[..good.len() / 2]);
    refused(&truncated, &set, &no_vtk, &["is truncated"]);
    let mut bytes = good.clone();
    bytes[..4].copy_from_slice(b"{\"a\"");
    let magic = bad("magic.bin", &bytes);
    refused(&magic, &set, &no_vtk, &["not a penetrate restart file"]);
    let mut bytes = good.clone();
    bytes[8..12].copy_from_slice(&99u32.to_le_bytes());
    let version = bad("version.bin", &bytes);
    refused(&version, &set, &no_vtk, &["restart format version 99"]);
    let mut bytes = good.clone();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x10;
    let flipped = bad("flipped.bin", &bytes);
    refused(&flipped, &set, &no_vtk, &["is corrupt", "checksum"]);
    let mut checkpoint = Checkpoint::decode(&good).unwrap();
    checkpoint.build = "penetrate 0.0.0 0123456789abcdef".into();
    let other_build = bad("build.bin", &checkpoint.encode());
    refused(
        &other_build,
        &set,
        &no_vtk,
        &["was written by penetrate 0.0.0 0123456789abcdef"],
    );

    // The good file, with what it does not fit.
    let file = dir.join("restart.bin");
    refused(
        &file,
        &["run.end_time=1e-5", "projectile.velocity=310"],
        &no_vtk,
        &["another scene", "projectile.velocity: 300 there, 310 here"],
    );
    refused(&file, &set, &[], &["--no-vtk"]);
    let history = dir.join("history.csv");
    let mut rows = std::fs::read(&history).unwrap();
    rows[0] = b'T';
    std::fs::write(&history, &rows).unwrap();
    refused(&file, &set, &no_vtk, &["does not continue the history"]);
    std::fs::write(&history, &rows[..rows.len() / 2]).unwrap();
    refused(
        &file,
        &set,
        &no_vtk,
        &["does not continue the history", "bytes"],
    );

    for every in ["0", "-1e-5", "soon", "inf"] {
        let out = smoke(&set, &["--checkpoint-every", every, "--out", arg(&dir)])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "--checkpoint-every {every}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&damaged);
}
