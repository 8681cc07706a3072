//! The runs of one validation: each run a section asks for made once, reused when asked again,
//! or taken from an earlier process's output (`--resume`).

use std::path::{Path, PathBuf};

use crate::output::plot::Chart;
use crate::scene::{self, Backend, Scene};
use crate::studies::sweep::{self, RunRecord, RunSettings, RunSpec};

use super::{Options, Section, Settings, ValidateError};

/// A run a section asks for: `case` (a file in the cases folder) with `overrides`.
pub(super) struct Ask {
    pub(super) label: String,
    pub(super) case: String,
    pub(super) overrides: Vec<String>,
    pub(super) backend: Backend,
}

/// The state of one validation: options, settings, and every run made so far.
pub(super) struct Context<'a> {
    pub(super) opts: &'a Options,
    pub(super) settings: Settings,
    /// Runs made so far; a run asked again with the same resolved scene and backend is reused.
    pub(super) done: Vec<RunRecord>,
    pub(super) failed: Vec<String>,
    pub(super) reused: usize,
    /// Runs taken from an earlier process's output (`--resume`).
    pub(super) resumed: usize,
    /// With a GPU backend: the adapter's name as run summaries give it; `--resume` takes only
    /// GPU runs made on it.
    pub(super) gpu_adapter: Option<String>,
    pub(super) estimate: usize,
    pub(super) progress: &'a mut dyn FnMut(&str),
}

impl Context<'_> {
    /// The backend every section but the convergence study runs on.
    pub(super) fn primary(&self) -> Backend {
        self.opts.backends[0]
    }

    pub(super) fn case(&self, file: &str) -> PathBuf {
        self.opts.cases.join(file)
    }

    /// A scene of the cases folder with `overrides`.
    pub(super) fn scene(&self, file: &str, overrides: &[String]) -> Result<Scene, ValidateError> {
        scene::load(&self.case(file), overrides).map_err(|e| ValidateError::Input(e.to_string()))
    }

    pub(super) fn dir(&self, section: Section) -> PathBuf {
        self.opts.out.join(section.name())
    }

    /// Runs `asks` in order, reusing any earlier run of the same resolved scene on the same
    /// backend. Every scene is loaded before the first run.
    pub(super) fn run(
        &mut self,
        section: Section,
        asks: Vec<Ask>,
        vtk: bool,
    ) -> Result<Vec<RunRecord>, ValidateError> {
        let runs = self.dir(section).join("runs");
        let specs = asks
            .into_iter()
            .map(|a| RunSpec {
                dir: runs.join(format!("{}-{}", a.label, a.backend.name())),
                label: a.label,
                case: self.case(&a.case),
                overrides: a.overrides,
                backend: a.backend,
            })
            .collect();
        let planned = sweep::plan(specs)
            .map_err(|e| ValidateError::Input(format!("{}: {e}", section.name())))?;
        let settings = RunSettings {
            adapter: self.opts.adapter.clone(),
            vtk,
            batch: 1,
        };
        let mut records = Vec::with_capacity(planned.len());
        for p in planned {
            let earlier = self
                .done
                .iter()
                .find(|r| r.backend == p.spec.backend && r.scene == p.scene);
            if let Some(r) = earlier {
                self.reused += 1;
                records.push(r.clone());
                continue;
            }
            let (label, backend) = (p.spec.label.clone(), p.spec.backend);
            let made = self.done.len() + 1;
            let estimate = self.estimate.max(made);
            let earlier_process = self
                .opts
                .resume
                .then(|| {
                    let adapter = self.gpu_adapter.as_deref();
                    let other = &self.opts.resume_builds;
                    self.resume_candidates(&p.spec.dir)
                        .into_iter()
                        .find_map(|dir| {
                            sweep::completed_run(&dir, &p.scene, backend, adapter, vtk, other)
                                .map(|summary| (dir, summary))
                        })
                })
                .flatten();
            let progress = &mut *self.progress;
            if let Some((dir, summary)) = earlier_process {
                let r = RunRecord {
                    label,
                    dir,
                    backend,
                    scene: p.scene,
                    outcome: Ok(summary),
                };
                progress(&format!(
                    "[{made}/≤{estimate}] {} {} on {}: {} (resumed from {})",
                    section.name(),
                    r.label,
                    backend.name(),
                    describe(&r),
                    r.dir.display()
                ));
                self.resumed += 1;
                self.done.push(r.clone());
                records.push(r);
                continue;
            }
            let mut new = sweep::run_set(vec![p], &settings, |r| {
                progress(&format!(
                    "[{made}/≤{estimate}] {} {label} on {}: {}",
                    section.name(),
                    backend.name(),
                    describe(r)
                ))
            })?;
            if crate::interrupt::requested() {
                return Err(ValidateError::Interrupted(format!(
                    "interrupted in {} {label} on {} (its run stopped where it was); run the \
                     same command with --resume to go on",
                    section.name(),
                    backend.name()
                )));
            }
            let Some(r) = new.pop() else { continue };
            if r.completed().is_none() {
                self.failed.push(format!(
                    "{} {label} on {}: {}",
                    section.name(),
                    backend.name(),
                    r.status()
                ));
            }
            self.done.push(r.clone());
            records.push(r);
        }
        Ok(records)
    }

    /// Where `--resume` looks for an earlier process's run that `own` would hold: `own` first,
    /// then every run folder of every section, since sections share runs (the Forrestal shots
    /// are also the rigid-vs-elastic study's λ = 0.2 runs) and an earlier process may have made
    /// a run for another section than the one now asking.
    pub(super) fn resume_candidates(&self, own: &Path) -> Vec<PathBuf> {
        let mut others: Vec<PathBuf> = Section::ALL
            .into_iter()
            .filter_map(|s| std::fs::read_dir(self.dir(s).join("runs")).ok())
            .flatten()
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|d| d.is_dir() && d != own)
            .collect();
        others.sort();
        std::iter::once(own.to_path_buf()).chain(others).collect()
    }

    /// Writes `rows` under `header` to the section's `file`; returns the report's link to it.
    pub(super) fn csv(
        &self,
        section: Section,
        file: &str,
        header: &[&str],
        rows: &[Vec<String>],
    ) -> Result<String, ValidateError> {
        let path = self.dir(section).join(file);
        crate::output::write_csv(&path, header, rows)
            .map_err(|e| ValidateError::Io(format!("{}: {e}", path.display())))?;
        Ok(format!("[{file}]({}/{file})", section.name()))
    }

    /// Draws `chart` into the section's `file`; returns the report's image link.
    pub(super) fn plot(
        &self,
        section: Section,
        file: &str,
        chart: &Chart,
    ) -> Result<String, ValidateError> {
        let path = self.dir(section).join(file);
        chart
            .write_png(&path)
            .map_err(|e| ValidateError::Io(format!("{}: {e}", path.display())))?;
        Ok(format!("![{}]({}/{file})\n", chart.title, section.name()))
    }

    /// `path` relative to the output directory, for the report and the CSVs.
    pub(super) fn rel(&self, path: &Path) -> String {
        path.strip_prefix(&self.opts.out)
            .unwrap_or(path)
            .display()
            .to_string()
    }
}

/// One line on how a run ended.
fn describe(r: &RunRecord) -> String {
    match &r.outcome {
        Ok(s) if s.particles > 0 => format!(
            "{}, depth {:.4} m, max damage {:.2}, {:.1} s",
            s.status, s.depth_m, s.max_damage, s.wall_s
        ),
        Ok(s) => format!(
            "{}, length {:.3} mm, {:.1} s",
            s.status,
            s.final_length_m * 1e3,
            s.wall_s
        ),
        Err(e) => e.clone(),
    }
}
