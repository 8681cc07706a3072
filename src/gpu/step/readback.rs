//! What a step reads back (gpu::step): the staging buffer's layout and the bound on the hits it
//! copies.

use super::{HIT_ENTRIES, STATUS_WORDS};

/// What one step's read-back holds.
pub struct Readback {
    /// The Δt this step integrated with.
    pub dt: f32,
    /// Whether the elements set it (their least stable step no larger than the particles').
    pub fem_limited: bool,
    pub status: [u32; STATUS_WORDS],
    /// (slave, master) pairs, in the order the GPU appended them.
    pub hits: Vec<(u32, u32)>,
    /// (r, z, vr, vz) of each hit's slave, node A and node B after integration.
    pub hit_data: Vec<[[f32; 4]; HIT_ENTRIES]>,
    /// Every node's z and v_z after integration.
    pub node_z: Vec<f32>,
    pub node_vz: Vec<f32>,
}

/// Byte offsets in the staging buffer: the fixed part first, then the hit count and as many
/// hits as the read-back's bound (`HitBound`), then their kinematics (`HIT_ENTRIES` each).
pub(super) struct Layout {
    pub moved2: u64,
    pub fem_limited: u64,
    pub status: u64,
    pub nodes: u64,
    pub hits: u64,
}

impl Layout {
    /// Where the slaves' kinematics start, and the bytes to map, when `bound` hits are copied.
    pub fn hit_data(&self, bound: usize) -> (u64, u64) {
        let at = self.hits + 4 * (1 + 2 * bound as u64);
        (at, at + 16 * (HIT_ENTRIES * bound) as u64)
    }
}

/// Steps over which the most hits is taken for `HitBound`.
pub(super) const HIT_WINDOW: u32 = 64;

/// How many hits the per-step read-back copies: the most of the last `HIT_WINDOW` steps with
/// a margin, so the common step reads about the hits that exist, not the list's capacity (a
/// slave each). A step with more reads them all in a second round trip and raises the bound at
/// once; the hits read are the same either way.
#[derive(Clone, Copy, Debug)]
pub(super) struct HitBound {
    pub bound: usize,
    capacity: usize,
    window_max: usize,
    steps: u32,
}

impl HitBound {
    pub fn new(capacity: usize) -> HitBound {
        HitBound {
            bound: Self::margin(0).min(capacity),
            capacity,
            window_max: 0,
            steps: 0,
        }
    }

    /// Room for `n` hits and a quarter more, and a few for a contact just starting: the count
    /// grows by a few hits a step while the nose enters.
    fn margin(n: usize) -> usize {
        n + n / 4 + 32
    }

    /// A step found `count` hits.
    pub fn saw(&mut self, count: usize) {
        self.window_max = self.window_max.max(count);
        self.steps += 1;
        if count > self.bound {
            self.bound = Self::margin(count).min(self.capacity);
        } else if self.steps >= HIT_WINDOW {
            self.bound = Self::margin(self.window_max).min(self.capacity);
            self.window_max = 0;
            self.steps = 0;
        }
    }
}
