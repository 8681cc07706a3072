//! Ctrl-C (SIGINT) and SIGTERM. The first asks the run under way to stop at the end of its
//! step and write what a finished run writes (the last history row and frame, `summary.json`
//! with the status `interrupted …`); a sweep, a validation or the stability suite then starts
//! no further run. A second signal ends the process at once (exit code 130).
//!
//! Without [`install`] (the library's tests) nothing is caught and [`requested`] stays false.

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Whether a stop has been asked for.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// Exit code of an interrupted command (128 + SIGINT, as a shell reports it).
pub const EXIT_CODE: u8 = 130;

/// Catch SIGINT and SIGTERM for the rest of the process. An error (a handler already set, or
/// none can be on this platform) leaves the default: a signal ends the process at once.
pub fn install() -> Result<(), String> {
    // ctrlc calls this on its own thread, not in the signal handler, so exiting from it is safe.
    ctrlc::set_handler(|| {
        if REQUESTED.swap(true, Ordering::Relaxed) {
            std::process::exit(EXIT_CODE.into());
        }
    })
    .map_err(|e| format!("cannot catch Ctrl-C and SIGTERM ({e})"))
}
