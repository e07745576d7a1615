//! The `wearsim` binary's runs: what they print and write (transient windows, budgets and
//! penetration ending a run, clearance limits reached, a sweep's rows and its bad fields).

mod common;
use common::{
    assert_exit, lgres_with, listing, run_into, scratch, scratch_out, stderr, wearsim, wearsim_out,
    write_scene,
};

#[test]
fn transient_window_longer_than_the_run_prints_n_a() {
    let dir = scratch("window");
    let scene = write_scene(
        &dir,
        // The benchmark's 5000 rpm overlaps reach 0.45 of the clearance, beyond the foundation's
        // thin-layer limit (its forces would be withheld): the one-point model shows the peaks.
        "extends = \"slider-crank\"\n[run]\ntransient_window = 0.05\n\
         [[clearance_joints]]\nname = \"rod-slider\"\ncontact = { model = \"line-of-centres\" }\n",
    );
    let out = dir.join("out");
    let o = run_into(scene.to_str().unwrap(), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    // Standard error is a pipe here, as in a log: progress comes as whole lines, never as a
    // terminal's redrawn bar.
    let log = stderr(&o);
    assert!(
        log.lines().any(|l| l.starts_with("response: 2 cycle(s)"))
            && log.lines().any(|l| l.starts_with("response: done in"))
            && !log.contains('\r'),
        "{log}"
    );
    assert!(text.contains("n/a after 0.05 s"), "{text}");
    assert!(!text.contains("from 0 cycle"), "{text}");
    // The deviations after the window are not 0.0 µm but not available, in the terminal and
    // in summary.json (null, not 0.0).
    assert!(
        text.contains("vs ideal after 0.05 s: n/a") && !text.contains("0.0 µm"),
        "{text}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let response = &summary["response"];
    assert!(
        response["deviation_after_transient"].is_null(),
        "{response}"
    );
    assert!(response["joints"][0]["normal_force_after_transient"].is_null());
    assert!(
        response["deviation"]["x_m"]
            .as_f64()
            .is_some_and(|x| x > 0.0)
    );
}

#[test]
fn budgets_and_penetration_end_runs_with_exit_1_naming_the_cause() {
    let (dir, out) = scratch_out("budget");
    let o = wearsim_out(&["run", "slider-crank", "--max-steps", "10"], &out);
    assert_exit(&o, 1, "solver.max_steps");
    let o = wearsim(&["check", "slider-crank", "--max-wall-time", "-1"]);
    assert_exit(&o, 2, "solver.max_wall_time");

    let scene = lgres_with(
        &dir,
        "[[clearance_joints]]\nname = \"A\"\n\
         bearing_material = { youngs_modulus = 1e6, poisson_ratio = 0.3 }\n\
         pin_material = { youngs_modulus = 1e6, poisson_ratio = 0.3 }\n\
         [run]\ncycles = 1\nperiod = 0.2\nwear_stages = 0\n",
    );
    let o = run_into(scene.to_str().unwrap(), &out);
    assert_exit(&o, 1, "peak penetration");
    assert_eq!(listing(&dir), ["scene.toml"], "nothing written on failure");
}

#[test]
fn sweep_writes_rows_and_names_bad_fields() {
    let dir = scratch("sweep");
    let file = dir.join("grid.toml");
    let text = r#"
scene = "slider-crank"
metrics = ["response.joints.rod-slider.max_penetration_m"]
[run]
cycles = 1
[[vary]]
path = "clearance_joints.rod-slider.clearance"
values = [5e-4, -1e-4]
"#;
    std::fs::write(&file, text).unwrap();
    let out = dir.join("out");
    let o = wearsim_out(&["sweep", file.to_str().unwrap()], &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = std::fs::read_to_string(out.join("samples.csv")).unwrap();
    let lines: Vec<&str> = rows.lines().collect();
    assert_eq!(lines.len(), 3, "{rows}");
    assert!(
        lines[1].starts_with("0,5e-4,") && lines[1].contains(",ok,"),
        "{rows}"
    );
    assert!(lines[2].contains(",failed,") && lines[2].contains("clearance_joints[0].clearance"));
    std::fs::write(
        &file,
        text.replace(
            "values = [5e-4, -1e-4]",
            "distribution = \"normal\"\nmean = 5e-4",
        ),
    )
    .unwrap();
    let o = wearsim_out(&["sweep", file.to_str().unwrap()], &out);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("vary[0].sd"), "{}", stderr(&o));
    let o = wearsim(&["sweep", file.to_str().unwrap(), "--cycles", "2"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--cycles"), "{}", stderr(&o));
}

#[test]
fn a_run_to_the_limit_says_how_far_and_prints_the_lives() {
    let (dir, out) = scratch_out("until-limit");
    let scene = |run_extra: &str| {
        write_scene(
            &dir,
            &format!(
                "extends = \"slider-crank\"\n\
                 [[clearance_joints]]\n\
                 name = \"rod-slider\"\n\
                 wear = {{ k_d = 1.8e-13, width = 0.02, cells = 360, k_d_scatter = 0.4 }}\n\
                 [run]\n\
                 cycles = 1\n\
                 wear_stages = 1\n\
                 cycles_per_stage = 2\n\
                 amplification = 1e5\n\
                 animation = false\n\
                 clearance_limit = 0.0006\n\
                 until_limit = true\n\
                 {run_extra}"
            ),
        )
    };
    // Without its budget: bad input, the field named, for check and run alike.
    let bad = scene("");
    for command in ["check", "run"] {
        let o = wearsim(&[command, bad.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{command}");
        assert!(
            stderr(&o).contains("run.max_cycles = \"none\": required with run.until_limit"),
            "{command}: {}",
            stderr(&o)
        );
    }
    let good = scene("max_cycles = 2e5\n");
    let o = wearsim(&["check", good.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    for line in [
        "wear on (k_d 1.8e-13, scatter 0.4 in ln k_d)",
        "run: wear stages until every wearing joint reaches 0.60 mm clearance, at most \
         2.000e5 cycles; k_d scatter shared between the joints",
    ] {
        assert!(text.contains(line), "{line}: {text}");
    }
    let o = run_into(good.to_str().unwrap(), &out);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    for line in [
        "joint rod-slider reaches 0.60 mm clearance after ",
        "under a k_d scatter of 0.4 (sd of ln k_d): B10 ",
        "life: every wearing joint reached the limit within the ",
    ] {
        assert!(text.contains(line), "{line}: {text}");
    }
    // Progress toward the limit, not toward a cycle count.
    assert!(
        stderr(&o).contains("% of the way to the 0.600 mm clearance limit (rod-slider 0."),
        "{}",
        stderr(&o)
    );
    for file in ["life_distribution.csv", "life_distribution.png"] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
}

#[test]
fn run_prints_when_each_joint_reaches_the_clearance_limit() {
    let (dir, out) = scratch_out("limit");
    // The run's standard output, with the scene's clearance limit `limit`.
    let run = |limit: &str| {
        let scene = write_scene(
            &dir,
            &format!(
                "extends = \"slider-crank\"\n\
                 [[clearance_joints]]\n\
                 name = \"rod-slider\"\n\
                 wear = {{ k_d = 1.8e-13, width = 0.02, cells = 360 }}\n\
                 [run]\n\
                 cycles = 1\n\
                 wear_stages = 1\n\
                 cycles_per_stage = 1\n\
                 amplification = 750.0\n\
                 clearance_limit = {limit}\n"
            ),
        );
        let o = run_into(scene.to_str().unwrap(), &out);
        assert!(o.status.success(), "{limit}: {}", stderr(&o));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let text = run("0.000505");
    assert!(
        text.contains("joint rod-slider reaches 0.505 mm clearance after "),
        "{text}"
    );
    for file in ["wear_life.csv", "wear_life_rod-slider.png"] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
    let text = run("0.001");
    // One stage of K = 1 cycle × 750 stands for 750 cycles, all applied.
    assert!(
        text.contains("joint rod-slider does not reach 1.00 mm clearance within 7.5e2 cycles"),
        "{text}"
    );
}
