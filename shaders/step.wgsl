// What the step's own passes share: the clock with atomic access. StepUniform and the status
// words (STATUS_*, which src/gpu/step.rs reads back every step) are in shader.rs's prelude.

// `Clock` of params.wgsl with atomic words: dt_bits is the step being taken, fem_limited whether
// the elements set it, and `next` two slots of running minima of the candidates for the next
// step (the particles' at 2 s, the elements' at 2 s + 1; positive f32 bits order like the
// floats), which the time-step fold and the integration use in turn (timestep.wgsl).
struct ClockAtomic {
    dt_bits: atomic<u32>,
    fem_limited: atomic<u32>,
    next: array<atomic<u32>, 4>,
}

