// What the step's own passes share: the clock with atomic access. StepUniform and the status
// words (STATUS_*, which src/gpu/step.rs reads back every step) are in shader.rs's prelude.

// `Clock` of params.wgsl with atomic words: dt_bits is the step being taken, dt_next_bits the
// running minimum of the next step's candidates (positive f32 bits order like the floats).
struct ClockAtomic {
    dt_bits: atomic<u32>,
    dt_next_bits: atomic<u32>,
}

