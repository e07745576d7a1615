//! Helpers shared by the sweep crate's test files: the fuzzing's seed sweep, runner, counts
//! and time limits on special files, and scratch folders. Each test file compiles this module
//! on its own and uses part of it, hence `dead_code` allowed.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use sweep::{LocalOptions, Row, Sweep, SweepError};

/// A random sweep of the slider-crank with all three distributions.
pub const RANDOM: &str = r#"
scene = "slider-crank"
samples = 6
seed = 3
metrics = ["response.joints.rod-slider.max_penetration_m", "response.dissipated_per_cycle_j"]
[run]
cycles = 1
cycles_per_stage = 1
[[vary]]
path = "clearance_joints.rod-slider.clearance"
name = "clearance"
distribution = "uniform"
low = 3e-4
high = 6e-4
[[vary]]
path = "clearance_joints.rod-slider.normal_law.restitution"
name = "restitution"
distribution = "normal"
mean = 0.8
sd = 0.05
[[vary]]
path = ["drivers.crank-speed.law.rate"]
distribution = "log-normal"
median = 500.0
sigma = 0.1
"#;

/// The repository's folder (this crate is `crates/sweep`).
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A temporary folder path named after `tag` and this test process, with nothing at it (a
/// sweep creates its output folder itself).
pub fn fresh_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sweep-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// A fresh, empty scratch folder.
pub fn scratch(tag: &str) -> PathBuf {
    let d = fresh_dir(tag);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Resumes `sweep` into `out` on one thread: every row of the sweep, and the samples that ran
/// (in the order they finished).
pub fn resume(sweep: &Sweep, out: &Path) -> (Vec<Row>, Vec<usize>) {
    let mut ran = Vec::new();
    let rows = sweep::run_local(
        sweep,
        out,
        &LocalOptions {
            jobs: 1,
            resume: true,
        },
        None,
        &mut |r, _, _| ran.push(r.sample),
    )
    .unwrap();
    (rows, ran)
}

/// How sweep file `text` is refused (a test failure if it is accepted).
pub fn refusal(text: &str) -> SweepError {
    match Sweep::from_str(text, "t") {
        Err(e) => e,
        Ok(_) => panic!("accepted:\n{text}"),
    }
}

/// A proptest runner with a fixed seed and no failure files.
pub fn runner(cases: u32, seed: u8) -> TestRunner {
    let config = Config {
        cases,
        failure_persistence: None,
        // A shrunk failure is nice, an endless shrink in CI is not.
        max_shrink_iters: 200,
        ..Config::default()
    };
    TestRunner::new_with_rng(
        config,
        TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
    )
}

/// Counts by kind, printed at the end of each door.
#[derive(Debug, Default)]
pub struct Counts(pub BTreeMap<String, usize>);

impl Counts {
    pub fn add(&mut self, kind: impl Into<String>) {
        *self.0.entry(kind.into()).or_default() += 1;
    }
    pub fn get(&self, kind: &str) -> usize {
        self.0.get(kind).copied().unwrap_or(0)
    }
    pub fn starting(&self, prefix: &str) -> usize {
        self.0
            .iter()
            .filter(|(k, _)| k.starts_with(prefix))
            .map(|(_, n)| n)
            .sum()
    }

    /// Prints the counts of door `door` since `started` (seen with `--nocapture`) and returns
    /// how many cases were accepted and refused (every kind not starting "accepted").
    pub fn report(&self, door: &str, started: Instant) -> (usize, usize) {
        let total: usize = self.0.values().sum();
        let accepted = self.starting("accepted");
        let refused = total - accepted;
        eprintln!(
            "{door}: {total} cases, {accepted} accepted, {refused} refused, in {:.1} s",
            started.elapsed().as_secs_f64()
        );
        for (kind, n) in &self.0 {
            eprintln!("  {n:4}  {kind}");
        }
        (accepted, refused)
    }
}

/// Fuzzes door `door` by `fuzz` and prints its counts: the cases must reach both sides of the
/// door (at least 200 accepted and 500 refused) and every kind in `kinds`.
#[track_caller]
pub fn fuzz_door(door: &str, fuzz: impl FnOnce() -> Counts, kinds: &[&str]) {
    let started = Instant::now();
    let c = fuzz();
    let (accepted, refused) = c.report(door, started);
    assert!(accepted >= 200 && refused >= 500, "{c:?}");
    for kind in kinds {
        assert!(c.get(kind) > 0, "no case of {kind}: {c:?}");
    }
}

/// Why [`answer`] got no answer.
#[derive(Debug)]
pub enum NoAnswer {
    Panicked,
    TimedOut,
}

/// Run `f` on another thread and wait at most `secs` for its answer. On time-out the thread
/// is left behind (blocked or spinning until the process ends).
pub fn answer<T: Send + 'static>(
    secs: u64,
    f: impl FnOnce() -> T + Send + 'static,
) -> Result<T, NoAnswer> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(Duration::from_secs(secs))
        .map_err(|e| match e {
            mpsc::RecvTimeoutError::Disconnected => NoAnswer::Panicked,
            mpsc::RecvTimeoutError::Timeout => NoAnswer::TimedOut,
        })
}

/// [`answer`] for special files: one must be refused at once, not blocked on (a FIFO without
/// a writer) or read forever (`/dev/zero`). `unblock` runs if time is up, to free the thread
/// (e.g. open the FIFO's other end).
pub fn within<T: Send + 'static>(
    secs: u64,
    what: &str,
    unblock: impl FnOnce(),
    f: impl FnOnce() -> T + Send + 'static,
) -> T {
    match answer(secs, f) {
        Ok(v) => v,
        Err(NoAnswer::Panicked) => panic!("{what}: panicked"),
        Err(NoAnswer::TimedOut) => {
            unblock();
            panic!("{what}: no answer within {secs} s (blocked, or reading without bound)")
        }
    }
}

/// `mkfifo path` (no writer: opening it for reading blocks).
#[cfg(unix)]
pub fn mkfifo(path: &Path) {
    let status = std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .expect("mkfifo");
    assert!(status.success(), "mkfifo {}", path.display());
}

/// Open the FIFO at `path` for writing and close it, which ends a reader's wait.
#[cfg(unix)]
pub fn release_fifo(path: &Path) {
    let _ = std::fs::OpenOptions::new().write(true).open(path);
}

/// A mutation: what to do, which candidate (modulo their count), a parameter.
#[derive(Debug, Clone, Copy)]
pub struct Mutation {
    pub kind: u8,
    pub pick: usize,
    pub param: u8,
}

pub fn mutation() -> impl Strategy<Value = Mutation> {
    (any::<u8>(), any::<usize>(), any::<u8>()).prop_map(|(kind, pick, param)| Mutation {
        kind,
        pick,
        param,
    })
}
