//! What crosses between the host and the GPU, counted: blocking waits (each a round trip: submit,
//! wait, map), bytes read back and bytes written; and the compute dispatches recorded, each a
//! pass the GPU finishes before the next may start. `Gpu` counts every transfer it makes; the GPU
//! step charges them to what asked for them (a step, a history row, a full read for a frame or
//! the summary), and `summary.json` reports the tallies (`gpu_transfers`, performance.md).

use std::sync::atomic::{AtomicU64, Ordering};

use serde::{Deserialize, Serialize};

/// Running counts of one device's transfers.
#[derive(Debug, Default)]
pub struct Counters {
    waits: AtomicU64,
    read: AtomicU64,
    written: AtomicU64,
    dispatches: AtomicU64,
}

impl Counters {
    pub fn wait(&self) {
        self.waits.fetch_add(1, Ordering::Relaxed);
    }

    pub fn read(&self, bytes: u64) {
        self.read.fetch_add(bytes, Ordering::Relaxed);
    }

    pub fn written(&self, bytes: u64) {
        self.written.fetch_add(bytes, Ordering::Relaxed);
    }

    pub fn dispatched(&self) {
        self.dispatches.fetch_add(1, Ordering::Relaxed);
    }

    /// The counts so far, as a tally of no calls.
    pub fn now(&self) -> Tally {
        Tally {
            calls: 0,
            waits: self.waits.load(Ordering::Relaxed),
            read_bytes: self.read.load(Ordering::Relaxed),
            written_bytes: self.written.load(Ordering::Relaxed),
            dispatches: self.dispatches.load(Ordering::Relaxed),
        }
    }
}

/// Transfers of one kind of request, summed over its calls.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Tally {
    pub calls: u64,
    /// Blocking waits for the GPU: each a submission waited for and, mostly, one mapping.
    pub waits: u64,
    pub read_bytes: u64,
    pub written_bytes: u64,
    /// Compute dispatches recorded (0 in summaries written before they were counted).
    #[serde(default)]
    pub dispatches: u64,
}

impl Tally {
    /// What happened between the counts `before` and `after`.
    pub fn between(before: Tally, after: Tally) -> Tally {
        Tally {
            calls: 0,
            waits: after.waits - before.waits,
            read_bytes: after.read_bytes - before.read_bytes,
            written_bytes: after.written_bytes - before.written_bytes,
            dispatches: after.dispatches - before.dispatches,
        }
    }

    fn add(&mut self, d: Tally) {
        self.waits += d.waits;
        self.read_bytes += d.read_bytes;
        self.written_bytes += d.written_bytes;
        self.dispatches += d.dispatches;
    }
}

/// A GPU run's transfers by what asked for them: the steps (the read-back of the hits and
/// nodes, the corrections written), the history rows' reads and the full reads (frames, the
/// summary, a failure's site).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Traffic {
    pub steps: Tally,
    pub history: Tally,
    pub full: Tally,
}

/// What a transfer is charged to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Charge {
    Step,
    History,
    Full,
}

impl Traffic {
    /// Add `d` to `to`'s tally; `call` counts one more call of it.
    pub fn charge(&mut self, to: Charge, d: Tally, call: bool) {
        let t = match to {
            Charge::Step => &mut self.steps,
            Charge::History => &mut self.history,
            Charge::Full => &mut self.full,
        };
        t.add(d);
        t.calls += u64::from(call);
    }
}
