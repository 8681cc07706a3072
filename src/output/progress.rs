//! Progress on the terminal: a bar when stderr is a terminal, else a plain line every few
//! seconds (CI logs, redirected runs).

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

pub struct Progress {
    bar: Option<ProgressBar>,
    end_time: f64,
    last_line: Instant,
    quiet: bool,
}

const PLAIN_EVERY: Duration = Duration::from_secs(10);

impl Progress {
    pub fn new(end_time: f64, quiet: bool) -> Progress {
        let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
            let bar = ProgressBar::new(1000);
            bar.set_style(
                ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {percent:>3}% {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar())
                    .progress_chars("=> "),
            );
            bar
        });
        Progress {
            bar,
            end_time,
            last_line: Instant::now(),
            quiet,
        }
    }

    pub fn update(&mut self, time: f64, step: u64, depth: f64, velocity: f64) {
        let msg = format!(
            "t {:.1} µs  step {step}  depth {} mm  v {} m/s",
            time * 1e6,
            super::fixed(depth * 1e3, 1),
            super::fixed(velocity, 1)
        );
        if let Some(bar) = &self.bar {
            bar.set_position(((time / self.end_time) * 1000.0).clamp(0.0, 1000.0) as u64);
            bar.set_message(msg);
        } else if !self.quiet && self.last_line.elapsed() >= PLAIN_EVERY {
            eprintln!("{msg}");
            self.last_line = Instant::now();
        }
    }

    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish();
        }
    }
}
