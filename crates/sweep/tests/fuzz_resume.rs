//! Fuzzing of the sweep crate's second input door, resume tables, with fixed seeds (every run
//! sees the same cases). Nothing is simulated. (The first door, sweep files, is
//! `fuzz_files.rs`.)
//!
//! A `samples.csv` written by [`sweep::table::write_rows`] (ok, failed and missing-metric rows)
//! and the shipped `docs/sweep/wear-ab/samples.csv` are mutated — rows lost, repeated, swapped;
//! cells NaN, inf, empty, garbage, huge; columns lost or added; header edited; binary garbage;
//! truncation — and read by [`sweep::pending`] with resume. A refusal must name where; every
//! row kept must be one this sweep could have written.
//!
//! Special files (a FIFO, a link to `/dev/zero`, a directory, a sparse terabyte) must be
//! answered at once, never blocked on or read without bound.
//!
//! Run with `--nocapture` to see the counts.

use std::cell::RefCell;
use std::path::Path;
use std::time::Instant;

use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

use sweep::{Row, Status, Sweep, SweepError};

mod common;
use common::{Counts, Mutation, RANDOM, fuzz_door, mutation, repo, runner, scratch, within};
#[cfg(unix)]
use common::{mkfifo, release_fifo};

/// A table to mutate: its sweep and a valid `samples.csv` of it.
struct Table {
    sweep: Sweep,
    text: String,
}

/// A small random sweep's table written by [`sweep::table::write_rows`]: `ok` rows (one with
/// a metric the summary has no number for), `failed` rows with an error, and one `ok` row
/// with a NaN metric (written as failed, naming it).
fn written_table(dir: &Path) -> Table {
    let sweep = Sweep::from_str(RANDOM, "fuzz").unwrap();
    let mut rows: Vec<Row> = (0..sweep.samples())
        .map(|k| {
            let failed = k % 3 == 2;
            Row {
                sample: k,
                inputs: sweep.input_values(k),
                metrics: if failed {
                    vec![None, None]
                } else {
                    vec![
                        Some(1.25e-5 * (k + 1) as f64),
                        (k != 1).then_some(0.5 + k as f64),
                    ]
                },
                status: if failed { Status::Failed } else { Status::Ok },
                error: if failed {
                    "clearance_joints[0].clearance: must be positive".into()
                } else {
                    String::new()
                },
                wall_time_s: 0.25 * k as f64,
            }
        })
        .collect();
    rows[3].metrics[0] = Some(f64::NAN);
    let path = dir.join("written.csv");
    sweep::table::write_rows(&sweep, &rows, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains(",ok,") && text.contains(",failed,"), "{text}");
    Table { sweep, text }
}

/// The shipped sweep and the rows a real run of it wrote, given this sweep's `settings`
/// column (the shipped file was written before rows recorded it, and with an earlier base
/// scene, so as shipped it is refused: [`shipped_rows_of_other_settings_are_refused`]).
fn shipped_table() -> Table {
    let sweep = Sweep::from_path(&repo().join("docs/sweep/wear-ab.toml")).unwrap();
    let text = std::fs::read_to_string(repo().join("docs/sweep/wear-ab/samples.csv")).unwrap();
    let settings = sweep.settings_id();
    let text = text
        .lines()
        .enumerate()
        .map(|(k, line)| {
            let (before, wall) = line.rsplit_once(',').unwrap();
            let cell = if k == 0 { "settings" } else { &settings };
            format!("{before},{cell},{wall}\n")
        })
        .collect();
    Table { sweep, text }
}

/// The shipped rows as they are (no `settings` column, an earlier base scene) are not resumed.
#[test]
fn shipped_rows_of_other_settings_are_refused() {
    let dir = scratch("shipped");
    let sweep = Sweep::from_path(&repo().join("docs/sweep/wear-ab.toml")).unwrap();
    std::fs::copy(
        repo().join("docs/sweep/wear-ab/samples.csv"),
        sweep::rows_path(&dir),
    )
    .unwrap();
    let e = sweep::pending(&sweep, &dir, true).unwrap_err();
    assert!(e.to_string().contains("columns"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Cell values a mutant may hold.
fn odd_cell(param: u8) -> String {
    match param % 22 {
        0 => "NaN".into(),
        1 => "nan".into(),
        2 => "inf".into(),
        3 => "-inf".into(),
        4 => "infinity".into(),
        5 => String::new(),
        6 => "garbage".into(),
        7 => "1e999".into(),
        8 => "-1e999".into(),
        9 => "1e300".into(),
        10 => "9".repeat(400),
        11 => "-0".into(),
        12 => "0x1p3".into(),
        13 => " 1".into(),
        14 => "\"1\"".into(),
        15 => "ok".into(),
        16 => "failed".into(),
        17 => "OK".into(),
        18 => "18446744073709551616".into(),
        19 => "-1".into(),
        20 => "1.5".into(),
        _ => "\u{0}\u{fffd}".into(),
    }
}

/// One mutation of a table's text.
fn mutate_table(text: &mut String, m: Mutation) {
    let mut lines: Vec<String> = text.split('\n').map(String::from).collect();
    // The last element is "" when the text ends in a newline: rows are 1..rows_end.
    let rows_end = if lines.last().is_some_and(String::is_empty) {
        lines.len() - 1
    } else {
        lines.len()
    };
    let row = |offset: usize| 1 + (m.pick / (offset + 1)) % (rows_end.max(2) - 1);
    let cell_count = lines[0].split(',').count();
    let col = (m.pick / 7) % cell_count;
    let set_cells = |line: &mut String, f: &dyn Fn(&mut Vec<String>)| {
        let mut cells: Vec<String> = line.split(',').map(String::from).collect();
        f(&mut cells);
        *line = cells.join(",");
    };
    match m.kind % 12 {
        // Lose, repeat or swap rows.
        0 if rows_end > 1 => {
            lines.remove(row(0));
        }
        1 if rows_end > 1 => {
            let copy = lines[row(0)].clone();
            lines.insert(row(1), copy);
        }
        2 if rows_end > 2 => {
            let (a, b) = (row(0), row(1));
            lines.swap(a, b);
        }
        // An odd value in one cell (the header's too).
        3 => {
            let k = if m.param.is_multiple_of(5) {
                0
            } else {
                row(0).min(lines.len() - 1)
            };
            let v = odd_cell(m.param / 5);
            set_cells(&mut lines[k], &|c| {
                if col < c.len() {
                    c[col] = v.clone();
                }
            });
        }
        // Lose a column: everywhere or in one row.
        4 => {
            let one = (m.param % 2 == 1).then(|| row(0));
            for (k, line) in lines.iter_mut().enumerate().take(rows_end) {
                if one.is_none_or(|r| r == k) {
                    set_cells(line, &|c| {
                        if col < c.len() {
                            c.remove(col);
                        }
                    });
                }
            }
        }
        // Gain a column: everywhere or in one row.
        5 => {
            let one = (m.param % 2 == 1).then(|| row(0));
            for (k, line) in lines.iter_mut().enumerate().take(rows_end) {
                if one.is_none_or(|r| r == k) {
                    let v = if k == 0 {
                        "extra".into()
                    } else {
                        odd_cell(m.param / 2)
                    };
                    set_cells(line, &|c| c.insert(col.min(c.len()), v.clone()));
                }
            }
        }
        // Header edits: a renamed column, two swapped, the header gone.
        6 => match m.param % 3 {
            0 => set_cells(&mut lines[0], &|c| c[col].push('x')),
            1 => set_cells(&mut lines[0], &|c| {
                let other = (col + 1) % c.len();
                c.swap(col, other);
            }),
            _ => {
                lines.remove(0);
            }
        },
        // Garbage at some byte: NUL and replacement characters, stray quotes, empty rows
        // (bytes that are not UTF-8 are the raw splice of [`TableCase`]).
        7 => {
            let mut joined = lines.join("\n");
            let at = (0..=m.pick % (joined.len() + 1))
                .rev()
                .find(|c| joined.is_char_boundary(*c))
                .unwrap_or(0);
            let garbage = ["\u{0}\u{fffd}\u{feff}", "\"", "\r\n\"\",,\n", "\n\n"];
            joined.insert_str(at, garbage[usize::from(m.param) % garbage.len()]);
            *text = joined;
            return;
        }
        // Truncation: within the last line, or anywhere.
        8 => {
            let joined = lines.join("\n");
            let last_start = joined
                .trim_end_matches('\n')
                .rfind('\n')
                .map_or(0, |i| i + 1);
            let end = joined.trim_end_matches('\n').len();
            let cut = if m.param.is_multiple_of(2) {
                last_start + m.pick % (end - last_start + 1)
            } else {
                m.pick % (joined.len() + 1)
            };
            let cut = (0..=cut)
                .rev()
                .find(|c| joined.is_char_boundary(*c))
                .unwrap_or(0);
            *text = joined[..cut].to_string();
            return;
        }
        // A byte flipped (kept as text: invalid UTF-8 is the binary case's).
        9 => {
            let mut bytes = lines.join("\n").into_bytes();
            if !bytes.is_empty() {
                let at = m.pick % bytes.len();
                bytes[at] ^= m.param | 1;
            }
            *text = String::from_utf8_lossy(&bytes).into_owned();
            return;
        }
        // Whole-file edits: CRLF, a byte-order mark, empty, header only, a row 1000 times.
        10 => match m.param % 5 {
            0 => {
                *text = lines.join("\r\n");
                return;
            }
            1 => lines[0].insert(0, '\u{feff}'),
            2 => lines.clear(),
            3 => lines.truncate(1),
            _ if rows_end > 1 => {
                let copy = lines[row(0)].clone();
                for _ in 0..1000 {
                    lines.insert(1, copy.clone());
                }
            }
            _ => {}
        },
        // Status flipped, or a failed row given a non-finite metric.
        _ if rows_end > 1 => {
            let k = row(0);
            let metric = odd_cell(m.param % 5);
            set_cells(&mut lines[k], &|c| {
                let n = c.len();
                if n < 4 {
                    return;
                }
                match c[n - 3].as_str() {
                    "ok" => c[n - 3] = "failed".into(),
                    "failed" if n > 5 => c[n - 5] = metric.clone(),
                    _ => c[n - 3] = "ok".into(),
                }
            });
        }
        _ => {}
    }
    *text = lines.join("\n");
}

/// A resume case: which table, its text mutations, and raw bytes to splice in (binary garbage
/// that is not UTF-8 survives only as bytes).
#[derive(Debug, Clone)]
struct TableCase {
    table: usize,
    mutations: Vec<Mutation>,
    raw: Option<(usize, u8)>,
}

/// What the kept rows of a resumed sweep must be: each one this sweep could have written for
/// a finished sample — a sample of the sweep, at most once, with that sample's inputs, the
/// sweep's column counts, every metric finite (an `ok` row with a NaN is no result, a failed
/// row's metrics are no result either) — and unchanged by the trip to a Dask worker as JSON
/// (`Row::to_json` / `from_json`); the samples to run are exactly the others.
fn check_resumed(s: &Sweep, todo: &[usize], kept: &[Row]) -> Result<(), TestCaseError> {
    let n = s.samples();
    let mut seen = vec![false; n];
    for r in kept {
        prop_assert!(r.sample < n, "kept sample {} of {}", r.sample, n);
        prop_assert!(!seen[r.sample], "sample {} kept twice", r.sample);
        seen[r.sample] = true;
        prop_assert_eq!(&r.inputs, &s.input_values(r.sample));
        prop_assert_eq!(r.metrics.len(), s.metrics.len());
        prop_assert!(
            r.metrics.iter().flatten().all(|m| m.is_finite()),
            "kept row with a non-finite metric: {:?}",
            r
        );
        let back = Row::from_json(&r.to_json());
        prop_assert!(
            back.as_ref().is_ok_and(|b| b == r),
            "kept row changes on its JSON trip: {:?} -> {:?}",
            r,
            back
        );
    }
    let expected: Vec<usize> = (0..n).filter(|k| !seen[*k]).collect();
    prop_assert_eq!(todo, &expected[..]);
    Ok(())
}

/// What a refusal to resume says, and the kind it is counted as (the first that matches).
const REFUSAL_KINDS: [(&str, &str); 10] = [
    ("columns", "header is not this sweep's"),
    ("other settings", "settings changed"),
    ("is not a number", "a cell is not a number"),
    ("not a duration", "wall time not a duration"),
    ("is beyond the sweep", "sample beyond the sweep"),
    ("inputs are not this sweep's", "inputs changed"),
    ("neither ok nor failed", "bad status"),
    ("twice", "sample twice"),
    ("fields", "row of another width (csv)"),
    ("UTF-8", "not UTF-8 (csv)"),
];

/// The kind of a refusal to resume, which must name the file and say where (a row, a line, a
/// column, the header).
fn resume_refusal(e: &SweepError, path: &Path) -> Result<String, String> {
    let msg = e.to_string();
    let SweepError::Resume { reason, .. } = e else {
        return Err(format!("not a resume error: {e:?}"));
    };
    if !msg.contains(&path.display().to_string()) {
        return Err(format!("does not name the file: {msg}"));
    }
    let kind = REFUSAL_KINDS
        .iter()
        .find(|(says, _)| reason.contains(*says))
        .map_or("other", |&(_, kind)| kind);
    let where_ = ["row ", "line", "column", "record", "header"];
    if !where_.iter().any(|w| reason.contains(w)) {
        return Err(format!("does not say where: {msg}"));
    }
    Ok(format!("refused: {kind}"))
}

fn fuzz_resume(cases: u32, seed: u8) -> Counts {
    let dir = scratch("resume");
    let tables = [written_table(&dir), shipped_table()];
    // The unmutated tables resume, keeping their finished rows.
    for t in &tables {
        let out = dir.join("plain");
        std::fs::create_dir_all(&out).unwrap();
        std::fs::write(sweep::rows_path(&out), &t.text).unwrap();
        let (todo, kept) = sweep::pending(&t.sweep, &out, true).unwrap();
        assert!(!kept.is_empty(), "{}", t.text);
        check_resumed(&t.sweep, &todo, &kept).unwrap();
    }
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let path = sweep::rows_path(&out);
    let strategy = (
        0..tables.len(),
        prop::collection::vec(mutation(), 1..4),
        prop::option::weighted(0.1, (any::<usize>(), any::<u8>())),
    )
        .prop_map(|(table, mutations, raw)| TableCase {
            table,
            mutations,
            raw,
        });
    let counts = RefCell::new(Counts::default());
    let result = runner(cases, seed).run(&strategy, |case| {
        let t = &tables[case.table];
        let mut text = t.text.clone();
        for m in &case.mutations {
            mutate_table(&mut text, *m);
        }
        let mut bytes = text.into_bytes();
        if let Some((at, b)) = case.raw {
            let at = at % (bytes.len() + 1);
            bytes.splice(at..at, [0xff, b, 0x80]);
        }
        std::fs::write(&path, &bytes).unwrap();
        let kind = match sweep::pending(&t.sweep, &out, true) {
            Ok((todo, kept)) => {
                check_resumed(&t.sweep, &todo, &kept)?;
                format!(
                    "accepted ({})",
                    ["written table", "shipped table"][case.table]
                )
            }
            Err(e) => resume_refusal(&e, &path).map_err(TestCaseError::fail)?,
        };
        counts.borrow_mut().add(kind);
        Ok(())
    });
    let _ = std::fs::remove_dir_all(&dir);
    if let Err(e) = result {
        panic!("resume tables: {e}");
    }
    counts.into_inner()
}

/// Door 2: no mutant panics, every refusal names the file and where in it, every row kept is
/// one this sweep could have written.
#[test]
fn fuzzed_resume_tables_are_refused_by_row_or_keep_only_finished_rows() {
    // Every kind is "accepted (…)" or "refused: …".
    fuzz_door(
        "resume tables",
        || fuzz_resume(8000, 43),
        &[
            "refused: sample twice",
            "refused: a cell is not a number",
            "refused: wall time not a duration",
        ],
    );
}

/// Door 2's special files: `samples.csv` as a FIFO (no writer), a link to `/dev/zero`, a
/// directory, a dangling link or a sparse terabyte is refused at once as not a regular file
/// or too large, when resuming; a link to a real rows file is followed. Without resume the
/// file is not looked at.
#[cfg(unix)]
#[test]
fn special_resume_files_are_refused_at_once() {
    let dir = scratch("special-resume");
    let t = written_table(&dir);
    let real = dir.join("real.csv");
    std::fs::write(&real, &t.text).unwrap();
    let case = |name: &str, make: &dyn Fn(&Path)| {
        let out = dir.join(name);
        std::fs::create_dir_all(&out).unwrap();
        let path = sweep::rows_path(&out);
        make(&path);
        let s = t.sweep.clone();
        let o = out.clone();
        let fifo = path.clone();
        let started = Instant::now();
        let r = within(
            10,
            name,
            || release_fifo(&fifo),
            move || sweep::pending(&s, &o, true).map(|(todo, kept)| (todo.len(), kept.len())),
        );
        let secs = started.elapsed().as_secs_f64();
        // Without resume nothing is read: every sample is to run.
        let (todo, kept) = sweep::pending(&t.sweep, &out, false).unwrap();
        assert_eq!((todo.len(), kept.len()), (t.sweep.samples(), 0));
        (r, path, secs)
    };
    let refused = |name: &str, make: &dyn Fn(&Path), why: &str| {
        let (r, path, secs) = case(name, make);
        match r {
            Err(e @ SweepError::Resume { .. }) => {
                let msg = e.to_string();
                assert!(
                    msg.contains(&path.display().to_string()) && msg.contains(why),
                    "{name}: {msg}"
                );
                eprintln!("special samples.csv, {name}: refused in {secs:.3} s: {msg}");
            }
            Err(e) => panic!("{name}: not a resume error: {e}"),
            Ok(counts) => panic!("{name}: accepted as (to run, kept) = {counts:?}"),
        }
    };
    refused("fifo", &|p| mkfifo(p), "not a regular file");
    refused(
        "dev-zero",
        &|p| std::os::unix::fs::symlink("/dev/zero", p).unwrap(),
        "not a regular file",
    );
    refused(
        "directory",
        &|p| std::fs::create_dir(p).unwrap(),
        "not a regular file",
    );
    refused(
        "dangling-link",
        &|p| std::os::unix::fs::symlink(dir.join("nothing-here.csv"), p).unwrap(),
        "cannot read",
    );
    let sparse_ok = std::fs::File::create(dir.join("probe"))
        .and_then(|f| f.set_len(1 << 40))
        .is_ok();
    let _ = std::fs::remove_file(dir.join("probe"));
    if sparse_ok {
        refused(
            "sparse-terabyte",
            &|p| {
                std::fs::File::create(p).unwrap().set_len(1 << 40).unwrap();
            },
            "too large",
        );
    }
    // A link to a real rows file is a rows file.
    let (r, _, _) = case("link-to-real", &|p| {
        std::os::unix::fs::symlink(&real, p).unwrap()
    });
    let (todo, kept) = r.unwrap();
    assert!(
        kept > 0 && todo + kept == t.sweep.samples(),
        "{todo} {kept}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
