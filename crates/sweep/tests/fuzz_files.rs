//! Fuzzing of the sweep crate's first input door, sweep files, with fixed seeds (every run sees
//! the same cases). Nothing is simulated: sweeps are built and their samples listed, never run.
//! (The second door, resume tables, is `fuzz_resume.rs`.)
//!
//! The shipped `docs/sweep/wear-ab.toml` and two small sweeps (a grid and a random one) are
//! mutated — numbers scaled by 1e±6, set to 0, negated, NaN, ±inf, 1e300; integers set to
//! fractions and huge counts; keys deleted or added; strings made empty, garbage, very long or
//! path-like; arrays emptied, doubled or stretched; then the text itself gets byte flips,
//! garbage, lost or repeated lines, truncation — and read with [`Sweep::from_path`], as
//! `wearsim sweep` does. A refusal must name a field or a line; an accepted sweep must have a
//! bounded sample count and finite input values in every sample.
//!
//! Special files (a FIFO, a link to `/dev/zero`, a directory, a sparse terabyte) must be
//! answered at once, never blocked on or read without bound.
//!
//! Run with `--nocapture` to see the counts.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

use sweep::{MAX_SAMPLES, Sampler, Sweep, SweepError};

mod common;
use common::{
    Counts, Mutation, NoAnswer, RANDOM, answer, fuzz_door, mutation, repo, runner, scratch, within,
};
#[cfg(unix)]
use common::{mkfifo, release_fifo};

/// A grid sweep of the slider-crank: 2 × 3 samples, both inputs float fields.
const GRID: &str = r#"
scene = "slider-crank"
metrics = ["response.joints.rod-slider.max_penetration_m", "response.dissipated_per_cycle_j"]
[run]
cycles = 1
stages = 0
rtol = 1e-6
max_steps = 100000
max_wall_time = 60.0
[[vary]]
path = "clearance_joints.rod-slider.clearance"
name = "clearance"
values = [4e-4, 5e-4]
[[vary]]
path = "drivers.crank-speed.law.rate"
values = [400.0, 450.0, 523.5988]
"#;

/// One step of a path into a TOML value.
#[derive(Debug, Clone)]
enum Seg {
    Key(String),
    Index(usize),
}

type TomlPath = Vec<Seg>;

/// Every path below `v`, with the value it leads to.
fn walk<'a>(v: &'a toml::Value, at: &TomlPath, out: &mut Vec<(TomlPath, &'a toml::Value)>) {
    let children: Vec<(Seg, &toml::Value)> = match v {
        toml::Value::Table(t) => t.iter().map(|(k, c)| (Seg::Key(k.clone()), c)).collect(),
        toml::Value::Array(a) => a
            .iter()
            .enumerate()
            .map(|(i, c)| (Seg::Index(i), c))
            .collect(),
        _ => return,
    };
    for (seg, child) in children {
        let mut p = at.clone();
        p.push(seg);
        out.push((p.clone(), child));
        walk(child, &p, out);
    }
}

fn get_mut<'a>(v: &'a mut toml::Value, path: &[Seg]) -> Option<&'a mut toml::Value> {
    path.iter().try_fold(v, |v, seg| match seg {
        Seg::Key(k) => v.as_table_mut()?.get_mut(k),
        Seg::Index(i) => v.as_array_mut()?.get_mut(*i),
    })
}

/// Strings a text field may become: empty, garbage, very long, path-like, a column's name, a
/// scene or an integer field.
fn odd_string(param: u8) -> String {
    match param % 16 {
        0 => String::new(),
        1 => "\u{0}garbage\u{7f}\u{2603}\n\"'".into(),
        2 => "a".repeat(100_000),
        3 => "../x".into(),
        4 => "/dev/zero".into(),
        5 => "/etc/passwd".into(),
        6 => "a..b".into(),
        7 => "x[0".into(),
        8 => "status".into(),
        9 => "sample".into(),
        10 => "lgres".into(),
        11 => "slider-crank".into(),
        12 => "run.cycles".into(),
        13 => "clearance_joints.rod-slider.wear.cells".into(),
        14 => "log-normal".into(),
        _ => "response.dissipated_per_cycle_j".into(),
    }
}

/// Keys a `[[vary]]` table (or the top level) may gain, with values that stress them.
fn odd_key(param: u8) -> (&'static str, toml::Value) {
    use toml::Value::{Array, Float, Integer, String as Str};
    match param % 12 {
        0 => ("values", Array(vec![Float(1.0), Float(2.5)])),
        1 => ("distribution", Str("normal".into())),
        2 => ("distribution", Str("log-normal".into())),
        3 => ("sd", Float(1e300)),
        4 => ("mean", Float(-1e300)),
        5 => ("sigma", Float(1e3)),
        6 => ("median", Float(1e300)),
        7 => ("low", Float(-1.7e308)),
        8 => ("high", Float(1.7e308)),
        9 => ("samples", Integer(1_000_000_000_000)),
        10 => ("seed", Integer(-1)),
        _ => ("bogus", Integer(1)),
    }
}

/// Apply one structural mutation to a parsed sweep file.
fn mutate(file: &mut toml::Value, m: Mutation) {
    use toml::Value::{Array, Boolean, Float, Integer, String as Str};
    let mut all = Vec::new();
    walk(file, &Vec::new(), &mut all);
    let pick = |filter: &dyn Fn(&toml::Value, &TomlPath) -> bool| -> Option<TomlPath> {
        let candidates: Vec<&TomlPath> = all
            .iter()
            .filter(|(p, v)| filter(v, p))
            .map(|(p, _)| p)
            .collect();
        (!candidates.is_empty()).then(|| candidates[m.pick % candidates.len()].clone())
    };
    let number = |v: &toml::Value, _: &TomlPath| v.is_float() || v.is_integer();
    let as_f64 = |v: &toml::Value| v.as_float().or(v.as_integer().map(|i| i as f64));
    let at =
        |file: &mut toml::Value, p: Option<TomlPath>| p.and_then(|p| get_mut(file, &p).map(|_| p));
    match m.kind % 10 {
        // Scale a number by 1e-6 or 1e6 (an integer stays one when it can).
        0 => {
            if let Some(p) = at(file, pick(&number)) {
                let v = get_mut(file, &p).unwrap();
                *v = match (&*v, m.param % 2) {
                    (Integer(i), 1) => i
                        .checked_mul(1_000_000)
                        .map_or(Float(*i as f64 * 1e6), Integer),
                    (other, 0) => Float(as_f64(other).unwrap_or(1.0) * 1e-6),
                    (other, _) => Float(as_f64(other).unwrap_or(1.0) * 1e6),
                };
            }
        }
        // Zero, negated, NaN, ±inf, ±1e300, 1e-300.
        1 => {
            if let Some(p) = at(file, pick(&number)) {
                let v = get_mut(file, &p).unwrap();
                let x = as_f64(v).unwrap_or(1.0);
                let new = [
                    0.0,
                    -x,
                    f64::NAN,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    1e300,
                    -1e300,
                    1e-300,
                ][usize::from(m.param % 8)];
                *v = match &*v {
                    Integer(i) if m.param % 8 < 2 => {
                        Integer(if m.param.is_multiple_of(8) { 0 } else { -i })
                    }
                    _ => Float(new),
                };
            }
        }
        // Counts and integer fields: fractions, huge counts, the type's edges.
        2 => {
            if let Some(p) = at(file, pick(&number)) {
                *get_mut(file, &p).unwrap() = match m.param % 8 {
                    0 => Float(0.5),
                    1 => Float(2.5),
                    2 => Integer(1_000_000_000_000),
                    3 => Integer(i64::MAX),
                    4 => Integer(-1),
                    5 => Integer(i64::from(u32::MAX) + 1),
                    6 => Integer(MAX_SAMPLES as i64 + 1),
                    _ => Float(1e12),
                };
            }
        }
        // Delete a key.
        3 => {
            if let Some(p) = pick(&|_, p: &TomlPath| matches!(p.last(), Some(Seg::Key(_))))
                && let Some((Seg::Key(k), parent)) = p.split_last()
                && let Some(t) = get_mut(file, parent).and_then(toml::Value::as_table_mut)
            {
                t.remove(k);
            }
        }
        // Replace a string.
        4 => {
            if let Some(p) = at(file, pick(&|v: &toml::Value, _: &TomlPath| v.is_str())) {
                *get_mut(file, &p).unwrap() = Str(odd_string(m.param));
            }
        }
        // Empty an array, double it, stretch it to 1001 elements, or reverse it.
        5 => {
            if let Some(p) = at(file, pick(&|v: &toml::Value, _: &TomlPath| v.is_array()))
                && let Some(a) = get_mut(file, &p).and_then(toml::Value::as_array_mut)
            {
                match m.param % 4 {
                    0 => a.clear(),
                    1 => a.extend(a.clone()),
                    2 if !a.is_empty() => {
                        // Distinct values (a grid of 1001 × 1001 = 1e6 + 2001 samples must be
                        // refused whatever the values).
                        let first = a[0].clone();
                        *a = (0..1001)
                            .map(|k| match &first {
                                Float(x) => Float(x * (1.0 + k as f64 * 1e-3)),
                                other => other.clone(),
                            })
                            .collect();
                    }
                    _ => a.reverse(),
                }
            }
        }
        // Change a value's type.
        6 => {
            if let Some(p) = at(file, pick(&|_, p: &TomlPath| !p.is_empty())) {
                let v = get_mut(file, &p).unwrap();
                *v = match (&*v, m.param % 3) {
                    (Float(_) | Integer(_), 0) => Str("1".into()),
                    (Str(_), 0) => Float(1.0),
                    (Array(a), 0) => a.first().cloned().unwrap_or(Boolean(true)),
                    (_, 1) => Boolean(true),
                    (other, _) => Array(vec![other.clone(), other.clone()]),
                };
            }
        }
        // Add a key (unknown, conflicting, or with a stressing value) to some table.
        7 => {
            if let Some(p) =
                at(file, pick(&|v: &toml::Value, _: &TomlPath| v.is_table())).or(Some(Vec::new()))
                && let Some(t) = get_mut(file, &p).and_then(toml::Value::as_table_mut)
            {
                let (k, v) = odd_key(m.param);
                t.insert(k.into(), v);
            }
        }
        // Duplicate a [[vary]] entry (its name then appears twice).
        8 => {
            if let Some(a) = file.get_mut("vary").and_then(toml::Value::as_array_mut)
                && !a.is_empty()
            {
                let copy = a[m.pick % a.len()].clone();
                a.push(copy);
            }
        }
        // Set the value of a key of a [[vary]] table from the stressing set.
        _ => {
            if let Some(a) = file.get_mut("vary").and_then(toml::Value::as_array_mut)
                && !a.is_empty()
                && let k = m.pick % a.len()
                && let Some(t) = a[k].as_table_mut()
            {
                let (k, v) = odd_key(m.param);
                t.insert(k.into(), v);
            }
        }
    }
}

/// A mutation of the file's bytes: flips, garbage, lines lost or repeated, truncation.
fn mutate_bytes(text: &mut Vec<u8>, m: Mutation) {
    const GARBAGE: [u8; 10] = [0x00, 0xff, 0xfe, 0xc3, b'"', b'[', b']', b'=', b'\n', b'#'];
    let at = if text.is_empty() {
        0
    } else {
        m.pick % text.len()
    };
    match m.kind % 5 {
        0 if !text.is_empty() => text[at] ^= m.param | 1,
        1 => text.truncate(at),
        2 => text.insert(at, GARBAGE[usize::from(m.param) % GARBAGE.len()]),
        kind => {
            let mut lines: Vec<Vec<u8>> = text.split(|b| *b == b'\n').map(<[u8]>::to_vec).collect();
            let k = m.pick % lines.len();
            if kind == 3 {
                let copy = lines[k].clone();
                lines.insert(k, copy);
            } else {
                lines.remove(k);
            }
            *text = lines.join(&b'\n');
        }
    }
}

/// A sweep-file case: the seed file, its mutations, and maybe a byte-level one.
#[derive(Debug, Clone)]
struct FileCase {
    seed: usize,
    mutations: Vec<Mutation>,
    bytes: Option<Mutation>,
}

/// Keys of the sweep format, one of which (or a line) a refusal must name.
const SWEEP_KEYS: [&str; 6] = ["scene", "samples", "seed", "metrics", "run", "vary"];

/// Whether a refusal of the sweep file at `file` says where: a field of the format, a line, or
/// (for a file it cannot read) the file, and for a file that is not text, the line.
fn says_where(e: &SweepError, file: &Path) -> Result<&'static str, String> {
    let msg = e.to_string();
    let top = |field: &str| {
        let first = field.split(['.', '[', ' ']).next().unwrap_or("");
        SWEEP_KEYS.contains(&first)
    };
    let ok = match e {
        SweepError::Io { source, .. } => {
            let names_file = msg.contains(&file.display().to_string());
            let kind = if source.kind() == std::io::ErrorKind::InvalidData {
                "io: not UTF-8"
            } else {
                "io: other"
            };
            // A file that is not text must say where it stops being text.
            if names_file && (kind == "io: other" || msg.contains("line")) {
                return Ok(kind);
            }
            false
        }
        SweepError::Toml { .. } => {
            if msg.contains("line") {
                return Ok("toml syntax (line)");
            }
            false
        }
        SweepError::Type { field, source, .. } => {
            let s = source.to_string();
            if top(field) || s.contains("field `") {
                return Ok("type / unknown or missing key (field)");
            }
            false
        }
        SweepError::Field { field, reason, .. } => {
            if top(field) {
                return Ok(
                    if reason.contains("exceeds") || reason.contains("must be 1 to") {
                        "too many samples (field)"
                    } else if reason.contains("largest number") || reason.contains("overflows") {
                        "draws would overflow (field)"
                    } else {
                        "bad value (field)"
                    },
                );
            }
            false
        }
        // The base scene (a file named by `scene`) is bad: its message names the scene file
        // and the line or field.
        SweepError::Scene(_) => {
            if msg.contains("line") || msg.contains("scene") {
                return Ok("base scene file");
            }
            false
        }
        _ => false,
    };
    debug_assert!(!ok);
    Err(format!("refusal names no field or line: {e:?}\n  {msg}"))
}

/// Sample indices to check: all of them up to 4096, else the first and last 2048 and a stride
/// between (a million draws would take minutes in a debug build).
fn indices(n: usize) -> Vec<usize> {
    if n <= 4096 {
        (0..n).collect()
    } else {
        let stride = (n / 2048).max(1);
        (0..2048)
            .chain((2048..n - 2048).step_by(stride))
            .chain(n - 2048..n)
            .collect()
    }
}

/// Longest a sample's scene may take to build and validate, s (it takes milliseconds).
const SCENE_SECONDS: u64 = 20;

/// What an accepted sweep must satisfy: 1 to [`MAX_SAMPLES`] samples (a grid's being the
/// product of its value counts), every sample's input values finite and, for a grid, from its
/// values; every sample pending (none kept) without resume and with resume from an empty
/// folder; and building sample 0's scene (no run) must neither panic nor take more than
/// [`SCENE_SECONDS`] (`None`: it did; the case is then reported and the fuzzing stopped, so
/// that no shrinking piles up more stuck threads).
fn check_accepted(s: &Sweep, empty: &Path) -> Result<Option<&'static str>, TestCaseError> {
    let n = s.samples();
    prop_assert!((1..=MAX_SAMPLES).contains(&n), "{n} samples");
    prop_assert!(!s.inputs.is_empty());
    if let sweep::Mode::Grid { samples } = s.mode {
        let product = s.inputs.iter().try_fold(1usize, |p, i| match &i.sampler {
            Sampler::Grid(v) => p.checked_mul(v.len()),
            _ => None,
        });
        prop_assert_eq!(product, Some(samples));
    }
    for k in indices(n) {
        let values = s.input_values(k);
        prop_assert_eq!(values.len(), s.inputs.len());
        for (v, input) in values.iter().zip(&s.inputs) {
            prop_assert!(
                v.is_finite(),
                "sample {} of {}: input {} = {} ({:?})",
                k,
                n,
                input.name,
                v,
                input.sampler
            );
            if let Sampler::Grid(g) = &input.sampler {
                prop_assert!(g.contains(v));
            }
        }
    }
    for resume in [false, true] {
        let (todo, kept) = sweep::pending(s, empty, resume)
            .map_err(|e| TestCaseError::fail(format!("pending: {e}")))?;
        prop_assert!(kept.is_empty());
        prop_assert!(todo.len() == n && todo.iter().enumerate().all(|(k, t)| k == *t));
    }
    let sample = s.clone();
    let built = match answer(SCENE_SECONDS, move || sample.scene(0).is_ok()) {
        Ok(built) => built,
        Err(NoAnswer::Panicked) => return Err(TestCaseError::fail("sample 0's scene: panic")),
        Err(NoAnswer::TimedOut) => return Ok(None),
    };
    Ok(Some(match (built, s.mode) {
        (true, sweep::Mode::Grid { .. }) => "accepted grid (sample 0's scene builds)",
        (true, _) => "accepted random (sample 0's scene builds)",
        (false, _) => "accepted, sample 0's scene refused (a failed row)",
    }))
}

/// Mutants of the shipped and the two small sweep files, read as `wearsim sweep` reads them.
fn fuzz_sweep_files(cases: u32, seed: u8) -> Counts {
    let shipped = std::fs::read_to_string(repo().join("docs/sweep/wear-ab.toml")).unwrap();
    let seeds: Vec<toml::Value> = [shipped.as_str(), GRID, RANDOM]
        .iter()
        .map(|t| toml::from_str(t).unwrap())
        .collect();
    let dir = scratch("files");
    let (file, empty) = (dir.join("mutant.toml"), dir.join("empty-out"));
    let strategy = (
        0..seeds.len(),
        prop::collection::vec(mutation(), 0..4),
        prop::option::weighted(0.3, mutation()),
    )
        .prop_map(|(seed, mutations, bytes)| FileCase {
            seed,
            mutations,
            bytes,
        });
    let counts = RefCell::new(Counts::default());
    let stuck = RefCell::new(None);
    let result = runner(cases, seed).run(&strategy, |case| {
        if stuck.borrow().is_some() {
            return Ok(());
        }
        let mut value = seeds[case.seed].clone();
        for m in &case.mutations {
            mutate(&mut value, *m);
        }
        let mut bytes = toml::to_string(&value).unwrap_or_default().into_bytes();
        if let Some(m) = case.bytes {
            mutate_bytes(&mut bytes, m);
        }
        std::fs::write(&file, &bytes).unwrap();
        let kind = match Sweep::from_path(&file) {
            Ok(s) => match check_accepted(&s, &empty)? {
                Some(kind) => kind,
                None => {
                    *stuck.borrow_mut() = Some(String::from_utf8_lossy(&bytes).into_owned());
                    return Ok(());
                }
            },
            Err(e) => says_where(&e, &file).map_err(TestCaseError::fail)?,
        };
        counts.borrow_mut().add(kind);
        Ok(())
    });
    let _ = std::fs::remove_dir_all(&dir);
    if let Some(text) = stuck.into_inner() {
        panic!("sweep files: sample 0's scene took over {SCENE_SECONDS} s to build:\n{text}");
    }
    if let Err(e) = result {
        panic!("sweep files: {e}");
    }
    counts.into_inner()
}

/// Door 1: no mutant panics, every refusal says where, every accepted sweep has a bounded
/// sample count and finite inputs.
#[test]
fn fuzzed_sweep_files_are_refused_by_field_or_give_finite_bounded_samples() {
    // The mutants must reach both sides of the door, and the bounds.
    fuzz_door(
        "sweep files",
        || fuzz_sweep_files(5000, 41),
        &[
            "toml syntax (line)",
            "bad value (field)",
            "too many samples (field)",
            "draws would overflow (field)",
            "io: not UTF-8",
        ],
    );
}

/// Door 1's bound, by hand: a sweep asking for more than [`MAX_SAMPLES`] samples (10¹² drawn,
/// or a 1001 × 1001 grid) is refused naming the field, before anything is allocated for them;
/// a grid of exactly [`MAX_SAMPLES`] is accepted and lists them all.
#[test]
fn huge_sample_counts_are_refused_not_allocated() {
    let grid = |n: usize| {
        let values: Vec<String> = (0..n).map(|k| format!("{}e-6", 400 + k)).collect();
        let rates: Vec<String> = (0..n).map(|k| format!("{}.0", 400 + k)).collect();
        format!(
            "scene = \"slider-crank\"\nmetrics = [\"response.dissipated_per_cycle_j\"]\n\
             [[vary]]\npath = \"clearance_joints.rod-slider.clearance\"\nvalues = [{}]\n\
             [[vary]]\npath = \"drivers.crank-speed.law.rate\"\nvalues = [{}]\n",
            values.join(", "),
            rates.join(", ")
        )
    };
    let refused = |text: &str, field: &str| {
        let started = Instant::now();
        match Sweep::from_str(text, "huge") {
            Err(e @ SweepError::Field { .. }) => {
                let msg = e.to_string();
                assert!(msg.contains(field), "{msg}");
                assert!(started.elapsed() < Duration::from_secs(10), "{msg}");
            }
            Err(e) => panic!("not a field error: {e}"),
            Ok(s) => panic!("accepted with {} samples", s.samples()),
        }
    };
    refused(
        &RANDOM.replace("samples = 6", "samples = 1000000000000"),
        "samples",
    );
    refused(
        &RANDOM.replace("samples = 6", &format!("samples = {}", MAX_SAMPLES + 1)),
        "samples",
    );
    refused(&grid(1001), "vary[1].values");
    let s = Sweep::from_str(&grid(1000), "huge").unwrap();
    assert_eq!(s.samples(), MAX_SAMPLES);
    let (todo, kept) = sweep::pending(&s, Path::new("/nonexistent/sweep-fuzz"), true).unwrap();
    assert_eq!((todo.len(), kept.len()), (MAX_SAMPLES, 0));
    assert_eq!(s.input_values(MAX_SAMPLES - 1), vec![1399e-6, 1399.0]);
}

/// Door 1's special files: a sweep file that is a link to `/dev/zero`, a FIFO fed without end,
/// a directory or a sparse terabyte is refused at once (by size or kind), never read without
/// bound; a FIFO that delivers a real sweep file (`wearsim sweep <(…)`) is read.
#[cfg(unix)]
#[test]
fn special_sweep_files_are_refused_at_once() {
    use std::io::Write;
    let dir = scratch("special-files");
    let refused = |path: PathBuf, what: &str| {
        let p = path.clone();
        let r = within(
            10,
            what,
            || {},
            move || Sweep::from_path(&p).map(|s| s.samples()),
        );
        match r {
            Err(e) => {
                let msg = e.to_string();
                assert!(msg.contains(&path.display().to_string()), "{what}: {msg}");
                eprintln!("special sweep file, {what}: refused: {msg}");
            }
            Ok(n) => panic!("{what}: accepted ({n} samples)"),
        }
    };

    let zero = dir.join("zero.toml");
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    refused(zero, "link to /dev/zero");

    let folder = dir.join("folder.toml");
    std::fs::create_dir(&folder).unwrap();
    refused(folder, "directory");

    let sparse = dir.join("sparse.toml");
    let f = std::fs::File::create(&sparse).unwrap();
    if f.set_len(1 << 40).is_ok() {
        refused(sparse.clone(), "sparse 1 TiB file");
    }
    drop(f);
    let _ = std::fs::remove_file(&sparse);

    // A FIFO fed by a writer that never stops: refused by size. The writer stops when the
    // reader closes its end (a broken pipe).
    let endless = dir.join("endless.toml");
    mkfifo(&endless);
    let e = endless.clone();
    let writer = std::thread::spawn(move || {
        if let Ok(mut w) = std::fs::OpenOptions::new().write(true).open(&e) {
            let line = b"# a comment that never ends\n".repeat(1024);
            while w.write_all(&line).is_ok() {}
        }
    });
    refused(endless, "FIFO fed without end");
    writer.join().unwrap();

    // A FIFO that delivers a real sweep file is read (process substitution).
    let piped = dir.join("piped.toml");
    mkfifo(&piped);
    let p = piped.clone();
    let writer = std::thread::spawn(move || {
        let mut w = std::fs::OpenOptions::new().write(true).open(&p).unwrap();
        w.write_all(GRID.as_bytes()).unwrap();
    });
    let p = piped.clone();
    let n = within(
        30,
        "FIFO delivering a sweep",
        || release_fifo(&piped),
        move || Sweep::from_path(&p).map(|s| s.samples()),
    );
    writer.join().unwrap();
    assert_eq!(n.unwrap(), 6);
    let _ = std::fs::remove_dir_all(&dir);
}
