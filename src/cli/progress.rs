//! The progress bar of `mbfx run` on stderr (indicatif), shown only when stderr is a
//! terminal so pipes and logs get the summary alone.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;

/// A bar of `len` ticks drawn with `template` when stderr is a terminal (None
/// otherwise: pipes and logs get no bar).
pub fn terminal_bar(len: u64, template: &str) -> Option<ProgressBar> {
    std::io::stderr().is_terminal().then(|| {
        let b = ProgressBar::new(len);
        if let Ok(style) = ProgressStyle::with_template(template) {
            b.set_style(style);
        }
        b
    })
}

/// Simulated time against the end time.
pub struct Progress {
    bar: Option<ProgressBar>,
    end: f64,
}

/// Ticks on the bar (the simulated time is shown in thousandths of the end time).
const TICKS: u64 = 1000;

impl Progress {
    pub fn new(end: f64) -> Progress {
        let bar = terminal_bar(TICKS, "{bar:40} {msg} [{elapsed_precise}, eta {eta}]");
        Progress { bar, end }
    }

    /// The run reached simulated time `t`.
    pub fn at(&self, t: f64) {
        if let Some(b) = &self.bar {
            b.set_position(((t / self.end).clamp(0.0, 1.0) * TICKS as f64) as u64);
            b.set_message(format!("t = {t:.6}"));
        }
    }

    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
