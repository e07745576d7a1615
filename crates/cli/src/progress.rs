//! Progress for `sim::Progress`: on a terminal one bar per phase (response run, each
//! wear-stage simulation), a study's parallel runs each on their own line ([`StudyBars`]); in a
//! log (standard error not a terminal) plain lines instead, each its own line and at most about
//! one a second ([`Throttle`]), so a long run is never silent and a log never runs updates
//! into one line.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Bar resolution: hundredths of a drive cycle.
const TICKS_PER_CYCLE: f64 = 100.0;

/// Shortest interval between two progress lines in a log.
const LINE_INTERVAL: Duration = Duration::from_secs(1);

/// Whether progress is drawn as bars (standard error is a terminal) or written as lines.
pub fn on_terminal() -> bool {
    std::io::stderr().is_terminal()
}

/// Lets a progress line through at most once per [`LINE_INTERVAL`].
#[derive(Default)]
pub struct Throttle {
    last: Option<Instant>,
}

impl Throttle {
    /// Whether a line may be written now (and, if so, counts it as written).
    pub fn due(&mut self) -> bool {
        let now = Instant::now();
        let due = self.last.is_none_or(|t| now - t >= LINE_INTERVAL);
        if due {
            self.last = Some(now);
        }
        due
    }
}

/// The phase a log is following: its label, length and start.
struct LinePhase {
    label: String,
    cycles: f64,
    started: Instant,
    percent: i64,
}

/// indicatif bars driven by the run's progress reports, or lines in a log.
pub struct Bars {
    visible: bool,
    bar: Option<ProgressBar>,
    /// The shared display when several runs show bars at once.
    multi: Option<MultiProgress>,
    /// Prefix of every log line (a study's run key).
    prefix: String,
    line: Option<LinePhase>,
    throttle: Throttle,
}

impl Bars {
    pub fn new() -> Self {
        Self {
            visible: on_terminal(),
            bar: None,
            multi: None,
            prefix: String::new(),
            line: None,
            throttle: Throttle::default(),
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
        let visible = on_terminal();
        Self {
            multi: MultiProgress::with_draw_target(draw_target(visible)),
            visible,
        }
    }
}

impl analysis::study::StudyProgress for StudyBars {
    fn run(&self, key: &str, index: usize, total: usize) -> Box<dyn sim::Progress + Send + '_> {
        let mut bars = Bars {
            visible: self.visible,
            bar: None,
            multi: Some(self.multi.clone()),
            prefix: format!("{key}: "),
            line: None,
            throttle: Throttle::default(),
        };
        sim::Progress::note(&mut bars, &format!("[{}/{total}] {key} starts", index + 1));
        Box::new(bars)
    }
}

/// A phase's length in cycles for a log line: `2.175`, not the binary residue `2.1750000000000003`
/// of `K + window / period` (six decimals are finer than any phase needs).
fn rounded(cycles: f64) -> f64 {
    (cycles * 1e6).round() / 1e6
}

impl sim::Progress for Bars {
    fn phase(&mut self, label: &str, cycles: f64) {
        self.finish();
        if !self.visible {
            errln!("{}{label}: {} cycle(s)", self.prefix, rounded(cycles));
            self.line = Some(LinePhase {
                label: label.to_string(),
                cycles,
                started: Instant::now(),
                percent: 0,
            });
            return;
        }
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
        if let Some(line) = &mut self.line {
            let percent = (100.0 * cycles / line.cycles.max(f64::MIN_POSITIVE)).floor() as i64;
            if percent > line.percent && self.throttle.due() {
                line.percent = percent;
                errln!(
                    "{}{}: {percent:>3} % ({cycles:.2} of {} cycles, {:.0} s)",
                    self.prefix,
                    line.label,
                    rounded(line.cycles),
                    line.started.elapsed().as_secs_f64()
                );
            }
        }
    }

    fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
        if let Some(line) = self.line.take() {
            errln!(
                "{}{}: done in {:.1} s",
                self.prefix,
                line.label,
                line.started.elapsed().as_secs_f64()
            );
        }
    }

    fn note(&mut self, text: &str) {
        match (&self.multi, &self.bar) {
            (Some(multi), _) if self.visible => {
                let _ = multi.println(text);
            }
            (None, Some(bar)) if self.visible => bar.println(text),
            _ => errln!("{text}"),
        }
    }
}

impl Drop for Bars {
    fn drop(&mut self) {
        sim::Progress::finish(self);
    }
}
