//! Building a simulation: the meshes, the state, the pass list and the first forces, on the
//! backend asked for.

use super::gpu_step::GpuStepper;
use super::{Account, Model, Pass, RunError, Simulation};
use crate::cpu::neighbours::CellGrid;
use crate::gpu::step::{GpuStep, StepSetup};
use crate::mesh;
use crate::scene::{Backend, Scene};
use crate::state::{FemParams, Particles, Projectile, SphParams};

impl Model {
    /// Build the meshes, the state and the pass list, at rest before the first forces.
    pub(super) fn assemble(scene: &Scene) -> Result<Model, RunError> {
        crate::estimate::check_fits(scene).map_err(RunError::Setup)?;
        // Built with the world's `origin_z` at z = 0, added back in frames and messages
        // (`world_z`): f32 positions resolve a step's motion only near the origin (a Taylor bar
        // placed at z = 100 m would not move at all).
        let spec = &scene.model_projectile();
        let pmesh = mesh::projectile::build(spec).map_err(|e| RunError::Setup(e.to_string()))?;
        let projectile = Projectile::from_mesh(
            &pmesh,
            spec.velocity as f32,
            spec.material.strength.t_room,
            spec.cell_pressure,
        );
        let fem = FemParams::new(&spec.material);
        let (particles, sph, hit_order) = match &scene.target {
            Some(t) => {
                let mut lattice = mesh::target::lattice(
                    t.radius,
                    t.thickness,
                    t.spacing,
                    t.concrete.density as f64,
                )
                .map_err(|e| RunError::Setup(e.to_string()))?;
                mesh::target::drill(&mut lattice, t.lead_hole_depth, t.lead_hole_diameter);
                (
                    Particles::from_lattice(&lattice, t),
                    Some(SphParams::new(t)),
                    lattice.site,
                )
            }
            None => (Particles::default(), None, Vec::new()),
        };
        let shank_from = (spec.nose_z + spec.shape.nose_length(spec.diameter)) as f32;
        let shank = (0..pmesh.elements.len() as u32)
            .filter(|&e| {
                let n = pmesh.elements[e as usize];
                n.iter().map(|&i| pmesh.node_z[i as usize]).sum::<f32>() / 3.0 > shank_from
            })
            .collect();
        let on_nose = nose_masters(&pmesh, shank_from);
        let r_max = pmesh.node_r.iter().copied().fold(0.0f32, f32::max);
        let k = scene.contact.slave_radius_factor as f32;
        // In the order the correction applies their hits (the CPU's detection keeps it).
        let mut slaves: Vec<u32> = (0..particles.len() as u32)
            .filter(|&i| particles.r[i as usize] <= k * r_max)
            .collect();
        slaves.sort_unstable_by_key(|&i| hit_order[i as usize]);
        let rigid = scene.contact.lambda == 0.0 && scene.wall.is_none();
        let images = scene.contact.kernel == crate::scene::SurfaceKernel::Images;
        let passes = crate::pass::for_scene(sph.is_some(), !rigid, images);
        let walls = super::Walls {
            offset: crate::cpu::wall::OFFSET_SPACINGS
                * scene.target.as_ref().map_or(0.0, |t| t.spacing as f32),
            ..Default::default()
        };
        let extent = scene
            .target
            .as_ref()
            .map_or(0.0, |t| t.radius.max(t.thickness))
            + spec.length
            + 0.5 * spec.diameter
            + spec.nose_z.abs();
        let mut sim = Model {
            scene: scene.clone(),
            particles,
            sph,
            grid: CellGrid::default(),
            projectile,
            fem,
            slaves,
            hit_order,
            walls,
            passes,
            time: 0.0,
            step: 0,
            dt: 0.0,
            fem_limited: false,
            account: Account::default(),
            last_hits: 0,
            origin: scene.origin_z(),
            wall_z: scene.wall.as_ref().map(|_| 0.0),
            escape: (20.0 * extent) as f32,
            shank,
            on_nose,
            adapter: "none (CPU reference path)".into(),
            reduced: None,
        };
        sim.account.initial_kinetic = sim.kinetic_energy();
        sim.account.initial_momentum = sim.momentum_z();
        sim.account.min_dt = f64::MAX;
        sim.account.segment_impulse = vec![0.0; sim.projectile.masters.len()];
        Ok(sim)
    }

    /// The first forces and Δt: unstable when the scene as built cannot take a step.
    pub(super) fn start(&mut self) -> Result<(), RunError> {
        self.forces(0.0)?;
        self.dt = self.stable_dt()?;
        Ok(())
    }
}

impl Simulation {
    /// Move the step onto a GPU adapter. The state as it stands is uploaded; from here on
    /// `step` runs there.
    pub fn use_gpu(&mut self, gpu: crate::gpu::Gpu) -> Result<(), RunError> {
        let adapter = gpu.adapter_name();
        let m = self.current(super::Fresh::Full)?;
        let setup = StepSetup {
            particles: m.sph.as_ref().map(|sp| (&m.particles, sp)),
            projectile: &m.projectile,
            fem: &m.fem,
            passes: &m.passes,
            slaves: &m.slaves,
            wall_z: m.wall_z,
            escape: m.escape,
            cfl: m.scene.run.cfl as f32,
            dt: m.dt,
            fem_limited: m.fem_limited,
            list_skin: crate::gpu::step::LIST_SKIN,
            walls: m
                .passes
                .contains(&Pass::Walls)
                .then_some((m.walls.offset, &m.walls.sums[..])),
        };
        let step =
            GpuStep::new(gpu, &setup).map_err(|error| RunError::Gpu { error, when: None })?;
        let base = m.account.clone();
        m.adapter = adapter;
        self.stepper = Box::new(GpuStepper {
            step: Box::new(step),
            base,
            wall_booked: (0.0, 0.0),
        });
        Ok(())
    }
}

/// Per master segment of `mesh`: whether it lies on the nose, its midpoint ahead of the
/// nose–shank junction at `shank_from` (a flat end's face counts, its midpoint on the
/// junction; a shell's cavity wall carries no masters).
pub(super) fn nose_masters(mesh: &mesh::ProjectileMesh, shank_from: f32) -> Vec<bool> {
    let z = &mesh.node_z;
    mesh.masters
        .iter()
        .map(|m| 0.5 * (z[m.a as usize] + z[m.b as usize]) <= shank_from)
        .collect()
}

/// Build the model on the backend asked for: `gpu` fails without a usable adapter; `auto` takes
/// a real GPU if there is one and the CPU otherwise.
pub fn build(
    scene: &Scene,
    backend: Backend,
    adapter: Option<&str>,
) -> Result<Simulation, RunError> {
    let mut sim = Simulation::new(scene)?;
    attach(&mut sim, backend, adapter)?;
    Ok(sim)
}

/// Move a started model onto the backend asked for (see [`build`]).
/// Under `auto`, why the CPU path runs when it does.
pub(super) fn attach(
    sim: &mut Simulation,
    backend: Backend,
    adapter: Option<&str>,
) -> Result<Option<String>, RunError> {
    match backend {
        Backend::Cpu => {}
        Backend::Gpu => {
            let gpu = crate::gpu::Gpu::new(adapter)
                .map_err(|e| RunError::Setup(format!("--backend gpu: {e}")))?;
            sim.use_gpu(gpu)?;
        }
        Backend::Auto => match auto_gpu(adapter) {
            Ok(gpu) => sim.use_gpu(gpu)?,
            Err(why) => return Ok(Some(why)),
        },
    }
    Ok(None)
}

/// What `auto` takes, the same in every command: a hardware GPU wgpu finds, or the adapter
/// `adapter` names (lavapipe included: named, it is wanted); else `Err` with why the CPU path
/// runs instead.
pub fn auto_gpu(adapter: Option<&str>) -> Result<crate::gpu::Gpu, String> {
    let gpu = crate::gpu::Gpu::new(adapter).map_err(|e| format!("no GPU adapter ({e})"))?;
    if adapter.is_some() || crate::gpu::is_hardware(&gpu.info) {
        Ok(gpu)
    } else {
        Err(format!(
            "only a software adapter, {} (name it with --adapter to use it)",
            gpu.adapter_name()
        ))
    }
}

/// The one backend `backend` means here: `auto` resolved by [`auto_gpu`], with why it fell
/// back to the CPU path when it did.
pub fn resolve(backend: Backend, adapter: Option<&str>) -> (Backend, Option<String>) {
    match backend {
        Backend::Auto => match auto_gpu(adapter) {
            Ok(_) => (Backend::Gpu, None),
            Err(why) => (Backend::Cpu, Some(why)),
        },
        b => (b, None),
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    /// The smoke scene's ogive: the nose's masters run from the tip to the junction and no
    /// further, and their lengths add up to the tangent ogive's arc s φ_tip (s = crh d, cos
    /// φ_tip = (s − a)/s) within the chords' shortfall; the shank and the tail face are not
    /// the nose. A Taylor bar's flat end is.
    #[test]
    fn nose_masters_are_the_ogive_arc() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let scene = crate::scene::load(&root.join("cases/smoke.toml"), &[]).unwrap();
        let spec = scene.model_projectile();
        let mesh = mesh::projectile::build(&spec).unwrap();
        let junction = (spec.nose_z + spec.shape.nose_length(spec.diameter)) as f32;
        let nose = nose_masters(&mesh, junction);
        let (z, r) = (&mesh.node_z, &mesh.node_r);
        let mut arc = 0.0f64;
        for (m, &on) in mesh.masters.iter().zip(&nose) {
            let (a, b) = (m.a as usize, m.b as usize);
            if on {
                assert!(
                    z[a] <= junction && z[b] <= junction,
                    "{m:?} behind the junction"
                );
                arc += ((r[a] - r[b]) as f64).hypot((z[a] - z[b]) as f64);
            } else {
                assert!(
                    z[a] >= junction && z[b] >= junction,
                    "{m:?} ahead of the junction"
                );
            }
        }
        let crate::scene::ProjectileShape::Ogive { crh } = spec.shape else {
            panic!("the smoke projectile is an ogive")
        };
        let d = spec.diameter;
        let s = crh * d;
        let expected = s * ((s - 0.5 * d) / s).acos();
        assert!(
            arc < expected && arc > 0.99 * expected,
            "the nose's masters are {arc} m long against the arc's {expected} m"
        );
        assert!(nose.iter().any(|&on| !on), "the shank has masters");

        let bar = crate::scene::load(&root.join("cases/taylor-4340-208.toml"), &[]).unwrap();
        let spec = bar.model_projectile();
        let mesh = mesh::projectile::build(&spec).unwrap();
        let nose = nose_masters(&mesh, spec.nose_z as f32);
        for (m, &on) in mesh.masters.iter().zip(&nose) {
            let face = mesh.node_z[m.a as usize] == spec.nose_z as f32
                && mesh.node_z[m.b as usize] == spec.nose_z as f32;
            assert_eq!(on, face, "{m:?}");
        }
        assert!(nose.iter().any(|&on| on), "the bar's end face has masters");
    }

    /// The correction's order is the lattice's, row by row from the face and each row from the
    /// axis out, though the particles are stored along the Z-order curve: the slave list (the
    /// order the CPU's detection gives hits in) follows it, and so does `hit_order`, which the
    /// GPU path sorts its hits by.
    #[test]
    fn hits_are_applied_row_by_row_whatever_the_storage_order() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let scene = crate::scene::load(&root.join("cases/smoke.toml"), &[]).unwrap();
        let mut sim = Simulation::new(&scene).unwrap();
        let m = sim.model().unwrap();
        let p = &m.particles;
        let row_by_row = |a: u32, b: u32| {
            let (a, b) = (a as usize, b as usize);
            (-p.z[a], p.r[a]).partial_cmp(&(-p.z[b], p.r[b])).unwrap()
        };
        let stored: Vec<u32> = (0..p.len() as u32).collect();
        assert!(
            !stored.is_sorted_by(|&a, &b| row_by_row(a, b).is_le()),
            "the particles are stored row by row: this test checks nothing"
        );
        assert!(m.slaves.len() > 100, "{} slaves", m.slaves.len());
        for pair in m.slaves.windows(2) {
            assert!(row_by_row(pair[0], pair[1]).is_lt(), "slaves {pair:?}");
            assert!(m.hit_order[pair[0] as usize] < m.hit_order[pair[1] as usize]);
        }
    }
}
