//! `contact_detect` on the GPU (shaders/contact_detect.wgsl; CPU twin `cpu::contact_detect`): the
//! slave-in-master-triangle test of the slaves inside the projectile's bounding box (which the
//! integration folds, `box_keys`) with an appended hit list and, for the read-back, the
//! kinematics of each hit's slave and of its segment's two nodes; and `apply`, which writes back
//! the slaves and the nodes the host corrected and adds the global shift to the other nodes.

use super::shader::Program;
use super::state::{GpuNodes, GpuParticles};
use super::timestep::DtSlots;
use super::{Gpu, GpuError, Kernel};
use crate::mesh::MasterSegment;

/// common.wgsl `float_key`: an order-preserving map of an f32 to a u32.
pub const fn float_key(x: f32) -> u32 {
    let b = x.to_bits();
    if b & 0x8000_0000 != 0 {
        !b
    } else {
        b | 0x8000_0000
    }
}

/// The empty bounding box as `box_keys` holds it: r_max from 0 (as the CPU's), z_min and z_max
/// from the far ends.
pub const EMPTY_BOX: [u32; 4] = [float_key(0.0), float_key(f32::MAX), float_key(-f32::MAX), 0];

pub struct ContactPass {
    detect: Kernel,
    apply: Kernel,
    recentre: Kernel,
    /// One bind group for each parity of the integration the box is from.
    binds: [wgpu::BindGroup; 2],
    /// The projectile's bounding box after the integration of each parity (integrate.wgsl).
    pub box_keys: wgpu::Buffer,
    /// `[count, (slave, master)…]`, `(r, z, vr, vz)` of each hit's slave, node A and node B,
    /// and the host's fixes of the slaves and of the nodes.
    pub hits: wgpu::Buffer,
    pub hit_data: wgpu::Buffer,
    pub fixes: wgpu::Buffer,
    node_fixes: wgpu::Buffer,
    /// The host's shift of every position along z for `recentre` (`Model::recentre`).
    recentre_by: wgpu::Buffer,
    n_slaves: u32,
    n_nodes: u32,
    n_particles: u32,
}

/// `hit_data`'s entries per hit: the slave, node A, node B.
pub const HIT_ENTRIES: usize = 3;

/// What the host's correction changed, for `apply`: the corrected slaves `(slave, [r, z, vr,
/// vz])`, the nodes it touched with their final values (the shift included) in ascending order,
/// and the global shift s with s·Δt as the host rounded it.
pub struct Fixes<'a> {
    pub slaves: &'a [(u32, [f32; 4])],
    pub nodes: &'a [(u32, [f32; 4])],
    pub shift: f32,
    pub shift_dt: f32,
}

impl ContactPass {
    pub fn new(
        gpu: &Gpu,
        step: &wgpu::Buffer,
        slaves: &[u32],
        masters: &[MasterSegment],
        particles: &GpuParticles,
        nodes: &GpuNodes,
        slots: &DtSlots,
    ) -> Result<ContactPass, GpuError> {
        let kernel = |entry: &str| gpu.kernel(Program::ContactDetect, entry, &[]);
        let n = slaves.len();
        let slave_buf = gpu.buffer("slaves", slaves);
        let m: Vec<[u32; 4]> = masters.iter().map(|m| [m.element, m.a, m.b, m.c]).collect();
        let master_buf = gpu.buffer("masters", &m);
        let hits = gpu.zeros::<u32>("hits", 1 + 2 * n);
        let hit_data = gpu.zeros::<[f32; 4]>("hit data", HIT_ENTRIES * n);
        let fixes = gpu.zeros::<u32>("contact fixes", 1 + 5 * n);
        let node_fixes = gpu.zeros::<u32>("contact node fixes", 3 + 5 * nodes.len);
        let box_keys = gpu.buffer("projectile box", &[EMPTY_BOX, EMPTY_BOX]);
        let recentre_by = gpu.zeros::<f32>("recentre shift", 1);
        let detect = kernel("detect")?;
        let bind = |slot: u32| {
            detect.bind(
                gpu,
                &[
                    ("u", step),
                    ("slaves", &slave_buf),
                    ("masters", &master_buf),
                    ("pr", &particles.r),
                    ("pz", &particles.z),
                    ("pvr", &particles.vr),
                    ("pvz", &particles.vz),
                    ("nr", &nodes.r),
                    ("nz", &nodes.z),
                    ("nvr", &nodes.vr),
                    ("nvz", &nodes.vz),
                    ("node_fixes", &node_fixes),
                    ("recentre_by", &recentre_by),
                    ("hits", &hits),
                    ("hit_data", &hit_data),
                    ("fixes", &fixes),
                    ("box_keys", &box_keys),
                    ("box_slot", slots.get(slot)),
                ],
            )
        };
        let binds = [bind(0)?, bind(1)?];
        Ok(ContactPass {
            detect,
            apply: kernel("apply")?,
            recentre: kernel("recentre")?,
            binds,
            box_keys,
            hits,
            hit_data,
            fixes,
            node_fixes,
            recentre_by,
            n_slaves: n as u32,
            n_nodes: nodes.len as u32,
            n_particles: particles.len as u32,
        })
    }

    /// Detect this step's hits, with their slaves' kinematics, after an integration of
    /// `parity`.
    pub fn record_detect(&self, pass: &mut wgpu::ComputePass, parity: u32) {
        self.detect
            .dispatch(pass, &self.binds[parity as usize], self.n_slaves);
    }

    /// Write back what the host wrote with `write_fixes` before this submission: `slaves`
    /// corrected slaves and, once after a correction (`nodes`), the nodes.
    pub fn record_apply(&self, pass: &mut wgpu::ComputePass, slaves: u32, nodes: bool) {
        let items = if nodes {
            slaves.max(self.n_nodes)
        } else {
            slaves
        };
        self.apply.dispatch(pass, &self.binds[0], items);
    }

    /// Move every particle and node by what `write_recentre` wrote, after `apply`.
    pub fn record_recentre(&self, pass: &mut wgpu::ComputePass) {
        self.recentre
            .dispatch(pass, &self.binds[0], self.n_particles.max(self.n_nodes));
    }

    /// The shift of every position along z for the next `recentre`.
    pub fn write_recentre(&self, gpu: &Gpu, by: f32) {
        gpu.write(&self.recentre_by, &[by]);
    }

    /// The host's correction, as `fixes` and `node_fixes` hold it.
    pub fn write_fixes(&self, gpu: &Gpu, f: &Fixes) {
        let words = |mut head: Vec<u32>, entries: &[(u32, [f32; 4])]| {
            head.reserve(5 * entries.len());
            for (index, v) in entries {
                head.push(*index);
                head.extend(v.iter().map(|x| x.to_bits()));
            }
            head
        };
        debug_assert!(f.nodes.windows(2).all(|w| w[0].0 < w[1].0));
        gpu.write(&self.fixes, &words(vec![f.slaves.len() as u32], f.slaves));
        let head = vec![
            f.nodes.len() as u32,
            f.shift.to_bits(),
            f.shift_dt.to_bits(),
        ];
        gpu.write(&self.node_fixes, &words(head, f.nodes));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::params::StepUniform;
    use crate::gpu::{run_once, test_gpu};
    use crate::solver::Simulation;

    /// The GPU finds exactly the CPU's hits (as a set; the host sorts them) on a state where the
    /// nose is inside the target, with the kinematics of their slaves and nodes, and `apply`
    /// writes back what it is given and shifts the other nodes as the host does.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn detect_matches_cpu_and_apply_writes_back() {
        let gpu = test_gpu();
        let scene =
            crate::scene::load(std::path::Path::new("cases/smoke.toml"), &[]).expect("smoke case");
        let mut sim = Simulation::new(&scene).expect("smoke builds");
        // Step until the nose is in; then move the particles by one more integration without
        // the correction, so that slaves sit inside the projectile.
        while sim.model().expect("smoke's state").last_hits == 0 {
            sim.step().expect("smoke steps");
        }
        let mut sim = sim.into_model().expect("smoke's state");
        let sph = sim.sph.unwrap();
        crate::cpu::integrate::particles(&mut sim.particles, &sph, sim.dt, 1.0e3).unwrap();
        crate::cpu::integrate::nodes(&mut sim.projectile.nodes, sim.dt, None, 1.0e3).unwrap();
        let cpu_hits = crate::cpu::contact_detect::run(
            &sim.slaves,
            &sim.particles,
            &sim.projectile.nodes,
            &sim.projectile.masters,
        );
        assert!(!cpu_hits.is_empty(), "the test state has hits");

        let u = StepUniform {
            n_particles: sim.particles.len() as u32,
            n_nodes: sim.projectile.nodes.len() as u32,
            n_slaves: sim.slaves.len() as u32,
            n_masters: sim.projectile.masters.len() as u32,
            ..Default::default()
        };
        let step = gpu.uniform("step", &u);
        let gp = GpuParticles::upload(&gpu, &sim.particles);
        let gn = GpuNodes::upload(&gpu, &sim.projectile.nodes);
        let slots = crate::gpu::timestep::DtSlots::new(&gpu);
        let pass = ContactPass::new(
            &gpu,
            &step,
            &sim.slaves,
            &sim.projectile.masters,
            &gp,
            &gn,
            &slots,
        )
        .unwrap();
        // The box of parity 1, as the integration folds it (`integrate_and_timestep_match_cpu`).
        let n = &sim.projectile.nodes;
        let r_max = n.r.iter().fold(0.0f32, |m, &r| m.max(r));
        let z_lo = n.z.iter().fold(f32::MAX, |m, &z| m.min(z));
        let z_hi = n.z.iter().fold(-f32::MAX, |m, &z| m.max(z));
        let box_1 = [float_key(r_max), float_key(z_lo), float_key(z_hi), 0];
        gpu.write(&pass.box_keys, &[EMPTY_BOX, box_1]);
        run_once(&gpu, |p| pass.record_detect(p, 1)).unwrap();
        let words: Vec<u32> = gpu.read(&pass.hits, 1 + 2 * sim.slaves.len()).unwrap();
        let count = words[0] as usize;
        let mut got: Vec<(u32, u32)> = (0..count)
            .map(|k| (words[1 + 2 * k], words[2 + 2 * k]))
            .collect();
        got.sort();
        let want: Vec<(u32, u32)> = cpu_hits.iter().map(|h| (h.slave, h.master)).collect();
        // Inside/outside is decided by the signs of exact-enough orientation products; a slave
        // within round-off of an edge could flip, so allow no more than one such difference.
        let same = got.iter().filter(|h| want.contains(h)).count();
        assert!(
            same + 1 >= want.len().max(got.len()),
            "GPU hits {got:?}\nCPU hits {want:?}"
        );
        let data: Vec<[[f32; 4]; HIT_ENTRIES]> = gpu.read(&pass.hit_data, count).unwrap();
        let p = &sim.particles;
        let n = &sim.projectile.nodes;
        let node = |i: u32| {
            let i = i as usize;
            [n.r[i], n.z[i], n.vr[i], n.vz[i]]
        };
        for (k, entries) in data.iter().enumerate() {
            let s = words[1 + 2 * k] as usize;
            let seg = sim.projectile.masters[words[2 + 2 * k] as usize];
            assert_eq!(entries[0], [p.r[s], p.z[s], p.vr[s], p.vz[s]]);
            assert_eq!(entries[1], node(seg.a));
            assert_eq!(entries[2], node(seg.b));
        }

        // A correction: one slave, two nodes touched, a shift for the rest.
        let s = want[0].0;
        let seg = sim.projectile.masters[want[0].1 as usize];
        let (lo, hi) = (seg.a.min(seg.b), seg.a.max(seg.b));
        let touched = [(lo, [1.0, 2.0, 3.0, 4.0]), (hi, [5.0, 6.0, 7.0, 8.0])];
        let (shift, shift_dt) = (-0.75f32, 1.5e-7f32);
        let fixes = Fixes {
            slaves: &[(s, [0.5, -0.25, 3.0, -4.0])],
            nodes: &touched,
            shift,
            shift_dt,
        };
        pass.write_fixes(&gpu, &fixes);
        run_once(&gpu, |p| pass.record_apply(p, 1, true)).unwrap();
        let mut back = sim.particles.clone();
        gp.download(&gpu, &mut back).unwrap();
        let s = s as usize;
        assert_eq!(
            [back.r[s], back.z[s], back.vr[s], back.vz[s]],
            [0.5, -0.25, 3.0, -4.0]
        );
        assert_eq!(back.r[s + 1], sim.particles.r[s + 1]);
        let mut nodes = sim.projectile.nodes.clone();
        gn.download(&gpu, &mut nodes).unwrap();
        for i in 0..nodes.len() {
            let got = [nodes.r[i], nodes.z[i], nodes.vr[i], nodes.vz[i]];
            let want = match touched.iter().find(|t| t.0 as usize == i) {
                Some(t) => t.1,
                None => [n.r[i], n.z[i] + shift_dt, n.vr[i], n.vz[i] + shift],
            };
            assert_eq!(got.map(f32::to_bits), want.map(f32::to_bits), "node {i}");
        }

        // No shift: the untouched nodes keep their bits (a −0 velocity included).
        gn.write(&gpu, &sim.projectile.nodes);
        let v0 = (0..n.len())
            .find(|&i| i != lo as usize && i != hi as usize)
            .unwrap();
        gpu.write_at(&gn.vz, v0, &[-0.0f32]);
        let fixes = Fixes {
            shift: 0.0,
            shift_dt: 0.0,
            ..fixes
        };
        pass.write_fixes(&gpu, &fixes);
        run_once(&gpu, |p| pass.record_apply(p, 1, true)).unwrap();
        gn.download(&gpu, &mut nodes).unwrap();
        assert_eq!(nodes.vz[v0].to_bits(), (-0.0f32).to_bits());
        for i in (0..n.len()).filter(|&i| i != lo as usize && i != hi as usize && i != v0) {
            assert_eq!(
                [nodes.r[i], nodes.z[i], nodes.vr[i], nodes.vz[i]].map(f32::to_bits),
                [n.r[i], n.z[i], n.vr[i], n.vz[i]].map(f32::to_bits),
                "node {i}"
            );
        }
    }
}
