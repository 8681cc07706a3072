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

/// Catch SIGINT and SIGTERM for the rest of the process (Unix; elsewhere the default stays).
pub fn install() {
    #[cfg(unix)]
    {
        let handler = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
        // SAFETY: the handler only swaps an atomic flag and may call `_exit`, both
        // async-signal-safe.
        unsafe {
            libc::signal(libc::SIGINT, handler);
            libc::signal(libc::SIGTERM, handler);
        }
    }
}

#[cfg(unix)]
extern "C" fn on_signal(_: libc::c_int) {
    if REQUESTED.swap(true, Ordering::Relaxed) {
        // SAFETY: `_exit` is async-signal-safe and ends the process without unwinding.
        unsafe { libc::_exit(EXIT_CODE as libc::c_int) }
    }
}
