//! The whole step on the GPU (architecture.md, "Shape of one step"), with one read-back per step.
//!
//! One submission holds the second half of step k−1 and the first half of step k:
//!
//! ```text
//! apply (k−1's corrected slaves) → neighbours → sph_rates → concrete → sph_forces
//!   → fem_stress → fem_forces → Δt reduction (clock.dt = Δt_k)
//!   → integrate (Δt_k) → displacement watch → contact detect
//!   → copy clock, watch, status, hits, nodes to the staging buffer
//! ```
//!
//! then one mapping brings back Δt_k, how far the particles have moved since the neighbour
//! lists were built, the status words, the nodes' positions and velocities, and the hits with
//! their slaves' kinematics, as many as the last steps' most with margin (`HitBound`; a step
//! with more reads them in a second round trip); the host applies the λ correction and the global shift
//! (physics.md §4, `contact::correct`) and writes the corrected slaves and nodes for the next
//! submission, which builds the neighbour lists again only when a particle may have moved half
//! the lists' skin (`LIST_SKIN`). `download` runs a pending second half and then copies what
//! it reads, all in one submission waited for once, so that the GPU state is the CPU's after
//! the same number of `Simulation::step` calls (for outputs).

use std::time::Instant;

use super::contact_detect::ContactPass;
use super::fem_forces::FemForcesPass;
use super::fem_stress::FemStressPass;
use super::integrate::{
    Accumulators, IntegratePass, STATUS_CLEAR, STATUS_INVERTED_ELEMENT, STATUS_NODE_ESCAPED,
    STATUS_NODE_NONFINITE, STATUS_PARTICLE_ESCAPED, STATUS_PARTICLE_NONFINITE, STATUS_WORDS,
};
use super::neighbours::{GpuGrid, NeighboursPass, MOVED2_OFFSET};
use super::params::{FemUniform, SphUniform, StepUniform};
use super::profiler::Profiler;
use super::state::{GpuElements, GpuNodes, GpuParticles};
use super::timestep::TimestepPass;
use super::traffic::{Charge, Tally, Traffic};
use super::ReadBatch;
use super::{Gpu, GpuError};
use crate::pass::Pass;
use crate::state::{FemParams, Nodes, Particles, Projectile, SphParams};

/// The neighbour lists hold the particles within the support grown by this fraction of it, so
/// they stay complete until some particle has moved half of the growth, and are built only
/// then. Measured on lavapipe at 10⁵ particles (`penetrate bench`): a build costs about as much
/// as both gathers together; a skin of 0.05 adds nothing measurable to the gathers, 0.1 adds a
/// third; the Forrestal 277 m/s shot at 4 mm spacing then builds once every 38 steps. 0 builds
/// them every step, as the CPU path searches its neighbours.
pub const LIST_SKIN: f32 = 0.05;

/// The lists are rebuilt once a particle may have moved this fraction of the half-skin (the
/// rest is margin for f32 round-off of the displacements).
const SKIN_USE: f32 = 0.9;

/// The SPH passes of a scene with a target.
struct SphPasses {
    particles: GpuParticles,
    neighbours: NeighboursPass,
    grid: GpuGrid,
    rates: super::sph_rates::SphRatesPass,
    concrete: super::concrete::ConcretePass,
    forces: super::sph_forces::SphForcesPass,
    contact: Option<ContactPass>,
}

/// What one step's read-back holds.
pub struct Readback {
    /// The Δt this step integrated with.
    pub dt: f32,
    pub status: [u32; STATUS_WORDS],
    /// (slave, master) pairs, in the order the GPU appended them.
    pub hits: Vec<(u32, u32)>,
    /// (r, z, vr, vz) of each hit's slave after integration.
    pub hit_data: Vec<[f32; 4]>,
    pub node_r: Vec<f32>,
    pub node_z: Vec<f32>,
    pub node_vr: Vec<f32>,
    pub node_vz: Vec<f32>,
}

/// Byte offsets in the staging buffer: the fixed part first, then the hit count and as many
/// hits as the read-back's bound (`HitBound`), then their slaves' kinematics.
struct Layout {
    moved2: u64,
    status: u64,
    nodes: u64,
    hits: u64,
}

impl Layout {
    /// Where the slaves' kinematics start, and the bytes to map, when `bound` hits are copied.
    fn hit_data(&self, bound: usize) -> (u64, u64) {
        let at = self.hits + 4 * (1 + 2 * bound as u64);
        (at, at + 16 * bound as u64)
    }
}

/// Steps over which the most hits is taken for `HitBound`.
const HIT_WINDOW: u32 = 64;

/// How many hits the per-step read-back copies: the most of the last `HIT_WINDOW` steps with
/// a margin, so the common step reads about the hits that exist, not the list's capacity (a
/// slave each). A step with more reads them all in a second round trip and raises the bound at
/// once; the hits read are the same either way.
#[derive(Clone, Copy, Debug)]
struct HitBound {
    bound: usize,
    capacity: usize,
    window_max: usize,
    steps: u32,
}

impl HitBound {
    fn new(capacity: usize) -> HitBound {
        HitBound {
            bound: Self::margin(0).min(capacity),
            capacity,
            window_max: 0,
            steps: 0,
        }
    }

    /// Room for `n` hits and a quarter more, and a few for a contact just starting: the count
    /// grows by a few hits a step while the nose enters.
    fn margin(n: usize) -> usize {
        n + n / 4 + 32
    }

    /// A step found `count` hits.
    fn saw(&mut self, count: usize) {
        self.window_max = self.window_max.max(count);
        self.steps += 1;
        if count > self.bound {
            self.bound = Self::margin(count).min(self.capacity);
        } else if self.steps >= HIT_WINDOW {
            self.bound = Self::margin(self.window_max).min(self.capacity);
            self.window_max = 0;
            self.steps = 0;
        }
    }
}

pub struct GpuStep {
    pub gpu: Gpu,
    sph: Option<SphPasses>,
    nodes: GpuNodes,
    elements: GpuElements,
    fem: Option<FemPasses>,
    /// The scene's passes in their order: `record_motion` runs the first half, the host the
    /// correction, `record_forces` the second half.
    passes: Vec<Pass>,
    integrate: IntegratePass,
    timestep: TimestepPass,
    acc: Accumulators,
    clock: wgpu::Buffer,
    status: wgpu::Buffer,
    plastic_total: wgpu::Buffer,
    // Uniforms, kept alive for the bind groups.
    _uniforms: Vec<wgpu::Buffer>,
    staging: wgpu::Buffer,
    layout: Layout,
    hit_bound: HitBound,
    n_nodes: usize,
    /// The nodes' r, z, vr, vz as the last read-back brought them: what the GPU holds until
    /// `correct` writes what the host changed.
    nodes_read: [Vec<f32>; 4],
    /// Corrected slaves written for the next submission.
    pending_fixes: u32,
    /// The second half of the last step (forces, Δt) has not been recorded yet.
    pending_forces: bool,
    /// How far a particle may move from where the neighbour lists were built before they must
    /// be built again (m), and a bound on how far one has moved (infinite: never built).
    list_slack: f32,
    since_build: f32,
    /// Neighbour-list builds so far.
    pub builds: u64,
    /// Host seconds spent in `advance` so far (`bench` splits the step's wall time by them).
    pub host: HostSeconds,
    /// Timestamps between passes (`bench`), where the adapter has them.
    profiler: Option<Profiler>,
    /// The transfers of the steps and the reads so far (summary.json's `gpu_transfers`), and
    /// the device's counts when they were last charged.
    pub traffic: Traffic,
    seen: Tally,
}

/// Host wall time of the steps' `advance` calls, summed: recording the command buffer, the
/// submission, and the wait for the read-back (which holds the GPU's own time for the step).
#[derive(Clone, Copy, Debug, Default)]
pub struct HostSeconds {
    pub record: f64,
    pub submit: f64,
    pub wait: f64,
}

/// The step's passes in recording order, as the profiler names its intervals.
pub const PROFILED: [&str; 10] = [
    "contact_apply",
    "neighbours",
    "sph_rates",
    "concrete",
    "sph_forces",
    "fem_stress",
    "fem_forces",
    "timestep",
    "integrate",
    "contact_detect",
];

/// The profiler's mark after the pass `name` of `PROFILED` (mark 0 opens the step).
fn profiled_slot(name: &str) -> u32 {
    1 + PROFILED
        .iter()
        .position(|n| *n == name)
        .unwrap_or(PROFILED.len()) as u32
}

/// What the GPU step needs from the model.
pub struct StepSetup<'a> {
    pub particles: Option<(&'a Particles, &'a SphParams)>,
    pub projectile: &'a Projectile,
    pub fem: &'a FemParams,
    /// The scene's pass list (`pass::for_scene`): what is built, and the order it runs in.
    pub passes: &'a [Pass],
    pub slaves: &'a [u32],
    pub wall_z: Option<f32>,
    pub escape: f32,
    pub cfl: f32,
    /// The first step's Δt (from the CPU's start-up evaluation).
    pub dt: f32,
    /// The neighbour lists' skin as a fraction of the support (`LIST_SKIN`; 0: every step).
    pub list_skin: f32,
}

impl GpuStep {
    pub fn new(gpu: Gpu, s: &StepSetup) -> Result<GpuStep, GpuError> {
        // Refuse what the adapter cannot hold before allocating anything.
        let n_particles = s.particles.map_or(0, |(p, _)| p.len());
        let n_elements = s.projectile.elements.len();
        gpu.check_binding_size("the particles' stress arrays", (n_particles * 12) as u64)?;
        gpu.check_binding_size("the elements' nodal forces", (n_elements * 24) as u64)?;
        let largest = n_particles.max(n_elements) as u64;
        let groups = largest.div_ceil(super::WORKGROUP as u64);
        if groups > gpu.limits.max_compute_workgroups_per_dimension as u64 {
            return Err(gpu.limit(format!(
                "{largest} particles or elements need {groups} workgroups in one dispatch, \
                 above its max_compute_workgroups_per_dimension of {}",
                gpu.limits.max_compute_workgroups_per_dimension
            )));
        }
        let nodes = GpuNodes::upload(&gpu, &s.projectile.nodes);
        let elements = GpuElements::upload(&gpu, &s.projectile.elements);
        let (h, alpha, beta) = s
            .particles
            .map_or((0.0, 0.0, 0.0), |(_, sp)| (sp.h, sp.alpha, sp.beta));
        let deformable = s.passes.contains(&Pass::FemStress);
        let contact = s.passes.contains(&Pass::ContactDetect);
        let slaves: &[u32] = if contact { s.slaves } else { &[] };
        // Each slave is a hit at most once a step.
        let hit_capacity = slaves.len().max(1);
        let u = StepUniform {
            n_particles: n_particles as u32,
            n_nodes: s.projectile.nodes.len() as u32,
            n_elements: s.projectile.elements.len() as u32,
            n_slaves: slaves.len() as u32,
            n_masters: s.projectile.masters.len() as u32,
            has_wall: u32::from(s.wall_z.is_some()),
            wall_z: s.wall_z.unwrap_or(0.0),
            escape: s.escape,
            r_min: 0.1 * h,
            h,
            alpha,
            beta,
            cfl: s.cfl,
            has_fem: u32::from(deformable),
        };
        let step_uniform = gpu.uniform("step", &u);
        let clock = gpu.buffer("clock", &[s.dt.to_bits(), f32::MAX.to_bits()]);
        let status = gpu.buffer("status", &[STATUS_CLEAR; STATUS_WORDS]);
        let plastic_total = gpu.zeros::<f32>("plastic work", s.projectile.elements.len());
        let acc = Accumulators::new(&gpu, n_particles, s.projectile.nodes.len());
        let mut uniforms = vec![step_uniform];

        let sph = match s.particles {
            Some((p, params)) => {
                let particles = GpuParticles::upload(&gpu, p);
                let sph_uniform = gpu.uniform("sph", &SphUniform::new(params, p.len()));
                let support = crate::cpu::integrate::support(params);
                let capacity = super::neighbours::capacity(&p.r, &p.z, support);
                let (neighbours, grid) = NeighboursPass::new(
                    &gpu,
                    &particles,
                    &sph_uniform,
                    capacity,
                    support * (1.0 + s.list_skin),
                )?;
                let rates = super::sph_rates::SphRatesPass::new(
                    &gpu,
                    &particles,
                    &grid,
                    &sph_uniform,
                    params,
                )?;
                let concrete = super::concrete::ConcretePass::new(
                    &gpu,
                    &particles,
                    &sph_uniform,
                    &clock,
                    params,
                )?;
                let forces = super::sph_forces::SphForcesPass::new(
                    &gpu,
                    &particles,
                    &grid,
                    &sph_uniform,
                    params.art_stress_eps > 0.0,
                    params.balsara,
                )?;
                let contact = if contact {
                    Some(ContactPass::new(
                        &gpu,
                        &uniforms[0],
                        slaves,
                        &s.projectile.masters,
                        &particles,
                        &nodes,
                    )?)
                } else {
                    None
                };
                uniforms.push(sph_uniform);
                Some(SphPasses {
                    particles,
                    neighbours,
                    grid,
                    rates,
                    concrete,
                    forces,
                    contact,
                })
            }
            None => None,
        };
        let fem = if deformable {
            let uniform = gpu.uniform("fem", &FemUniform::new(s.fem, elements.len, nodes.len));
            Some(FemPasses {
                stress: FemStressPass::new(
                    &gpu,
                    &nodes,
                    &elements,
                    &uniform,
                    s.fem.damage.is_some(),
                    &clock,
                    &status,
                    &plastic_total,
                )?,
                forces: FemForcesPass::new(&gpu, &nodes, &elements, &uniform)?,
                _uniform: uniform,
            })
        } else {
            None
        };
        let integrate = IntegratePass::new(
            &gpu,
            &uniforms[0],
            &clock,
            &status,
            sph.as_ref().map(|p| &p.particles),
            &nodes,
            &acc,
        )?;
        let timestep = TimestepPass::new(
            &gpu,
            &uniforms[0],
            &clock,
            sph.as_ref().map(|p| &p.particles),
            if deformable { Some(&elements) } else { None },
            &nodes.r,
        )?;

        let nn = s.projectile.nodes.len() as u64;
        let status_at = 16u64;
        let nodes_at = status_at + 4 * STATUS_WORDS as u64;
        let layout = Layout {
            moved2: 8,
            status: status_at,
            nodes: nodes_at,
            hits: nodes_at + 16 * nn,
        };
        let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("step read-back"),
            size: layout.hit_data(hit_capacity).1,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        if let Some(e) = gpu.take_error() {
            return Err(GpuError::Device(format!("GPU set-up failed: {e}")));
        }
        Ok(GpuStep {
            gpu,
            sph,
            nodes,
            elements,
            fem,
            passes: s.passes.to_vec(),
            integrate,
            timestep,
            acc,
            clock,
            status,
            plastic_total,
            _uniforms: uniforms,
            staging,
            layout,
            hit_bound: HitBound::new(hit_capacity),
            n_nodes: nn as usize,
            nodes_read: Default::default(),
            pending_fixes: 0,
            pending_forces: false,
            list_slack: SKIN_USE * 0.5 * s.list_skin * h * crate::kernel::SUPPORT,
            since_build: f32::INFINITY,
            builds: 0,
            host: HostSeconds::default(),
            profiler: None,
            traffic: Traffic::default(),
            seen: Tally::default(),
        })
    }

    /// Time each pass with GPU timestamps from now on. False where the adapter has none.
    pub fn enable_profiling(&mut self) -> bool {
        if !self.gpu.timestamps {
            return false;
        }
        self.profiler = Some(Profiler::new(&self.gpu, PROFILED.len() as u32 + 1));
        true
    }

    /// Seconds spent in each pass of `PROFILED` during the last `advance` (profiling on).
    pub fn pass_seconds(&self) -> Result<Vec<f64>, GpuError> {
        match &self.profiler {
            Some(p) => p.intervals(&self.gpu),
            None => Ok(Vec::new()),
        }
    }

    /// Mean seconds of a bare read-back (submit a copy of the clock, wait, map) over `n`.
    pub fn readback_latency(&self, n: usize) -> Result<f64, GpuError> {
        let start = std::time::Instant::now();
        for _ in 0..n {
            let mut encoder = self
                .gpu
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
            encoder.copy_buffer_to_buffer(&self.clock, 0, &self.staging, 0, 8);
            self.gpu.queue.submit([encoder.finish()]);
            self.gpu.map_read(&self.staging, 8)?;
        }
        Ok(start.elapsed().as_secs_f64() / n.max(1) as f64)
    }

    /// Bytes of GPU buffers this step allocated.
    pub fn gpu_bytes(&self) -> u64 {
        self.gpu.allocated()
    }

    fn mark(&self, pass: &mut wgpu::ComputePass, slot: u32) {
        if let Some(p) = &self.profiler {
            p.mark(pass, slot);
        }
    }

    /// Charge the transfers since the last charge to `to` (None: to nothing, as what `bench`
    /// or a test reads between steps); `call` counts one more call of it.
    fn charge(&mut self, to: Option<Charge>, call: bool) {
        let now = self.gpu.traffic.now();
        if let Some(to) = to {
            self.traffic
                .charge(to, Tally::between(self.seen, now), call);
        }
        self.seen = now;
    }

    /// Build the neighbour lists in the next step whatever the particles did (`bench`).
    pub fn force_list_build(&mut self) {
        self.since_build = f32::INFINITY;
    }

    /// Whether the next gathers need the neighbour lists built again: some particle may have
    /// moved too far (or NaN: build, and let the step report the particle).
    fn lists_stale(&self) -> bool {
        self.since_build.is_nan() || self.since_build > self.list_slack
    }

    /// The second half of a step: corrected slaves written back, rates, stresses, forces and
    /// the next Δt; the neighbour lists built first when `build`.
    fn record_forces(&self, pass: &mut wgpu::ComputePass, build: bool) {
        let sph = self.sph.as_ref();
        if let Some(c) = sph.and_then(|s| s.contact.as_ref()) {
            c.record_apply(pass, self.pending_fixes);
        }
        self.mark(pass, 1);
        // Each pass's timestamp slot is its place in PROFILED; a pass the scene lacks gets its
        // slot marked where it would have run, an empty interval.
        let mut next = 2;
        for p in self.passes.iter().filter(|p| p.is_force()) {
            let at = profiled_slot(p.name());
            for skipped in next..at {
                self.mark(pass, skipped);
            }
            match (p, sph, &self.fem) {
                (Pass::Neighbours, Some(s), _) => s.neighbours.record(pass, build),
                (Pass::SphRates, Some(s), _) => s.rates.record(pass),
                (Pass::Concrete, Some(s), _) => s.concrete.record(pass),
                (Pass::SphForces, Some(s), _) => s.forces.record(pass),
                (Pass::FemStress, _, Some(f)) => f.stress.record(pass),
                (Pass::FemForces, _, Some(f)) => f.forces.record(pass),
                // A pass is built exactly when it is in the list (`new`).
                _ => {}
            }
            self.mark(pass, at);
            next = at + 1;
        }
        for skipped in next..profiled_slot("timestep") {
            self.mark(pass, skipped);
        }
        self.timestep.record(pass);
        self.mark(pass, 8);
    }

    /// The first half of a step, up to what the host corrects: the scene's passes before its
    /// force passes (integration, then contact detection), each marked in its profiler slot.
    fn record_motion(&self, pass: &mut wgpu::ComputePass) {
        let sph = self.sph.as_ref();
        let mut next = profiled_slot("integrate");
        for p in self.passes.iter().filter(|p| !p.is_force()) {
            match (p, sph.and_then(|s| s.contact.as_ref())) {
                (Pass::Integrate, _) => {
                    self.integrate.record(pass);
                    if let Some(s) = sph {
                        s.neighbours.record_displacement(pass);
                    }
                }
                (Pass::ContactDetect, Some(c)) => c.record_detect(pass),
                // The correction runs on the host, between this submission and the next.
                _ => continue,
            }
            let at = profiled_slot(p.name());
            for skipped in next..at {
                self.mark(pass, skipped);
            }
            self.mark(pass, at);
            next = at + 1;
        }
        for skipped in next..=profiled_slot("contact_detect") {
            self.mark(pass, skipped);
        }
    }

    /// An encoder that first finishes the last step (its forces and the next Δt), where that
    /// is pending, so that what it copies after sees the complete state; and whether those
    /// forces build the neighbour lists (None: nothing was pending). `finished` records it
    /// once submitted.
    fn finishing_encoder(&self) -> (wgpu::CommandEncoder, Option<bool>) {
        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("finish step"),
            });
        let build = self.pending_forces.then(|| self.lists_stale());
        if let Some(build) = build {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            self.record_forces(&mut pass, build);
        }
        (encoder, build)
    }

    /// The last step's second half has run (`finishing_encoder`).
    fn finished(&mut self, build: Option<bool>) {
        if let Some(build) = build {
            self.built(build);
            self.pending_forces = false;
            self.pending_fixes = 0;
        }
    }

    fn built(&mut self, build: bool) {
        if build && self.sph.is_some() {
            self.since_build = 0.0;
            self.builds += 1;
        }
    }

    /// Advance one step up to the contact correction and read back what the host needs.
    pub fn advance(&mut self) -> Result<Readback, GpuError> {
        self.charge(None, false);
        let start = Instant::now();
        let build = self.pending_forces && self.lists_stale();
        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("step"),
            });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("step"),
                timestamp_writes: None,
            });
            self.mark(&mut pass, 0);
            if self.pending_forces {
                self.record_forces(&mut pass, build);
            } else {
                for slot in 1..=8 {
                    self.mark(&mut pass, slot);
                }
            }
            self.record_motion(&mut pass);
        }
        if let Some(p) = &self.profiler {
            p.resolve(&mut encoder);
        }
        let l = &self.layout;
        encoder.copy_buffer_to_buffer(&self.clock, 0, &self.staging, 0, 8);
        if let Some(sph) = &self.sph {
            encoder.copy_buffer_to_buffer(
                &sph.grid.info,
                MOVED2_OFFSET,
                &self.staging,
                l.moved2,
                4,
            );
        }
        encoder.copy_buffer_to_buffer(
            &self.status,
            0,
            &self.staging,
            l.status,
            4 * STATUS_WORDS as u64,
        );
        let contact = self.sph.as_ref().and_then(|s| s.contact.as_ref());
        let bound = if contact.is_some() {
            self.hit_bound.bound
        } else {
            0
        };
        let (hit_data_at, size) = l.hit_data(bound);
        if let Some(c) = contact {
            let b = bound as u64;
            encoder.copy_buffer_to_buffer(&c.hits, 0, &self.staging, l.hits, 4 * (1 + 2 * b));
            encoder.copy_buffer_to_buffer(&c.hit_data, 0, &self.staging, hit_data_at, 16 * b);
        }
        let nn = 4 * self.n_nodes as u64;
        for (k, b) in [&self.nodes.r, &self.nodes.z, &self.nodes.vr, &self.nodes.vz]
            .into_iter()
            .enumerate()
        {
            encoder.copy_buffer_to_buffer(b, 0, &self.staging, l.nodes + k as u64 * nn, nn);
        }
        let recorded = Instant::now();
        self.gpu.queue.submit([encoder.finish()]);
        let submitted = Instant::now();
        self.built(build);
        self.pending_forces = true;
        self.pending_fixes = 0;
        let l = &self.layout;
        let bytes = self.gpu.map_read(&self.staging, size as usize)?;
        self.host.record += (recorded - start).as_secs_f64();
        self.host.submit += (submitted - recorded).as_secs_f64();
        self.host.wait += submitted.elapsed().as_secs_f64();
        let words: &[u32] = bytemuck::cast_slice(&bytes);
        let floats: &[f32] = bytemuck::cast_slice(&bytes);
        let at = |offset: u64| (offset / 4) as usize;
        if self.sph.is_some() {
            // Measured after this step's integration, from the positions of the last build.
            self.since_build = f32::from_bits(words[at(l.moved2)]).sqrt();
        }
        let mut status = [0u32; STATUS_WORDS];
        status.copy_from_slice(&words[at(l.status)..at(l.status) + STATUS_WORDS]);
        let n = self.n_nodes;
        let node = |k: usize| floats[at(l.nodes) + k * n..at(l.nodes) + (k + 1) * n].to_vec();
        let mut rb = Readback {
            dt: f32::from_bits(words[0]),
            status,
            hits: Vec::new(),
            hit_data: Vec::new(),
            node_r: node(0),
            node_z: node(1),
            node_vr: node(2),
            node_vz: node(3),
        };
        self.nodes_read = [&rb.node_r, &rb.node_z, &rb.node_vr, &rb.node_vz].map(|v| v.clone());
        if let Some(c) = self.sph.as_ref().and_then(|s| s.contact.as_ref()) {
            let count = words[at(l.hits)] as usize;
            let h = at(l.hits) + 1;
            let d = at(hit_data_at);
            if count <= bound {
                rb.hits = (0..count)
                    .map(|k| (words[h + 2 * k], words[h + 2 * k + 1]))
                    .collect();
                rb.hit_data = (0..count)
                    .map(|k| {
                        [
                            floats[d + 4 * k],
                            floats[d + 4 * k + 1],
                            floats[d + 4 * k + 2],
                            floats[d + 4 * k + 3],
                        ]
                    })
                    .collect();
            } else {
                // More hits than the read-back's bound: read them all, in one more round trip.
                let mut batch = ReadBatch::new();
                let hits = batch.add::<u32>(&c.hits, 1 + 2 * count);
                let data = batch.add::<[f32; 4]>(&c.hit_data, count);
                let encoder = self
                    .gpu
                    .device
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
                let read = batch.read(&self.gpu, encoder)?;
                let all: Vec<u32> = read.take(hits);
                rb.hits = (0..count)
                    .map(|k| (all[1 + 2 * k], all[2 + 2 * k]))
                    .collect();
                rb.hit_data = read.take(data);
            }
            self.hit_bound.saw(count);
        }
        self.charge(Some(Charge::Step), true);
        Ok(rb)
    }

    /// Write the host's corrections: slaves `(index, [r, z, vr, vz])`, which moved them by at
    /// most `moved` (m), and the nodes' positions and velocities. Of each node array only the
    /// span from the first to the last value the correction changed is written: the hits move
    /// a few nodes' r and vr, the global shift every node's z and vz.
    pub fn correct(&mut self, fixes: &[(u32, [f32; 4])], moved: f32, nodes: &Nodes) {
        if let Some(c) = self.sph.as_ref().and_then(|s| s.contact.as_ref()) {
            c.write_fixes(&self.gpu, fixes);
            self.pending_fixes = fixes.len() as u32;
            self.since_build += moved;
        }
        let n = &self.nodes;
        let now = [&nodes.r, &nodes.z, &nodes.vr, &nodes.vz];
        for ((buffer, read), now) in [&n.r, &n.z, &n.vr, &n.vz]
            .into_iter()
            .zip(&self.nodes_read)
            .zip(now)
        {
            let differs = |k: &usize| read[*k].to_bits() != now[*k].to_bits();
            let mut changed = (0..now.len()).filter(differs);
            if let Some(first) = changed.next() {
                let last = changed.next_back().unwrap_or(first);
                self.gpu.write_at(buffer, first, &now[first..=last]);
            }
        }
        self.charge(Some(Charge::Step), false);
    }

    /// Finish the step and read the state back into the CPU structures, with the accumulated
    /// boundary impulse, wall loss and plastic work (sums over entities, f64), and the next Δt.
    /// `Sync::Full` reads every field; `Sync::History` only what a history row and the check
    /// for slaves left inside need (the particles' positions, velocities and energies, the
    /// projectile), a sixth of the bytes.
    pub fn download(
        &mut self,
        particles: &mut Particles,
        projectile: &mut Projectile,
        what: Sync,
    ) -> Result<Totals, GpuError> {
        self.charge(None, false);
        let (encoder, build) = self.finishing_encoder();
        let mut batch = ReadBatch::new();
        let n_p = particles.len();
        let n_n = projectile.nodes.len();
        let n_e = projectile.elements.len();
        let sph = self.sph.as_ref().map(|s| match what {
            Sync::Full => s.particles.queue(&mut batch, particles),
            Sync::History => [
                &s.particles.r,
                &s.particles.z,
                &s.particles.vr,
                &s.particles.vz,
                &s.particles.energy,
            ]
            .map(|b| batch.add::<f32>(b, n_p))
            .to_vec(),
        });
        let nodes = self.nodes.queue(&mut batch, &projectile.nodes);
        let elements = self
            .fem
            .as_ref()
            .map(|_| self.elements.queue(&mut batch, &projectile.elements));
        let clock = batch.add::<u32>(&self.clock, 2);
        let particle_impulse = batch.add::<f32>(&self.acc.particle_impulse, n_p);
        let node_impulse = batch.add::<f32>(&self.acc.node_impulse, n_n);
        let node_lost = batch.add::<f32>(&self.acc.node_lost, n_n);
        let plastic = batch.add::<f32>(&self.plastic_total, n_e);
        let read = batch.read(&self.gpu, encoder)?;
        self.finished(build);
        match (sph, what) {
            (Some(parts), Sync::Full) => GpuParticles::take(&read, &parts, particles),
            (Some(parts), Sync::History) => {
                let [r, z, vr, vz, energy] = [0, 1, 2, 3, 4].map(|k| read.take(parts[k]));
                (particles.r, particles.z, particles.vr, particles.vz) = (r, z, vr, vz);
                particles.energy = energy;
            }
            (None, _) => {}
        }
        GpuNodes::take(&read, &nodes, &mut projectile.nodes);
        if let Some(parts) = elements {
            GpuElements::take(&read, &parts, &mut projectile.elements);
        }
        let sum = |part| {
            read.take::<f32>(part)
                .iter()
                .map(|&x| x as f64)
                .sum::<f64>()
        };
        let totals = Totals {
            boundary_impulse: sum(particle_impulse) + sum(node_impulse),
            wall_lost: sum(node_lost),
            plastic_work: sum(plastic),
            next_dt: f32::from_bits(read.take::<u32>(clock)[0]),
        };
        let to = match what {
            Sync::Full => Charge::Full,
            Sync::History => Charge::History,
        };
        self.charge(Some(to), true);
        Ok(totals)
    }

    /// Where a status word says the step went wrong, the message (entity, reason).
    pub fn status_problem(
        status: &[u32; STATUS_WORDS],
    ) -> Option<(&'static str, u32, &'static str)> {
        let checks = [
            (STATUS_INVERTED_ELEMENT, "element", "inverted"),
            (
                STATUS_PARTICLE_NONFINITE,
                "particle",
                "non-finite position or velocity",
            ),
            (
                STATUS_PARTICLE_ESCAPED,
                "particle",
                "escaped far beyond the scene",
            ),
            (
                STATUS_NODE_NONFINITE,
                "node",
                "non-finite position or velocity",
            ),
            (STATUS_NODE_ESCAPED, "node", "escaped far beyond the scene"),
        ];
        checks
            .into_iter()
            .find(|(slot, _, _)| status[*slot] != STATUS_CLEAR)
            .map(|(slot, what, reason)| (what, status[slot], reason))
    }

    /// The passes built, in step order.
    pub fn has_sph(&self) -> bool {
        self.sph.is_some()
    }
}

/// The projectile's two passes and the FemUniform they share.
struct FemPasses {
    stress: FemStressPass,
    forces: FemForcesPass,
    // Kept alive for the bind groups.
    _uniform: wgpu::Buffer,
}

/// How much of the state `GpuStep::download` reads back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sync {
    Full,
    History,
}

/// Sums the host takes from the GPU's per-entity accumulators.
#[derive(Clone, Copy, Debug, Default)]
pub struct Totals {
    pub boundary_impulse: f64,
    pub wall_lost: f64,
    pub plastic_work: f64,
    pub next_dt: f32,
}

#[cfg(test)]
mod tests;
