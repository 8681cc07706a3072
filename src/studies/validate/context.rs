//! The runs of one validation: each run a section asks for made once, reused when asked again,
//! or taken from an earlier process's output (`--resume`).

use std::path::{Path, PathBuf};

use crate::output::plot::Chart;
use crate::output::summary::build_id;
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
    /// The solver build of every run each section used, made here or taken (`--resume`).
    pub(super) builds: Vec<(Section, String)>,
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

    /// A scene of the cases folder with `overrides` and the `--set` values that apply to it.
    pub(super) fn scene(&self, file: &str, overrides: &[String]) -> Result<Scene, ValidateError> {
        let overrides = self.with_set(file, overrides.to_vec())?;
        scene::load(&self.case(file), &overrides).map_err(|e| ValidateError::Input(e.to_string()))
    }

    /// `overrides` and then the `--set` values that apply to the scene `file` with them: a
    /// `target.` or `contact.` key only where the scene has a target (the Taylor bars have
    /// none).
    fn with_set(
        &self,
        file: &str,
        mut overrides: Vec<String>,
    ) -> Result<Vec<String>, ValidateError> {
        if self.opts.set.is_empty() {
            return Ok(overrides);
        }
        let input = |e: scene::SceneError| ValidateError::Input(format!("{file}: {e}"));
        let has_target = scene::load(&self.case(file), &overrides)
            .map_err(input)?
            .target
            .is_some();
        overrides.extend(
            self.opts
                .set
                .iter()
                .filter(|s| has_target || !(s.starts_with("target.") || s.starts_with("contact.")))
                .cloned(),
        );
        Ok(overrides)
    }

    pub(super) fn dir(&self, section: Section) -> PathBuf {
        self.opts.out.join(section.name())
    }

    /// Runs `asks`, reusing any earlier run of the same resolved scene on the same backend,
    /// and returns their records in the order asked. Every scene is loaded before the first
    /// run; the runs still to make go `opts.batch` at a time (`sweep --batch`), those on the
    /// CPU path first and then those on the GPU.
    pub(super) fn run(
        &mut self,
        section: Section,
        asks: Vec<Ask>,
        vtk: bool,
    ) -> Result<Vec<RunRecord>, ValidateError> {
        let runs = self.dir(section).join("runs");
        let specs = asks
            .into_iter()
            .map(|a| {
                Ok(RunSpec {
                    dir: runs.join(format!("{}-{}", a.label, a.backend.name())),
                    label: a.label,
                    overrides: self.with_set(&a.case, a.overrides)?,
                    case: self.case(&a.case),
                    backend: a.backend,
                })
            })
            .collect::<Result<Vec<_>, ValidateError>>()?;
        let planned = sweep::plan(specs)
            .map_err(|e| ValidateError::Input(format!("{}: {e}", section.name())))?;
        let mut records: Vec<Option<RunRecord>> = vec![None; planned.len()];
        // The runs to make, by the place they were asked at; and asks of a run already among
        // them, which take its record.
        let mut todo: Vec<(usize, sweep::Planned)> = Vec::new();
        let mut twins: Vec<(usize, usize)> = Vec::new();
        for (k, p) in planned.into_iter().enumerate() {
            let same = |b: Backend, s: &Scene| b == p.spec.backend && *s == p.scene;
            if let Some(r) = self.done.iter().find(|r| same(r.backend, &r.scene)) {
                self.reused += 1;
                records[k] = Some(r.clone());
                continue;
            }
            if let Some(&(first, _)) = todo.iter().find(|(_, q)| same(q.spec.backend, &q.scene)) {
                self.reused += 1;
                twins.push((k, first));
                continue;
            }
            match self.resumed_run(section, &p, vtk) {
                Some(r) => {
                    self.resumed += 1;
                    self.done.push(r.clone());
                    records[k] = Some(r);
                }
                None => todo.push((k, p)),
            }
        }
        let (on_gpu, rest): (Vec<_>, Vec<_>) = todo
            .into_iter()
            .partition(|(_, p)| p.spec.backend == Backend::Gpu);
        for group in [rest, on_gpu] {
            let (places, planned): (Vec<usize>, Vec<sweep::Planned>) = group.into_iter().unzip();
            if planned.is_empty() {
                continue;
            }
            // Every run saves checkpoints, so that a validation killed in a long run loses
            // only the last stretch of it: --resume goes on from there.
            let settings = RunSettings {
                adapter: self.opts.adapter.clone(),
                vtk,
                batch: self.opts.batch,
                checkpoint: true,
                restart: self.opts.resume,
            };
            let made_before = self.done.len();
            let estimate = self.estimate;
            let progress = &mut *self.progress;
            let mut made = made_before;
            let new = sweep::run_set(planned, &settings, |r| {
                made += 1;
                progress(&format!(
                    "[{made}/≤{}] {} {} on {}: {}",
                    estimate.max(made),
                    section.name(),
                    r.label,
                    r.backend.name(),
                    describe(r)
                ))
            })?;
            if crate::interrupt::requested() {
                return Err(ValidateError::Interrupted(format!(
                    "interrupted in {} (a run under way stopped where it was); run the same \
                     command with --resume to go on",
                    section.name(),
                )));
            }
            for (k, r) in places.into_iter().zip(new) {
                if r.completed().is_none() {
                    self.failed.push(format!(
                        "{} {} on {}: {}",
                        section.name(),
                        r.label,
                        r.backend.name(),
                        r.status()
                    ));
                }
                self.done.push(r.clone());
                records[k] = Some(r);
            }
        }
        for (k, first) in twins {
            records[k] = records[first].clone();
        }
        let records: Vec<RunRecord> = records.into_iter().flatten().collect();
        self.builds.extend(records.iter().map(|r| {
            let build = r.summary().map_or(build_id(), |s| s.solver_build.as_str());
            (section, build.to_string())
        }));
        Ok(records)
    }

    /// With `--resume`, an earlier process's completed run of `p` (said in the progress).
    fn resumed_run(
        &mut self,
        section: Section,
        p: &sweep::Planned,
        vtk: bool,
    ) -> Option<RunRecord> {
        if !self.opts.resume {
            return None;
        }
        let backend = p.spec.backend;
        let adapter = self.gpu_adapter.as_deref();
        let other = &self.opts.resume_builds;
        let (dir, summary) = self
            .resume_candidates(&p.spec.dir)
            .into_iter()
            .find_map(|dir| {
                sweep::completed_run(&dir, &p.scene, backend, adapter, vtk, other)
                    .map(|summary| (dir, summary))
            })?;
        let r = RunRecord {
            label: p.spec.label.clone(),
            dir,
            backend,
            scene: p.scene.clone(),
            outcome: Ok(summary),
        };
        let made = self.done.len() + 1;
        (self.progress)(&format!(
            "[{made}/≤{}] {} {} on {}: {} (resumed from {})",
            self.estimate.max(made),
            section.name(),
            r.label,
            backend.name(),
            describe(&r),
            r.dir.display()
        ));
        Some(r)
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
