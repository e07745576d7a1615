//! Progress bars for `lgres::run::Progress`: one bar per phase (response run, each wear-stage
//! simulation), hidden when stdout is not a terminal so logs and pipes stay clean. A study's
//! runs in parallel each get their own line ([`StudyBars`]).

use std::io::IsTerminal;

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Bar resolution: hundredths of a drive cycle.
const TICKS_PER_CYCLE: f64 = 100.0;

/// indicatif bars driven by the run's progress reports.
pub struct Bars {
    visible: bool,
    bar: Option<ProgressBar>,
    /// The shared display when several runs show bars at once.
    multi: Option<MultiProgress>,
}

impl Bars {
    pub fn new() -> Self {
        Self {
            visible: std::io::stdout().is_terminal(),
            bar: None,
            multi: None,
        }
    }
}

/// Bars go to stderr on a terminal and nowhere otherwise.
fn draw_target(visible: bool) -> ProgressDrawTarget {
    if visible {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    }
}

/// One line of bars per study run in progress (runs go on in parallel threads).
pub struct StudyBars {
    multi: MultiProgress,
    visible: bool,
}

impl StudyBars {
    pub fn new() -> Self {
        let visible = std::io::stdout().is_terminal();
        Self {
            multi: MultiProgress::with_draw_target(draw_target(visible)),
            visible,
        }
    }
}

impl lgres::analysis::study::StudyProgress for StudyBars {
    fn run(
        &self,
        key: &str,
        index: usize,
        total: usize,
    ) -> Box<dyn lgres::run::Progress + Send + '_> {
        let mut bars = Bars {
            visible: self.visible,
            bar: None,
            multi: Some(self.multi.clone()),
        };
        lgres::run::Progress::note(&mut bars, &format!("[{}/{total}] {key} starts", index + 1));
        Box::new(bars)
    }
}

impl lgres::run::Progress for Bars {
    fn phase(&mut self, label: &str, cycles: f64) {
        self.finish();
        let length = Some((cycles * TICKS_PER_CYCLE) as u64);
        let bar = match &self.multi {
            // The shared display draws it.
            Some(multi) => multi.add(ProgressBar::with_draw_target(
                length,
                ProgressDrawTarget::hidden(),
            )),
            None => ProgressBar::with_draw_target(length, draw_target(self.visible)),
        };
        if let Ok(style) = ProgressStyle::with_template(
            "{msg:<36} [{bar:40}] {percent:>3}% {elapsed_precise} (eta {eta})",
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
        match (&self.multi, &self.bar) {
            (Some(multi), _) if self.visible => {
                let _ = multi.println(text);
            }
            (None, Some(bar)) if self.visible => bar.println(text),
            _ => eprintln!("{text}"),
        }
    }
}

impl Drop for Bars {
    fn drop(&mut self) {
        lgres::run::Progress::finish(self);
    }
}
