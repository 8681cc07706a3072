//! Up-front estimates for `penetrate check`: counts, stable step, step count, memory.

use std::path::{Path, PathBuf};

use crate::materials::hjc;
use crate::mesh::geometry::Geometry;
use crate::mesh::{self, ProjectileMesh};
use crate::scene::{Scene, TargetSpec};

/// Bytes of state per particle (28 scalar arrays, 2 three-vectors and the 2 index arrays of
/// the cell grid), per element and per node (with its share of the node → element CSR).
const BYTES_PER_PARTICLE: usize = (28 + 6 + 2) * 4;
/// Bytes of the CPU path's neighbour list per neighbour (`cpu::neighbours::Pair`).
const BYTES_PER_NEIGHBOUR: usize = 20;
const BYTES_PER_ELEMENT: usize = 22 * 4;
const BYTES_PER_NODE: usize = 12 * 4;

/// Entity counts and state bytes of a scene, from its sizes alone (nothing is allocated).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    pub particles: usize,
    pub nodes: usize,
    pub elements: usize,
    pub bytes: f64,
}

pub fn footprint(s: &Scene) -> Footprint {
    let p = &s.projectile;
    // Closed-form bound first (quads of the element size over the half-section); the exact count
    // walks every cell and is only worth it when the bound is reasonable.
    let cells = (p.length / p.element_size + 2.0) * (0.5 * p.diameter / p.element_size + 2.0);
    let (nodes, elements) = if cells * 4.0 * BYTES_PER_ELEMENT as f64 > 0.5 * available_memory() {
        ((2.0 * cells) as usize, (4.0 * cells) as usize)
    } else {
        mesh::projectile::estimate_counts(p)
    };
    let particles = s.target.as_ref().map_or(0, particle_count);
    let bytes = particles as f64 * s.target.as_ref().map_or(0, particle_bytes) as f64
        + elements as f64 * BYTES_PER_ELEMENT as f64
        + nodes as f64 * BYTES_PER_NODE as f64;
    Footprint {
        particles,
        nodes,
        elements,
        bytes,
    }
}

/// Bytes per particle: its state and the CPU path's list of its neighbours, the lattice sites
/// within the kernel's support 2h = 2 (h/Δ) Δ of it (the GPU's lists are smaller).
fn particle_bytes(t: &TargetSpec) -> usize {
    let reach = 2.0 * t.smoothing_ratio;
    let neighbours = (std::f64::consts::PI * reach * reach).ceil() as usize;
    BYTES_PER_PARTICLE + neighbours * BYTES_PER_NEIGHBOUR
}

/// Particles of a target: its lattice less those a lead hole leaves out.
fn particle_count(t: &TargetSpec) -> usize {
    let (cols, rows) = mesh::target::lattice_count(t.radius, t.thickness, t.spacing);
    let drilled = mesh::target::drilled_count(
        t.radius,
        t.thickness,
        t.spacing,
        t.lead_hole_depth,
        t.lead_hole_diameter,
    );
    // A lattice whose count overflows cannot be built, hole or not.
    cols.checked_mul(rows).map_or(usize::MAX, |n| n - drilled)
}

/// Memory this machine can give a run (bytes): MemAvailable of /proc/meminfo (8 GiB where it
/// cannot be read), or less where the process's memory cgroup has less room left: a batch
/// job's limit (Slurm's `--mem`) is its cgroup's, whatever the node has free.
pub fn available_memory() -> f64 {
    let free = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
            let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
            Some(kib * 1024.0)
        })
        .unwrap_or(8.0 * 1024.0 * 1024.0 * 1024.0);
    std::fs::read_to_string("/proc/self/cgroup")
        .ok()
        .and_then(|text| cgroup_room(&text, Path::new("/sys/fs/cgroup")))
        .map_or(free, |room| room.min(free))
}

/// Room left under the memory limits of the cgroup that `proc_cgroup` (the text of
/// /proc/self/cgroup) names and of its ancestors, the hierarchies mounted under `root`: the
/// limit less the usage that cannot be reclaimed (inactive file pages can): v2's `memory.max`,
/// `memory.current` and `memory.stat`'s `inactive_file`, v1's `memory.limit_in_bytes`,
/// `memory.usage_in_bytes` and `total_inactive_file`. None where no limit is set or readable.
fn cgroup_room(proc_cgroup: &str, root: &Path) -> Option<f64> {
    let bytes = |path: PathBuf| -> Option<f64> {
        std::fs::read_to_string(path)
            .ok()?
            .trim()
            .parse::<u64>()
            .ok()
            .map(|b| b as f64)
    };
    let stat = |path: PathBuf, key: &str| -> f64 {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        text.lines()
            .find_map(|l| {
                l.strip_prefix(key)?
                    .strip_prefix(' ')?
                    .trim()
                    .parse::<u64>()
                    .ok()
            })
            .map_or(0.0, |b| b as f64)
    };
    let mut room: Option<f64> = None;
    for line in proc_cgroup.lines() {
        let mut fields = line.splitn(3, ':');
        let (Some(_), Some(controllers), Some(path)) =
            (fields.next(), fields.next(), fields.next())
        else {
            continue;
        };
        // v2 is mounted at the root, or beside v1 at unified/ (the hybrid layout).
        let (mounts, limit, usage, inactive) = if controllers.is_empty() {
            (
                vec![root.to_path_buf(), root.join("unified")],
                "memory.max",
                "memory.current",
                "inactive_file",
            )
        } else if controllers.split(',').any(|c| c == "memory") {
            (
                vec![root.join("memory")],
                "memory.limit_in_bytes",
                "memory.usage_in_bytes",
                "total_inactive_file",
            )
        } else {
            continue;
        };
        for mount in mounts {
            let mut at = mount.join(path.trim_start_matches('/'));
            loop {
                if let (Some(l), Some(u)) = (bytes(at.join(limit)), bytes(at.join(usage))) {
                    let used = (u - stat(at.join("memory.stat"), inactive)).max(0.0);
                    let left = (l - used).max(0.0);
                    room = Some(room.map_or(left, |r: f64| r.min(left)));
                }
                if at == mount || !at.pop() {
                    break;
                }
            }
        }
    }
    room
}

/// Refuse a scene whose state would not fit in half of the available memory, before anything is
/// allocated, with the estimate and what to change.
pub fn check_fits(s: &Scene) -> Result<Footprint, String> {
    let f = footprint(s);
    let available = available_memory();
    // The meshers and outputs need working room beside the state; u32 indices cap the counts.
    if f.bytes > 0.5 * available
        || f.particles > u32::MAX as usize / 4
        || f.nodes > u32::MAX as usize / 4
    {
        return Err(format!(
            "the scene needs ≈ {:.1} GiB for {} particles, {} nodes and {} elements, more than this machine can give (≈ {:.1} GiB available): coarsen target.spacing or projectile.element_size, or shrink the target",
            f.bytes / GIB,
            if f.particles == usize::MAX {
                format!("more than {:.1e}", usize::MAX as f64)
            } else {
                f.particles.to_string()
            },
            f.nodes,
            f.elements,
            available / GIB
        ));
    }
    Ok(f)
}

pub const GIB: f64 = 1024.0 * MIB;

#[derive(Clone, Copy, Debug)]
pub struct Estimate {
    pub particles: usize,
    pub slaves: usize,
    /// The projectile mesh's smallest element altitude (m), which sets `dt_fem`.
    pub fem_altitude: f64,
    pub dt_fem: f64,
    pub dt_sph: f64,
    pub dt: f64,
    /// Steps to `run.end_time` at the estimated step (not capped by `run.max_steps`).
    pub steps: u64,
    pub bytes: usize,
    /// VTK frames a run writes unless `--no-vtk`: the first, one per `run.output_interval`
    /// (at most one a step, to `end_time` or `run.max_steps`) and the last (unless one of
    /// those fell on the last step).
    pub frames: u64,
    /// The binary VTU bytes of one frame, target and projectile.
    pub frame_bytes: usize,
    /// Rows a run writes to `history.csv`: the first, one per `run.history_interval` reached
    /// (at most one a step, to `end_time` or `run.max_steps`) and the last (unless one of
    /// those fell on the last step).
    pub history_rows: u64,
}

impl Estimate {
    /// `steps` as a message says it: `≈ N`, or, where `run.end_time / dt` is beyond what a
    /// `u64` counts (`steps` saturated), `more than 1.8e19` rather than that bound as a count.
    pub fn steps_text(&self) -> String {
        match self.steps {
            u64::MAX => format!("more than {:.1e}", u64::MAX as f64),
            n => format!("≈ {n}"),
        }
    }

    /// The bytes of every frame a run writes.
    pub fn frames_bytes(&self) -> f64 {
        self.frames as f64 * self.frame_bytes as f64
    }

    /// The bytes of `history.csv`.
    pub fn history_bytes(&self) -> f64 {
        self.history_rows as f64 * HISTORY_BYTES_PER_ROW as f64
    }
}

pub const MIB: f64 = 1024.0 * 1024.0;

/// Bytes of one `history.csv` row, a little above what a shot's rows take (the 277 m/s shot
/// at ×2 and the shell at 112.5 m/s: 265 and 266 on average before the contact's impulse and
/// force were added; the smoke scene at 800 m/s with them: 305; with the nose's two more: 341,
/// at most 359).
const HISTORY_BYTES_PER_ROW: usize = 400;

/// Binary VTU bytes a frame takes for each particle, node and element (`output::vtk`): a
/// particle's position (3 × f32), vertex cell (connectivity and offset i32, type u8) and 10
/// f32 fields; a node's position and 2 fields; an element's 3 corners, offset, type and 6
/// fields.
const FRAME_BYTES_PER_PARTICLE: usize = 12 + 9 + 10 * 4;
const FRAME_BYTES_PER_NODE: usize = 12 + 2 * 4;
const FRAME_BYTES_PER_ELEMENT: usize = 12 + 5 + 6 * 4;
/// The XML headers of a frame's two files and their arrays' byte counts, a little above the
/// smoke case's 1826 + 1617 bytes.
const FRAME_HEADER_BYTES: usize = 4096;

/// The intervals of length `interval` that reach `end` (the last may end past it): `end /
/// interval` rounded up, but a quotient within round-off of a whole number (2e-5 / 2e-6 =
/// 10.000000000000002) is that number, as a run's accumulated due times find it.
fn intervals(end: f64, interval: f64) -> u64 {
    let q = end / interval;
    let whole = q.round();
    let n = if (q - whole).abs() <= 1e-9 * whole {
        whole
    } else {
        q.ceil()
    };
    n.min(u64::MAX as f64) as u64
}

pub fn estimate(s: &Scene, m: &ProjectileMesh) -> Estimate {
    let c_steel = s.projectile.material.wave_speed();
    let l_min = m
        .elements
        .iter()
        .map(|el| Geometry::new(el, &m.node_r, &m.node_z).min_altitude() as f64)
        .fold(f64::MAX, f64::min);
    let dt_fem = l_min / c_steel;
    let (particles, slaves, dt_sph) = match &s.target {
        Some(t) => {
            let (cols, rows) = mesh::target::lattice_count(t.radius, t.thickness, t.spacing);
            let r_max = s.projectile.diameter / 2.0;
            let slave_cols =
                ((s.contact.slave_radius_factor * r_max / t.spacing).ceil() as usize).min(cols);
            let c = &t.concrete;
            let k = hjc::stiffest_tangent_to_lock(c) as f64;
            let c_dense = ((k + 4.0 / 3.0 * c.shear_modulus as f64) / c.density as f64).sqrt();
            let h = t.spacing * t.smoothing_ratio;
            (
                particle_count(t),
                slave_cols.saturating_mul(rows),
                h / (c_dense * (1.0 + 1.2 * t.viscosity_alpha)),
            )
        }
        None => (0, 0, f64::MAX),
    };
    let dt = s.run.cfl * dt_fem.min(dt_sph);
    let steps = (s.run.end_time / dt).ceil().min(u64::MAX as f64) as u64;
    let bytes = particles * s.target.as_ref().map_or(0, particle_bytes)
        + m.elements.len() * BYTES_PER_ELEMENT
        + m.node_r.len() * BYTES_PER_NODE;
    // After the first, one at each interval reached (at most one a step of those the run
    // takes), the last at the end unless one of those fell on the last step.
    let taken = steps.min(s.run.max_steps);
    let frames = if s.run.output_interval > 0.0 {
        intervals(s.run.end_time, s.run.output_interval)
            .min(taken)
            .saturating_add(1)
    } else {
        2
    };
    let history_rows = intervals(s.run.end_time, s.run.history_interval)
        .min(taken)
        .saturating_add(1);
    Estimate {
        particles,
        slaves,
        fem_altitude: l_min,
        dt_fem,
        dt_sph,
        dt,
        steps,
        bytes,
        frames,
        frame_bytes: FRAME_HEADER_BYTES
            + particles * FRAME_BYTES_PER_PARTICLE
            + m.node_r.len() * FRAME_BYTES_PER_NODE
            + m.elements.len() * FRAME_BYTES_PER_ELEMENT,
        history_rows,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn smoke(overrides: &[&str]) -> Scene {
        crate::scene::shipped_case("smoke.toml", overrides)
    }

    /// A job's memory cgroup bounds what a run may take: the tightest limit among the cgroup
    /// and its ancestors, less the usage that cannot be reclaimed, in the v2, hybrid and v1
    /// layouts; no limit, or none readable, bounds nothing.
    #[test]
    fn a_memory_cgroup_bounds_the_room() {
        let root = std::env::temp_dir().join(format!("penetrate-cgroup-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let write = |dir: &Path, files: &[(&str, &str)]| {
            std::fs::create_dir_all(dir).unwrap();
            for (name, text) in files {
                std::fs::write(dir.join(name), text).unwrap();
            }
        };
        const GIB: u64 = 1 << 30;
        let (job, step) = ("slurm/uid_0/job_7", "slurm/uid_0/job_7/step_0/task_0");
        // v2: the job's limit 4 GiB, 1 GiB used of which 0.25 GiB inactive file pages; the
        // task's own cgroup sets none, the node's root none either.
        let v2 = root.join("v2");
        write(&v2, &[("memory.max", "max\n"), ("memory.current", "1\n")]);
        write(
            &v2.join(job),
            &[
                ("memory.max", &format!("{}\n", 4 * GIB)),
                ("memory.current", &format!("{}\n", GIB)),
                (
                    "memory.stat",
                    &format!("anon 1\ninactive_file {}\n", GIB / 4),
                ),
            ],
        );
        write(
            &v2.join(step),
            &[("memory.max", "max\n"), ("memory.current", "5\n")],
        );
        let proc_v2 = format!("0::/{step}\n");
        let room = cgroup_room(&proc_v2, &v2).unwrap();
        assert_eq!(room, (4 * GIB - GIB + GIB / 4) as f64);
        // The same tree beside v1 controllers (hybrid): found under unified/.
        let hybrid = root.join("hybrid");
        std::fs::create_dir_all(&hybrid).unwrap();
        std::fs::rename(&v2, hybrid.join("unified")).unwrap();
        let proc_hybrid = format!("4:memory:/elsewhere\n1:cpu:/\n0::/{step}\n");
        assert_eq!(cgroup_room(&proc_hybrid, &hybrid), Some(room));
        // v1: a 2 GiB limit on the job, its usage all in use.
        let v1 = root.join("v1").join("memory");
        write(
            &v1,
            &[
                ("memory.limit_in_bytes", "9223372036854771712\n"),
                ("memory.usage_in_bytes", "0\n"),
            ],
        );
        write(
            &v1.join(job),
            &[
                ("memory.limit_in_bytes", &format!("{}\n", 2 * GIB)),
                ("memory.usage_in_bytes", &format!("{}\n", GIB / 2)),
                ("memory.stat", "total_inactive_file 0\n"),
            ],
        );
        let proc_v1 = format!("7:cpuacct,cpu:/\n4:memory:/{job}\n0::/\n");
        assert_eq!(
            cgroup_room(&proc_v1, &root.join("v1")),
            Some((2 * GIB - GIB / 2) as f64)
        );
        // No limit anywhere, and no cgroup files at all.
        assert_eq!(cgroup_room("0::/\n", &root.join("none")), None);
        let open = root.join("open");
        write(&open, &[("memory.max", "max\n"), ("memory.current", "9\n")]);
        assert_eq!(cgroup_room("0::/\n", &open), None);
        let _ = std::fs::remove_dir_all(&root);
    }

    /// The memory estimate counts the CPU path's list at its size: the shipped cases'
    /// h = 1.5 Δ gives each interior particle the 28 lattice sites within 3 Δ, which the
    /// estimate takes as the disc's area rounded up, 29.
    #[test]
    fn the_neighbour_list_is_counted_at_its_size() {
        use crate::cpu::neighbours::Pair;
        assert_eq!(std::mem::size_of::<Pair>(), BYTES_PER_NEIGHBOUR);
        let scene = smoke(&["target.smoothing_ratio=1.5"]);
        let t = scene.target.as_ref().unwrap();
        assert_eq!(
            particle_bytes(t),
            BYTES_PER_PARTICLE + 29 * BYTES_PER_NEIGHBOUR
        );
    }

    /// The smoke scene with `key = interval`: its estimate, and the folder a CPU run of it
    /// wrote (frames with `vtk`), for the caller to read and remove.
    fn estimate_and_run(key: &str, interval: &str, vtk: bool) -> (Estimate, std::path::PathBuf) {
        let scene = smoke(&[&format!("{key}={interval}")]);
        let m = mesh::projectile::build(&scene.model_projectile()).unwrap();
        let dir =
            std::env::temp_dir().join(format!("penetrate-{key}-{}-{interval}", std::process::id()));
        let mut opts = crate::solver::RunOptions::new(dir.clone());
        opts.quiet = true;
        opts.vtk = vtk;
        opts.backend = Some(crate::scene::Backend::Cpu);
        crate::solver::run(&scene, &opts).unwrap();
        (estimate(&scene, &m), dir)
    }

    /// `check`'s frame count is what a run to `end_time` writes, and its size a little above
    /// the frames'; one frame a step at most, and the last
    /// not written twice when an output interval ends on the last step (20 µs at 5 µs: 0, 5,
    /// 10, 15, 20; at 3 µs: 0, 3, …, 18 and 20).
    #[test]
    fn frames_are_counted_and_sized() {
        for (interval, frames) in [("5e-6", 5), ("3e-6", 8)] {
            let (e, dir) = estimate_and_run("run.output_interval", interval, true);
            assert_eq!(e.frames, frames);
            let (mut written, mut bytes) = (0, 0);
            for entry in std::fs::read_dir(&dir).unwrap() {
                let entry = entry.unwrap();
                let name = entry.file_name().into_string().unwrap();
                written += u64::from(name.starts_with("projectile_"));
                if name.ends_with(".vtu") {
                    bytes += entry.metadata().unwrap().len() as usize;
                }
            }
            let pvd = std::fs::read_to_string(dir.join("frames.pvd")).unwrap();
            let _ = std::fs::remove_dir_all(&dir);
            assert_eq!(written, e.frames);
            let times: Vec<&str> = pvd
                .lines()
                .filter(|l| l.contains("part=\"1\""))
                .map(|l| l.split('"').nth(1).unwrap())
                .collect();
            let mut distinct = times.clone();
            distinct.dedup();
            assert_eq!(distinct, times, "a frame written twice: {pvd}");
            let estimated = e.frames as usize * e.frame_bytes;
            assert!(
                estimated >= bytes && estimated < 2 * bytes,
                "{estimated} against {bytes}"
            );
        }
        let every_step = smoke(&["run.output_interval=1e-12"]);
        let m = mesh::projectile::build(&every_step.model_projectile()).unwrap();
        assert_eq!(
            estimate(&every_step, &m).frames,
            estimate(&every_step, &m).steps + 1
        );
        assert_eq!(estimate(&smoke(&["run.output_interval=0"]), &m).frames, 2);
    }

    /// `check`'s history row count is what a run to `end_time` writes, and its size a little
    /// above the file's; one row a step at most, and the last not written twice when a
    /// history interval ends on the last step (20 µs at 2 µs: 0, 2, …, 20; at 3 µs: 0, 3, …,
    /// 18 and 20).
    #[test]
    fn history_rows_are_counted_and_sized() {
        for (interval, rows) in [("2e-6", 11), ("3e-6", 8)] {
            let (e, dir) = estimate_and_run("run.history_interval", interval, false);
            assert_eq!(e.history_rows, rows);
            let csv = std::fs::read_to_string(dir.join("history.csv")).unwrap();
            let _ = std::fs::remove_dir_all(&dir);
            let steps: Vec<&str> = csv
                .lines()
                .skip(1)
                .map(|l| l.split(',').nth(1).unwrap())
                .collect();
            assert_eq!(steps.len() as u64, e.history_rows, "{csv}");
            let mut distinct = steps.clone();
            distinct.dedup();
            assert_eq!(distinct, steps, "a row written twice: {csv}");
            let estimated = e.history_bytes();
            let bytes = csv.len() as f64;
            assert!(
                estimated >= bytes && estimated < 2.0 * bytes,
                "{estimated} against {bytes}"
            );
        }
        // No more rows than the first and one a step of those `run.max_steps` lets the run take.
        let capped = smoke(&["run.history_interval=1e-12", "run.max_steps=100"]);
        let m = mesh::projectile::build(&capped.model_projectile()).unwrap();
        assert_eq!(estimate(&capped, &m).history_rows, 101);
    }

    /// The target's step is set by the stiffest EOS tangent the concrete can reach: K₁ for the
    /// reference constants, the elastic P_crush/μ_crush when that is stiffer (it is the sound
    /// speed every particle starts with), so `check` does not promise 10⁴ times too few steps.
    #[test]
    fn sph_step_follows_the_stiffest_tangent() {
        let sph_step = |s: &Scene| {
            let m = mesh::projectile::build(&s.projectile).unwrap();
            estimate(s, &m).dt_sph
        };
        let wave = |k: f64, s: &Scene| {
            let t = s.target.as_ref().unwrap();
            let c = ((k + 4.0 / 3.0 * t.concrete.shear_modulus as f64) / t.concrete.density as f64)
                .sqrt();
            t.spacing * t.smoothing_ratio / (c * (1.0 + 1.2 * t.viscosity_alpha))
        };
        let reference = smoke(&[]);
        let k1 = reference.target.as_ref().unwrap().concrete.k1 as f64;
        let got = sph_step(&reference);
        assert!((got / wave(k1, &reference) - 1.0).abs() < 1e-6, "{got}");
        // μ_crush 1e-9: K_el = 1.2e16 Pa, 10⁵ times K₁.
        let stiff = smoke(&["target.concrete.mu_crush=1e-9"]);
        let t = stiff.target.as_ref().unwrap();
        let k_el = t.concrete.p_crush as f64 / t.concrete.mu_crush as f64;
        assert!(k_el > 1e5 * k1);
        let got = sph_step(&stiff);
        assert!((got / wave(k_el, &stiff) - 1.0).abs() < 1e-5, "{got}");
    }

    /// The count a message gives: exact where it fits, and a saturated count (an end time
    /// 10³⁷ steps away) said as a bound, not printed as 18446744073709551615 steps.
    #[test]
    fn steps_beyond_a_u64_are_said_as_a_bound() {
        let m = mesh::projectile::build(&smoke(&[]).model_projectile()).unwrap();
        let e = estimate(&smoke(&[]), &m);
        assert_eq!(e.steps_text(), format!("≈ {}", e.steps));
        let far = estimate(&smoke(&["run.end_time=1e30"]), &m);
        assert_eq!(far.steps, u64::MAX);
        assert_eq!(far.steps_text(), "more than 1.8e19");
    }
}
