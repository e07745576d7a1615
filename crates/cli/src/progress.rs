//! Progress bars for `lgres::run::Progress`: one bar per phase (response run, each wear-stage
//! simulation), hidden when stdout is not a terminal so logs and pipes stay clean.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Bar resolution: hundredths of a drive cycle.
const TICKS_PER_CYCLE: f64 = 100.0;

/// indicatif bars driven by the run's progress reports.
pub struct Bars {
    visible: bool,
    bar: Option<ProgressBar>,
}

impl Bars {
    pub fn new() -> Self {
        Self {
            visible: std::io::stdout().is_terminal(),
            bar: None,
        }
    }
}

impl lgres::run::Progress for Bars {
    fn phase(&mut self, label: &str, cycles: f64) {
        self.finish();
        let target = if self.visible {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(Some((cycles * TICKS_PER_CYCLE) as u64), target);
        if let Ok(style) = ProgressStyle::with_template(
            "{msg:<24} [{bar:40}] {percent:>3}% {elapsed_precise} (eta {eta})",
        ) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_message(label.to_string());
        self.bar = Some(bar);
    }

    fn advance(&mut self, cycles: f64) {
        if let Some(bar) = &self.bar {
            bar.set_position((cycles * TICKS_PER_CYCLE) as u64);
        }
    }

    fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }

    fn note(&mut self, text: &str) {
        match &self.bar {
            Some(bar) if self.visible => bar.println(text),
            _ => eprintln!("{text}"),
        }
    }
}

impl Drop for Bars {
    fn drop(&mut self) {
        lgres::run::Progress::finish(self);
    }
}
