//! Checkpoints of a run (`penetrate run --checkpoint-every`) and the restart from one
//! (`--restart`). A checkpoint holds everything that decides the steps still to come and the
//! outputs still to be written, so that a run killed and restarted ends as it would have
//! uninterrupted: bit for bit on the CPU path, whose neighbour lists are built again from the
//! positions they were last built at. A GPU run's state is read back to be written, and a
//! restart may go onto either backend; the GPU's neighbour lists are rebuilt on it.
//!
//! The file, `restart.bin` in the output folder, little-endian throughout:
//!
//! | bytes | what |
//! |---|---|
//! | 8 | magic, `PENETRST` |
//! | 4 | format version, [`VERSION`] |
//! | 8 | payload length in bytes |
//! | 4 | CRC-32 (IEEE) of the payload |
//! | … | payload |
//!
//! The payload, in order: the solver build that wrote it (`output::summary::build_id`), the
//! resolved scene (`Scene::resolved_table`); the model's time, step, next Δt, last hit count
//! and origin, its [`Account`]; every array of the particles, the projectile's nodes and its
//! elements, in their structs' field order; the wall images' last sums per master segment
//! (`Model::walls`: the reaction the next integration books; none without images); the
//! positions the CPU path's neighbour lists were built at, r then z (none where they must be
//! built again), and its count of builds; the run loop's [`Counters`]; where `history.csv` stood ([`Mark`]); the entries of `frames.pvd`, or
//! none for a run without frames. An array is its length (u64) and its items, a string its
//! length in bytes (u64) and its UTF-8, an option a byte 0 or 1 and the value, a `usize` a
//! u64, a struct its fields in order. The field lists below are exhaustive patterns: a field added to a state struct does not compile
//! until it is written here too (and [`VERSION`] goes up).
//!
//! A restart is refused unless the same build of the solver wrote the file (the executable's
//! fingerprint, as `validate --resume` asks of a run): the run's `summary.json` names one
//! build, and another build's step need not be the same step, so a run continued by another
//! would be a mixture that no build reproduces. The scene must resolve to the same table, and
//! the output folder must hold the `history.csv` the checkpoint counts.

use std::fmt;
use std::path::{Path, PathBuf};

use codec::{Get, Lengths, Put, Reader};

use super::{Account, Model, Output, RunError, RunOptions, Simulation};
use crate::output::history::{self, History, Mark};
use crate::output::summary::{build_id, same_build};
use crate::output::{self, vtk, RESTART_FILE};
use crate::scene::Scene;
use crate::state::{Elements, Nodes, Particles};

/// The format's version: raised whenever the payload changes, so that an older file is
/// refused by name rather than misread.
pub const VERSION: u32 = 8;

const MAGIC: [u8; 8] = *b"PENETRST";

/// Magic, version, payload length and checksum.
const HEADER: usize = 24;

/// A frame as `frames.pvd` lists it: time (s), part (0 the target, 1 the projectile), file.
pub type FrameEntry = (f64, usize, String);

/// What a restart file holds.
#[derive(Clone, Debug)]
pub struct Checkpoint {
    /// The solver build that wrote it (`output::summary::build_id`).
    pub build: String,
    /// The run's resolved scene (`Scene::resolved_table`).
    pub scene: String,
    pub state: State,
    pub counters: Counters,
    pub history: Mark,
    /// The entries of `frames.pvd`; `None` for a run without frames (`--no-vtk`).
    pub frames: Option<Vec<FrameEntry>>,
}

/// What of a model changes as it steps; the rest is built again from the scene.
#[derive(Clone, Debug, Default)]
pub struct State {
    /// s
    pub time: f64,
    pub step: u64,
    /// The next step's Δt (s), evaluated at the end of the last one.
    pub dt: f32,
    pub last_hits: usize,
    /// World z of the model's z = 0 (`Model::recentre`), m.
    pub origin: f64,
    pub account: Account,
    pub particles: Particles,
    pub nodes: Nodes,
    pub elements: Elements,
    /// The wall images' sums per master segment (`Model::walls`), empty without images.
    pub wall_sums: Vec<[f32; 4]>,
    /// Where the CPU path's neighbour lists were built (`CellGrid::built_at`): r, then z.
    pub lists_built_at: [Vec<f32>; 2],
    /// How many times the CPU path built them (`CellGrid::builds`).
    pub list_builds: u64,
}

/// Where the run loop stood besides the model: the frames and rows it had written, and when
/// the next ones are due.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Counters {
    /// Frames written: the next frame's number.
    pub frame: usize,
    /// The step of the last frame written.
    pub frame_step: Option<u64>,
    /// The step of the last history row written.
    pub history_step: u64,
    /// When the next history row is due (s).
    pub next_history: f64,
    /// When the next frame is due (s).
    pub next_frame: f64,
}

/// A checkpoint's contents, borrowed: from a running model to write it, or from a
/// [`Checkpoint`]. [`Checkpoint::decode`] reads them back in this order.
struct Parts<'a> {
    build: &'a str,
    scene: &'a str,
    time: f64,
    step: u64,
    dt: f32,
    last_hits: usize,
    origin: f64,
    account: &'a Account,
    particles: &'a Particles,
    nodes: &'a Nodes,
    elements: &'a Elements,
    wall_sums: &'a [[f32; 4]],
    lists_built_at: [&'a [f32]; 2],
    list_builds: u64,
    counters: &'a Counters,
    history: &'a Mark,
    frames: Option<&'a [FrameEntry]>,
}

impl<'a> Parts<'a> {
    /// The checkpoint of `m`, of the scene whose resolved table is `scene`, by this build.
    fn of(
        m: &'a Model,
        scene: &'a str,
        counters: &'a Counters,
        history: &'a Mark,
        frames: Option<&'a [FrameEntry]>,
    ) -> Parts<'a> {
        Parts {
            build: build_id(),
            scene,
            time: m.time,
            step: m.step,
            dt: m.dt,
            last_hits: m.last_hits,
            origin: m.origin,
            account: &m.account,
            particles: &m.particles,
            nodes: &m.projectile.nodes,
            elements: &m.projectile.elements,
            wall_sums: &m.walls.sums,
            lists_built_at: m.grid.built_at().into(),
            list_builds: m.grid.builds,
            counters,
            history,
            frames,
        }
    }

    /// The file's bytes: header and payload.
    fn encode(&self) -> Vec<u8> {
        let mut out = vec![0; HEADER];
        let w = &mut out;
        self.build.put(w);
        self.scene.put(w);
        self.time.put(w);
        self.step.put(w);
        self.dt.put(w);
        self.last_hits.put(w);
        self.origin.put(w);
        self.account.put(w);
        self.particles.put(w);
        self.nodes.put(w);
        self.elements.put(w);
        self.wall_sums.put(w);
        self.lists_built_at[0].put(w);
        self.lists_built_at[1].put(w);
        self.list_builds.put(w);
        self.counters.put(w);
        self.history.put(w);
        self.frames.put(w);
        let payload = &out[HEADER..];
        let mut header = Vec::with_capacity(HEADER);
        header.extend(MAGIC);
        VERSION.put(&mut header);
        (payload.len() as u64).put(&mut header);
        crc32fast::hash(payload).put(&mut header);
        out[..HEADER].copy_from_slice(&header);
        out
    }
}

impl Checkpoint {
    /// The file's bytes.
    pub fn encode(&self) -> Vec<u8> {
        let s = &self.state;
        Parts {
            build: &self.build,
            scene: &self.scene,
            time: s.time,
            step: s.step,
            dt: s.dt,
            last_hits: s.last_hits,
            origin: s.origin,
            account: &s.account,
            particles: &s.particles,
            nodes: &s.nodes,
            elements: &s.elements,
            wall_sums: &s.wall_sums,
            lists_built_at: [&s.lists_built_at[0], &s.lists_built_at[1]],
            list_builds: s.list_builds,
            counters: &self.counters,
            history: &self.history,
            frames: self.frames.as_deref(),
        }
        .encode()
    }

    /// A checkpoint from a file's bytes: refused when they are short, not a restart file, of
    /// another format version, or not what was written (checksum).
    pub fn decode(bytes: &[u8]) -> Result<Checkpoint, Refusal> {
        let seen = bytes.len().min(MAGIC.len());
        if bytes[..seen] != MAGIC[..seen] {
            return Err(Refusal::NotACheckpoint);
        }
        let truncated = |needed: usize| Refusal::Truncated {
            bytes: bytes.len() as u64,
            needed: needed as u64,
        };
        let mut header = Reader::new(bytes.get(MAGIC.len()..HEADER).ok_or(truncated(HEADER))?);
        let malformed = Refusal::Malformed;
        let version = u32::get(&mut header).map_err(malformed)?;
        if version != VERSION {
            return Err(Refusal::Version { found: version });
        }
        let length = u64::get(&mut header).map_err(malformed)?;
        let stored = u32::get(&mut header).map_err(malformed)?;
        let payload = &bytes[HEADER..];
        if (payload.len() as u64) < length {
            return Err(truncated(HEADER.saturating_add(length as usize)));
        }
        if payload.len() as u64 > length {
            return Err(Refusal::Malformed(format!(
                "{} bytes follow the {length} of the payload its header gives",
                payload.len() as u64 - length
            )));
        }
        let computed = crc32fast::hash(payload);
        if computed != stored {
            return Err(Refusal::Checksum { stored, computed });
        }
        Checkpoint::parse(&mut Reader::new(payload)).map_err(malformed)
    }

    /// The payload, in the order [`Parts::encode`] writes it.
    fn parse(r: &mut Reader<'_>) -> Result<Checkpoint, String> {
        let build = Get::get(r)?;
        let scene = Get::get(r)?;
        let state = State {
            time: Get::get(r)?,
            step: Get::get(r)?,
            dt: Get::get(r)?,
            last_hits: Get::get(r)?,
            origin: Get::get(r)?,
            account: Get::get(r)?,
            particles: Get::get(r)?,
            nodes: Get::get(r)?,
            elements: Get::get(r)?,
            wall_sums: Get::get(r)?,
            lists_built_at: [Get::get(r)?, Get::get(r)?],
            list_builds: Get::get(r)?,
        };
        let checkpoint = Checkpoint {
            build,
            scene,
            state,
            counters: Get::get(r)?,
            history: Get::get(r)?,
            frames: Get::get(r)?,
        };
        match r.left() {
            0 => Ok(checkpoint),
            left => Err(format!("{left} bytes are left after its last field")),
        }
    }

    /// The checkpoint in `file`.
    pub fn read(file: &Path) -> Result<Checkpoint, RestartError> {
        let refused = |refusal| RestartError {
            file: file.to_path_buf(),
            refusal,
        };
        let bytes = std::fs::read(file).map_err(|e| refused(Refusal::Unreadable(e.to_string())))?;
        Checkpoint::decode(&bytes).map_err(refused)
    }
}

/// Writes the checkpoint of `sim` into `out`, whole or not at all (the last one stays until
/// the new one is complete): its state (read back first from a GPU), the loop's `counters`, the
/// history, its rows sent to the file first so that the file holds every row the checkpoint
/// counts, and `frames`, the run's frame collection where it writes frames. A read-back that
/// fails is the outer error; an output the disk refused, the inner one.
pub(super) fn save(
    sim: &mut Simulation,
    out: &Path,
    history: &mut History,
    frames: Option<&vtk::Collection>,
    counters: Counters,
) -> Result<Result<(), (Output, std::io::Error)>, RunError> {
    let mark = match history.mark() {
        Ok(mark) => mark,
        Err(e) => return Ok(Err((Output::History, e))),
    };
    let m = sim.model()?;
    let scene = m.scene.resolved_table();
    let frames = frames.map(vtk::Collection::entries);
    let bytes = Parts::of(m, &scene, &counters, &mark, frames).encode();
    Ok(output::write_whole(&out.join(RESTART_FILE), &bytes).map_err(|e| (Output::Checkpoint, e)))
}

/// When the checkpoint after `time` is due (s): the next multiple of `every`; never without.
pub(super) fn next_due(time: f64, every: Option<f64>) -> f64 {
    every.map_or(f64::INFINITY, |every| {
        every * ((time / every).floor() + 1.0)
    })
}

/// A checkpoint a run goes on from (`RunOptions::restart`), checked against the scene and the
/// output folder.
pub(super) struct Restart {
    file: PathBuf,
    checkpoint: Checkpoint,
}

impl Restart {
    /// The checkpoint `opts.restart` names, if any, read and checked: written by this build,
    /// of `scene` as resolved, with frames as `opts.vtk` asks, its `history.csv` in `opts.out`
    /// as it was then. Nothing in the output folder is touched here.
    pub(super) fn open(scene: &Scene, opts: &RunOptions) -> Result<Option<Restart>, RunError> {
        let Some(file) = &opts.restart else {
            return Ok(None);
        };
        let refused = |refusal| {
            RunError::Restart(Box::new(RestartError {
                file: file.clone(),
                refusal,
            }))
        };
        let checkpoint = Checkpoint::read(file).map_err(|e| RunError::Restart(Box::new(e)))?;
        if !same_build(&checkpoint.build) {
            return Err(refused(Refusal::OtherBuild {
                file: checkpoint.build,
                this: build_id().to_string(),
            }));
        }
        let differences = scene_differences(&checkpoint.scene, &scene.resolved_table());
        if !differences.is_empty() {
            return Err(refused(Refusal::OtherScene(differences)));
        }
        if checkpoint.frames.is_some() != opts.vtk {
            return Err(refused(Refusal::Frames {
                written: checkpoint.frames.is_some(),
            }));
        }
        history::check_prefix(&opts.out.join("history.csv"), &checkpoint.history)
            .map_err(|why| refused(Refusal::History(why)))?;
        Ok(Some(Restart {
            file: file.clone(),
            checkpoint,
        }))
    }

    /// Puts the checkpoint's state into `model`, built from the same scene: the forces and the
    /// Δt of the step it had reached come with it. Refused where its arrays do not fit the
    /// model (only a file made by hand gets past the build and scene checks with such).
    pub(super) fn restore(&mut self, model: &mut Model) -> Result<(), RunError> {
        if let Some(why) = self.misfit(model) {
            return Err(self.refused(Refusal::OtherModel(why)));
        }
        let s = &mut self.checkpoint.state;
        model.particles = std::mem::take(&mut s.particles);
        model.projectile.nodes = std::mem::take(&mut s.nodes);
        model.projectile.elements = std::mem::take(&mut s.elements);
        model.walls.sums = std::mem::take(&mut s.wall_sums);
        model.time = s.time;
        model.step = s.step;
        model.dt = s.dt;
        // Which side set Δt is not stored; the state it was taken from is.
        model.least_steps();
        model.last_hits = s.last_hits;
        model.origin = s.origin;
        model.account = std::mem::take(&mut s.account);
        // The CPU step builds its lists where the run had (so that it sums each particle's
        // neighbours in the same order); the GPU never reads the host's and builds its own.
        let [r, z] = std::mem::take(&mut s.lists_built_at);
        model.grid.restore(r, z, s.list_builds);
        Ok(())
    }

    /// The outputs as they stood at the checkpoint, to be written on: `history.csv` cut back
    /// to its rows, the frames written after it and a `summary.json` removed, `frames.pvd`
    /// listing the frames before it.
    pub(super) fn resume_outputs(&self, out: &Path) -> std::io::Result<(History, vtk::Collection)> {
        let c = &self.checkpoint;
        output::clear_after_checkpoint(out, c.counters.frame).map_err(|e| output::named(out, e))?;
        let history = History::resume(&out.join("history.csv"), &c.history)?;
        let path = out.join("frames.pvd");
        let frames = match &c.frames {
            Some(entries) => vtk::Collection::resume(path, entries.clone())?,
            None => vtk::Collection::new(path),
        };
        Ok((history, frames))
    }

    /// Why the checkpoint's state does not fit `model`, if it does not: an array of another
    /// length, or other indices for a step to follow (a file that passes the build and scene
    /// checks has this scene's mesh, unless it was made by hand).
    fn misfit(&self, model: &Model) -> Option<String> {
        let (s, p) = (&self.checkpoint.state, &model.projectile);
        let sizes = [
            (
                "particles",
                s.particles.lengths(),
                model.particles.lengths(),
            ),
            ("nodes", s.nodes.lengths(), p.nodes.lengths()),
            ("elements", s.elements.lengths(), p.elements.lengths()),
        ];
        for (what, saved, built) in sizes {
            if let Some(((name, n), (_, m))) = saved.iter().zip(&built).find(|(a, b)| a != b) {
                return Some(format!(
                    "its {what}.{name} holds {n} values, this scene's model {m}"
                ));
            }
        }
        let segments = if model.passes.contains(&super::Pass::Walls) {
            p.masters.len()
        } else {
            0
        };
        if s.wall_sums.len() != segments {
            return Some(format!(
                "it holds the wall images' sums of {} master segments, this scene's model {segments}",
                s.wall_sums.len()
            ));
        }
        (s.elements.nodes != p.elements.nodes
            || s.elements.cells != p.elements.cells
            || s.nodes.elem_offsets != p.nodes.elem_offsets
            || s.nodes.elem_refs != p.nodes.elem_refs)
            .then(|| "its projectile's mesh is not the one this scene builds".into())
    }

    /// Where the run loop stood.
    pub(super) fn counters(&self) -> Counters {
        self.checkpoint.counters
    }

    fn refused(&self, refusal: Refusal) -> RunError {
        RunError::Restart(Box::new(RestartError {
            file: self.file.clone(),
            refusal,
        }))
    }
}

/// The keys whose values differ between two resolved scenes, each as `key: A there, B here`
/// (`there` the checkpoint's), the first few of them.
fn scene_differences(there: &str, here: &str) -> Vec<String> {
    /// `key = value  # unit` lines as (key, value).
    fn settings(table: &str) -> Vec<(&str, &str)> {
        table
            .lines()
            .filter_map(|line| line.split_once(" = "))
            .map(|(key, rest)| (key, rest.split_once("  # ").map_or(rest, |(v, _)| v)))
            .collect()
    }
    if there == here {
        return Vec::new();
    }
    let (a, b) = (settings(there), settings(here));
    let value = |table: &[(&str, &str)], key: &str| {
        table
            .iter()
            .find(|(k, _)| *k == key)
            .map_or("unset".to_string(), |(_, v)| v.to_string())
    };
    let mut seen = Vec::new();
    let mut differences = Vec::new();
    for (key, _) in a.iter().chain(&b) {
        if seen.contains(key) {
            continue;
        }
        seen.push(key);
        let (x, y) = (value(&a, key), value(&b, key));
        if x != y {
            differences.push(format!("{key}: {x} there, {y} here"));
        }
    }
    const SHOWN: usize = 5;
    if differences.len() > SHOWN {
        let more = differences.len() - SHOWN;
        differences.truncate(SHOWN);
        differences.push(format!("{more} more"));
    }
    if differences.is_empty() {
        // The same values, written otherwise (units): still not this build's table.
        differences.push("the resolved tables differ in their text".into());
    }
    differences
}

/// A restart file refused: which, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct RestartError {
    pub file: PathBuf,
    pub refusal: Refusal,
}

impl fmt::Display for RestartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "restart file {} {}", self.file.display(), self.refusal)
    }
}

/// Why a restart file is refused.
#[derive(Clone, Debug, PartialEq)]
pub enum Refusal {
    /// It could not be read (the system's reason).
    Unreadable(String),
    /// It ends before its header or its payload does.
    Truncated { bytes: u64, needed: u64 },
    /// It does not start with the magic.
    NotACheckpoint,
    /// It is in another version of the format.
    Version { found: u32 },
    /// Its payload is not what was written.
    Checksum { stored: u32, computed: u32 },
    /// Its payload does not parse though its checksum holds: written by hand, or a bug.
    Malformed(String),
    /// Another build of the solver wrote it.
    OtherBuild { file: String, this: String },
    /// It is of another scene: the values that differ.
    OtherScene(Vec<String>),
    /// Its state does not fit the model the scene builds.
    OtherModel(String),
    /// Its run wrote frames and this one would not (`written`), or the other way round.
    Frames { written: bool },
    /// The `history.csv` it continues is not in the output folder as it was.
    History(String),
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Refusal::Unreadable(why) => write!(f, "cannot be read: {why}"),
            Refusal::Truncated { bytes, needed } => write!(
                f,
                "is truncated: it has {bytes} bytes, its header and payload need {needed}"
            ),
            Refusal::NotACheckpoint => write!(
                f,
                "is not a penetrate restart file (it does not start with {})",
                String::from_utf8_lossy(&MAGIC)
            ),
            Refusal::Version { found } => write!(
                f,
                "is in restart format version {found}; this build reads version {VERSION} \
                 only: rerun the scene from the start"
            ),
            Refusal::Checksum { stored, computed } => write!(
                f,
                "is corrupt: its checksum says {stored:08x}, its payload gives {computed:08x}"
            ),
            Refusal::Malformed(why) => write!(f, "is malformed: {why}"),
            Refusal::OtherBuild { file, this } => write!(
                f,
                "was written by {file}, and this is {this}: a run goes on only with the build \
                 that started it (its summary.json names one build, and another build's step \
                 need not be the same); rerun the scene from the start, or restart with that build"
            ),
            Refusal::OtherScene(differences) => write!(
                f,
                "is of another scene ({}): restart with the case and --set values of the run \
                 that wrote it",
                differences.join("; ")
            ),
            Refusal::OtherModel(why) => {
                write!(f, "does not fit the model this scene builds: {why}")
            }
            Refusal::Frames { written: true } => write!(
                f,
                "is of a run that writes VTK frames: restart it without --no-vtk"
            ),
            Refusal::Frames { written: false } => write!(
                f,
                "is of a run started with --no-vtk: restart it with --no-vtk"
            ),
            Refusal::History(why) => write!(
                f,
                "does not continue the history in the output folder: {why}; restart into the \
                 folder it was written in"
            ),
        }
    }
}

mod codec;
#[cfg(test)]
mod tests;
