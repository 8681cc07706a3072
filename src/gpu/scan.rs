//! Inclusive prefix sum of a u32 buffer in place on the GPU (shaders/scan.wgsl), reduce-then-
//! scan over a hierarchy of blocks: each level's block totals are the next level's data, down
//! to a single block. CPU twin: a running sum (the test below).

use super::params::ScanLevel;
use super::shader::Program;
use super::{Gpu, GpuError, Kernel};

/// Entries one workgroup scans (shaders/scan.wgsl SCAN_BLOCK).
pub const SCAN_BLOCK: u32 = 1024;

pub struct PrefixScan {
    block: Kernel,
    add: Kernel,
    /// Per level, finest first: its bind group and its block count.
    levels: Vec<(wgpu::BindGroup, u32)>,
    // The block totals and the level uniforms, kept alive for the bind groups.
    _buffers: Vec<wgpu::Buffer>,
}

impl PrefixScan {
    /// A scan of the first `len` entries of `data`.
    pub fn new(gpu: &Gpu, data: &wgpu::Buffer, len: u32) -> Result<PrefixScan, GpuError> {
        let block = gpu.kernel(Program::Scan, "scan_block", &[])?;
        let add = gpu.kernel(Program::Scan, "scan_add", &[])?;
        let max_groups = gpu.limits.max_compute_workgroups_per_dimension;
        let mut levels = Vec::new();
        let mut buffers = Vec::new();
        let mut len = len.max(1);
        let mut level_data = data.clone();
        loop {
            let groups = len.div_ceil(SCAN_BLOCK);
            if groups > max_groups {
                return Err(gpu.limit(format!(
                    "a prefix scan of {len} entries needs {groups} workgroups, \
                     max_compute_workgroups_per_dimension is {max_groups}"
                )));
            }
            let sums = gpu.zeros::<u32>("scan block totals", groups as usize);
            let uniform = gpu.uniform("scan level", &ScanLevel { len });
            let bind = block.bind(
                gpu,
                &[("level", &uniform), ("data", &level_data), ("sums", &sums)],
            )?;
            levels.push((bind, groups));
            buffers.push(uniform);
            buffers.push(sums.clone());
            if groups == 1 {
                break;
            }
            level_data = sums;
            len = groups;
        }
        Ok(PrefixScan {
            block,
            add,
            levels,
            _buffers: buffers,
        })
    }

    pub fn record(&self, pass: &mut wgpu::ComputePass) {
        for (bind, groups) in &self.levels {
            self.block.dispatch_groups(pass, bind, *groups);
        }
        // The coarsest level is one block: nothing to add there.
        for (bind, groups) in self.levels.iter().rev().skip(1) {
            self.add.dispatch_groups(pass, bind, *groups);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::{run_once, test_gpu};

    /// The GPU scan equals a running sum, for lengths across one, two and three levels and
    /// around block edges.
    #[test]
    #[ignore = "full tier: needs a GPU adapter (bash scripts/test)"]
    fn scan_matches_running_sum() {
        let gpu = test_gpu();
        for len in [1usize, 5, 1024, 1025, 3000, 1024 * 1024 + 7] {
            let data: Vec<u32> = (0..len).map(|i| ((i * 7919) % 13) as u32).collect();
            let buffer = gpu.buffer("scan data", &data);
            let scan = PrefixScan::new(&gpu, &buffer, len as u32).unwrap();
            run_once(&gpu, |p| scan.record(p)).unwrap();
            let got: Vec<u32> = gpu.read(&buffer, len).unwrap();
            let mut run = 0u32;
            let want: Vec<u32> = data
                .iter()
                .map(|&x| {
                    run += x;
                    run
                })
                .collect();
            assert_eq!(got, want, "length {len}");
        }
    }
}
