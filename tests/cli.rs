//! What `penetrate run` says at its start: where `--backend auto` runs and why, and whether the
//! scene lies inside the validated scope; and what the commands' help lists.

use std::path::{Path, PathBuf};
use std::process::Output;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("penetrate-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// `penetrate run cases/CASE --quiet --no-vtk --out DIR` with `args`, 0.1 µs of flight.
fn run(case: &str, dir: &Path, args: &[&str]) -> Output {
    run_whole(case, dir, &[&["--set", "run.end_time=1e-7"], args].concat())
}

/// `penetrate run cases/CASE --quiet --no-vtk --out DIR` with `args`.
fn run_whole(case: &str, dir: &Path, args: &[&str]) -> Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_penetrate"))
        .current_dir(root())
        .args([
            "run",
            &format!("cases/{case}"),
            "--quiet",
            "--no-vtk",
            "--out",
        ])
        .arg(dir)
        .args(args)
        .output()
        .unwrap()
}

/// `auto` takes a hardware GPU or, falling back to the CPU, says so first with why and the
/// steps the run will take; the summary names the path that ran. Both ways are checked by what
/// the machine has: the summary must agree with the line.
#[test]
fn auto_says_where_it_runs() {
    let dir = scratch("auto");
    let out = run("smoke.toml", &dir, &["--backend", "auto"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let fell_back = err.contains("--backend auto: ");
    match summary["backend"].as_str().unwrap() {
        "cpu" => assert!(
            fell_back && err.contains("the CPU path runs ≈ ") && err.contains("check's estimate"),
            "{err}"
        ),
        "gpu" => assert!(!fell_back, "{err}"),
        other => panic!("backend {other}"),
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Without a usable adapter (no Vulkan driver at all), `auto` falls back and says why.
#[test]
fn auto_without_an_adapter_falls_back_to_the_cpu() {
    let dir = scratch("no-adapter");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penetrate"))
        .current_dir(root())
        .env("VK_DRIVER_FILES", "/nonexistent")
        .env("VK_ICD_FILENAMES", "/nonexistent")
        .args([
            "run",
            "cases/smoke.toml",
            "--quiet",
            "--no-vtk",
            "--backend",
            "auto",
        ])
        .args(["--set", "run.end_time=1e-7", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("--backend auto: no GPU adapter") && err.contains("the CPU path runs"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A shipped Forrestal shot is inside the validated scope and says nothing of it; the smoke
/// scene's small projectile is outside and says so in one line beside its result, naming the
/// scale and where the validation summary is.
#[test]
fn a_scene_outside_the_validated_scope_is_told_so() {
    let dir = scratch("scope");
    let said = |out: &Output| {
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr)
    };
    let out = run("forrestal1994-277.toml", &dir, &["--backend", "cpu"]);
    assert!(out.status.success(), "{}", said(&out));
    assert!(!said(&out).contains("validated scope"), "{}", said(&out));
    let out = run("smoke.toml", &dir, &["--backend", "cpu"]);
    let text = said(&out);
    let lines: Vec<&str> = text
        .lines()
        .filter(|l| l.contains("validated scope"))
        .collect();
    assert_eq!(lines.len(), 1, "{text}");
    assert!(
        lines[0].starts_with("note: outside the validated scope (diameter 20 mm")
            && lines[0].contains("see README.md, \"Accuracy at a glance\""),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A penetration that reaches its end time with the projectile still going (the smoke scene
/// stops after 20 µs at 299 m/s) says that its depth is not final.
#[test]
fn a_penetration_cut_short_says_its_depth_is_not_final() {
    let dir = scratch("unfinished");
    let out = run_whole("smoke.toml", &dir, &["--backend", "cpu"]);
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{text}");
    // Struck at 300 m/s, it has lost a few m/s by then.
    let speed: f64 = text
        .split("warning: the projectile still moves at ")
        .nth(1)
        .and_then(|rest| {
            rest.split(" m/s at the end time, so the depth is not final")
                .next()
        })
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{text}"));
    assert!((250.0..300.0).contains(&speed), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `validate --help` names every section `--only` takes.
#[test]
fn validate_help_names_every_section() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_penetrate"))
        .args(["validate", "--help"])
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&out.stdout).into_owned();
    let listed: Vec<&str> = help
        .lines()
        .find(|l| l.contains("--only"))
        .and_then(|l| l.split_once("(comma-separated):"))
        .map(|(_, list)| {
            list.split(',')
                .map(|s| s.trim().trim_end_matches('.'))
                .collect()
        })
        .unwrap_or_default();
    for section in penetrate::studies::validate::Section::ALL {
        assert!(
            listed.contains(&section.name()),
            "validate --help does not name `{}` in --only's list {listed:?}",
            section.name()
        );
    }
}
