//! The study machinery on tiny runs (1 response cycle, K = 1, a stage standing for 1e4 cycles
//! so one adaptive sub-step suffices), and the trend judge on numbers with known answers.

use analysis::study::judge::{Comparison, Verdict, judge_increase, judge_trend};
use analysis::study::{self, StudyOptions};

/// A comparison's low, high and noise.
type Lhn = (f64, f64, f64);

fn c(low: f64, high: f64, noise: f64) -> Comparison {
    Comparison {
        quantity: "q".into(),
        low,
        high,
        noise,
    }
}

#[test]
fn judge_known_answers() {
    assert_eq!(judge_increase(1.0, 2.0, 0.0), Verdict::Holds);
    assert_eq!(judge_increase(2.0, 1.0, 0.0), Verdict::DoesNotHold);
    // Within the 5 % margin, or within the noise.
    assert_eq!(judge_increase(1.0, 1.02, 0.0), Verdict::Inconclusive);
    assert_eq!(judge_increase(10.0, 12.0, 3.0), Verdict::Inconclusive);
    assert_eq!(judge_increase(10.0, 14.0, 3.0), Verdict::Holds);
    assert_eq!(judge_increase(f64::NAN, 1.0, 0.0), Verdict::Inconclusive);

    // (low, high, noise) of each comparison, and the trend's verdict.
    let trends: [(&[Lhn], Verdict); 7] = [
        (&[(1.0, 2.0, 0.0), (3.0, 5.0, 0.0)], Verdict::Holds),
        // Most grow, one ties: still holds; one of three shrinks: holds in part.
        (
            &[(1.0, 2.0, 0.0), (3.0, 5.0, 0.0), (1.0, 1.0, 0.0)],
            Verdict::Holds,
        ),
        (
            &[(1.0, 2.0, 0.0), (3.0, 5.0, 0.0), (2.0, 1.0, 0.0)],
            Verdict::HoldsInPart,
        ),
        // As many against as with: does not hold; all against: does not hold.
        (&[(1.0, 2.0, 0.0), (2.0, 1.0, 0.0)], Verdict::DoesNotHold),
        (&[(2.0, 1.0, 0.0), (5.0, 3.0, 0.0)], Verdict::DoesNotHold),
        // Half or more within noise: the noise decides, whatever moved.
        (&[(1.0, 2.0, 0.0), (1.0, 1.01, 0.0)], Verdict::Inconclusive),
        (
            &[(1.0, 2.0, 0.0), (10.0, 14.0, 5.0), (1.0, 1.0, 0.0)],
            Verdict::Inconclusive,
        ),
    ];
    for (comparisons, verdict) in trends {
        let comparisons: Vec<Comparison> =
            comparisons.iter().map(|&(l, h, n)| c(l, h, n)).collect();
        assert_eq!(judge_trend(&comparisons), verdict, "{comparisons:?}");
    }
    assert_eq!(judge_trend(&[]), Verdict::Inconclusive);
}

#[test]
fn bad_names_and_options_are_bad_input() {
    let e = study::resolve("nope").unwrap_err();
    assert!(e.is_bad_input());
    assert!(e.to_string().contains("extrapolation"));
    // Every study of the list, and the extrapolation study.
    assert_eq!(
        study::resolve(study::ALL).map(|s| s.len()).ok(),
        Some(lgres::studies::STUDIES.len() + 1)
    );
    // Every name offered resolves, `all` last.
    let choices = study::choices();
    assert_eq!(choices.last().map(|c| c.name), Some(study::ALL));
    for c in &choices {
        assert!(study::resolve(c.name).is_ok(), "{}", c.name);
        assert!(!c.summary.is_empty(), "{}", c.name);
    }

    let dir = std::env::temp_dir().join(format!("lgres-study-bad-{}", std::process::id()));
    let mut o = StudyOptions::new(&dir);
    o.cycles_per_stage = 0;
    let studies = study::resolve("clearance").expect("known study");
    let e = study::run_studies(&studies, &o, &()).unwrap_err();
    assert!(e.is_bad_input(), "{e}");
    assert!(!dir.join("report.md").exists());
}

/// Options of a tiny study writing to a fresh temporary folder named after `name`.
fn tiny_options(name: &str) -> StudyOptions {
    let dir = std::env::temp_dir().join(format!("lgres-study-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut o = StudyOptions::new(&dir);
    o.cycles_per_stage = 1;
    o.response_cycles = 1;
    o.cycles_represented = Some(1e4);
    o
}

#[test]
fn tiny_study_writes_a_report_listing_every_scene() {
    let o = tiny_options("report");
    let dir = o.out.clone();
    let studies = study::resolve("clearance").expect("known study");
    let mut studies = studies;
    studies.extend(study::resolve("extrapolation").expect("known study"));
    let (results, path) = study::run_studies(&studies, &o, &()).expect("study runs");
    // lgres is shared by both studies and run once.
    let keys: Vec<&str> = results.runs.iter().map(|r| r.key.as_str()).collect();
    assert_eq!(
        keys,
        [
            "lgres-c02",
            "lgres",
            lgres::studies::EXTRAPOLATION.single_jump_run
        ]
    );
    let md = std::fs::read_to_string(&path).expect("report written");
    for key in &keys {
        assert!(md.contains(&format!("`{key}`")), "report lists {key}");
        assert!(dir.join(key).join("summary.json").is_file());
    }
    assert!(md.contains("K = 1 simulated cycles per stage"));
    assert!(md.contains("15.86 kN"), "paper values cited");
    assert!(
        ["HOLDS", "HOLDS IN PART", "DOES NOT HOLD", "INCONCLUSIVE"]
            .iter()
            .any(|v| md.contains(&format!("**{v}**")))
    );
    assert!(dir.join("extrapolation_wear_A.png").is_file());
    assert!(dir.join("clearance_wear_B.png").is_file());
    // The same report as a page: the verdict table first, every study figure embedded, a link
    // to each scene's own report (which exists), nothing fetched from the network.
    let page = std::fs::read_to_string(dir.join("report.html")).expect("report.html written");
    let verdicts = page.find("<h2>Verdicts</h2>").expect("verdict heading");
    assert!(verdicts < page.find("<h2>Study").expect("a study section"));
    assert!(page[verdicts..].contains("<table>"));
    for figure in ["extrapolation_wear_A.png", "clearance_wear_B.png"] {
        let bytes = std::fs::read(dir.join(figure)).unwrap();
        let uri = output::html::data_uri("image/png", &bytes);
        assert!(page.contains(&uri), "{figure} embedded");
    }
    for key in &keys {
        assert!(
            page.contains(&format!("href=\"{key}/report.html\"")),
            "{key} linked"
        );
        assert!(
            dir.join(key).join("report.html").is_file(),
            "{key}/report.html"
        );
    }
    assert!(!page.contains("http://") && !page.contains("https://"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `value` with every `wall_time_s` removed: the only field allowed to differ between runs.
fn without_wall_times(mut value: serde_json::Value) -> serde_json::Value {
    match &mut value {
        serde_json::Value::Object(map) => {
            map.remove("wall_time_s");
            for v in map.values_mut() {
                *v = without_wall_times(std::mem::take(v));
            }
        }
        serde_json::Value::Array(items) => {
            for v in items.iter_mut() {
                *v = without_wall_times(std::mem::take(v));
            }
        }
        _ => {}
    }
    value
}

#[test]
fn parallel_runs_give_the_same_results_as_serial_ones() {
    let studies = study::resolve("clearance").expect("known study");
    let summaries = |jobs: usize| {
        let mut o = tiny_options(&format!("j{jobs}"));
        o.jobs = jobs;
        let (results, _) = study::run_studies(&studies, &o, &()).expect("study runs");
        let _ = std::fs::remove_dir_all(&o.out);
        results
            .runs
            .iter()
            .map(|r| {
                let json = serde_json::to_value(&r.outcome.summary).expect("serialisable");
                (r.key.clone(), without_wall_times(json))
            })
            .collect::<Vec<_>>()
    };
    let serial = summaries(1);
    let parallel = summaries(2);
    assert_eq!(serial.len(), 2, "the clearance study has two scenes");
    // Same runs, in the same order, with bit-identical numbers.
    assert_eq!(serial, parallel);
}
