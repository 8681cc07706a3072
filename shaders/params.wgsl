// The clock the passes read; the uniform blocks come from src/gpu/params.rs (shader.rs prelude).

// The step's clock on the GPU: `dt` is the step being taken (written by the integration from
// the time-step reduction, read by every pass that advances state), so a whole step needs no
// upload.
struct Clock {
    dt: f32,
    // 1 when the elements set `dt` (their least step no larger than the particles'), else 0.
    fem_limited: u32,
    // Two slots of the next step's candidates as ordered bits (atomicMin targets), the
    // particles' and the elements' apart; see step.wgsl.
    next: array<u32, 4>,
}
