//! The step on the GPU: up to contact detection there, the λ correction on the host, the rest
//! there in the next submission (gpu::step).

use super::cpu_step::{collapsed, correct_contact, Slaves};
use super::{Account, Entity, Instability, Model, Pass, RunError, Stepper, Unstable};
use crate::contact::Hit;
use crate::gpu::contact_detect::Fixes;
use crate::gpu::step::{GpuStep, Sync};

/// The GPU path: the state lives on the GPU, and the host's copy is brought up to date by
/// `sync`.
pub struct GpuStepper {
    pub(super) step: Box<GpuStep>,
    /// The account when the GPU took over (its accumulators add to it).
    pub(super) base: Account,
    /// The wall images' z-impulse booked so far from the GPU's accumulators, in all and on the
    /// nose (the host books the correction's each step, so the images' is added as it grows).
    pub(super) wall_booked: (f64, f64),
}

impl Stepper for GpuStepper {
    fn step(&mut self, model: &mut Model) -> Result<(), RunError> {
        model.step_gpu(&mut self.step)
    }

    fn sync(&mut self, sim: &mut Model, what: Sync) -> Result<(), RunError> {
        let t = self
            .step
            .download(&mut sim.particles, &mut sim.projectile, what)
            .map_err(|error| RunError::Gpu {
                error,
                when: Some(sim.when()),
            })?;
        let base = &self.base;
        sim.account.boundary_impulse = base.boundary_impulse + t.boundary_impulse;
        sim.account.wall_dissipated = base.wall_dissipated + t.wall_lost;
        sim.account.plastic_work = base.plastic_work + t.plastic_work;
        if let Some(per_segment) = &t.wall_impulse {
            let total: f64 = per_segment.iter().map(|&x| x as f64).sum();
            let nose: f64 = per_segment
                .iter()
                .zip(&sim.on_nose)
                .filter(|(_, &on)| on)
                .map(|(&x, _)| x as f64)
                .sum();
            sim.account.contact_impulse += total - self.wall_booked.0;
            sim.account.nose_impulse += nose - self.wall_booked.1;
            self.wall_booked = (total, nose);
        }
        if let Some(sums) = t.wall_sums {
            sim.walls.sums = sums;
        }
        sim.dt = t.next_dt;
        sim.reduced = t.particles;
        Ok(())
    }

    fn backend(&self) -> &'static str {
        "gpu"
    }

    fn keeps_host_current(&self) -> bool {
        false
    }

    fn gpu(&mut self) -> Option<&mut GpuStep> {
        Some(&mut self.step)
    }

    fn builds(&self) -> Option<u64> {
        Some(self.step.builds)
    }

    fn traffic(&self) -> Option<crate::gpu::traffic::Traffic> {
        Some(self.step.traffic)
    }
}

impl Model {
    /// One step on the GPU: up to contact detection there, the correction here, and the rest
    /// there in the next submission (gpu::step).
    pub(super) fn step_gpu(&mut self, g: &mut GpuStep) -> Result<(), RunError> {
        let when = self.when();
        let gpu_err = |error| RunError::Gpu {
            error,
            when: Some(when),
        };
        let rb = g.advance().map_err(gpu_err)?;
        let dt = rb.dt;
        if collapsed(dt) || dt > 1.0 {
            // The site of the collapse is read from the state: bring it back first.
            g.download(&mut self.particles, &mut self.projectile, Sync::Full)
                .map_err(gpu_err)?;
        }
        self.check_dt(dt)?;
        // Of the nodes, the read-back brings every z and v_z (the correction's momentum and the
        // stop test read them) and the hits' own nodes whole: the host's r and v_r of the others
        // stay as the last full or history read left them.
        {
            let n = &mut self.projectile.nodes;
            n.z = rb.node_z;
            n.vz = rb.node_vz;
        }
        if let Some((what, index, reason)) = GpuStep::status_problem(&rb.status) {
            let (r, z) = self.locate(g, what, index as usize);
            return Err(RunError::from(Instability {
                what: Unstable::Entity {
                    entity: Entity::named(what, index as usize),
                    reason,
                    r: r as f64,
                    z: self.world_z(z),
                },
                when,
            }));
        }
        if self.has(Pass::ContactDetect) {
            self.last_hits = rb.hits.len();
            if !rb.hits.is_empty() {
                let mut order: Vec<usize> = (0..rb.hits.len()).collect();
                order.sort_by_key(|&k| self.hit_order[rb.hits[k].0 as usize]);
                let slave = |k: usize| rb.hits[order[k]].0;
                let data = |k: usize| rb.hit_data[order[k]][0];
                let m = order.len();
                let mut touched: Vec<u32> = Vec::with_capacity(2 * m);
                let n = &mut self.projectile.nodes;
                for (&(_, master), entries) in rb.hits.iter().zip(&rb.hit_data) {
                    let seg = self.projectile.masters[master as usize];
                    // Their z and v_z came with every node's.
                    for (node, v) in [(seg.a, entries[1]), (seg.b, entries[2])] {
                        let i = node as usize;
                        (n.r[i], n.vr[i]) = (v[0], v[2]);
                        touched.push(node);
                    }
                }
                touched.sort_unstable();
                touched.dedup();
                let mut sr: Vec<f32> = (0..m).map(|k| data(k)[0]).collect();
                let mut sz: Vec<f32> = (0..m).map(|k| data(k)[1]).collect();
                let mut svr: Vec<f32> = (0..m).map(|k| data(k)[2]).collect();
                let mut svz: Vec<f32> = (0..m).map(|k| data(k)[3]).collect();
                let sm: Vec<f32> = (0..m)
                    .map(|k| self.particles.mass[slave(k) as usize])
                    .collect();
                let hits: Vec<Hit> = (0..m)
                    .map(|k| Hit {
                        slave: k as u32,
                        master: rb.hits[order[k]].1,
                    })
                    .collect();
                let shift = correct_contact(
                    &hits,
                    Slaves {
                        r: &mut sr,
                        z: &mut sz,
                        vr: &mut svr,
                        vz: &mut svz,
                        mass: &sm,
                    },
                    &mut self.projectile,
                    &self.on_nose,
                    &self.scene.contact,
                    dt,
                    &mut self.account,
                );
                let fixes: Vec<(u32, [f32; 4])> = (0..m)
                    .map(|k| (slave(k), [sr[k], sz[k], svr[k], svz[k]]))
                    .collect();
                // How far the correction moved a slave (the neighbour lists' watch).
                let moved = (0..m)
                    .map(|k| (sr[k] - data(k)[0]).hypot(sz[k] - data(k)[1]))
                    .fold(0.0f32, f32::max);
                let n = &self.projectile.nodes;
                let nodes: Vec<(u32, [f32; 4])> = touched
                    .iter()
                    .map(|&k| {
                        let i = k as usize;
                        (k, [n.r[i], n.z[i], n.vr[i], n.vz[i]])
                    })
                    .collect();
                let fixes = Fixes {
                    slaves: &fixes,
                    nodes: &nodes,
                    shift,
                    // As contact::correct rounds it for the host's nodes.
                    shift_dt: shift * dt,
                };
                g.correct(&fixes, moved);
            }
        }
        // After the correction, as the CPU's step does it; the GPU moves its state in the
        // next submission's second half, and the host's copies here.
        if let Some(by) = self.recentre_by() {
            self.recentre(by);
            g.recentre(by);
        }
        self.time += dt as f64;
        self.step += 1;
        self.dt = dt;
        self.account.count_limit(rb.fem_limited);
        self.account.min_dt = self.account.min_dt.min(dt as f64);
        self.account.max_dt = self.account.max_dt.max(dt as f64);
        Ok(())
    }

    /// Position of an entity the GPU flagged (the state is read back for it).
    pub(super) fn locate(&mut self, g: &mut GpuStep, what: &str, index: usize) -> (f32, f32) {
        if g.download(&mut self.particles, &mut self.projectile, Sync::Full)
            .is_err()
        {
            return (f32::NAN, f32::NAN);
        }
        let n = &self.projectile.nodes;
        match what {
            "particle" => (self.particles.r[index], self.particles.z[index]),
            "node" => (n.r[index], n.z[index]),
            _ => {
                let el = self.projectile.elements.nodes[index];
                let c = |v: &[f32]| el.iter().map(|&k| v[k as usize]).sum::<f32>() / 3.0;
                (c(&n.r), c(&n.z))
            }
        }
    }
}
