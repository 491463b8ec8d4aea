//! Progress lines on stderr: rewritten in place on a terminal, a few plain lines otherwise.

use std::io::{IsTerminal, Write};

/// Reports `done / total` progress of one phase of work.
pub struct Progress {
    label: &'static str,
    terminal: bool,
    last_quarter: usize,
}

impl Progress {
    /// A reporter for the phase `label` (e.g. "reading mocap").
    pub fn new(label: &'static str) -> Self {
        Progress {
            label,
            terminal: std::io::stderr().is_terminal(),
            last_quarter: 0,
        }
    }

    /// Reports that `done` of `total` items are finished; `item` names the last one.
    pub fn tick(&mut self, done: usize, total: usize, item: &str) {
        let mut err = std::io::stderr().lock();
        if self.terminal {
            let _ = write!(err, "\r\x1b[2K{} [{done}/{total}] {item}", self.label);
            if done == total {
                let _ = writeln!(err);
            }
        } else {
            // Without a terminal, one line per quarter of the work.
            let quarter = (done * 4).checked_div(total).unwrap_or(4);
            if quarter > self.last_quarter {
                self.last_quarter = quarter;
                let _ = writeln!(err, "{} [{done}/{total}]", self.label);
            }
        }
        let _ = err.flush();
    }
}

/// One Newton iteration of a fit as a line for standard error: its number, the seconds since
/// the fit started, objective, gradient norm, step and how its direction was found.
pub fn newton_line(log: &camloc::learning::IterationLog, seconds: f64) -> String {
    format!(
        "  newton {:>3} at {seconds:6.1} s: objective {:.6e}  |grad|_inf {:.3e}  step {:.3}  ({})",
        log.iteration,
        log.objective,
        log.gradient_norm,
        log.step,
        log.direction_summary()
    )
}
