//! A sweep of lives to a clearance limit: the columns it keeps, the samples' lives combined
//! into one mixture, and its page.

use sweep::{LocalOptions, Status, Sweep};

mod common;
use common::scratch;

/// The worn slider-crank run to 0.6 mm (k_d scatter 0.4), over two clearances.
const BASE: &str = r#"
extends = "slider-crank"
[[clearance_joints]]
name = "rod-slider"
wear = { k_d = 1.8e-13, width = 0.02, cells = 360, k_d_scatter = 0.4 }
[run]
cycles = 1
wear_stages = 1
cycles_per_stage = 2
amplification = 1e5
animation = false
max_clearance_change = 0.02
clearance_limit = 0.0006
until_limit = true
max_cycles = 2e5
"#;

const SWEEP: &str = r#"
scene = "base.toml"
metrics = ["wear.cycles_applied"]
[[vary]]
path = "clearance_joints.rod-slider.clearance"
values = [4.8e-4, 5.2e-4]
"#;

#[test]
fn a_sweeps_lives_combine_into_one_distribution() {
    let dir = scratch("life");
    std::fs::write(dir.join("base.toml"), BASE).unwrap();
    std::fs::write(dir.join("life.toml"), SWEEP).unwrap();
    let s = Sweep::from_path(&dir.join("life.toml")).unwrap();
    // The file's metric, then the joint's cycles to the limit and their noise.
    assert_eq!(
        s.metrics,
        [
            "wear.cycles_applied",
            "wear.joints.rod-slider.clearance_limit.cycles",
            "wear.joints.rod-slider.clearance_limit.cycles_noise"
        ]
    );
    let out = dir.join("out");
    let rows = sweep::run_local(
        &s,
        &out,
        &LocalOptions {
            jobs: 2,
            resume: false,
        },
        None,
        &mut |_, _, _| {},
    )
    .unwrap();
    assert!(rows.iter().all(|r| r.status == Status::Ok), "{rows:?}");
    let cycles: Vec<f64> = rows.iter().map(|r| r.metrics[1].unwrap()).collect();
    // Less wear to the same limit from the larger clearance: a shorter life.
    assert!(cycles[1] < cycles[0], "{cycles:?}");
    let life = sweep::life::combine(&s, &rows).unwrap();
    assert_eq!(life.used, [0, 1]);
    assert!(life.not_reached.is_empty());
    let sampled = life.distributions.unwrap();
    assert_eq!(sampled.curves.len(), 1, "one joint: no mechanism curve");
    let b = sampled.curves[0].lives;
    // The mixture's median lies between the samples' medians, where half of the two
    // lognormals (both s = 0.4) have ended: Φ(ln(m/N0)/s) + Φ(ln(m/N1)/s) = 1.
    assert!(
        b.b50_cycles > cycles[1] && b.b50_cycles < cycles[0],
        "{b:?}"
    );
    let phi = sim::life_distribution::standard_normal_cdf;
    let half =
        phi((b.b50_cycles / cycles[0]).ln() / 0.4) + phi((b.b50_cycles / cycles[1]).ln() / 0.4);
    assert!((half - 1.0).abs() < 1e-9, "{half}");
    // Its noise holds the bootstrap over two samples: at least their spread's scale.
    assert!(
        b.b50_noise.unwrap() > 0.1 * (cycles[0] - cycles[1]),
        "{b:?}"
    );
    // The page says it and shows it.
    let page = std::fs::read_to_string(out.join("samples.html")).unwrap();
    assert!(page.contains("<h2>Life to the clearance limit</h2>"));
    assert!(page.contains("the bootstrap over the 2 samples used"));
    assert!(out.join(sweep::life::LIFE_FILE).is_file());
    std::fs::remove_dir_all(&dir).unwrap();
}
