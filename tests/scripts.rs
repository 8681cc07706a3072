//! The set-up the two README commands share (`scripts/setup.sh`): its Rust version gate keeps a
//! recent enough `cargo` and replaces an older one, and its minimum is what the locked crates
//! ask for.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// `PENETRATE_MIN_RUST` as `scripts/setup.sh` sets it.
fn scripted_minimum() -> String {
    let text = std::fs::read_to_string(root().join("scripts/setup.sh")).expect("scripts/setup.sh");
    text.lines()
        .find_map(|l| l.strip_prefix("PENETRATE_MIN_RUST="))
        .expect("scripts/setup.sh sets PENETRATE_MIN_RUST")
        .trim()
        .to_string()
}

/// A version `major.minor[.patch]` as three numbers (a missing patch is 0).
fn version(text: &str) -> [u64; 3] {
    let mut v = [0; 3];
    for (slot, part) in v.iter_mut().zip(text.split('.')) {
        *slot = part.parse().unwrap_or_else(|_| panic!("version {text}"));
    }
    v
}

/// Whether the gate takes a `cargo` that reports `reported` as recent enough: a stand-in
/// `cargo` first on a PATH that holds nothing else of Rust.
fn gate_accepts(dir: &Path, reported: &str) -> bool {
    std::fs::write(
        dir.join("cargo"),
        format!("#!/bin/sh\necho 'cargo {reported} (0 2026-01-01)'\n"),
    )
    .unwrap();
    let chmod = Command::new("chmod")
        .arg("+x")
        .arg(dir.join("cargo"))
        .status()
        .unwrap();
    assert!(chmod.success());
    gate_passes(dir)
}

/// Whether `setup_cargo_recent` succeeds on a PATH of `dir` and the system's directories.
fn gate_passes(dir: &Path) -> bool {
    Command::new("bash")
        .arg("-c")
        .arg("source scripts/setup.sh && setup_cargo_recent")
        .current_dir(root())
        .env("PATH", format!("{}:/usr/bin:/bin", dir.display()))
        .status()
        .expect("bash")
        .success()
}

#[test]
fn the_rust_version_gate_keeps_a_recent_cargo_and_replaces_an_older_one() {
    let dir: PathBuf =
        std::env::temp_dir().join(format!("penetrate-test-{}-scripts", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let min = scripted_minimum();
    let v = version(&min);
    let (major, minor) = (v[0], v[1]);
    assert!(
        gate_accepts(&dir, &format!("{major}.{minor}.0")),
        "{min}.0 refused"
    );
    assert!(
        gate_accepts(&dir, &format!("{major}.{}.3", minor + 10)),
        "a newer minor refused"
    );
    assert!(
        !gate_accepts(&dir, &format!("{major}.{}.9", minor - 1)),
        "an older minor kept"
    );
    assert!(!gate_accepts(&dir, "1.63.0"), "Debian 12's cargo kept");
    // No cargo at all: the stand-in removed.
    std::fs::remove_file(dir.join("cargo")).unwrap();
    assert!(!gate_passes(&dir), "no cargo taken for a recent one");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_scripted_minimum_is_what_the_locked_crates_ask() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let host = Command::new("rustc")
        .arg("-vV")
        .output()
        .expect("rustc -vV");
    let host = String::from_utf8_lossy(&host.stdout)
        .lines()
        .find_map(|l| l.strip_prefix("host: ").map(str::to_string))
        .expect("rustc -vV names the host");
    let out = Command::new(cargo)
        .args([
            "metadata",
            "--format-version",
            "1",
            "--locked",
            "--offline",
            "--filter-platform",
        ])
        .arg(&host)
        .current_dir(root())
        .output()
        .expect("cargo metadata");
    assert!(
        out.status.success(),
        "cargo metadata: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let meta: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let asked = meta["packages"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|p| Some((p["rust_version"].as_str()?, p["name"].as_str()?)))
        .max_by_key(|(v, _)| version(v))
        .expect("some crate names a rust-version");
    assert_eq!(
        version(&scripted_minimum()),
        version(asked.0),
        "scripts/setup.sh's PENETRATE_MIN_RUST against {} {} (the locked crates' highest)",
        asked.1,
        asked.0
    );
}
