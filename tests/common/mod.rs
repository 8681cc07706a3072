//! Helpers shared by the integration tests (each test crate uses some of them).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use penetrate::scene::{Backend, Scene};
use penetrate::solver::{self, Model, RunOptions, RunOutcome};

/// `penetrate run` of `scene` on the CPU path into `out`, quiet, with or without VTK frames.
pub fn run_cpu(scene: &Scene, out: &Path, vtk: bool) -> RunOutcome {
    solver::run(
        scene,
        &RunOptions {
            out: out.to_path_buf(),
            quiet: true,
            vtk,
            backend: Some(Backend::Cpu),
            adapter: None,
            checkpoint_every: None,
            restart: None,
            share: None,
        },
    )
    .unwrap()
}

/// `err` names the entity of `sim` whose own stable step is the least, and where it is.
pub fn assert_smallest_step_named(sim: &Model, err: &str) {
    let e = &sim.projectile.elements;
    let p = &sim.particles;
    let sph = sim.sph.as_ref().unwrap();
    let element = (0..e.len())
        .min_by(|&a, &b| e.dt[a].total_cmp(&e.dt[b]))
        .unwrap();
    let step = |i| penetrate::cpu::timestep::particle_step(p, sph, i);
    let particle = (0..p.len())
        .min_by(|&a, &b| step(a).total_cmp(&step(b)))
        .unwrap();
    let named = if e.dt[element] <= step(particle) {
        format!("element {element} has the smallest stable step")
    } else {
        format!("particle {particle} has the smallest stable step")
    };
    assert!(
        err.contains(&named) && err.contains(" at (r "),
        "{err}: not {named}"
    );
}

/// A column of the `history.csv` in `dir`, by header name.
pub fn history_column(dir: &Path, name: &str) -> Vec<f64> {
    let path = dir.join("history.csv");
    let file = std::fs::File::open(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut columns = penetrate::output::history::read_columns(&path, file, &[name])
        .unwrap_or_else(|e| panic!("{e}"));
    columns.remove(0)
}

/// The header and the rows of the CSV file `path`, `#` lines skipped. Rows may differ in
/// length from the header (the caller checks).
pub fn csv_file(path: &Path) -> (csv::StringRecord, Vec<csv::StringRecord>) {
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .flexible(true)
        .from_path(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header = reader
        .headers()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .clone();
    let rows = reader
        .records()
        .map(|r| r.unwrap_or_else(|e| panic!("{}: {e}", path.display())))
        .collect();
    (header, rows)
}

/// The repository's root: the shipped cases and data are read from it.
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A fresh folder under the temp dir for one test, `penetrate-<tag>-<pid>-<name>`.
pub fn scratch(tag: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("penetrate-{tag}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// The built `penetrate` binary with `args`, run from the repository's root.
pub fn penetrate(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_penetrate"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("the penetrate binary runs")
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}
