// The clock the passes read; the uniform blocks come from src/gpu/params.rs (shader.rs prelude).

// The step's clock on the GPU: `dt` is the step being taken (written by the time-step
// reduction, read by every pass that advances state), so a whole step needs no upload.
struct Clock {
    dt: f32,
    // Next step's candidates as ordered bits (atomicMin targets), the particles' and the
    // elements' apart; see timestep.wgsl.
    dt_next_bits: u32,
    fem_next_bits: u32,
    // 1 when the elements set `dt` (their least step no larger than the particles'), else 0.
    fem_limited: u32,
}
