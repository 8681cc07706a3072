//! The GPU state read back for outputs (gpu::step): a history row's share of it or all of it,
//! after the pending second half of the last step, in one submission waited for once.

use super::super::history::ParticleTotals;
use super::super::state::{GpuElements, GpuNodes, GpuParticles};
use super::super::timestep::{slot_dt, CLOCK_SLOTS};
use super::super::traffic::Charge;
use super::super::{GpuError, Part, ReadBatch};
use super::GpuStep;
use crate::state::{Particles, Projectile};

impl GpuStep {
    /// An encoder that first finishes the last step (its forces and the next Δt), where that
    /// is pending, so that what it copies after sees the complete state, and for a history
    /// row reduces the particles; and whether those forces build the neighbour lists (None:
    /// nothing was pending). `finished` records it once submitted.
    fn finishing_encoder(&self, what: Sync) -> (wgpu::CommandEncoder, Option<bool>) {
        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("finish step"),
            });
        let build = self.pending_forces.then(|| self.lists_stale());
        let history = self
            .sph
            .as_ref()
            .map(|s| &s.history)
            .filter(|_| what == Sync::History);
        if build.is_some() || history.is_some() {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            if let Some(build) = build {
                self.record_forces(&mut pass, build);
            }
            if let Some(h) = history {
                h.record(&mut pass);
            }
        }
        (encoder, build)
    }

    /// The last step's second half has run (`finishing_encoder`).
    fn finished(&mut self, build: Option<bool>) {
        if let Some(build) = build {
            self.built(build);
            self.pending_forces = false;
            self.pending_fixes = 0;
            self.pending_nodes = false;
            self.pending_recentre = false;
            self.folded = true;
        }
    }

    /// Finish the step and read the state back into the CPU structures, with the accumulated
    /// boundary impulse, wall loss and plastic work (sums over entities, f64), and the next Δt.
    /// `Sync::Full` reads every field; `Sync::History` only what a history row and the check
    /// for slaves left inside need: the projectile, the slaves' positions and the particles'
    /// sums as `history.wgsl` reduces them (`Totals::particles`), the host's other particle
    /// fields left as they were.
    pub fn download(
        &mut self,
        particles: &mut Particles,
        projectile: &mut Projectile,
        what: Sync,
    ) -> Result<Totals, GpuError> {
        self.charge(None, false);
        let (encoder, build) = self.finishing_encoder(what);
        let mut batch = ReadBatch::new();
        let n_p = particles.len();
        let n_n = projectile.nodes.len();
        let n_e = projectile.elements.len();
        let sph = self.sph.as_ref().map(|s| match what {
            Sync::Full => Reads::Full(
                s.particles.queue(&mut batch, particles),
                batch.add::<f32>(&self.acc.particle_impulse, n_p),
            ),
            Sync::History => Reads::History(s.history.queue(&mut batch)),
        });
        let nodes = self.nodes.queue(&mut batch, &projectile.nodes);
        let elements = self
            .fem
            .as_ref()
            .map(|_| self.elements.queue(&mut batch, &projectile.elements));
        // The segments' reactions, past the elements' forces (`walls::csr`).
        let n_m = projectile.masters.len();
        let walls = self.sph.as_ref().and_then(|s| s.walls.as_ref());
        let wall_sums = walls.map(|_| batch.add_at::<[f32; 6]>(&self.elements.force, n_e, n_m));
        let wall_impulse = walls.map(|w| batch.add::<f32>(&w.impulse, n_m));
        let clock = batch.add::<u32>(&self.clock, (CLOCK_SLOTS / 4 + 4) as usize);
        let node_impulse = batch.add::<f32>(&self.acc.node_impulse, n_n);
        let node_lost = batch.add::<f32>(&self.acc.node_lost, n_n);
        let plastic = batch.add::<f32>(&self.plastic_total, n_e);
        let read = batch.read(&self.gpu, encoder)?;
        self.finished(build);
        let sum = |part| {
            read.take::<f32>(part)
                .iter()
                .map(|&x| x as f64)
                .sum::<f64>()
        };
        let (particle_impulse, reduced) = match (sph, &self.sph) {
            (Some(Reads::Full(parts, impulse)), _) => {
                GpuParticles::take(&read, &parts, particles);
                (sum(impulse), None)
            }
            (Some(Reads::History(parts)), Some(s)) => {
                let t = s
                    .history
                    .take(&read, parts, &mut particles.r, &mut particles.z);
                (t.impulse, Some(t))
            }
            _ => (0.0, None),
        };
        GpuNodes::take(&read, &nodes, &mut projectile.nodes);
        if let Some(parts) = elements {
            GpuElements::take(&read, &parts, &mut projectile.elements);
            // The GPU gathers the nodal forces at the start of the next integration: the
            // host's are the same gather, in the same order, of the forces just read.
            crate::cpu::fem_forces::run(&mut projectile.nodes, &projectile.elements);
        }
        let wall_sums = wall_sums.map(|part| {
            let sums: Vec<[f32; 4]> = read
                .take::<[f32; 6]>(part)
                .iter()
                .map(|f| [-f[0], -f[1], -f[2], -f[3]])
                .collect();
            crate::cpu::wall::react(&mut projectile.nodes, &projectile.masters, &sums);
            sums
        });
        let wall_impulse = wall_impulse.map(|part| read.take::<f32>(part));
        let totals = Totals {
            boundary_impulse: particle_impulse + sum(node_impulse),
            particles: reduced,
            wall_lost: sum(node_lost),
            wall_impulse,
            wall_sums,
            plastic_work: sum(plastic),
            next_dt: self.next_dt(&read.take::<u32>(clock)),
        };
        let to = match what {
            Sync::Full => Charge::Full,
            Sync::History => Charge::History,
        };
        self.charge(Some(to), true);
        Ok(totals)
    }
}

impl GpuStep {
    /// The Δt the next integration takes, from the clock's words: the slot a fold filled
    /// (as integrate.wgsl makes it), or the clock's own where none has run since.
    fn next_dt(&self, clock: &[u32]) -> f32 {
        if !self.folded {
            return f32::from_bits(clock[0]);
        }
        let at = (CLOCK_SLOTS / 4) as usize + 2 * self.dt_slot as usize;
        slot_dt(clock[at], clock[at + 1], self.cfl)
    }
}

/// How much of the state `GpuStep::download` reads back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sync {
    Full,
    History,
}

/// What `download` reads of the particles: every field and the wall impulses, or the history
/// pass's partials and the slaves' positions.
enum Reads {
    Full(Vec<Part>, Part),
    History([Part; 2]),
}

/// Sums the host takes from the GPU's per-entity accumulators.
#[derive(Clone, Debug, Default)]
pub struct Totals {
    /// The particles' part of a history row as the GPU reduced it (`Sync::History`); `None`
    /// when the host's particles were read whole.
    pub particles: Option<ParticleTotals>,
    pub boundary_impulse: f64,
    pub wall_lost: f64,
    /// With wall images: per master segment, the z-impulse their reaction gave the projectile
    /// since the GPU took over (N s).
    pub wall_impulse: Option<Vec<f32>>,
    /// With wall images: the segments' last sums (`Model::walls`), as the entries past the
    /// elements' forces hold them reversed.
    pub wall_sums: Option<Vec<[f32; 4]>>,
    pub plastic_work: f64,
    pub next_dt: f32,
}
