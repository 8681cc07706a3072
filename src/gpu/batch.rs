//! Runs that share one GPU submit their steps together (`penetrate sweep --batch N`).
//!
//! Each member is a whole run on its own thread, with its own buffers, Δt, contact correction
//! and outputs, on one device shared by all (`Gpu::share`). A member's step (`GpuStep::advance`)
//! hands its command buffer to the batch and waits; the last of the members to hand one in
//! submits them all in one `queue.submit`, and every member then waits for that one submission
//! with its own read-back. A member does exactly the work it does alone, so its results are its
//! solo run's to the bit; what the members share is the submission and the wait. A member that
//! ends (its `GpuStep` dropped) leaves, and the others no longer wait for it.

use std::sync::{Arc, Condvar, Mutex, MutexGuard};

use super::Gpu;

/// The members' rendezvous: a round closes when every member has handed in its step.
#[derive(Default)]
pub struct Batch {
    round: Mutex<Round>,
    closed: Condvar,
}

#[derive(Default)]
struct Round {
    members: usize,
    pending: Vec<wgpu::CommandBuffer>,
    /// Rounds submitted so far.
    submitted: u64,
    /// Steps handed in so far.
    steps: u64,
}

impl Batch {
    pub fn new() -> Arc<Batch> {
        Arc::new(Batch::default())
    }

    /// A member's thread panicked holding the lock: the counts are still whole (each change
    /// is made in one statement), so go on with them.
    fn lock(&self) -> MutexGuard<'_, Round> {
        self.round.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// One more member steps with the batch.
    pub fn join(&self) {
        self.lock().members += 1;
    }

    /// A member is done: the round no longer waits for it, and closes now if it was the last
    /// one the round waited for.
    pub fn leave(&self, queue: &wgpu::Queue) {
        let mut round = self.lock();
        round.members = round.members.saturating_sub(1);
        Self::close_if_full(&mut round, queue, &self.closed);
    }

    /// Hand in a member's step and return once the round holding it is submitted.
    pub fn submit(&self, queue: &wgpu::Queue, step: wgpu::CommandBuffer) {
        let mut round = self.lock();
        round.pending.push(step);
        round.steps += 1;
        let mine = round.submitted;
        Self::close_if_full(&mut round, queue, &self.closed);
        while round.submitted == mine {
            round = self.closed.wait(round).unwrap_or_else(|e| e.into_inner());
        }
    }

    fn close_if_full(round: &mut Round, queue: &wgpu::Queue, closed: &Condvar) {
        if !round.pending.is_empty() && round.pending.len() >= round.members {
            queue.submit(round.pending.drain(..));
            round.submitted += 1;
            closed.notify_all();
        }
    }

    /// Submissions made and steps handed in so far: their ratio is the steps a submission
    /// carried (`bench`-like figures of a batched sweep).
    pub fn counts(&self) -> (u64, u64) {
        let round = self.lock();
        (round.submitted, round.steps)
    }
}

/// One device and the batch its members step in (`RunOptions::share`).
pub struct GpuShare {
    pub gpu: Gpu,
    pub batch: Arc<Batch>,
}

impl std::fmt::Debug for GpuShare {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuShare")
            .field("adapter", &self.gpu.adapter_name())
            .finish()
    }
}
