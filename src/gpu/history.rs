//! `history` on the GPU (shaders/history.wgsl): the particles' part of a history row, reduced
//! per chunk of [`CHUNK`] particles, and the slaves' positions, so that a row reads eight words
//! per chunk and a pair per slave instead of five fields of every particle and their impulses.

use super::shader::Program;
use super::state::GpuParticles;
use super::{Batched, Gpu, GpuError, Kernel, Part, ReadBatch};

/// Words per chunk in `partials` (history.wgsl).
const PARTIAL: usize = 8;

/// Particles each thread folds: at 10⁶ particles the partials are 0.5 MB against the 24 MB of
/// the fields they stand for.
pub const CHUNK: u32 = 64;

/// What a history row takes of the particles, as the GPU reduced it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParticleTotals {
    /// Σ ½ m |v|² (J).
    pub kinetic: f64,
    /// Σ m e (J).
    pub internal: f64,
    /// Σ of the particles' wall impulses (N s).
    pub impulse: f64,
    /// Σ m v_z (N s).
    pub momentum_z: f64,
    /// The fastest particle (the lowest index of the fastest): index, r, z, speed.
    pub fastest: Option<(usize, f32, f32, f32)>,
}

pub struct HistoryPass {
    kernel: Kernel,
    bind: wgpu::BindGroup,
    _counts: wgpu::Buffer,
    partials: wgpu::Buffer,
    slave_at: wgpu::Buffer,
    slaves: Vec<u32>,
    n_particles: usize,
}

impl HistoryPass {
    pub fn new(
        gpu: &Gpu,
        particles: &GpuParticles,
        impulse: &wgpu::Buffer,
        slaves: &[u32],
    ) -> Result<HistoryPass, GpuError> {
        let kernel = gpu.kernel(Program::History, "reduce", &[])?;
        let n = particles.len;
        let counts = gpu.buffer("history counts", &[n as u32, slaves.len() as u32]);
        let slave_buf = gpu.buffer("history slaves", slaves);
        let partials = gpu.zeros::<f32>("history partials", PARTIAL * n.div_ceil(CHUNK as usize));
        let slave_at = gpu.zeros::<[f32; 2]>("slave positions", slaves.len());
        let p = particles;
        let bind = kernel.bind(
            gpu,
            &[
                ("counts", &counts),
                ("r", &p.r),
                ("z", &p.z),
                ("vr", &p.vr),
                ("vz", &p.vz),
                ("mass", &p.mass),
                ("energy", &p.energy),
                ("impulse", impulse),
                ("slaves", &slave_buf),
                ("partials", &partials),
                ("slave_at", &slave_at),
            ],
        )?;
        Ok(HistoryPass {
            kernel,
            bind,
            _counts: counts,
            partials,
            slave_at,
            slaves: slaves.to_vec(),
            n_particles: n,
        })
    }

    /// Record the reduction: a thread per chunk of particles and per slave.
    pub fn record(&self, pass: &mut wgpu::ComputePass) {
        let threads = self.chunks().max(self.slaves.len());
        self.kernel.dispatch(pass, &self.bind, threads as u32);
    }

    fn chunks(&self) -> usize {
        self.n_particles.div_ceil(CHUNK as usize)
    }

    /// Add the reads of the partials and the slaves' positions to `batch`.
    pub fn queue<'a>(&'a self, batch: &mut ReadBatch<'a>) -> [Part; 2] {
        [
            batch.add::<f32>(&self.partials, PARTIAL * self.chunks()),
            batch.add::<[f32; 2]>(&self.slave_at, self.slaves.len()),
        ]
    }

    /// The totals from what `queue` read (the chunks summed in their order, in f64), and
    /// the slaves' positions written into `r`, `z`.
    pub fn take(
        &self,
        read: &Batched,
        parts: [Part; 2],
        r: &mut [f32],
        z: &mut [f32],
    ) -> ParticleTotals {
        let partials = read.take::<f32>(parts[0]);
        let mut t = ParticleTotals {
            kinetic: 0.0,
            internal: 0.0,
            impulse: 0.0,
            momentum_z: 0.0,
            fastest: None,
        };
        // As the host's fold: a particle at rest is nobody's fastest.
        let mut best = 0.0f32;
        for w in partials.chunks_exact(PARTIAL) {
            t.kinetic += w[0] as f64;
            t.internal += w[1] as f64;
            t.impulse += w[2] as f64;
            t.momentum_z += w[7] as f64;
            if w[3] > best {
                best = w[3];
                t.fastest = Some((w[4].to_bits() as usize, w[5], w[6], w[3]));
            }
        }
        for (&s, at) in self.slaves.iter().zip(read.take::<[f32; 2]>(parts[1])) {
            r[s as usize] = at[0];
            z[s as usize] = at[1];
        }
        t
    }
}
