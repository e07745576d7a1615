//! Fuzzing the worn-surface door (`wearsim run --surfaces DIR`): mutants of a valid wear file
//! (cells' numbers replaced by NaN, ±inf, 1e300, negatives or garbage; rows deleted, duplicated
//! or swapped; angles shifted; columns dropped or added; the header changed; random bytes
//! flipped; the text truncated; an empty or binary file) go through
//! `output::surfaces::load_last_stage`. None may panic; a refusal names the file; an
//! accepted file gives surfaces whose every depth is finite, non-negative and leaves each
//! surface a radius, equal to the file's numbers row by row (so shuffled rows can never be
//! accepted as another surface). The seed is fixed: every CI run sees the same mutants. Run
//! with `--nocapture` for the counts.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sim::build::unworn_joints;

const CELLS: usize = 1000;

fn good_text() -> String {
    let mut text = String::from("angle [deg],bearing_depth [m],pin_depth [m]\n");
    for k in 0..CELLS {
        let angle = (k as f64 + 0.5) * 360.0 / CELLS as f64;
        let bump = |c: f64| 2e-5 * (-((angle - c) / 20.0).powi(2)).exp();
        text.push_str(&format!("{angle},{:e},{:e}\n", bump(181.0), bump(172.0)));
    }
    text
}

/// One mutant of `text` (a valid wear file) drawn from `rng`; its kind for the counts.
fn mutate(text: &str, rng: &mut ChaCha8Rng) -> (Vec<u8>, &'static str) {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let row = rng.random_range(1..lines.len());
    let kind = rng.random_range(0..11);
    let odd = [
        "NaN", "inf", "-inf", "1e300", "-1e-6", "abc", "", "0x10", "1e-320", "0.2",
    ];
    match kind {
        0 => {
            let column = rng.random_range(0..3);
            let mut cells: Vec<String> = lines[row].split(',').map(str::to_string).collect();
            cells[column] = odd[rng.random_range(0..odd.len())].to_string();
            lines[row] = cells.join(",");
        }
        1 => {
            lines.remove(row);
        }
        2 => {
            let copy = lines[row].clone();
            lines.insert(row, copy);
        }
        3 => {
            let other = rng.random_range(1..lines.len());
            lines.swap(row, other);
        }
        4 => {
            let shift = [360.0, 720.0, -360.0, 0.5, 1e-3][rng.random_range(0..5)];
            for line in lines.iter_mut().skip(1) {
                if let Some((angle, rest)) = line.split_once(',') {
                    let angle: f64 = angle.parse().unwrap_or(0.0);
                    *line = format!("{},{rest}", angle + shift);
                }
            }
        }
        5 => {
            lines[row] = lines[row]
                .rsplit_once(',')
                .map_or(String::new(), |(a, _)| a.into());
        }
        6 => lines[row].push_str(",1e-6"),
        7 => lines[0] = ["angle,bearing,pin", "", "a,b,c,d"][rng.random_range(0..3)].into(),
        8 => {
            let mut bytes = (lines.join("\n") + "\n").into_bytes();
            for _ in 0..rng.random_range(1..8) {
                let at = rng.random_range(0..bytes.len());
                bytes[at] = rng.random();
            }
            return (bytes, "bytes flipped");
        }
        9 => {
            let bytes = (lines.join("\n") + "\n").into_bytes();
            let cut = rng.random_range(0..bytes.len());
            return (bytes[..cut].to_vec(), "truncated");
        }
        _ => {
            let garbage: Vec<u8> = (0..rng.random_range(0..4096))
                .map(|_| rng.random())
                .collect();
            return (garbage, "binary");
        }
    }
    let name = [
        "number replaced",
        "row deleted",
        "row duplicated",
        "rows swapped",
        "angles shifted",
        "column dropped",
        "column added",
        "header changed",
    ][kind];
    (format!("{}\n", lines.join("\n")).into_bytes(), name)
}

/// The depths a file's rows give, when they parse (to compare with what was loaded).
fn parsed_depths(bytes: &[u8]) -> Option<Vec<(f64, f64)>> {
    let text = std::str::from_utf8(bytes).ok()?;
    text.lines()
        .skip(1)
        .map(|l| {
            let cells: Vec<f64> = l
                .split(',')
                .map(|c| c.trim().parse().ok())
                .collect::<Option<_>>()?;
            (cells.len() == 3).then(|| (cells[1], cells[2]))
        })
        .collect()
}

#[test]
fn fuzzed_wear_files_are_loaded_exactly_or_refused_by_name() {
    let dir = std::env::temp_dir().join(format!("wornjoint-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp folder");
    let scene = lgres::scenes::builtin("lgres").expect("built-in");
    let unworn = unworn_joints(&scene).expect("joints");
    let good = good_text();
    std::fs::write(dir.join("wear_A_stage1.csv"), &good).expect("writes");
    let file = dir.join("wear_B_stage1.csv");
    let mut rng = ChaCha8Rng::seed_from_u64(22);
    let (mut accepted, mut refused) = (0, 0);
    let mut kinds: std::collections::BTreeMap<&str, [u32; 2]> = Default::default();
    for _ in 0..400 {
        let (bytes, kind) = mutate(&good, &mut rng);
        std::fs::write(&file, &bytes).expect("writes");
        let loaded = output::surfaces::load_last_stage(&dir, &scene, &unworn);
        let count = kinds.entry(kind).or_default();
        match loaded {
            Ok(joints) => {
                accepted += 1;
                count[0] += 1;
                check_accepted(&joints[1], &bytes, kind);
            }
            Err(e) => {
                refused += 1;
                count[1] += 1;
                assert!(e.to_string().contains("wear_B_stage1.csv"), "{kind}: {e}");
            }
        }
    }
    eprintln!(
        "wear-file mutants: {accepted} accepted, {refused} refused; by kind [accepted, refused]: {kinds:?}"
    );
    assert!(refused > 200, "the mutants are mostly invalid");
    std::fs::remove_dir_all(&dir).ok();
}

/// An accepted mutant: every depth finite, ≥ 0 and leaving a radius, and the surfaces equal to
/// the file's rows in order.
fn check_accepted(joint: &Option<wear::WornJoint>, bytes: &[u8], kind: &str) {
    let joint = joint.as_ref().expect("B wears");
    let rows = parsed_depths(bytes).unwrap_or_else(|| panic!("{kind}: accepted but unparsable"));
    let (bearing, pin) = (joint.bearing(), joint.pin());
    assert_eq!(rows.len(), bearing.cells(), "{kind}");
    for (k, (b, p)) in rows.iter().enumerate() {
        assert_eq!(
            (bearing.depth()[k], pin.depth()[k]),
            (*b, *p),
            "{kind}: row {k}"
        );
        for (h, radius) in [(b, bearing.nominal_radius()), (p, pin.nominal_radius())] {
            assert!(
                h.is_finite() && *h >= 0.0 && *h < 2.0 * radius,
                "{kind}: {h}"
            );
        }
    }
}

/// Names that only look like a stage's wear file, by kind (a sign, leading zeros, another case,
/// a suffix, spaces, other digits): none is read as a stage. Beside `wear_A_stage1.csv` and
/// `wear_B_stage1.csv`, stage 1 loads; a run named them as stage 2 and then failed reading
/// `wear_A_stage2.csv`, a file that does not exist. A scene with no joint that wears refuses
/// the folder instead of ignoring it.
#[test]
fn only_the_names_a_run_writes_are_stage_files() {
    let dir = std::env::temp_dir().join(format!("wornjoint-names-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp folder");
    let scene = lgres::scenes::builtin("lgres").expect("built-in");
    let unworn = unworn_joints(&scene).expect("joints");
    let good = good_text();
    for joint in ["A", "B"] {
        std::fs::write(dir.join(format!("wear_{joint}_stage1.csv")), &good).expect("writes");
    }
    let stage1 = output::surfaces::load_last_stage(&dir, &scene, &unworn).expect("stage 1");
    for stray in [
        "+2",
        "02",
        "002",
        "+02",
        " 2",
        "2 ",
        "٢",
        "2.0",
        "2e0",
        "0x2",
        "-2",
        "4294967298",
    ] {
        let name = format!("wear_A_stage{stray}.csv");
        std::fs::write(dir.join(&name), "not a wear file").expect("writes");
        let loaded = output::surfaces::load_last_stage(&dir, &scene, &unworn)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        for (a, b) in loaded.iter().zip(&stage1) {
            let (a, b) = (a.as_ref().expect("wears"), b.as_ref().expect("wears"));
            assert_eq!(a.bearing().depth(), b.bearing().depth(), "{name}");
            assert_eq!(a.pin().depth(), b.pin().depth(), "{name}");
        }
        std::fs::remove_file(dir.join(&name)).expect("removes");
    }
    // The name a run writes is read: stage 2 here (a file of no wear grid, refused by name).
    std::fs::write(dir.join("wear_A_stage2.csv"), "not a wear file").expect("writes");
    let e = output::surfaces::load_last_stage(&dir, &scene, &unworn).expect_err("stage 2 read");
    assert!(e.to_string().contains("wear_A_stage2.csv"), "{e}");
    for name in ["slider-crank", "lgres-ideal"] {
        let scene = lgres::scenes::builtin(name).expect("built-in");
        let unworn = unworn_joints(&scene).expect("joints");
        let e = output::surfaces::load_last_stage(&dir, &scene, &unworn).expect_err(name);
        assert!(
            e.to_string().contains("no clearance joint with wear"),
            "{name}: {e}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
