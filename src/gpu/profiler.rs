//! GPU timestamps between the passes of a step, for `bench`: where the adapter has timestamp
//! queries inside compute passes.

use super::{Gpu, GpuError};

/// Timestamps written at marks inside a step's compute pass, resolved and read back.
pub struct Profiler {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    staging: wgpu::Buffer,
    slots: u32,
}

impl Profiler {
    /// A profiler of `slots` marks (one more than the intervals between them).
    pub fn new(gpu: &Gpu, slots: u32) -> Profiler {
        let bytes = 8 * slots as u64;
        Profiler {
            queries: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: slots,
            }),
            resolve: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps"),
                size: bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            staging: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps read-back"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            slots,
        }
    }

    /// Write mark `slot` at this point of the pass.
    pub fn mark(&self, pass: &mut wgpu::ComputePass, slot: u32) {
        pass.write_timestamp(&self.queries, slot);
    }

    /// Resolve the marks into the read-back buffer (after the pass, in its encoder).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..self.slots, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.staging, 0, 8 * self.slots as u64);
    }

    /// Seconds between consecutive marks of the last resolved step.
    pub fn intervals(&self, gpu: &Gpu) -> Result<Vec<f64>, GpuError> {
        let bytes = gpu.map_read(&self.staging, 8 * self.slots as usize)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        let period = gpu.queue.get_timestamp_period() as f64 * 1e-9;
        Ok(ticks
            .windows(2)
            .map(|w| w[1].saturating_sub(w[0]) as f64 * period)
            .collect())
    }
}
