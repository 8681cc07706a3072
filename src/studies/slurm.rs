//! `penetrate sweep … --emit slurm DIR` and `penetrate sweep --collect DIR`: a sweep planned
//! here exactly as the in-process sweep plans it ([`sweep::plan_members`]), run by a cluster's
//! own scheduler as a Slurm job array of `penetrate run`s, and its summaries collected into the
//! in-process sweep's `sweep.csv` ([`sweep::write_sweep_csv`]).
//!
//! DIR holds `scenes/<label>.toml` (each member's resolved scene: what its run writes as
//! `scene.toml`), `members.csv` (the manifest `--collect` reads), `sweep.sbatch` (the array
//! script), `logs/` (one log per array task) and, once the tasks run, one run folder per member,
//! named as the in-process sweep names it (`velocity-300/`).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::sweep::{self, NoSummary, Planned, RunRecord, SweepError, Vary};
use crate::scene::{self, Backend};

/// The manifest: one row per member, `index,task,<varied key>,scene,dir,backend`, the paths
/// relative to DIR.
pub const MANIFEST: &str = "members.csv";

/// The job-array script.
pub const SCRIPT: &str = "sweep.sbatch";

/// The folder of the members' scene files.
const SCENES: &str = "scenes";

/// The folder of the array tasks' logs: Slurm does not make the folder of `--output` itself,
/// and a task whose log cannot be opened fails without a word.
const LOGS: &str = "logs";

/// Options the script sets itself, long and short forms: one more `#SBATCH` line of them
/// would leave it unclear which one Slurm takes.
const SCRIPT_SETS: [(&str, &str); 4] = [
    ("--array", "-a"),
    ("--job-name", "-J"),
    ("--output", "-o"),
    ("--error", "-e"),
];

/// How the members run on the cluster: the flags every `penetrate run` is given, and the
/// script's Slurm options.
#[derive(Clone, Debug)]
pub struct EmitOptions {
    /// `--backend` of every run, as the sweep was given it (`None`: each scene's
    /// `run.backend`): `auto` is resolved on the node that runs, not where the sweep is emitted.
    pub backend: Option<Backend>,
    /// `--adapter` of every run.
    pub adapter: Option<String>,
    /// Write VTK frames (else `--no-vtk`).
    pub vtk: bool,
    /// Members one array task runs, one after the other (1: one member per task).
    pub per_task: usize,
    /// Extra `#SBATCH` options (`--sbatch`), each whitespace-separated word one line.
    pub sbatch: Vec<String>,
    /// The job's name (a character other than a letter, digit, `-`, `_` or `.` becomes `_`).
    pub job_name: String,
    /// The `penetrate` the script runs unless the `PENETRATE` environment variable names
    /// another: the executable that emitted it.
    pub penetrate: String,
}

/// What [`emit`] wrote.
#[derive(Clone, Debug)]
pub struct Emitted {
    pub members: usize,
    /// Array tasks: 0 to `tasks` − 1.
    pub tasks: usize,
    pub scenes: PathBuf,
    pub manifest: PathBuf,
    pub script: PathBuf,
}

/// One row of the manifest.
#[derive(Clone, Debug, PartialEq)]
struct Member {
    index: usize,
    /// The array task that runs it.
    task: usize,
    /// The varied key's value.
    value: f64,
    /// Its scene file, relative to DIR.
    scene: String,
    /// Its run folder, relative to DIR: the in-process sweep's label.
    dir: String,
    /// `--backend` as given, or the scene's `run.backend`.
    backend: Backend,
}

impl Member {
    /// The same run as `other` (the task aside: it follows `--members-per-task`).
    fn same_run(&self, other: &Member) -> bool {
        (self.index, self.value, &self.scene, &self.dir, self.backend)
            == (
                other.index,
                other.value,
                &other.scene,
                &other.dir,
                other.backend,
            )
    }
}

/// Writes the planned sweep ([`sweep::plan_members`] into `dir`) for Slurm: each member's
/// resolved scene, the manifest and the job-array script. Runs nothing. `dir` must be new,
/// empty, or hold an earlier emit of the same members (then the script and manifest are
/// written again, e.g. with other `#SBATCH` options, and any runs are kept).
pub fn emit(
    planned: &[Planned],
    vary: &Vary,
    opts: &EmitOptions,
    dir: &Path,
) -> Result<Emitted, SweepError> {
    let sbatch = sbatch_lines(&opts.sbatch)?;
    let per_task = opts.per_task.max(1);
    let absolute =
        std::path::absolute(dir).map_err(|e| SweepError::Io(format!("{}: {e}", dir.display())))?;
    let script_dir = script_path(&absolute)?;
    let members: Vec<Member> = planned
        .iter()
        .zip(&vary.values)
        .enumerate()
        .map(|(index, (p, &value))| Member {
            index,
            task: index / per_task,
            value,
            scene: format!("{SCENES}/{}.toml", p.spec.label),
            dir: p.spec.label.clone(),
            backend: p.spec.backend,
        })
        .collect();
    let scenes: Vec<String> = planned.iter().map(|p| p.scene.resolved_table()).collect();
    check_folder(dir, &vary.key, &members, &scenes)?;

    let io = |path: &Path, e: std::io::Error| SweepError::Io(format!("{}: {e}", path.display()));
    for folder in [dir.to_path_buf(), dir.join(SCENES), dir.join(LOGS)] {
        crate::output::create_folder(&folder).map_err(|e| SweepError::Io(e.to_string()))?;
    }
    for (m, text) in members.iter().zip(&scenes) {
        let path = dir.join(&m.scene);
        crate::output::write_whole(&path, text.as_bytes()).map_err(|e| io(&path, e))?;
    }
    let manifest = dir.join(MANIFEST);
    write_manifest(&manifest, &vary.key, &members).map_err(|e| io(&manifest, e))?;
    let tasks = members.len().div_ceil(per_task);
    let labels: Vec<&str> = members.iter().map(|m| m.dir.as_str()).collect();
    let text = script(&script_dir, &vary.key, &labels, per_task, opts, &sbatch);
    let script = dir.join(SCRIPT);
    crate::output::write_whole(&script, text.as_bytes()).map_err(|e| io(&script, e))?;
    Ok(Emitted {
        members: members.len(),
        tasks,
        scenes: dir.join(SCENES),
        manifest,
        script,
    })
}

/// `dir` may take the emit of `members`: it is new, empty, or holds an earlier emit of the same
/// members with the same scenes.
fn check_folder(
    dir: &Path,
    key: &str,
    members: &[Member],
    scenes: &[String],
) -> Result<(), SweepError> {
    let mut entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(SweepError::Io(format!("{}: {e}", dir.display()))),
    };
    if entries.next().is_none() {
        return Ok(());
    }
    let shown = dir.display();
    if !dir.join(MANIFEST).exists() {
        return Err(SweepError::Folder(format!(
            "--emit slurm {shown}: the folder is not empty and holds no emitted sweep (no \
             {MANIFEST}); emit into a new or empty folder"
        )));
    }
    let same = read_manifest(dir).is_ok_and(|(earlier_key, earlier)| {
        earlier_key == key
            && earlier.len() == members.len()
            && earlier.iter().zip(members).all(|(a, b)| a.same_run(b))
            && members.iter().zip(scenes).all(|(m, text)| {
                std::fs::read_to_string(dir.join(&m.scene)).is_ok_and(|t| t == *text)
            })
    });
    match same {
        true => Ok(()),
        false => Err(SweepError::Folder(format!(
            "--emit slurm {shown}: the folder holds another emitted sweep (its {MANIFEST} or \
             scenes differ from this one's); emit into a new folder, or remove {shown} first"
        ))),
    }
}

/// The extra `#SBATCH` lines of `--sbatch`: each word an option as sbatch takes it
/// (`--partition=gpu`), none the script sets itself.
fn sbatch_lines(options: &[String]) -> Result<Vec<String>, SweepError> {
    let mut lines = Vec::new();
    for word in options.iter().flat_map(|o| o.split_whitespace()) {
        let bad = |why: String| SweepError::Spec(format!("--sbatch {word}: {why}"));
        if !word.starts_with('-') || word.chars().any(char::is_control) {
            return Err(bad(
                "not an sbatch option; write each as sbatch takes it, with `=` before its value, \
                 e.g. --sbatch \"--partition=gpu --gres=gpu:1\""
                    .into(),
            ));
        }
        let name = match word.starts_with("--") {
            true => word.split('=').next().unwrap_or(word),
            false => word.get(..2).unwrap_or(word),
        };
        if let Some((long, _)) = SCRIPT_SETS.iter().find(|(l, s)| name == *l || name == *s) {
            return Err(bad(format!(
                "the script sets {long} itself; give it to sbatch instead (`sbatch {long}=… \
                 DIR/{SCRIPT}`), whose command line overrides the script's lines"
            )));
        }
        lines.push(word.to_string());
    }
    Ok(lines)
}

/// `dir` as the script writes it, also in `#SBATCH --output`, which no shell reads: refused
/// when it has a character such a line cannot carry (`%` is Slurm's file-name pattern).
fn script_path(dir: &Path) -> Result<String, SweepError> {
    let refuse = |what: String| {
        SweepError::Spec(format!(
            "--emit slurm {}: the folder's path {what}, which a #SBATCH line cannot carry; emit \
             into a folder whose path has none",
            dir.display()
        ))
    };
    let text = dir.to_str().ok_or_else(|| refuse("is not UTF-8".into()))?;
    let awkward = |c: char| c.is_whitespace() || c.is_control() || "%\"'\\".contains(c);
    match text.chars().find(|&c| awkward(c)) {
        Some(c) => Err(refuse(format!("has {c:?}"))),
        None => Ok(text.to_string()),
    }
}

/// `s` as one shell word.
fn sh_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

/// The job-array script: task i runs members i·`per_task` up to the next task's first, each
/// `penetrate run <its scene> --out <its folder> --quiet` with the sweep's flags, and exits
/// with the last failing run's code (0 when every run completed).
fn script(
    dir: &str,
    key: &str,
    labels: &[&str],
    per_task: usize,
    opts: &EmitOptions,
    sbatch: &[String],
) -> String {
    let tasks = labels.len().div_ceil(per_task);
    let last = tasks.saturating_sub(1);
    let job: String = opts
        .job_name
        .chars()
        .map(|c| match c.is_ascii_alphanumeric() || "-_.".contains(c) {
            true => c,
            false => '_',
        })
        .collect();
    let mut flags = String::new();
    if let Some(b) = opts.backend {
        flags += &format!(" --backend {}", b.name());
    }
    if let Some(a) = &opts.adapter {
        flags += &format!(" --adapter {}", sh_quote(a));
    }
    if !opts.vtk {
        flags += " --no-vtk";
    }
    let per = match per_task {
        1 => "one member per array task".to_string(),
        n => format!("{n} members per array task"),
    };
    let mut s = format!(
        r#"#!/bin/bash
# A penetrate sweep over {key}: {n} members, {per}, written by
# `penetrate sweep --emit slurm`; {MANIFEST} beside it lists each member's value, scene and
# run folder.
#   submit:        sbatch {dir}/{SCRIPT}
#   rerun task 0:  sbatch --array=0 {dir}/{SCRIPT}
#   one task here: SLURM_ARRAY_TASK_ID=0 bash {dir}/{SCRIPT}
#   then:          penetrate sweep --collect {dir}
#SBATCH --job-name={job}
#SBATCH --array=0-{last}
#SBATCH --output={dir}/{LOGS}/%A_%a.out
"#,
        n = labels.len(),
    );
    for line in sbatch {
        let _ = writeln!(s, "#SBATCH {line}");
    }
    let members: Vec<String> = labels.iter().map(|l| sh_quote(l)).collect();
    let _ = write!(
        s,
        r#"
set -euo pipefail

sweep={dir}
penetrate=${{PENETRATE:-{exe}}}
members=({members})
per_task={per_task}
tasks={tasks}

if [[ -z ${{SLURM_ARRAY_TASK_ID+set}} ]]; then
    echo "{SCRIPT}: SLURM_ARRAY_TASK_ID is not set: submit it with sbatch $sweep/{SCRIPT}," \
        "or set it to a task 0-$((tasks - 1)) to run that one here" >&2
    exit 2
fi
task=$SLURM_ARRAY_TASK_ID
if [[ ! $task =~ ^[0-9]{{1,9}}$ ]] || ((10#$task >= tasks)); then
    echo "{SCRIPT}: SLURM_ARRAY_TASK_ID=$task is out of range:" \
        "not one of this sweep's tasks, 0-$((tasks - 1))" >&2
    exit 2
fi
task=$((10#$task))

status=0
for ((i = task * per_task; i < (task + 1) * per_task && i < ${{#members[@]}}; i++)); do
    member=${{members[i]}}
    echo "member $i ($member): task $task of array job ${{SLURM_ARRAY_JOB_ID:-(none)}}, $penetrate"
    "$penetrate" run "$sweep/{SCENES}/$member.toml" --out "$sweep/$member" \
        --quiet{flags} || status=$?
done
exit "$status"
"#,
        dir = sh_quote(dir),
        exe = sh_quote(&opts.penetrate),
        members = members.join(" "),
    );
    s
}

/// Writes the manifest of `members`, the varied key naming the value column.
fn write_manifest(path: &Path, key: &str, members: &[Member]) -> std::io::Result<()> {
    let header = ["index", "task", key, "scene", "dir", "backend"];
    let rows: Vec<Vec<String>> = members
        .iter()
        .map(|m| {
            vec![
                m.index.to_string(),
                m.task.to_string(),
                scene::number_text(m.value),
                m.scene.clone(),
                m.dir.clone(),
                m.backend.name().to_string(),
            ]
        })
        .collect();
    crate::output::write_csv(path, &header, &rows)
}

/// The varied key and the members of the manifest in `dir`, or why it is not one [`emit`]
/// wrote.
fn read_manifest(dir: &Path) -> Result<(String, Vec<Member>), String> {
    let path = dir.join(MANIFEST);
    let bytes = scene::read_capped(&path, scene::SCENE_FILE_LIMIT)
        .map_err(|e| e.to_string())?
        .ok_or("too large for a manifest")?;
    let mut reader = csv::ReaderBuilder::new().from_reader(bytes.as_slice());
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| e.to_string())?
        .iter()
        .map(String::from)
        .collect();
    let key = match header.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["index", "task", key, "scene", "dir", "backend"] if !key.is_empty() => key.to_string(),
        _ => return Err(format!("header `{}` is not a manifest's", header.join(","))),
    };
    let mut members = Vec::new();
    for (i, row) in reader.records().enumerate() {
        let row = row.map_err(|e| e.to_string())?;
        let bad = || {
            format!(
                "row {} (`{}`) is not a member's",
                i + 1,
                row.iter().collect::<Vec<_>>().join(",")
            )
        };
        let field = |n: usize| row.get(n).filter(|f| !f.is_empty()).ok_or_else(bad);
        let member = Member {
            index: field(0)?.parse().map_err(|_| bad())?,
            task: field(1)?.parse().map_err(|_| bad())?,
            value: field(2)?
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .ok_or_else(bad)?,
            scene: field(3)?.to_string(),
            dir: field(4)?.to_string(),
            backend: [Backend::Cpu, Backend::Gpu, Backend::Auto]
                .into_iter()
                .find(|b| b.name() == row.get(5).unwrap_or(""))
                .ok_or_else(bad)?,
        };
        if member.index != i {
            return Err(bad());
        }
        members.push(member);
    }
    match members.is_empty() {
        true => Err("lists no members".into()),
        false => Ok((key, members)),
    }
}

/// A member `--collect` found without a completed run.
#[derive(Clone, Debug, PartialEq)]
pub struct Unfinished {
    /// Its run folder's name (the in-process sweep's label).
    pub label: String,
    /// The array task that runs it.
    pub task: usize,
    /// Why: `missing: …`, the summary's status, or what is wrong with the run folder.
    pub why: String,
}

/// What [`collect`] found.
#[derive(Clone, Debug)]
pub struct Collected {
    pub key: String,
    pub members: usize,
    /// `DIR/sweep.csv`.
    pub csv: PathBuf,
    /// Members with no `summary.json`: not run yet, under way, or killed.
    pub missing: Vec<Unfinished>,
    /// Members whose run did not complete, or whose folder holds another run or a damaged
    /// summary.
    pub failed: Vec<Unfinished>,
    /// Each build (`solver_build`) the completed members ran on, with their labels.
    pub builds: BTreeMap<String, Vec<String>>,
}

impl Collected {
    /// Every member completed, all on one build, as the rows of an in-process sweep are.
    pub fn complete(&self) -> bool {
        self.missing.is_empty() && self.failed.is_empty() && self.builds.len() <= 1
    }

    /// The array tasks that run the missing and failed members, in order.
    pub fn tasks_to_rerun(&self) -> Vec<usize> {
        let mut tasks: Vec<usize> = self
            .missing
            .iter()
            .chain(&self.failed)
            .map(|u| u.task)
            .collect();
        tasks.sort_unstable();
        tasks.dedup();
        tasks
    }
}

/// Reads the manifest [`emit`] wrote into `dir` and each member's `summary.json`, and writes
/// `dir/sweep.csv` as the in-process sweep writes it, a member without a completed run having
/// why in its `status`. A member's run folder counts only when its `scene.toml` is the
/// member's scene and its summary reads back plausible ([`sweep::summary_left`]).
pub fn collect(dir: &Path) -> Result<Collected, SweepError> {
    let shown = dir.display();
    if !dir.join(MANIFEST).exists() {
        return Err(SweepError::Folder(format!(
            "--collect {shown}: no {MANIFEST}, so no emitted sweep; `penetrate sweep CASE --vary \
             … --emit slurm {shown}` writes one"
        )));
    }
    let (key, members) = read_manifest(dir).map_err(|why| {
        SweepError::Folder(format!(
            "--collect {shown}: {}: {why}; emit the sweep again",
            dir.join(MANIFEST).display()
        ))
    })?;
    let mut records = Vec::with_capacity(members.len());
    let (mut missing, mut failed) = (Vec::new(), Vec::new());
    let mut builds: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for m in &members {
        let scene = scene::load(&dir.join(&m.scene), &[]).map_err(SweepError::Scene)?;
        let run_dir = dir.join(&m.dir);
        let unfinished = |why: &str| Unfinished {
            label: m.dir.clone(),
            task: m.task,
            why: why.to_string(),
        };
        let outcome = match sweep::summary_left(&run_dir, &scene) {
            Ok(summary) if summary.status == "completed" => {
                let build = builds.entry(summary.solver_build.clone()).or_default();
                build.push(m.dir.clone());
                Ok(summary)
            }
            Ok(summary) => {
                failed.push(unfinished(&summary.status));
                Ok(summary)
            }
            Err(NoSummary::Missing) => {
                let why = "no summary.json: not run yet, still running, or killed";
                missing.push(unfinished(why));
                Err(format!("missing: {why}"))
            }
            Err(other) => {
                let why = match other {
                    NoSummary::Damaged(why) => why,
                    _ => format!("another run: its scene.toml is not {}", m.scene),
                };
                failed.push(unfinished(&why));
                Err(why)
            }
        };
        let record = RunRecord {
            label: m.dir.clone(),
            dir: run_dir,
            backend: m.backend,
            scene,
            outcome,
        };
        records.push(record);
    }
    let vary = Vary {
        key: key.clone(),
        values: members.iter().map(|m| m.value).collect(),
    };
    let csv = dir.join("sweep.csv");
    sweep::write_sweep_csv(&csv, &vary, &records)
        .map_err(|e| SweepError::Io(format!("{}: {e}", csv.display())))?;
    Ok(Collected {
        key,
        members: members.len(),
        csv,
        missing,
        failed,
        builds,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sbatch_options_are_lines_and_the_scripts_own_are_refused() {
        let words = vec![
            "--partition=gpu  --gres=gpu:1".to_string(),
            "-t 1:00:00".into(),
        ];
        assert!(sbatch_lines(&words)
            .unwrap_err()
            .to_string()
            .contains("1:00:00"));
        let words = vec!["--partition=gpu  --gres=gpu:1".to_string(), "-N1".into()];
        assert_eq!(
            sbatch_lines(&words).unwrap(),
            ["--partition=gpu", "--gres=gpu:1", "-N1"]
        );
        for own in [
            "--array=0-3",
            "-a0-3",
            "--job-name=x",
            "-Jx",
            "--output=x",
            "-e",
            "--error",
        ] {
            let e = sbatch_lines(&[own.to_string()]).unwrap_err().to_string();
            assert!(
                e.contains("the script sets") && e.contains("sbatch --"),
                "{own}: {e}"
            );
        }
    }

    #[test]
    fn a_folder_a_sbatch_line_cannot_carry_is_refused() {
        assert_eq!(
            script_path(Path::new("/scratch/a-b.c")).unwrap(),
            "/scratch/a-b.c"
        );
        for bad in [
            "/scratch/a b",
            "/scratch/100%",
            "/scratch/a'b",
            "/scratch/a\nb",
        ] {
            let e = script_path(Path::new(bad)).unwrap_err().to_string();
            assert!(e.contains("a #SBATCH line cannot carry"), "{bad}: {e}");
        }
        assert_eq!(sh_quote("it's"), r"'it'\''s'");
    }
}
