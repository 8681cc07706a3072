// The clock the passes read; the uniform blocks come from src/gpu/params.rs (shader.rs prelude).

// The step's clock on the GPU: `dt` is the step being taken (written by the time-step
// reduction, read by every pass that advances state), so a whole step needs no upload.
struct Clock {
    dt: f32,
    // Next step's candidate as ordered bits (atomicMin target); see integrate.wgsl.
    dt_next_bits: u32,
}
