//! Progress on the terminal: a bar when stderr is a terminal, else a plain line every few
//! seconds (CI logs, redirected runs).

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

pub struct Progress {
    bar: Option<ProgressBar>,
    end_time: f64,
    started: Instant,
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
            started: Instant::now(),
            last_line: Instant::now(),
            quiet,
        }
    }

    pub fn update(&mut self, time: f64, step: u64, depth: f64, velocity: f64) {
        let left = time_left(self.started.elapsed(), time / self.end_time)
            .map_or(String::new(), |s| format!("  left ~{s}"));
        let msg = format!(
            "t {:.1} µs  step {step}  depth {} mm  v {} m/s{left}",
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

/// The wall time left to `end_time` at the pace so far, once there is a pace to go by: a
/// second of wall time and a thousandth of the run. A run that stops early (the projectile
/// at rest) ends sooner.
fn time_left(elapsed: Duration, done: f64) -> Option<String> {
    let s = elapsed.as_secs_f64();
    if s < 1.0 || !(1e-3..1.0).contains(&done) {
        return None;
    }
    let left = (s * (1.0 - done) / done).round() as u64;
    Some(match left {
        0..=99 => format!("{left} s"),
        100..=5999 => format!("{}m{:02}s", left / 60, left % 60),
        _ => format!("{}h{:02}m", left / 3600, left / 60 % 60),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quarter done in a minute leaves three; too early or done, nothing is said.
    #[test]
    fn time_left_follows_the_pace() {
        let minute = Duration::from_secs(60);
        assert_eq!(time_left(minute, 0.25).as_deref(), Some("3m00s"));
        assert_eq!(time_left(minute, 0.9).as_deref(), Some("7 s"));
        assert_eq!(time_left(minute * 60, 0.25).as_deref(), Some("3h00m"));
        assert_eq!(time_left(Duration::from_millis(500), 0.5), None);
        assert_eq!(time_left(minute, 1e-4), None);
        assert_eq!(time_left(minute, 1.0), None);
        assert_eq!(time_left(minute, f64::NAN), None);
    }
}
