//! Runs that start from worn surfaces (`RunOptions::surfaces`), and the energy law of the worn
//! contact in the whole mechanism.
//!
//! The surfaces are smooth dents written in `wearsim run`'s wear-file format, placed where the
//! LGRES wears (bearing and pin contact angles of joints A and B), 20 µm deep and ±15° wide:
//! the size the paper's formulation wears in one stage, inside the model's validity.

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

use contact::{ContactModel, ValidityMeasure};
use scene::{ContactSpec, ValidScene};
use sim::surfaces::SurfacesError;
use sim::{RunError, RunOptions, run_scene};

/// A Gaussian dent `depth · exp(−((θ − centre)/width)²)` on `cells` cells (wrapped).
fn dent(cells: usize, centre_deg: f64, depth: f64) -> Vec<f64> {
    let width = 15f64.to_radians();
    (0..cells)
        .map(|k| {
            let angle = (k as f64 + 0.5) * TAU / cells as f64;
            let offset = (angle - centre_deg.to_radians() + TAU / 2.0).rem_euclid(TAU) - TAU / 2.0;
            depth * (-(offset / width).powi(2)).exp()
        })
        .collect()
}

fn write_wear(dir: &Path, joint: &str, bearing: &[f64], pin: &[f64]) {
    let mut text = String::from("angle [deg],bearing_depth [m],pin_depth [m]\n");
    for (k, (b, p)) in bearing.iter().zip(pin).enumerate() {
        let angle = (k as f64 + 0.5) * 360.0 / bearing.len() as f64;
        text.push_str(&format!("{angle:e},{b:e},{p:e}\n"));
    }
    std::fs::write(dir.join(format!("wear_{joint}_stage1.csv")), text).expect("writes");
}

fn worn_folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("wornjoint-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp folder");
    write_wear(
        &dir,
        "A",
        &dent(1000, 131.0, 2e-5),
        &dent(1000, 158.0, 2e-5),
    );
    write_wear(
        &dir,
        "B",
        &dent(1000, 181.0, 2e-5),
        &dent(1000, 172.0, 2e-5),
    );
    dir
}

/// On worn surfaces, an elastic frictionless contact neither dissipates nor creates energy:
/// the contact's work over the run (energy audit, Gauss quadrature on the interpolant) equals
/// minus the change of its stored energy. The line-of-centres force it replaces put ~100 J
/// per cycle into this mechanism on worn profiles. Tolerance: 0.05 J per cycle against a
/// stored energy that peaks at tens of joules per impact.
#[test]
fn elastic_contact_on_worn_surfaces_conserves_energy() {
    for model in [
        ContactSpec::default(),
        ContactSpec::line_of_centres(),
        ContactSpec::ThinGap(Default::default()),
    ] {
        elastic_contact_conserves_energy(model);
    }
}

fn elastic_contact_conserves_energy(model: ContactSpec) {
    let name = model.name();
    let dir = worn_folder(&format!("elastic-{name}"));
    let scene = one_cycle_on("lgres-elastic", model);
    let outcome = run_scene("lgres-elastic", &scene, &from_surfaces(&dir), &mut ()).expect("runs");
    let r = &outcome.summary.response;
    eprintln!(
        "elastic LGRES on 20 µm dents ({name}): dissipated {:.4} J per cycle (A {:.4}, B {:.4})",
        r.dissipated_per_cycle_j,
        r.joints[0].contact_dissipation_per_cycle_j,
        r.joints[1].contact_dissipation_per_cycle_j
    );
    assert!(r.dissipated_per_cycle_j.abs() < 0.05, "{r:?}");
    assert_eq!(r.damping_per_cycle_j, 0.0);
    assert_eq!(r.friction_per_cycle_j, 0.0);
    assert!(r.energy_warnings.is_empty(), "{:?}", r.energy_warnings);
    for (j, joint) in r.joints.iter().zip(&scene.clearance_joints) {
        let v = j.validity.as_ref().expect("measured");
        let model = joint.contact_model().expect("a model");
        assert_eq!(v.model, model.name());
        // The run did sample the dents: each measure the model is judged by that a dent
        // makes non-zero was measured so.
        for measure in model.validity_measures() {
            match measure {
                ValidityMeasure::SlopeRatio => assert!(v.max_slope_ratio > 0.0, "{v:?}"),
                ValidityMeasure::OverlapError => assert!(v.overlap_frames > 0, "{v:?}"),
                ValidityMeasure::OverlapRatio => assert!(v.max_overlap_ratio > 0.0, "{v:?}"),
                ValidityMeasure::ResolutionError => {
                    assert!(v.narrowest_zone_cells.is_some(), "{v:?}")
                }
                ValidityMeasure::NeglectedTerms => assert!(v.max_neglected_terms > 0.0, "{v:?}"),
                _ => {}
            }
        }
    }
    std::fs::remove_dir_all(dir).ok();
}

/// `scene`'s clearance joints on the contact model `model`: the scene's own table where it
/// names the same model (its nodes kept), else `model`.
fn set_model(scene: &mut scene::Scene, model: ContactSpec) {
    for joint in &mut scene.clearance_joints {
        if joint.contact.name() != model.name() {
            joint.contact = model;
        }
    }
}

/// A [`worn_folder`] named `name`, the default scene and its joints' unworn surfaces (what a
/// start from the folder is checked against).
fn lgres_beside_worn_folder(name: &str) -> (PathBuf, ValidScene, Vec<Option<wear::WornJoint>>) {
    let dir = worn_folder(name);
    let scene = lgres::scenes::builtin("lgres").expect("built-in");
    let unworn = sim::build::unworn_joints(&scene).expect("joints");
    (dir, scene, unworn)
}

/// The built-in scene `name` for one response cycle, its clearance joints on `model`.
fn one_cycle_on(name: &str, model: ContactSpec) -> ValidScene {
    lgres::scenes::builtin(name)
        .expect("built-in")
        .edit(&format!("{name}, one cycle, {}", model.name()), |s| {
            s.run.cycles = 1;
            set_model(s, model);
        })
        .expect("valid")
}

/// The run's options for a start from the surfaces in `dir`.
fn from_surfaces(dir: &Path) -> RunOptions {
    RunOptions {
        surfaces: Some(output::surfaces::folder(dir)),
        ..RunOptions::default()
    }
}

#[test]
fn missing_or_mismatched_wear_files_are_named_errors() {
    let dir = worn_folder("errors");
    let scene = lgres::scenes::builtin("lgres")
        .expect("built-in")
        .edit("lgres, one cycle, no wear", |s| {
            s.run.cycles = 1;
            s.run.wear_stages = 0;
        })
        .expect("valid");
    let run = |dir: &Path| match run_scene("lgres", &scene, &from_surfaces(dir), &mut ()) {
        Err(e @ RunError::Surfaces(_)) => {
            assert!(e.is_bad_input(), "{e}");
            e
        }
        other => panic!("expected a surfaces error, got {other:?}"),
    };
    std::fs::remove_file(dir.join("wear_B_stage1.csv")).expect("removes");
    let e = run(&dir);
    assert!(
        matches!(&e, RunError::Surfaces(SurfacesError::Missing { joint, .. }) if joint == "B"),
        "{e}"
    );
    write_wear(&dir, "B", &dent(500, 181.0, 2e-5), &dent(500, 172.0, 2e-5));
    let e = run(&dir);
    assert!(
        matches!(
            &e,
            RunError::Surfaces(SurfacesError::GridMismatch {
                expected: 1000,
                found: 500,
                ..
            })
        ),
        "{e}"
    );
    std::fs::write(
        dir.join("wear_B_stage2.csv"),
        "angle [deg],bearing_depth [m],pin_depth [m]\n0.18,1e-6,oops\n",
    )
    .expect("writes");
    let e = run(&dir);
    assert!(e.to_string().contains("wear_B_stage2.csv"), "{e}");
    assert!(e.to_string().contains("line 2"), "{e}");
    std::fs::remove_dir_all(dir).ok();
}

/// On the line-of-centres contact, the default run's stage ends where its worn geometry reaches
/// the model's slope limit, and on the surfaces it writes an elastic, frictionless contact
/// conserves energy (the check of `wearsim run lgres-elastic --surfaces out/lgres`, over one
/// cycle here).
#[test]
fn line_of_centres_stage_stops_at_the_validity_limit_and_its_surfaces_conserve_energy() {
    let dir = std::env::temp_dir().join(format!("wornjoint-default-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let scene = one_cycle_on("lgres", ContactSpec::line_of_centres());
    let options = RunOptions {
        cycles_per_stage: Some(1),
        ..RunOptions::default()
    };
    let outcome = run_scene("lgres", &scene, &options, &mut ()).expect("runs");
    let wear = outcome.summary.wear.as_ref().expect("a stage ran");
    let applied = wear.cycles_applied_at_limits[0].expect("ended at the validity limit");
    assert!(applied > 1e3 && applied < 2e6, "{applied} cycles");
    let worn = outcome
        .summary
        .worn_response
        .as_ref()
        .expect("worn response");
    for j in &worn.joints {
        let v = j.validity.as_ref().expect("validity measured");
        // Stopped at the slope limit 0.3 (a bound on the profile; measured at the contacts).
        assert!(v.max_slope_ratio <= 0.3, "joint {}: {v:?}", j.name);
    }
    output::artifacts::write_run(&outcome, &dir).expect("writes");

    let elastic = one_cycle_on("lgres-elastic", ContactSpec::line_of_centres());
    let outcome =
        run_scene("lgres-elastic", &elastic, &from_surfaces(&dir), &mut ()).expect("runs");
    let dissipated = outcome.summary.response.dissipated_per_cycle_j;
    eprintln!("elastic LGRES on the default run's surfaces: {dissipated:.4} J per cycle");
    assert!(dissipated.abs() < 0.05, "{dissipated} J per cycle");
    std::fs::remove_dir_all(dir).ok();
}

/// The exact Jacobian of the worn clearance joints, inside the whole LGRES: at a state where a
/// joint is loaded and sliding (away from the friction ramp's corners), `System::check_partials`
/// finds its partials equal to central differences of its forces.
#[test]
fn worn_joints_partials_match_finite_differences_in_the_mechanism() {
    use multibody::OutputTimes;
    use sim::build::{Surfaces, build};
    let (dir, scene, unworn) = lgres_beside_worn_folder("partials");
    let worn = output::surfaces::load_last_stage(&dir, &scene, &unworn).expect("loads");
    let build_worn = || {
        build(
            &scene,
            Surfaces {
                worn: &worn,
                ..Surfaces::default()
            },
        )
        .expect("builds")
    };
    let mut built = build_worn();
    let (q0, qd0) = built.system.initial_guess();
    let start = built.system.assemble(0.0, &q0, &qd0).expect("assembles");
    let options = sim::simulation_options(&scene, 0.4, OutputTimes::Every(1e-3), true);
    let result = built
        .system
        .simulate(&start, &options, &mut ())
        .expect("runs");
    let trajectory = &result.trajectory;
    for handle in &built.joints {
        let loaded = (0..trajectory.len()).find(|&f| {
            handle.probe(built.system.elements()).is_some_and(|p| {
                let d = p.contact(trajectory.q(f), trajectory.qd(f)).diagnostics;
                d.normal_force > 1e3 && d.tangential_velocity.abs() > 2e-3
            })
        });
        let f = loaded.expect("a frame with the joint loaded and sliding");
        // Simulate again up to that frame, so the element's impact memory (the onset velocity
        // of the current contact, a constant of the force law) belongs to that state.
        let mut fresh = build_worn();
        let t = trajectory.times[f];
        let options = sim::simulation_options(&scene, t, OutputTimes::At(vec![t]), true);
        let run = fresh
            .system
            .simulate(&start, &options, &mut ())
            .expect("runs");
        let last = run.trajectory.len() - 1;
        let (q, qd) = (run.trajectory.q(last), run.trajectory.qd(last));
        let report = fresh
            .system
            .check_partials(t, q, qd, 1e-9, 1e-7)
            .expect("checks");
        let check = report
            .iter()
            .find(|c| c.element == handle.name)
            .expect("the joint's element");
        eprintln!(
            "joint {} at t = {}: {:.2e} {:?}",
            handle.name, trajectory.times[f], check.max_relative_error, check.worst
        );
        assert!(check.max_relative_error < 1e-4, "{check:?}");
    }
    std::fs::remove_dir_all(dir).ok();
}

/// A worn-surface file is read only when it is a regular file of bounded size whose rows are
/// the grid's cells in order with finite, physically possible depths; anything else is a
/// named error (file, line, value), at once: no abort on a device that never ends, no wait on
/// a FIFO, no silent surface from shuffled rows or a depth of 1e300 m.
#[test]
fn corrupt_or_special_wear_files_are_refused_by_name() {
    let (dir, scene, unworn) = lgres_beside_worn_folder("corrupt");
    let file = dir.join("wear_B_stage1.csv");
    let good = std::fs::read_to_string(&file).expect("reads");
    let refused = |what: &str| -> String {
        match output::surfaces::load_last_stage(&dir, &scene, &unworn) {
            Err(e) => {
                let text = e.to_string();
                assert!(text.contains("wear_B_stage1.csv"), "{what}: {text}");
                text
            }
            Ok(_) => panic!("{what}: accepted"),
        }
    };
    let rows: Vec<&str> = good.lines().collect();
    let with_rows = |edit: &dyn Fn(&mut Vec<String>)| {
        let mut lines: Vec<String> = rows.iter().map(|l| l.to_string()).collect();
        edit(&mut lines);
        std::fs::write(&file, lines.join("\n") + "\n").expect("writes");
    };

    // Rows out of order (two cells swapped), a duplicated angle, angles shifted by 720°.
    with_rows(&|l| l.swap(10, 11));
    let e = refused("swapped rows");
    assert!(e.contains("line 11") && e.contains("angle"), "{e}");
    with_rows(&|l| l[11] = l[10].clone());
    assert!(refused("duplicated angle").contains("line 12"));
    with_rows(&|l| {
        for line in l.iter_mut().skip(1) {
            let (angle, rest) = line.split_once(',').expect("three columns");
            let shifted = angle.parse::<f64>().expect("number") + 720.0;
            *line = format!("{shifted},{rest}");
        }
    });
    assert!(refused("angles + 720°").contains("line 2"));
    // Depths that are not physical: 1e300 m, more than the bearing's radius, negative, NaN.
    for (depth, word) in [("1e300", "line 501"), ("0.17", "below 0.16 m")] {
        with_rows(&|l| {
            let parts: Vec<&str> = l[500].split(',').collect();
            l[500] = format!("{},{depth},{}", parts[0], parts[2]);
        });
        let e = refused(depth);
        assert!(e.contains(word), "{depth}: {e}");
    }
    for depth in ["-1e-6", "NaN", "inf"] {
        with_rows(&|l| {
            let parts: Vec<&str> = l[7].split(',').collect();
            l[7] = format!("{},{},{depth}", parts[0], parts[1]);
        });
        let e = refused(depth);
        assert!(
            e.contains("line 8") && e.contains("pin_depth"),
            "{depth}: {e}"
        );
    }
    // A link to a device that never ends, and a FIFO nobody writes: refused at once.
    std::fs::remove_file(&file).expect("removes");
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("/dev/zero", &file).expect("links");
        assert!(refused("/dev/zero").contains("not a regular file"));
        std::fs::remove_file(&file).expect("removes");
        let made = std::process::Command::new("mkfifo").arg(&file).status();
        if made.is_ok_and(|s| s.success()) {
            assert!(refused("FIFO").contains("not a regular file"));
            std::fs::remove_file(&file).expect("removes");
        }
    }
    // The good file loads again.
    std::fs::write(&file, &good).expect("writes");
    assert!(output::surfaces::load_last_stage(&dir, &scene, &unworn).is_ok());
    std::fs::remove_dir_all(dir).ok();
}
