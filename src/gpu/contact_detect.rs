//! `contact_detect` on the GPU (shaders/contact_detect.wgsl; CPU twin `cpu::contact_detect`): the
//! projectile's bounding box, the slave-in-master-triangle test with an appended hit list, the
//! gather of the hits' slave kinematics for the read-back, and `apply`, which writes back the
//! slaves the host corrected.

use super::shader::Program;
use super::state::{GpuNodes, GpuParticles};
use super::{Gpu, GpuError, Kernel};
use crate::mesh::MasterSegment;

pub struct ContactPass {
    bounding_box: Kernel,
    detect: Kernel,
    gather: Kernel,
    apply: Kernel,
    bind: wgpu::BindGroup,
    /// `[count, (slave, master)…]`, `(r, z, vr, vz)` per hit, and the host's fixes.
    pub hits: wgpu::Buffer,
    pub hit_data: wgpu::Buffer,
    pub fixes: wgpu::Buffer,
    n_slaves: u32,
}

impl ContactPass {
    pub fn new(
        gpu: &Gpu,
        step: &wgpu::Buffer,
        slaves: &[u32],
        masters: &[MasterSegment],
        particles: &GpuParticles,
        nodes: &GpuNodes,
    ) -> Result<ContactPass, GpuError> {
        let kernel = |entry: &str| gpu.kernel(Program::ContactDetect, entry, &[]);
        let n = slaves.len();
        let slave_buf = gpu.buffer("slaves", slaves);
        let m: Vec<[u32; 4]> = masters.iter().map(|m| [m.element, m.a, m.b, m.c]).collect();
        let master_buf = gpu.buffer("masters", &m);
        let hits = gpu.zeros::<u32>("hits", 1 + 2 * n);
        let hit_data = gpu.zeros::<[f32; 4]>("hit data", n);
        let fixes = gpu.zeros::<u32>("contact fixes", 1 + 5 * n);
        let bounds = gpu.zeros::<f32>("projectile box", 4);
        let bounding_box = kernel("bounding_box")?;
        let bind = bounding_box.bind(
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
                ("hits", &hits),
                ("hit_data", &hit_data),
                ("fixes", &fixes),
                ("bounds", &bounds),
            ],
        )?;
        Ok(ContactPass {
            bounding_box,
            detect: kernel("detect")?,
            gather: kernel("gather")?,
            apply: kernel("apply")?,
            bind,
            hits,
            hit_data,
            fixes,
            n_slaves: n as u32,
        })
    }

    /// Detect this step's hits and gather their slaves' kinematics.
    pub fn record_detect(&self, pass: &mut wgpu::ComputePass) {
        self.bounding_box.dispatch_groups(pass, &self.bind, 1);
        self.detect.dispatch(pass, &self.bind, self.n_slaves);
        self.gather.dispatch(pass, &self.bind, self.n_slaves);
    }

    /// Write back the slaves in `fixes` (the host wrote it before this submission).
    pub fn record_apply(&self, pass: &mut wgpu::ComputePass, count: u32) {
        self.apply.dispatch(pass, &self.bind, count);
    }

    /// The host's corrected slaves: `(slave, r, z, vr, vz)` for each, as `fixes` holds them.
    pub fn write_fixes(&self, gpu: &Gpu, fixes: &[(u32, [f32; 4])]) {
        let mut words = Vec::with_capacity(1 + 5 * fixes.len());
        words.push(fixes.len() as u32);
        for (s, v) in fixes {
            words.push(*s);
            words.extend(v.iter().map(|x| x.to_bits()));
        }
        gpu.write(&self.fixes, &words);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::params::StepUniform;
    use crate::gpu::{run_once, test_gpu};
    use crate::solver::Simulation;

    /// The GPU finds exactly the CPU's hits (as a set; the host sorts them) on a state where the
    /// nose is inside the target, and `apply` writes back what it is given.
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
        let pass =
            ContactPass::new(&gpu, &step, &sim.slaves, &sim.projectile.masters, &gp, &gn).unwrap();
        run_once(&gpu, |p| pass.record_detect(p)).unwrap();
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
        let data: Vec<[f32; 4]> = gpu.read(&pass.hit_data, count).unwrap();
        for k in 0..count {
            let s = words[1 + 2 * k] as usize;
            let p = &sim.particles;
            assert_eq!(data[k], [p.r[s], p.z[s], p.vr[s], p.vz[s]]);
        }

        let s = want[0].0;
        pass.write_fixes(&gpu, &[(s, [0.5, -0.25, 3.0, -4.0])]);
        run_once(&gpu, |p| pass.record_apply(p, 1)).unwrap();
        let mut back = sim.particles.clone();
        gp.download(&gpu, &mut back).unwrap();
        let s = s as usize;
        assert_eq!(
            [back.r[s], back.z[s], back.vr[s], back.vz[s]],
            [0.5, -0.25, 3.0, -4.0]
        );
        assert_eq!(back.r[s + 1], sim.particles.r[s + 1]);
    }
}
