//! `penetrate sweep … --emit slurm DIR` and `penetrate sweep --collect DIR` through the built
//! binary, the array's tasks run as Slurm runs them: `bash DIR/sweep.sbatch` with the job
//! array's environment variables, one process per task. No Slurm is needed; a real one was not
//! at hand where these were written (see docs/cli.md, "sweep").
#![cfg(unix)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;

use common::{penetrate, root, stderr, stdout};

fn scratch(name: &str) -> PathBuf {
    common::scratch("slurm", name)
}

/// The smoke scene over three speeds, 10 µs of flight each, on the CPU without frames.
const PLAN: [&str; 10] = [
    "cases/smoke.toml",
    "--vary",
    "projectile.velocity=200:400:100",
    "--set",
    "run.end_time=1e-5",
    "--backend",
    "cpu",
    "--no-vtk",
    "--sbatch",
    "--partition=debug --time=10",
];

/// `penetrate sweep PLAN --emit slurm DIR` with `more`.
fn emit(dir: &Path, more: &[&str]) -> Output {
    let mut args = vec!["sweep"];
    args.extend(PLAN);
    args.extend(["--emit", "slurm", dir.to_str().unwrap()]);
    args.extend(more);
    penetrate(&args)
}

/// Array task `task` of job 4242 as Slurm starts it: the batch script run by bash in a fresh
/// process with the job array's variables, its output into the log `--output` names, and
/// `PENETRATE` naming `exe` (the penetrate under test, or a wrapper of it).
fn task(dir: &Path, task: &str, exe: &Path) -> Output {
    let log = dir.join("logs").join(format!("4242_{task}.out"));
    let out = Command::new("bash")
        .arg(dir.join("sweep.sbatch"))
        .current_dir(std::env::temp_dir())
        .env("PENETRATE", exe)
        .env("SLURM_ARRAY_JOB_ID", "4242")
        .env(
            "SLURM_JOB_ID",
            format!("{}", 4243 + task.parse::<u64>().unwrap_or(0)),
        )
        .env("SLURM_ARRAY_TASK_ID", task)
        .env("SLURM_ARRAY_TASK_MIN", "0")
        .env("SLURM_ARRAY_TASK_MAX", "2")
        .env("SLURM_ARRAY_TASK_COUNT", "3")
        .output()
        .expect("bash runs");
    std::fs::write(log, [out.stdout.as_slice(), &out.stderr].concat()).unwrap();
    out
}

fn bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_penetrate"))
}

/// The rows of a `sweep.csv`, header first.
fn csv_rows(path: &Path) -> Vec<Vec<String>> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_path(path)
        .unwrap();
    reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect()
}

/// The emit writes one resolved scene per member (the very scene the in-process sweep runs),
/// the manifest, and an array script of one task per member, or of `--members-per-task`
/// members; it runs nothing and opens no GPU. A folder that holds something else is refused.
#[test]
fn emit_writes_scenes_a_manifest_and_an_array_script() {
    let dir = scratch("emit");
    let o = emit(&dir, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let shown = dir.display();
    let said = stdout(&o);
    assert!(
        said.contains(&format!("sbatch {shown}/sweep.sbatch")),
        "{said}"
    );
    assert!(
        said.contains(&format!("penetrate sweep --collect {shown}")),
        "{said}"
    );
    assert!(
        stderr(&o).contains("3 runs of cases/smoke.toml"),
        "{}",
        stderr(&o)
    );

    let labels = ["velocity-200", "velocity-300", "velocity-400"];
    for (label, v) in labels.iter().zip(["200", "300", "400"]) {
        let file = dir.join(format!("scenes/{label}.toml"));
        let mut emitted = penetrate::scene::load(&file, &[]).unwrap();
        let sets = [
            "run.end_time=1e-5".to_string(),
            format!("projectile.velocity={v}"),
        ];
        let planned = penetrate::scene::load(&root().join("cases/smoke.toml"), &sets).unwrap();
        emitted.path = planned.path.clone();
        assert_eq!(emitted, planned, "{label}");
        assert!(!dir.join(label).exists(), "nothing runs");
    }
    let manifest = std::fs::read_to_string(dir.join("members.csv")).unwrap();
    assert_eq!(
        manifest,
        "index,task,projectile.velocity,scene,dir,backend\n\
         0,0,200,scenes/velocity-200.toml,velocity-200,cpu\n\
         1,1,300,scenes/velocity-300.toml,velocity-300,cpu\n\
         2,2,400,scenes/velocity-400.toml,velocity-400,cpu\n"
    );
    let script = std::fs::read_to_string(dir.join("sweep.sbatch")).unwrap();
    for line in [
        "#!/bin/bash",
        "#SBATCH --job-name=penetrate-smoke-velocity",
        "#SBATCH --array=0-2",
        &format!("#SBATCH --output={shown}/logs/%A_%a.out"),
        "#SBATCH --partition=debug",
        "#SBATCH --time=10",
        "set -euo pipefail",
        &format!("penetrate=${{PENETRATE:-'{}'}}", bin().display()),
        "members=('velocity-200' 'velocity-300' 'velocity-400')",
    ] {
        assert!(script.lines().any(|l| l == line), "{line}:\n{script}");
    }
    assert!(
        script.contains("--quiet --backend cpu --no-vtk"),
        "{script}"
    );
    assert!(
        dir.join("logs").is_dir(),
        "Slurm does not make the log folder"
    );
    // Every #SBATCH line comes before the first command, where sbatch stops reading them.
    let first_command = script
        .lines()
        .position(|l| !l.is_empty() && !l.starts_with('#'))
        .unwrap();
    assert!(script
        .lines()
        .skip(first_command)
        .all(|l| !l.starts_with("#SBATCH")));

    // The same plan again, two members per task: the array halves, the scenes stay.
    let o = emit(&dir, &["--members-per-task", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let script = std::fs::read_to_string(dir.join("sweep.sbatch")).unwrap();
    assert!(script.contains("#SBATCH --array=0-1\n"), "{script}");
    let manifest = std::fs::read_to_string(dir.join("members.csv")).unwrap();
    let tasks: Vec<&str> = manifest.lines().skip(1).map(|l| &l[2..3]).collect();
    assert_eq!(tasks, ["0", "0", "1"], "{manifest}");

    // Another plan into the same folder, or into a folder of other files, is refused.
    let mut args = vec!["sweep"];
    args.extend(PLAN);
    args[3] = "projectile.velocity=200:500:100";
    let o = penetrate(&[&args[..], &["--emit", "slurm", dir.to_str().unwrap()]].concat());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("holds another emitted sweep"),
        "{}",
        stderr(&o)
    );
    let other = scratch("emit-other");
    std::fs::create_dir_all(&other).unwrap();
    std::fs::write(other.join("notes.txt"), "mine").unwrap();
    let o = emit(&other, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("holds no emitted sweep"),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        std::fs::read_dir(&other).unwrap().count(),
        1,
        "nothing written"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&other);
}

/// `--backend gpu` is written for the nodes to open: the emit needs no adapter of its own.
#[test]
fn emit_for_the_gpu_needs_no_gpu_here() {
    let dir = scratch("emit-gpu");
    let o = Command::new(env!("CARGO_BIN_EXE_penetrate"))
        .current_dir(root())
        .env("VK_DRIVER_FILES", "/nonexistent")
        .env("VK_ICD_FILENAMES", "/nonexistent")
        .args([
            "sweep",
            "cases/smoke.toml",
            "--vary",
            "projectile.velocity=200:300:100",
        ])
        .args([
            "--backend",
            "gpu",
            "--adapter",
            "NVIDIA H200",
            "--emit",
            "slurm",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let script = std::fs::read_to_string(dir.join("sweep.sbatch")).unwrap();
    assert!(
        script.contains("--quiet --backend gpu --adapter 'NVIDIA H200' ||"),
        "{script}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The array's tasks, each run as Slurm runs it, give the sweep the in-process sweep gives:
/// `--collect` writes a `sweep.csv` whose every column but the wall time and the folder is the
/// same, bit for bit on the CPU path; each member ran its emitted scene, with the sweep's flags,
/// by the `penetrate` that `PENETRATE` names.
#[test]
fn the_array_run_task_by_task_is_the_sweep_run_here() {
    let base = scratch("array");
    let (emitted, here) = (base.join("emitted"), base.join("here"));
    let o = emit(&emitted, &[]);
    assert!(o.status.success(), "{}", stderr(&o));

    // A `penetrate` that notes how it was called, so that PENETRATE is seen to be taken.
    let wrapper = base.join("penetrate-wrapper");
    let calls = base.join("calls.txt");
    std::fs::write(
        &wrapper,
        format!(
            "#!/bin/bash\necho \"$*\" >> '{}'\nexec '{}' \"$@\"\n",
            calls.display(),
            bin().display()
        ),
    )
    .unwrap();
    std::fs::set_permissions(
        &wrapper,
        std::os::unix::fs::PermissionsExt::from_mode(0o755),
    )
    .unwrap();
    for i in ["0", "1", "2"] {
        let o = task(&emitted, i, &wrapper);
        assert!(o.status.success(), "task {i}: {}", stderr(&o));
        assert!(
            stdout(&o).contains(&format!("task {i} of array job 4242")),
            "{}",
            stdout(&o)
        );
    }
    let calls = std::fs::read_to_string(&calls).unwrap();
    let e = emitted.display();
    for label in ["velocity-200", "velocity-300", "velocity-400"] {
        let call =
            format!("run {e}/scenes/{label}.toml --out {e}/{label} --quiet --backend cpu --no-vtk");
        assert!(calls.lines().any(|l| l == call), "{call}:\n{calls}");
        let ran = std::fs::read(emitted.join(label).join("scene.toml")).unwrap();
        let scene = std::fs::read(emitted.join(format!("scenes/{label}.toml"))).unwrap();
        assert!(
            ran == scene,
            "{label}: the run's scene.toml is its emitted scene"
        );
    }

    let o = penetrate(&["sweep", "--collect", emitted.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains(&format!("{e}/sweep.csv")),
        "{}",
        stdout(&o)
    );
    assert!(
        stderr(&o).contains("3 completed, 0 missing, 0 failed"),
        "{}",
        stderr(&o)
    );
    let mut args = vec!["sweep"];
    args.extend(&PLAN[..8]);
    let o = penetrate(&[&args[..], &["--out", here.to_str().unwrap()]].concat());
    assert!(o.status.success(), "{}", stderr(&o));

    let (collected, swept) = (
        csv_rows(&emitted.join("sweep.csv")),
        csv_rows(&here.join("sweep.csv")),
    );
    assert_eq!(collected[0], swept[0], "the same columns");
    assert_eq!(collected.len(), 4);
    let header = &swept[0];
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (wall, dir) = (column("wall_s"), column("dir"));
    for (c, s) in collected.iter().zip(&swept).skip(1) {
        for (i, name) in header.iter().enumerate() {
            if i == dir {
                let label = Path::new(&s[i]).file_name().unwrap();
                assert_eq!(Path::new(&c[i]), emitted.join(label), "{name}");
            } else if i != wall {
                assert_eq!(c[i], s[i], "{name} of {}", s[0]);
            }
        }
        assert_eq!(c[column("status")], "completed");
    }
    let _ = std::fs::remove_dir_all(&base);
}

/// `--collect` names each member without a completed run and the array task to run again,
/// and exits 1: one never run (missing), one that went unstable (failed), one run by another
/// build than the rest. The script refuses a task id outside the array with exit 2 and runs
/// nothing. A folder with no emitted sweep is refused with exit 2.
#[test]
fn collect_names_what_did_not_complete_and_a_task_outside_the_array_fails() {
    let dir = scratch("collect");
    let o = emit(&dir, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let collect = || penetrate(&["sweep", "--collect", dir.to_str().unwrap()]);

    for (id, says) in [
        (
            "3",
            "SLURM_ARRAY_TASK_ID=3 is out of range: not one of this sweep's tasks, 0-2",
        ),
        ("-1", "SLURM_ARRAY_TASK_ID=-1 is out of range"),
        ("x", "SLURM_ARRAY_TASK_ID=x is out of range"),
    ] {
        let o = task(&dir, id, &bin());
        assert_eq!(o.status.code(), Some(2), "{id}: {}", stderr(&o));
        assert!(stderr(&o).contains(says), "{id}: {}", stderr(&o));
    }
    let o = Command::new("bash")
        .arg(dir.join("sweep.sbatch"))
        .env_remove("SLURM_ARRAY_TASK_ID")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("SLURM_ARRAY_TASK_ID is not set"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.join("velocity-200").exists(), "nothing ran");

    // Tasks 0 and 2 ran; task 1 never did.
    for i in ["0", "2"] {
        assert!(task(&dir, i, &bin()).status.success());
    }
    let o = collect();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("missing: velocity-300 (array task 1): no summary.json"),
        "{err}"
    );
    assert!(err.contains("2 completed, 1 missing, 0 failed"), "{err}");
    assert!(
        err.contains(&format!(
            "`sbatch --array=1 {}/sweep.sbatch`",
            dir.display()
        )),
        "{err}"
    );
    let rows = csv_rows(&dir.join("sweep.csv"));
    assert_eq!(rows.len(), 4, "every member has its row");
    assert!(
        rows[2][1].starts_with("missing: no summary.json"),
        "{:?}",
        rows[2]
    );

    // Task 1 runs; the 400 m/s member is made to read as unstable.
    assert!(task(&dir, "1", &bin()).status.success());
    let edit = |label: &str, field: &str, value: &str| {
        let path = dir.join(label).join("summary.json");
        let mut s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        s[field] = value.into();
        std::fs::write(&path, s.to_string()).unwrap();
    };
    edit("velocity-400", "status", "unstable: made so by the test");
    let o = collect();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("failed: velocity-400 (array task 2): unstable: made so"),
        "{err}"
    );
    assert!(err.contains("--array=2 "), "{err}");
    assert_eq!(
        csv_rows(&dir.join("sweep.csv"))[3][1],
        "unstable: made so by the test"
    );

    // Rerun, it completes; a member from another build keeps the sweep from being one.
    assert!(task(&dir, "2", &bin()).status.success());
    assert!(collect().status.success(), "{}", stderr(&collect()));
    edit(
        "velocity-200",
        "solver_build",
        "penetrate 0.0.1 0123456789abcdef",
    );
    let o = collect();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("ran on penetrate 0.0.1 0123456789abcdef: velocity-200\n"),
        "{err}"
    );
    assert!(err.contains("on 2 builds"), "{err}");

    // Misuse.
    let o = penetrate(&["sweep", "--collect", root().join("cases").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("no members.csv"), "{}", stderr(&o));
    let o = penetrate(&[
        "sweep",
        "--collect",
        dir.to_str().unwrap(),
        "--vary",
        "k=1:2:1",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("cannot be used with"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&dir);
}
