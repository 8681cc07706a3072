// What the step's own passes share: the step uniform, the clock with atomic access, and the
// status words (src/gpu/step.rs reads them back every step).

struct StepUniform {
    n_particles: u32,
    n_nodes: u32,
    n_elements: u32,
    n_slaves: u32,
    n_masters: u32,
    has_wall: u32,
    wall_z: f32,
    escape: f32,
    // Particles are kept at least this far off the axis (0.1 h).
    r_min: f32,
    h: f32,
    alpha: f32,
    beta: f32,
    cfl: f32,
    // 1 when the elements' stable step takes part (a deformable projectile).
    has_fem: u32,
    // Largest number of hits the per-step read-back holds (the rest is read separately).
    hit_capacity: u32,
}

// `Clock` of params.wgsl with atomic words: dt_bits is the step being taken, dt_next_bits the
// running minimum of the next step's candidates (positive f32 bits order like the floats).
struct ClockAtomic {
    dt_bits: atomic<u32>,
    dt_next_bits: atomic<u32>,
}

// Status words: the smallest index of an entity that went wrong (0xffffffff: none).
const STATUS_INVERTED_ELEMENT: u32 = 0u;
const STATUS_PARTICLE_NONFINITE: u32 = 1u;
const STATUS_PARTICLE_ESCAPED: u32 = 2u;
const STATUS_NODE_NONFINITE: u32 = 3u;
const STATUS_NODE_ESCAPED: u32 = 4u;
const STATUS_WORDS: u32 = 8u;
const F32_MAX_BITS: u32 = 0x7f7fffffu;
