//! `penetrate bench`: the coupled step's speed at several target sizes, on the GPU and on the
//! CPU reference path. The scene is a shipped penetration case with its particle spacing set so
//! the target holds about the asked number of particles; the projectile starts at the surface,
//! so contact is live within the first steps. A benchmark, not a test: it reports numbers.

use std::path::Path;
use std::time::Instant;

use crate::gpu::step::PROFILED;
use crate::scene::{self, Backend};
use crate::solver::{self, Simulation};

/// One row of the table.
#[derive(Clone, Debug)]
pub struct BenchRow {
    pub backend: String,
    pub particles: usize,
    pub elements: usize,
    pub steps: usize,
    pub ms_per_step: f64,
    pub particle_steps_per_s: f64,
    /// (pass, ms per step) from GPU timestamps; empty without them.
    pub pass_ms: Vec<(&'static str, f64)>,
    /// A bare submit + copy + map of the step's clock, µs (GPU only).
    pub readback_us: Option<f64>,
    /// GPU buffer bytes per particle (GPU only).
    pub bytes_per_particle: Option<f64>,
    /// Neighbour-list builds during the timed steps, and what a step that builds them costs
    /// more, ms (GPU only).
    pub list_builds: Option<u64>,
    pub build_ms: Option<f64>,
    /// The host's share of a timed GPU step, µs: recording the passes, finishing and
    /// submitting them, waiting for the read-back (the GPU's work and the round trip), and the
    /// rest (the contact correction, its writes and the solver's bookkeeping).
    pub host_us: Option<[f64; 4]>,
    /// Compute dispatches a step records (GPU only): the fewest over the timed steps (a step
    /// that builds no lists), and the mean of the steps that each build them.
    pub dispatches: Option<(u64, f64)>,
    /// Bytes a timed step read back and wrote, on average (GPU only; `gpu_transfers`' steps).
    pub step_bytes: Option<(f64, f64)>,
    /// Why this size did not run on this backend (a limit of the adapter, say).
    pub refused: Option<String>,
}

/// Run the benchmark of `case` at each size on each backend. `steps` is the GPU's timed step
/// count; the CPU takes fewer at large sizes (about 2·10⁶ particle-steps per size).
pub fn run(
    case: &Path,
    sizes: &[usize],
    backends: &[Backend],
    adapter: Option<&str>,
    steps: usize,
    mut log: impl FnMut(&str),
) -> Result<Vec<BenchRow>, String> {
    let base = scene::load(case, &[]).map_err(|e| e.to_string())?;
    let target = base
        .target
        .as_ref()
        .ok_or_else(|| format!("{}: bench needs a scene with a target", case.display()))?;
    if steps == 0 {
        return Err("bench --steps 0: at least one timed step".into());
    }
    // The target's spacing may not exceed the projectile's radius (one particle per radius).
    let radius = 0.5 * base.projectile.diameter;
    let fewest = ((target.radius * target.thickness / (radius * radius)).ceil() as usize).max(100);
    let mut rows = Vec::new();
    for &n in sizes {
        if n < fewest {
            return Err(format!(
                "bench size {n}: {} needs at least {fewest} particles (a spacing of at most \
                 the projectile's radius, {radius} m)",
                case.display()
            ));
        }
        let spacing = (target.radius * target.thickness / n as f64).sqrt();
        let set = vec![format!("target.spacing={spacing:e}")];
        let scene = scene::load(case, &set).map_err(|e| e.to_string())?;
        for &backend in backends {
            let name = backend.name();
            log(&format!("bench: {n} particles on the {name}: building"));
            let mut sim = match solver::build(&scene, backend, adapter) {
                Ok(sim) => sim,
                Err(e) => {
                    log(&format!("bench: {n} particles on the {name}: {e}"));
                    rows.push(BenchRow {
                        backend: name.into(),
                        particles: n,
                        elements: 0,
                        steps: 0,
                        ms_per_step: 0.0,
                        particle_steps_per_s: 0.0,
                        pass_ms: Vec::new(),
                        readback_us: None,
                        bytes_per_particle: None,
                        list_builds: None,
                        build_ms: None,
                        host_us: None,
                        dispatches: None,
                        step_bytes: None,
                        refused: Some(e.to_string()),
                    });
                    continue;
                }
            };
            let timed = match backend {
                Backend::Cpu => (2_000_000
                    / sim
                        .model()
                        .map_err(|e| e.to_string())?
                        .particles
                        .len()
                        .max(1))
                .max(3)
                .min(steps),
                _ => steps,
            };
            for _ in 0..5 {
                sim.step().map_err(|e| e.to_string())?;
            }
            log(&format!(
                "bench: {n} particles on the {name}: {timed} steps"
            ));
            let builds_before = sim.list_builds();
            let host_before = sim.gpu_step().map(|g| g.host);
            let step_traffic = |sim: &mut Simulation| sim.gpu_step().map(|g| g.traffic.steps);
            let traffic_before = step_traffic(&mut sim);
            let dispatched = |sim: &mut Simulation| sim.gpu_step().map(|g| g.dispatches());
            let mut fewest_dispatches: Option<u64> = None;
            let mut wall = 0.0;
            for _ in 0..timed {
                let before = dispatched(&mut sim);
                let start = Instant::now();
                sim.step().map_err(|e| e.to_string())?;
                wall += start.elapsed().as_secs_f64();
                if let (Some(a), Some(b)) = (dispatched(&mut sim), before) {
                    fewest_dispatches = Some(fewest_dispatches.map_or(a - b, |f| f.min(a - b)));
                }
            }
            let host_us = sim
                .gpu_step()
                .map(|g| g.host)
                .zip(host_before)
                .map(|(a, b)| {
                    let per_step = |x: f64| 1e6 * x / timed as f64;
                    let (record, submit, wait) =
                        (a.record - b.record, a.submit - b.submit, a.wait - b.wait);
                    [
                        per_step(record),
                        per_step(submit),
                        per_step(wait),
                        per_step(wall - record - submit - wait),
                    ]
                });
            let step_bytes = step_traffic(&mut sim).zip(traffic_before).map(|(a, b)| {
                let per_step = |x: u64, y: u64| (x - y) as f64 / timed as f64;
                (
                    per_step(a.read_bytes, b.read_bytes),
                    per_step(a.written_bytes, b.written_bytes),
                )
            });
            let list_builds = Some(sim.list_builds() - builds_before);
            // Steps that each build the lists: their extra time, and on the GPU their dispatches.
            let building = timed.min(10);
            let before = dispatched(&mut sim);
            let build_ms = build_cost(&mut sim, 1e3 * wall / timed as f64, building)?;
            let per_build = dispatched(&mut sim)
                .zip(before)
                .map(|(a, b)| (a - b) as f64 / building.max(1) as f64);
            let on_gpu = sim.backend() == "gpu";
            let m = sim.model().map_err(|e| e.to_string())?;
            let (particles, elements) = (m.particles.len(), m.projectile.elements.len());
            let mut row = BenchRow {
                backend: if on_gpu {
                    format!("gpu: {}", m.adapter)
                } else {
                    "cpu".into()
                },
                particles,
                elements,
                steps: timed,
                ms_per_step: 1e3 * wall / timed as f64,
                particle_steps_per_s: particles as f64 * timed as f64 / wall,
                pass_ms: Vec::new(),
                readback_us: None,
                bytes_per_particle: None,
                list_builds,
                build_ms: Some(build_ms),
                host_us,
                dispatches: None,
                step_bytes,
                refused: None,
            };
            if let Some(g) = sim.gpu_step() {
                row.bytes_per_particle = Some(g.gpu_bytes() as f64 / particles.max(1) as f64);
                row.readback_us = Some(g.readback_latency(50).map_err(|e| e.to_string())? * 1e6);
                row.dispatches = fewest_dispatches.zip(per_build);
            }
            row.pass_ms = profile(&mut sim, 10)?;
            rows.push(row);
        }
    }
    Ok(rows)
}

/// How much longer a step is when it builds the neighbour lists than `plain_ms`, over `steps`
/// steps that each build them (ms).
fn build_cost(sim: &mut Simulation, plain_ms: f64, steps: usize) -> Result<f64, String> {
    let start = Instant::now();
    for _ in 0..steps {
        sim.force_list_build();
        sim.step().map_err(|e| e.to_string())?;
    }
    Ok(1e3 * start.elapsed().as_secs_f64() / steps.max(1) as f64 - plain_ms)
}

/// Mean GPU time per pass over `steps` profiled steps (ms), where the adapter has timestamps.
fn profile(sim: &mut Simulation, steps: usize) -> Result<Vec<(&'static str, f64)>, String> {
    let on = sim.gpu_step().is_some_and(|g| g.enable_profiling());
    if !on {
        return Ok(Vec::new());
    }
    let mut sums = vec![0.0; PROFILED.len()];
    for _ in 0..steps {
        sim.step().map_err(|e| e.to_string())?;
        let Some(g) = sim.gpu_step() else { break };
        for (s, t) in sums
            .iter_mut()
            .zip(g.pass_seconds().map_err(|e| e.to_string())?)
        {
            *s += t;
        }
    }
    Ok(PROFILED
        .iter()
        .zip(sums)
        .map(|(name, s)| (*name, 1e3 * s / steps as f64))
        .collect())
}

/// The table as Markdown.
pub fn table(rows: &[BenchRow]) -> String {
    let mut out = String::from(
        "| backend | particles | elements | steps | ms/step | particle-steps/s | read-back µs | GPU bytes/particle | list builds | ms per list build | dispatches/step (building lists) | host µs/step: record / submit / wait / rest | bytes/step read / written |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        if let Some(why) = &r.refused {
            out += &format!(
                "| {} | ~{} | – | – | – | not run: {} | – | – | – | – | – | – | – |\n",
                r.backend,
                r.particles,
                why.replace('|', "/")
            );
            continue;
        }
        out += &format!(
            "| {} | {} | {} | {} | {:.3} | {:.3e} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.backend,
            r.particles,
            r.elements,
            r.steps,
            r.ms_per_step,
            r.particle_steps_per_s,
            r.readback_us.map_or("–".into(), |v| format!("{v:.0}")),
            r.bytes_per_particle
                .map_or("–".into(), |v| format!("{v:.0}")),
            r.list_builds.map_or("–".into(), |v| v.to_string()),
            r.build_ms.map_or("–".into(), |v| format!("{v:.2}")),
            r.dispatches.map_or("–".into(), |(plain, build)| format!(
                "{plain} ({build:.1})"
            )),
            r.host_us.map_or("–".into(), |h| format!(
                "{:.0} / {:.0} / {:.0} / {:.0}",
                h[0], h[1], h[2], h[3]
            )),
            r.step_bytes.map_or("–".into(), |(read, written)| format!(
                "{read:.0} / {written:.0}"
            )),
        );
    }
    let profiled: Vec<&BenchRow> = rows.iter().filter(|r| !r.pass_ms.is_empty()).collect();
    if !profiled.is_empty() {
        out += "\nGPU time per pass (ms per step, timestamp queries):\n\n| particles |";
        for p in PROFILED {
            out += &format!(" {p} |");
        }
        out += "\n|---|";
        out += &"---|".repeat(PROFILED.len());
        out += "\n";
        for r in profiled {
            out += &format!("| {} |", r.particles);
            for (_, ms) in &r.pass_ms {
                out += &format!(" {ms:.3} |");
            }
            out += "\n";
        }
    }
    out
}
