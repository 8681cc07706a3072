//! The run loop of `penetrate run`: stop conditions, history rows and frames as the run goes,
//! and outputs kept whole when it stops early.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use super::build::attach;
use super::checkpoint::{self, Counters, Restart};
use super::{Kept, Model, Output, OutputError, OutputFailure, RunError, Simulation};
use crate::gpu::batch::GpuShare;
use crate::mesh;
use crate::output;
use crate::output::frames::FrameWriter;
use crate::output::history::History;
use crate::output::progress::Progress;
use crate::output::summary::Summary;
use crate::output::vtk;
use crate::scene::{Backend, Scene};

/// Options of `penetrate run`.
#[derive(Clone, Debug)]
pub struct RunOptions {
    pub out: PathBuf,
    pub quiet: bool,
    /// Write VTK frames (tests turn them off).
    pub vtk: bool,
    /// Overrides the scene's `run.backend`.
    pub backend: Option<Backend>,
    /// Part of the GPU adapter's name (`--adapter`).
    pub adapter: Option<String>,
    /// Write a checkpoint into `out` every this much simulated time (s, `--checkpoint-every`).
    pub checkpoint_every: Option<f64>,
    /// Go on from this checkpoint instead of starting (`--restart`).
    pub restart: Option<PathBuf>,
    /// Step on this device, submitting with the other runs of its batch (`sweep --batch`):
    /// overrides `backend` and `adapter`.
    pub share: Option<Arc<GpuShare>>,
}

impl RunOptions {
    /// CPU or scene backend, progress shown, VTK frames on.
    pub fn new(out: PathBuf) -> RunOptions {
        RunOptions {
            out,
            quiet: false,
            vtk: true,
            backend: None,
            adapter: None,
            checkpoint_every: None,
            restart: None,
            share: None,
        }
    }
}

/// The resolved scene a run writes into its output folder.
pub const SCENE_FILE: &str = "scene.toml";

/// The result of a run: its summary, and whether it ended normally.
pub struct RunOutcome {
    pub summary: Summary,
    pub ok: bool,
}

/// Run a scene to its end, writing the outputs as it goes. An unstable run stops, says what and
/// where in `status`, and keeps what it had written. So does a run whose outputs the disk stops
/// taking, as far as the disk lets it: its files end whole, `summary.json` is written where it
/// fits, and it returns [`RunError::Output`] saying which output, when, and what was kept.
/// With `opts.restart` it goes on from a checkpoint, writing on the outputs that checkpoint's
/// run left, as if it had never stopped; a checkpoint that does not fit is refused
/// ([`RunError::Restart`]) before anything is written.
pub fn run(scene: &Scene, opts: &RunOptions) -> Result<RunOutcome, RunError> {
    // A refusal before the run steps: there is nothing of it to keep yet.
    let early = |what: Output| {
        move |e: std::io::Error| {
            RunError::from(OutputError::from(OutputFailure::new(what, &e, None)))
        }
    };
    output::create_folder(&opts.out).map_err(early(Output::Folder))?;
    let mut restart = Restart::open(scene, opts)?;
    if restart.is_none() {
        output::clear_previous_run(&opts.out)
            .map_err(|e| early(Output::Previous)(output::named(&opts.out, e)))?;
    }
    // What exactly ran, every default resolved (`penetrate validate --resume` compares it).
    let resolved = scene.resolved_table();
    output::write_whole(&opts.out.join(SCENE_FILE), resolved.as_bytes())
        .map_err(early(Output::Scene))?;
    let started = Instant::now();
    let backend = opts.backend.unwrap_or(scene.run.backend);
    let history_file = opts.out.join("history.csv");
    let mut model = Model::assemble(scene)?;
    let started_up = match restart.as_mut() {
        // The checkpoint's state comes with the forces and Δt of the step it had reached.
        Some(r) => {
            r.restore(&mut model)?;
            Ok(())
        }
        None => model.start(),
    };
    let mut sim = Simulation::on_cpu(model);
    if let Err(e) = started_up {
        // The scene as built cannot take a step (its first forces or Δt, on the CPU): the
        // state at rest and why, as any unstable run leaves them.
        let mut history = History::create(&history_file).map_err(early(Output::History))?;
        history
            .write(&sim.history_row()?)
            .and_then(|()| history.flush())
            .map_err(early(Output::History))?;
        let status = format!("{e} (before the first step, evaluated on the CPU)");
        let summary = sim.summary(&status, "", started.elapsed().as_secs_f64());
        write_summary(&opts.out, &summary).map_err(early(Output::Summary))?;
        return Ok(RunOutcome { summary, ok: false });
    }
    let fell_back = match &opts.share {
        Some(share) => {
            sim.use_gpu(share.gpu.share())?;
            if let Some(g) = sim.gpu_step() {
                g.join_batch(share.batch.clone());
            }
            None
        }
        None => attach(&mut sim, backend, opts.adapter.as_deref())?,
    };
    warn_from_estimate(scene, &opts.out, opts.vtk, fell_back.as_deref());
    let (mut history, mut pvd) = match &restart {
        Some(r) => r
            .resume_outputs(&opts.out)
            .map_err(early(Output::Previous))?,
        None => (
            History::create(&history_file).map_err(early(Output::History))?,
            vtk::Collection::new(opts.out.join("frames.pvd")),
        ),
    };
    let mut frame = 0;
    // The step of the last frame written: the last frame is not written twice.
    let mut frame_step = None;
    if opts.vtk && restart.is_none() {
        // Written here: a disk that refuses the first frame stops the run before it steps.
        sim.frame(frame)?
            .write(&opts.out, &mut pvd)
            .map_err(early(Output::Frame(frame)))?;
        frame += 1;
        frame_step = Some(sim.steps());
    }
    if restart.is_none() {
        history
            .write(&sim.history_row()?)
            .map_err(early(Output::History))?;
    }
    // The later frames are written by a thread of their own while the run steps on.
    let mut frames = opts.vtk.then(|| FrameWriter::spawn(opts.out.clone(), pvd));
    // The step of the last row written: the last row is not written twice.
    let mut history_step = sim.steps();
    // Set once the disk refused an output: the run stops there.
    let mut refused = None;
    let mut next_history = scene.run.history_interval;
    let mut next_frame = if scene.run.output_interval > 0.0 {
        scene.run.output_interval
    } else {
        f64::MAX
    };
    if let Some(r) = &restart {
        // Where the run the checkpoint was written of stood: frames and rows go on from there.
        Counters {
            frame,
            frame_step,
            history_step,
            next_history,
            next_frame,
        } = r.counters();
    }
    let mut next_checkpoint = checkpoint::next_due(sim.time(), opts.checkpoint_every);
    let mut progress = Progress::new(scene.run.end_time, opts.quiet);
    let (status, reason, ok) = loop {
        if crate::interrupt::requested() {
            break (
                format!(
                    "interrupted (Ctrl-C or SIGTERM) at step {}, t {:.4e} s",
                    sim.steps(),
                    sim.time()
                ),
                String::new(),
                false,
            );
        }
        // A step leaves the nodes' z and v_z current (`Fresh::Nodes`), all that this reads.
        if let Some(reason) = sim.model.stop_reason() {
            break ("completed".to_string(), reason.to_string(), true);
        }
        if sim.steps() >= scene.run.max_steps {
            break (
                format!(
                    "stopped: max_steps = {} reached at t {:.4e} s",
                    scene.run.max_steps,
                    sim.time()
                ),
                String::new(),
                false,
            );
        }
        if let Err(e) = sim.step() {
            break (e.to_string(), String::new(), false);
        }
        let frame_due = opts.vtk && sim.time() >= next_frame;
        if sim.time() >= next_history {
            let row = match sim.check_slaves_inside().and_then(|()| sim.history_row()) {
                Ok(row) => row,
                Err(e) => break (e.to_string(), String::new(), false),
            };
            if let Err(e) = history.write(&row) {
                let failure = OutputFailure::new(Output::History, &e, Some(sim.model.when()));
                let status = failure.to_string();
                refused = Some(failure);
                break (status, String::new(), false);
            }
            history_step = sim.steps();
            next_history += scene.run.history_interval;
            progress.update(sim.time(), sim.steps(), row.depth, row.velocity);
            if let Err(e) = sim.model.energy_guard(row.energy_error) {
                break (e.to_string(), String::new(), false);
            }
        }
        // A due frame is handed over; a frame handed over earlier and refused stops the run.
        let written = match frames.as_mut() {
            Some(frames) if frame_due => match sim.frame(frame) {
                Ok(taken) => frames.send(taken),
                Err(e) => break (e.to_string(), String::new(), false),
            },
            Some(frames) => frames.check(),
            None => Ok(()),
        };
        if let Err(r) = written {
            let failure = OutputFailure::from(r);
            let status = failure.to_string();
            refused = Some(failure);
            break (status, String::new(), false);
        }
        if frame_due {
            frame += 1;
            frame_step = Some(sim.steps());
            next_frame += scene.run.output_interval;
        }
        if sim.time() >= next_checkpoint {
            let counters = Counters {
                frame,
                frame_step,
                history_step,
                next_history,
                next_frame,
            };
            // The frames it counts are on disk and listed before the checkpoint says so.
            let pvd = match frames.take().map(FrameWriter::drain).transpose() {
                Ok(pvd) => pvd,
                Err(e) => {
                    let failure = OutputFailure::from(e);
                    let status = failure.to_string();
                    refused = Some(failure);
                    break (status, String::new(), false);
                }
            };
            let saved = checkpoint::save(&mut sim, &opts.out, &mut history, pvd.as_ref(), counters);
            frames = pvd.map(|pvd| FrameWriter::spawn(opts.out.clone(), pvd));
            match saved {
                Ok(Ok(())) => {}
                Ok(Err((what, e))) => {
                    let failure = OutputFailure::new(what, &e, Some(sim.model.when()));
                    let status = failure.to_string();
                    refused = Some(failure);
                    break (status, String::new(), false);
                }
                Err(e) => break (e.to_string(), String::new(), false),
            }
            next_checkpoint = checkpoint::next_due(sim.time(), opts.checkpoint_every);
        }
    };
    progress.finish();
    // A run that stopped for another reason keeps that reason alone.
    let checked = sim
        .model()
        .and_then(|m| if ok { m.check_energy() } else { Ok(()) });
    let (mut status, reason, ok) = match checked {
        Ok(()) => (status, reason, ok),
        Err(e) if ok => (e.to_string(), String::new(), false),
        // Keep what stopped the run first.
        Err(e) => (format!("{status}; then {e}"), reason, false),
    };
    // Where the read-back failed, the status says so already.
    let _ = sim.check_slaves_inside();
    if refused.is_none() {
        // The last row and frame; after a refused write the disk has had its say.
        let step = sim.steps();
        let mut last = Ok(());
        if history_step != step {
            match sim.history_row() {
                Ok(row) => last = history.write(&row),
                Err(e) => status = format!("{status}; then {e}"),
            }
        }
        let when = Some(sim.model.when());
        let mut last = last
            .and_then(|()| history.flush())
            .map_err(|e| OutputFailure::new(Output::History, &e, when));
        if let Some(frames) = frames.as_mut() {
            if last.is_ok() && frame_step != Some(step) {
                match sim.frame(frame) {
                    Ok(taken) => last = frames.send(taken).map_err(OutputFailure::from),
                    Err(e) => status = format!("{status}; then {e}"),
                }
            }
        }
        // Every frame handed over written, or the first the disk refused.
        if let Some(frames) = frames.take() {
            let finished = frames.finish().map_err(OutputFailure::from);
            last = last.and(finished);
        }
        if let Err(failure) = last {
            status = format!("{status}; then {failure}");
            refused = Some(failure);
        }
    }
    // After a refusal too, the frames handed over are written before the summary.
    drop(frames);
    let summary = sim.summary(&status, &reason, started.elapsed().as_secs_f64());
    let saved = write_summary(&opts.out, &summary);
    if let Some(failure) = refused {
        return Err(RunError::from(OutputError {
            failure,
            kept: Some(Kept {
                status,
                folder: opts.out.clone(),
                summary: saved.map_err(|e| e.to_string()),
            }),
        }));
    }
    saved.map_err(|e| {
        let failure = OutputFailure::new(Output::Summary, &e, Some(sim.model.when()));
        RunError::from(OutputError::from(failure))
    })?;
    Ok(RunOutcome { summary, ok })
}

pub(super) fn write_summary(out: &Path, summary: &Summary) -> std::io::Result<()> {
    let json = serde_json::to_string_pretty(summary).map_err(std::io::Error::other)?;
    output::write_whole(&out.join("summary.json"), (json + "\n").as_bytes())
}

/// Says on stderr what `check`'s estimate foresees going wrong before the run starts: more
/// steps than `run.max_steps` to `run.end_time`, and outputs that overfill the disk.
/// `fell_back`: why `--backend auto` runs on the CPU path, said first with the steps to run.
pub(super) fn warn_from_estimate(scene: &Scene, out: &Path, vtk: bool, fell_back: Option<&str>) {
    let Ok(mesh) = mesh::projectile::build(&scene.model_projectile()) else {
        return;
    };
    let e = crate::estimate::estimate(scene, &mesh);
    if let Some(why) = fell_back {
        eprintln!(
            "penetrate run: --backend auto: {why}; the CPU path runs {} steps to run.end_time \
             (check's estimate), its time left shown as it goes",
            e.steps_text()
        );
    }
    if let Some(line) = steps_warning(scene, &e) {
        eprintln!("{line}");
    }
    if let Some(free) = output::free_bytes(out) {
        warn_if_outputs_overfill(&e, out, vtk, free);
    }
}

/// The warning for a run whose estimated steps to `run.end_time` exceed `run.max_steps` (a
/// sliver in the projectile's mesh, from a feature far smaller than its elements, can ask for
/// billions), naming what sets the step; `None` when the cap is not in reach. The estimate
/// takes the concrete at its stiffest, so a run may take fewer steps than it says.
pub(super) fn steps_warning(scene: &Scene, e: &crate::estimate::Estimate) -> Option<String> {
    if e.steps <= scene.run.max_steps {
        return None;
    }
    let by = if e.dt_fem <= e.dt_sph {
        format!(
            "the projectile mesh's smallest element, {:.3e} m high ({:.2e} of projectile.element_size)",
            e.fem_altitude,
            e.fem_altitude / scene.projectile.element_size
        )
    } else {
        "the concrete's particles (target.spacing and its stiffness)".to_string()
    };
    Some(format!(
        "penetrate: warning: this run needs {} steps to run.end_time = {} s at check's estimated step of {:.3e} s, set by {by}; run.max_steps = {} would stop it near t ≈ {:.3e} s",
        e.steps_text(),
        crate::scene::number_text(scene.run.end_time),
        e.dt,
        scene.run.max_steps,
        scene.run.max_steps as f64 * e.dt
    ))
}

/// Says on stderr when the frames (unless `--no-vtk`) and the history rows a run writes, by
/// `check`'s estimate, need more than the `free` bytes where they go: such a run stops when
/// the disk is full (exit code 3).
pub(super) fn warn_if_outputs_overfill(
    e: &crate::estimate::Estimate,
    out: &Path,
    vtk: bool,
    free: u64,
) {
    let frame_bytes = if vtk { e.frames_bytes() } else { 0.0 };
    if frame_bytes + e.history_bytes() > free as f64 {
        use crate::estimate::MIB;
        let rows = format!(
            "{} history rows, ≈ {:.1} MiB,",
            e.history_rows,
            e.history_bytes() / MIB
        );
        let what = if vtk {
            format!(
                "{} frames, ≈ {:.1} MiB of binary VTU, and {rows}",
                e.frames,
                frame_bytes / MIB
            )
        } else {
            rows
        };
        let remedy = if vtk {
            "raise run.output_interval or run.history_interval, or pass --no-vtk"
        } else {
            "raise run.history_interval"
        };
        eprintln!(
            "penetrate: warning: this run may write {what} and {} has {:.1} MiB free: the run stops (exit code 3) when the disk is full; {remedy}",
            out.display(),
            free as f64 / MIB
        );
    }
}
