//! The whole step on the GPU (architecture.md, "Shape of one step"), with one read-back per step.
//!
//! One submission holds the second half of step k−1 and the first half of step k:
//!
//! ```text
//! apply (k−1's corrected slaves) → neighbours → sph_rates → concrete → sph_forces
//!   → fem_stress → integrate (nodal forces gathered, Δt_k into the clock) → contact detect
//!   → copy clock, watch, status, nodes, hits to the staging buffer (`readback.rs`)
//! ```
//!
//! Each is one dispatch on a step that builds no lists: what a step reduces is folded where it
//! is made, with an atomic only where a value widens the result (`sph_forces` and `fem_stress`
//! the stable-step candidates, the integration the displacement since the list build and the
//! projectile's bounding box), into slots that alternate with the integration's parity
//! (`dt_slot`), so that no pass has to empty them before the next fold.
//!
//! then one mapping brings back Δt_k and whether the elements set it, how far the particles have
//! moved since the neighbour lists were built, the status words, every node's z and v_z (the
//! correction's momentum and the run's stop test read them), and the hits with the kinematics of
//! their slaves and their segments' nodes, as many as the last steps' most with a margin
//! (`HitBound`; a step with more reads them in a second round trip). The host applies the λ
//! correction and the global shift (physics.md §4, `contact::correct`) and writes the corrected
//! slaves, the nodes it touched and the shift for the next submission, whose `apply` adds the
//! shift to the other nodes as the host does; that submission builds the neighbour lists again
//! only when a particle may have moved half the lists' skin (`LIST_SKIN`). `download`
//! (`sync.rs`) runs a pending second half and copies what it reads in one submission waited for
//! once, so that the GPU state is the CPU's after the same number of `Simulation::step` calls.

use std::sync::Arc;
use std::time::Instant;

use super::batch::Batch;
use super::contact_detect::{ContactPass, Fixes, HIT_ENTRIES};
use super::fem_stress::FemStressPass;
use super::integrate::{
    Accumulators, IntegratePass, TargetBindings, STATUS_CLEAR, STATUS_INVERTED_ELEMENT,
    STATUS_NODE_ESCAPED, STATUS_NODE_NONFINITE, STATUS_PARTICLE_ESCAPED, STATUS_PARTICLE_NONFINITE,
    STATUS_WORDS,
};
use super::neighbours::{GpuGrid, NeighboursPass, MOVED2_OFFSET};
use super::params::{FemUniform, SphUniform, StepUniform};
use super::profiler::Profiler;
use super::state::{GpuElements, GpuNodes, GpuParticles};
use super::timestep::{DtSlots, DT_FROM_CLOCK};
use super::traffic::{Charge, Tally, Traffic};
use super::walls::{WallBuffers, WallsPass, WallsSetup};
use super::ReadBatch;
use super::{Gpu, GpuError};
use crate::pass::Pass;
use crate::state::{FemParams, Particles, Projectile, SphParams};

mod readback;
mod sync;

pub use readback::Readback;
use readback::{HitBound, Layout};
pub use sync::{Sync, Totals};

pub use crate::cpu::neighbours::LIST_SKIN;

/// The SPH passes of a scene with a target.
struct SphPasses {
    particles: GpuParticles,
    neighbours: NeighboursPass,
    grid: GpuGrid,
    rates: super::sph_rates::SphRatesPass,
    concrete: super::concrete::ConcretePass,
    forces: super::sph_forces::SphForcesPass,
    contact: Option<ContactPass>,
    history: super::history::HistoryPass,
    /// The wall images' buffers (placeholders without them) and passes (`contact.kernel`).
    _wall_buffers: WallBuffers,
    walls: Option<WallsPass>,
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
    /// The parity of the next integration: the clock's slot of running minima the next
    /// time-step fold fills and the integration takes its Δt from (unless no fold has run
    /// yet), and the contact's box slot it folds the nodes into; it empties the other's, and
    /// the two swap. And whether a fold has filled the slot since the last integration.
    dt_slot: u32,
    folded: bool,
    cfl: f32,
    _slots: DtSlots,
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
    /// Corrected slaves written for the next submission, and whether a correction of the nodes
    /// was (`ContactPass::write_fixes`).
    pending_fixes: u32,
    pending_nodes: bool,
    /// Whether the host moved the model's origin (`recentre`) for the next submission.
    pending_recentre: bool,
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
    /// The runs this one submits its steps with, when it shares the device (`batch`).
    batch: Option<Arc<Batch>>,
}

impl Drop for GpuStep {
    fn drop(&mut self) {
        if let Some(b) = &self.batch {
            b.leave(&self.gpu.queue);
        }
    }
}

/// Host wall time of the steps' `advance` calls, summed: recording the command buffer, the
/// submission, and the wait for the read-back (which holds the GPU's own time for the step).
#[derive(Clone, Copy, Debug, Default)]
pub struct HostSeconds {
    pub record: f64,
    pub submit: f64,
    pub wait: f64,
}

/// The step's passes in recording order, as the profiler names its intervals (`fem_forces`'
/// is empty on the GPU, where the integration gathers the nodal forces).
pub const PROFILED: [&str; 11] = [
    "contact_apply",
    "neighbours",
    "walls",
    "sph_rates",
    "concrete",
    "sph_forces",
    "fem_stress",
    "fem_forces",
    "wall_forces",
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
    /// The first step's Δt (from the CPU's start-up evaluation), and whether the elements set it.
    pub dt: f32,
    pub fem_limited: bool,
    /// The neighbour lists' skin as a fraction of the support (`LIST_SKIN`; 0: every step).
    pub list_skin: f32,
    /// With wall images (the pass list has `Pass::Walls`): the mirror line's depth inside the
    /// surface (m) and the master segments' last sums (`Model::walls`), which the first
    /// integration gathers.
    pub walls: Option<(f32, &'a [[f32; 4]])>,
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
        let images = s.passes.contains(&Pass::Walls);
        let mut nodes = GpuNodes::upload(&gpu, &s.projectile.nodes);
        let mut elements = GpuElements::upload(&gpu, &s.projectile.elements);
        let masters = &s.projectile.masters;
        if images {
            // The segments' reactions are force entries past the elements' (`walls::csr`).
            let n_e = s.projectile.elements.len();
            let (offsets, refs) = super::walls::csr(&s.projectile.nodes, n_e, masters);
            nodes.elem_offsets = gpu.buffer("node CSR with the walls", &offsets);
            nodes.elem_refs = gpu.buffer("node CSR refs with the walls", &refs);
            let sums = s.walls.map_or(&[][..], |w| w.1);
            let mut force = s.projectile.elements.force.clone();
            force.extend((0..masters.len()).map(|m| {
                let v = sums.get(m).copied().unwrap_or_default();
                [-v[0], -v[1], -v[2], -v[3], 0.0, 0.0]
            }));
            elements.force = gpu.buffer("nodal forces with the walls", &force);
        }
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
        let clock = gpu.buffer("clock", &super::timestep::clock_words(s.dt, s.fem_limited));
        let status = gpu.buffer("status", &[STATUS_CLEAR; STATUS_WORDS]);
        let plastic_total = gpu.zeros::<f32>("plastic work", s.projectile.elements.len());
        let acc = Accumulators::new(&gpu, n_particles, s.projectile.nodes.len());
        let mut uniforms = vec![step_uniform];
        let slots = DtSlots::new(&gpu);

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
                let wall_buffers = WallBuffers::new(&gpu, p.len(), images)?;
                let rates = super::sph_rates::SphRatesPass::new(
                    &gpu,
                    &particles,
                    &grid,
                    &sph_uniform,
                    params,
                    &wall_buffers,
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
                    &concrete.pairs,
                    &grid,
                    &sph_uniform,
                    &clock,
                    &slots,
                    params,
                    &wall_buffers,
                )?;
                let contact = if contact {
                    Some(ContactPass::new(
                        &gpu,
                        &uniforms[0],
                        slaves,
                        &s.projectile.masters,
                        &particles,
                        &nodes,
                        &slots,
                    )?)
                } else {
                    None
                };
                let walls = match (&contact, images) {
                    (Some(c), true) => Some(WallsPass::new(
                        &gpu,
                        &WallsSetup {
                            buffers: &wall_buffers,
                            grid: &grid,
                            nodes: &nodes,
                            force: &elements.force,
                            masters,
                            clock: &clock,
                            n_particles: p.len(),
                            n_elements: s.projectile.elements.len(),
                            box_keys: &c.box_keys,
                            slots: &slots,
                            support,
                            offset: s.walls.map_or(0.0, |w| w.0),
                            list_radius: support * (1.0 + s.list_skin),
                        },
                    )?),
                    _ => None,
                };
                uniforms.push(sph_uniform);
                let history = super::history::HistoryPass::new(
                    &gpu,
                    &particles,
                    &acc.particle_impulse,
                    slaves,
                )?;
                Some(SphPasses {
                    particles,
                    neighbours,
                    grid,
                    rates,
                    concrete,
                    forces,
                    contact,
                    history,
                    _wall_buffers: wall_buffers,
                    walls,
                })
            }
            None => None,
        };
        let fem = if deformable {
            let n_cells = s.projectile.elements.cells.len() - 1;
            let uniform = gpu.uniform(
                "fem",
                &FemUniform::new(s.fem, elements.len, nodes.len, n_cells),
            );
            Some(FemPasses {
                stress: FemStressPass::new(
                    &gpu,
                    &nodes,
                    &elements,
                    &uniform,
                    s.fem.damage.is_some(),
                    n_cells,
                    &clock,
                    &slots,
                    &status,
                    &plastic_total,
                )?,
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
            &slots,
            sph.as_ref().map(|p| TargetBindings {
                particles: &p.particles,
                x_build: p.neighbours.x_build(),
                grid_info: &p.grid.info,
                contact: p.contact.as_ref().map(|c| (&c.box_keys, &c.hits)),
            }),
            &nodes,
            &elements,
            &acc,
        )?;

        let nn = s.projectile.nodes.len() as u64;
        let status_at = 16u64;
        let nodes_at = status_at + 4 * STATUS_WORDS as u64;
        // The fixed part: the clock's Δt and fem_limited words, then moved² at 8, then (after
        // a free word) the status words, then the nodes' z and v_z.
        let layout = Layout {
            moved2: 8,
            fem_limited: 4,
            status: status_at,
            nodes: nodes_at,
            hits: nodes_at + 8 * nn,
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
            dt_slot: 0,
            folded: false,
            cfl: s.cfl,
            _slots: slots,
            acc,
            clock,
            status,
            plastic_total,
            _uniforms: uniforms,
            staging,
            layout,
            hit_bound: HitBound::new(hit_capacity),
            n_nodes: nn as usize,
            pending_fixes: 0,
            pending_nodes: false,
            pending_recentre: false,
            pending_forces: false,
            list_slack: crate::cpu::neighbours::list_slack(h * crate::kernel::SUPPORT, s.list_skin),
            since_build: f32::INFINITY,
            builds: 0,
            host: HostSeconds::default(),
            profiler: None,
            traffic: Traffic::default(),
            seen: Tally::default(),
            batch: None,
        })
    }

    /// Submit the steps from now on with the other members of `batch` (on the same device).
    pub fn join_batch(&mut self, batch: Arc<Batch>) {
        batch.join();
        if let Some(old) = self.batch.replace(batch) {
            old.leave(&self.gpu.queue);
        }
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

    /// Compute dispatches this device has recorded so far (`bench`).
    pub fn dispatches(&self) -> u64 {
        self.gpu.traffic.now().dispatches
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
            c.record_apply(pass, self.pending_fixes, self.pending_nodes);
            if self.pending_recentre {
                c.record_recentre(pass);
            }
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
                // The box is the last integration's, of the parity before this one.
                (Pass::Walls, Some(s), _) => {
                    if let Some(w) = &s.walls {
                        w.record_find(pass, 1 - self.dt_slot)
                    }
                }
                (Pass::SphForces, Some(s), _) => s.forces.record(pass, self.dt_slot),
                (Pass::FemStress, _, Some(f)) => f.stress.record(pass, self.dt_slot),
                (Pass::WallForces, Some(s), _) => {
                    if let Some(w) = &s.walls {
                        w.record_sums(pass)
                    }
                }
                // The integration gathers the nodal forces (integrate.wgsl).
                (Pass::FemForces, _, Some(_)) => {}
                // A pass is built exactly when it is in the list (`new`).
                _ => {}
            }
            self.mark(pass, at);
            next = at + 1;
        }
        for skipped in next..profiled_slot("integrate") {
            self.mark(pass, skipped);
        }
    }

    /// The first half of a step, up to what the host corrects: the scene's passes before its
    /// force passes (integration, then contact detection), each marked in its profiler slot.
    fn record_motion(&self, pass: &mut wgpu::ComputePass, dt_source: u32) {
        let sph = self.sph.as_ref();
        let mut next = profiled_slot("integrate");
        for p in self.passes.iter().filter(|p| !p.is_force()) {
            match (p, sph.and_then(|s| s.contact.as_ref())) {
                (Pass::Integrate, _) => self.integrate.record(pass, dt_source),
                (Pass::ContactDetect, Some(c)) => c.record_detect(pass, self.dt_slot),
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
        // The integration's Δt: the slot this submission's fold fills, or an earlier
        // submission's (a download's) fold, or the host's where none has run yet.
        let dt_source = if self.pending_forces || self.folded {
            self.dt_slot
        } else {
            DT_FROM_CLOCK
        };
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
                for slot in 1..profiled_slot("integrate") {
                    self.mark(&mut pass, slot);
                }
            }
            self.record_motion(&mut pass, dt_source);
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
            let entries = HIT_ENTRIES as u64 * b;
            encoder.copy_buffer_to_buffer(&c.hit_data, 0, &self.staging, hit_data_at, 16 * entries);
        }
        let nn = 4 * self.n_nodes as u64;
        for (k, b) in [&self.nodes.z, &self.nodes.vz].into_iter().enumerate() {
            encoder.copy_buffer_to_buffer(b, 0, &self.staging, l.nodes + k as u64 * nn, nn);
        }
        let recorded = Instant::now();
        match &self.batch {
            Some(b) => b.submit(&self.gpu.queue, encoder.finish()),
            None => {
                self.gpu.queue.submit([encoder.finish()]);
            }
        }
        let submitted = Instant::now();
        self.built(build);
        self.pending_forces = true;
        self.pending_fixes = 0;
        self.pending_nodes = false;
        self.pending_recentre = false;
        // The Δt's source is the clock only before the first fold, at parity 0.
        debug_assert!(dt_source != DT_FROM_CLOCK || self.dt_slot == 0);
        self.dt_slot = 1 - self.dt_slot;
        self.folded = false;
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
            fem_limited: words[at(l.fem_limited)] != 0,
            status,
            hits: Vec::new(),
            hit_data: Vec::new(),
            node_z: node(0),
            node_vz: node(1),
        };
        if let Some(c) = self.sph.as_ref().and_then(|s| s.contact.as_ref()) {
            let count = words[at(l.hits)] as usize;
            let h = at(l.hits) + 1;
            let d = at(hit_data_at);
            if count <= bound {
                rb.hits = (0..count)
                    .map(|k| (words[h + 2 * k], words[h + 2 * k + 1]))
                    .collect();
                let entry =
                    |e: usize| -> [f32; 4] { std::array::from_fn(|c| floats[d + 4 * e + c]) };
                rb.hit_data = (0..count)
                    .map(|k| std::array::from_fn(|e| entry(HIT_ENTRIES * k + e)))
                    .collect();
            } else {
                // More hits than the read-back's bound: read them all, in one more round trip.
                let mut batch = ReadBatch::new();
                let hits = batch.add::<u32>(&c.hits, 1 + 2 * count);
                let data = batch.add::<[[f32; 4]; HIT_ENTRIES]>(&c.hit_data, count);
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

    /// Write the host's correction (`Fixes`), which moved the slaves by at most `moved` (m),
    /// for the next submission's `apply`.
    pub fn correct(&mut self, fixes: &Fixes, moved: f32) {
        if let Some(c) = self.sph.as_ref().and_then(|s| s.contact.as_ref()) {
            c.write_fixes(&self.gpu, fixes);
            self.pending_fixes = fixes.slaves.len() as u32;
            self.pending_nodes = true;
            self.since_build += moved;
        }
        self.charge(Some(Charge::Step), false);
    }

    /// Move every position by `by` along z in the next submission's second half, after the
    /// correction's `apply`, as `Model::recentre` moves the host's: the neighbour lists are
    /// built again there, from the moved positions.
    pub fn recentre(&mut self, by: f32) {
        if let Some(c) = self.sph.as_ref().and_then(|s| s.contact.as_ref()) {
            c.write_recentre(&self.gpu, by);
            self.pending_recentre = true;
            self.since_build = f32::INFINITY;
        }
        self.charge(Some(Charge::Step), false);
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

/// The projectile's stress pass and its FemUniform (the integration gathers the nodal forces).
struct FemPasses {
    stress: FemStressPass,
    // Kept alive for the bind group.
    _uniform: wgpu::Buffer,
}

#[cfg(test)]
mod tests;
