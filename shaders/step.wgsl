// What the step's own passes share: the clock with atomic access. StepUniform and the status
// words (STATUS_*, which src/gpu/step.rs reads back every step) are in shader.rs's prelude.

// `Clock` of params.wgsl with atomic words: dt_bits is the step being taken, dt_next_bits and
// fem_next_bits the running minima of the particles' and the elements' candidates for the next
// (positive f32 bits order like the floats), fem_limited whether the elements set dt_bits.
struct ClockAtomic {
    dt_bits: atomic<u32>,
    dt_next_bits: atomic<u32>,
    fem_next_bits: atomic<u32>,
    fem_limited: atomic<u32>,
}

