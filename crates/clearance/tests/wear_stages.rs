//! The wear-stage driver against Archard's law in closed form: a shaft turned at constant
//! speed hangs by its weight in a ground bearing, so after the start-up impacts every run
//! wears `V = K_d m g ω R_pin T` (frictionless: the load stays vertical), and a stage of
//! amplification `A` adds `A V`.

use clearance::multibody::{
    Body, BodyId, Coordinate, DriveTarget, Gravity, Model, OutputTimes, Ramp, SimulationOptions,
    System,
};
use clearance::{
    ClearanceJointBuilder, Ensemble, JointSide, LankaraniNikravesh, Material, StagePlan,
    StageSimulation, WearParams, WearStagesError, run_ensemble_stages, run_wear_stages,
};
use contact::{ContactModelKind, Foundation, LineOfCentres};
use wear::{Extrapolation, RunContext, WornJoint};

const MASS: f64 = 10.0;
const BEARING_RADIUS: f64 = 0.05;
const PIN_RADIUS: f64 = 0.0495;
/// Two turns a second.
const SPEED: f64 = 4.0 * std::f64::consts::PI;
/// Wear is gathered from here on (the impacts of the concentric start have died out)...
const WEAR_FROM: f64 = 0.5;
/// ... to here: two whole turns, one per half.
const T_END: f64 = 1.5;

fn shaft_joint(
    model: ContactModelKind,
) -> Result<ClearanceJointBuilder, Box<dyn std::error::Error>> {
    let steel = Material::new(200e9, 0.3)?;
    Ok(ClearanceJointBuilder::new(
        "shaft",
        JointSide::ground([0.0, 0.0], BEARING_RADIUS, steel),
        JointSide::on(BodyId(0), [0.0, 0.0], PIN_RADIUS, steel),
        LankaraniNikravesh::new(0.5)?,
    )
    .contact_model(model))
}

/// The elastic foundation on the wear grid's 720 cells.
fn foundation() -> Result<ContactModelKind, Box<dyn std::error::Error>> {
    let steel = Material::new(200e9, 0.3)?;
    Ok(ContactModelKind::Foundation(
        Foundation::calibrated(&steel, &steel).with_cells(720)?,
    ))
}

/// Each stage's worn volume (the first joint's, printed after `label`) against the Archard
/// volume of `stage × amplification` runs, `K_d m g ω R_pin T` each, within 2e-3.
fn check_stage_volumes(label: &str, surfaces: &[Vec<WornJoint>], amplification: f64) {
    let per_run = 1e-13 * MASS * 9.81 * SPEED * PIN_RADIUS * (T_END - WEAR_FROM);
    for (stage, s) in surfaces.iter().enumerate() {
        let expected = (stage + 1) as f64 * amplification * per_run;
        let volume = s[0].worn_volume();
        eprintln!(
            "{label}stage {}: worn volume {volume:.5e} m³, Archard {expected:.5e} m³ ({:+.3} %)",
            stage + 1,
            100.0 * (volume / expected - 1.0)
        );
        assert!((volume / expected - 1.0).abs() < 2e-3);
    }
}

/// The hanging shaft on `surfaces`, wearing from [`WEAR_FROM`], halves split at 1 s.
fn hanging_shaft(
    surfaces: &WornJoint,
    contact_model: ContactModelKind,
) -> Result<StageSimulation, Box<dyn std::error::Error>> {
    let mut model = Model::new();
    let shaft = model.add_body(Body::new("shaft", MASS, 0.02, [0.0, 0.0, 0.0]))?;
    let spin = DriveTarget::Coordinate(shaft, Coordinate::Theta);
    model.add_driver("spin", spin, Box::new(Ramp::new(0.0, SPEED)))?;
    let gravity = Gravity::new(&model, [0.0, -9.81]);
    let mut system = System::new(model)?;
    system.add_element(Box::new(gravity));
    let element = shaft_joint(contact_model)?
        .on_surfaces(surfaces)?
        .with_stage_wear(surfaces.start_stage(), WEAR_FROM)
        .with_halves(surfaces.start_stage(), 0.5 * (WEAR_FROM + T_END));
    let element = system.add_element(Box::new(element));
    let (q, qd) = system.initial_guess();
    let start = system.assemble(0.0, &q, &qd)?;
    let mut options = SimulationOptions::until(T_END);
    options.output = OutputTimes::At(vec![T_END]);
    // Wear is deposited at each accepted step's two ends, and resting contact lets BDF take
    // steps of a tenth of a second: bound them so the turning pin is worn at ≤ 1.5 cells a
    // step, not at a few spots. (The step across WEAR_FROM wears nothing: ≤ 1e-3 of T.)
    options.max_step = Some(1e-3);
    Ok(StageSimulation {
        system,
        start,
        options,
        elements: vec![element],
    })
}

#[test]
fn each_stage_adds_the_archard_volume_of_a_dead_load_times_the_amplification()
-> Result<(), Box<dyn std::error::Error>> {
    stages_add_the_archard_volume(ContactModelKind::from(LineOfCentres))
}

#[test]
fn the_foundation_wears_the_archard_volume_from_its_pressure()
-> Result<(), Box<dyn std::error::Error>> {
    stages_add_the_archard_volume(foundation()?)
}

fn stages_add_the_archard_volume(
    model: ContactModelKind,
) -> Result<(), Box<dyn std::error::Error>> {
    let amplification = 10.0;
    let params = WearParams::new(1e-13, 0.02, 720)?;
    let mut joints = vec![shaft_joint(model)?.unworn_surfaces(&params)?];
    let jump = Extrapolation::SingleJump { warn_fraction: 0.1 };
    let plan = StagePlan::new(2, amplification, jump);
    let mut runs = |_: RunContext, surfaces: &[WornJoint]| hanging_shaft(&surfaces[0], model);
    let stages = run_wear_stages(&mut joints, &plan, &mut runs).map_err(|e| e.to_string())?;

    assert_eq!(stages.reports.len(), 2);
    assert_eq!(stages.surfaces.len(), 2);
    // 2e-3: the step across WEAR_FROM is lost (≤ 1e-3 of the run) and the deposit spreads the
    // pressure over the arc, not its chord (+θ²/6 ≈ 1e-4 for this load).
    check_stage_volumes(&format!("{model:?} "), &stages.surfaces, amplification);
    // The bearing wears where the load presses: at the bottom.
    let bottom = stages.surfaces[1][0].bearing().peak();
    assert!(
        (bottom.angle - 1.5 * std::f64::consts::PI).abs() < 0.02,
        "{bottom:?}"
    );
    // Two turns under the same load wear alike.
    assert_eq!(stages.halves_differences.len(), 2);
    for d in &stages.halves_differences {
        let d = d.ok_or("halves were kept")?;
        eprintln!("halves differ by {:.2} % of the mean", 100.0 * d);
        assert!(d < 0.01, "halves differ by {d}");
    }
    Ok(())
}

#[test]
fn an_element_without_a_stage_buffer_is_named() -> Result<(), Box<dyn std::error::Error>> {
    let params = WearParams::new(1e-13, 0.02, 720)?;
    let mut joints =
        vec![shaft_joint(ContactModelKind::from(LineOfCentres))?.unworn_surfaces(&params)?];
    let mut runs = |_: RunContext, surfaces: &[WornJoint]| {
        let mut run = hanging_shaft(&surfaces[0], ContactModelKind::from(LineOfCentres))?;
        // The gravity element (0) is no clearance joint.
        run.elements = vec![clearance::multibody::ElementId(0)];
        Ok::<_, Box<dyn std::error::Error>>(run)
    };
    match run_wear_stages(&mut joints, &StagePlan::paper(1), &mut runs) {
        Err(WearStagesError::NotWearing {
            element: 0,
            context,
        }) => {
            assert_eq!((context.stage, context.substep), (0, 0));
        }
        other => panic!("expected NotWearing, got {other:?}"),
    }
    Ok(())
}

/// Records when each simulation it is part of takes its first step.
struct FirstStep {
    starts: std::sync::Arc<std::sync::Mutex<Vec<f64>>>,
    seen: bool,
}

impl clearance::multibody::ForceElement for FirstStep {
    fn name(&self) -> &str {
        "first step"
    }

    fn add_forces(&self, _t: f64, _q: &[f64], _qd: &[f64], _forces: &mut [f64]) {}

    /// No forces: no partials.
    fn add_partials(
        &self,
        _t: f64,
        _q: &[f64],
        _qd: &[f64],
        _partials: &mut clearance::multibody::ForcePartials<'_>,
    ) {
    }

    fn on_accepted_step(&mut self, t_previous: f64, _t: f64, _q: &[f64], _qd: &[f64]) {
        if !self.seen {
            self.seen = true;
            if let Ok(mut starts) = self.starts.lock() {
                starts.push(t_previous);
            }
        }
    }
}

/// Two trajectories per run: in the first stage both start from the assembled state and wear
/// over one half of the window each ([0.5, 1] s and [1, 1.5] s); in the second each continues
/// from where it ended (1 s and 1.5 s) for another half window. Under the dead load every
/// stage still wears the Archard volume, the two trajectories (the halves) wear alike, and the
/// surfaces do not depend on the number of threads, bit for bit.
#[test]
fn an_ensemble_continues_its_trajectories_and_wears_the_archard_volume_on_any_thread_count()
-> Result<(), Box<dyn std::error::Error>> {
    let amplification = 10.0;
    let params = WearParams::new(1e-13, 0.02, 720)?;
    let plan = StagePlan::new(
        2,
        amplification,
        Extrapolation::SingleJump { warn_fraction: 0.1 },
    );
    let mut surfaces = Vec::new();
    for threads in [1, 2] {
        let starts = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let mut joints =
            vec![shaft_joint(ContactModelKind::from(LineOfCentres))?.unworn_surfaces(&params)?];
        let mut runs = |_: RunContext, surfaces: &[WornJoint]| {
            let mut run = hanging_shaft(&surfaces[0], ContactModelKind::from(LineOfCentres))?;
            run.system.add_element(Box::new(FirstStep {
                starts: starts.clone(),
                seen: false,
            }));
            Ok::<_, Box<dyn std::error::Error>>(run)
        };
        let stages = run_ensemble_stages(&mut joints, &plan, Ensemble::new(2, threads), &mut runs)
            .map_err(|e| e.to_string())?;
        let mut starts = starts.lock().map_err(|e| e.to_string())?.clone();
        starts.sort_by(f64::total_cmp);
        eprintln!("{threads} thread(s): trajectories start at {starts:?} s");
        assert_eq!(starts.len(), 4);
        assert_eq!(&starts[..2], &[0.0, 0.0]);
        assert!((starts[2] - 1.0).abs() < 1e-12 && (starts[3] - 1.5).abs() < 1e-12);
        // As for one trajectory, less the step lost across WEAR_FROM: each trajectory's
        // window starts exactly at a step here.
        check_stage_volumes("  ", &stages.surfaces, amplification);
        for d in &stages.halves_differences {
            let d = d.ok_or("two trajectories are two halves")?;
            eprintln!(
                "  the trajectories differ by {:.2} % of the mean",
                100.0 * d
            );
            assert!(d < 0.01, "trajectories differ by {d}");
        }
        surfaces.push(stages.surfaces);
    }
    assert!(
        surfaces[0] == surfaces[1],
        "1 and 2 threads gave different surfaces"
    );
    Ok(())
}

/// An odd number of trajectories has no halves to compare.
#[test]
fn three_trajectories_have_no_halves() -> Result<(), Box<dyn std::error::Error>> {
    let params = WearParams::new(1e-13, 0.02, 720)?;
    let mut joints =
        vec![shaft_joint(ContactModelKind::from(LineOfCentres))?.unworn_surfaces(&params)?];
    let plan = StagePlan::new(1, 10.0, Extrapolation::SingleJump { warn_fraction: 0.1 });
    let mut runs = |_: RunContext, surfaces: &[WornJoint]| {
        hanging_shaft(&surfaces[0], ContactModelKind::from(LineOfCentres))
    };
    let stages = run_ensemble_stages(&mut joints, &plan, Ensemble::new(3, 2), &mut runs)
        .map_err(|e| e.to_string())?;
    assert_eq!(stages.halves_differences, vec![None]);
    assert_eq!(stages.stage_halves, vec![None]);
    Ok(())
}

/// Error-controlled sub-steps through the driver: the runs' halves reach the estimate, every
/// run's wear is weighted into the stage, and under the dead load (a constant Archard rate)
/// the stage wears its Archard volume however it was split.
#[test]
fn controlled_sub_steps_wear_the_archard_volume() -> Result<(), Box<dyn std::error::Error>> {
    let amplification = 1000.0;
    let params = WearParams::new(1e-13, 0.02, 720)?;
    let fresh = shaft_joint(ContactModelKind::from(LineOfCentres))?.unworn_surfaces(&params)?;
    let mut runs = |_: RunContext, surfaces: &[WornJoint]| {
        hanging_shaft(&surfaces[0], ContactModelKind::from(LineOfCentres))
    };
    // The clearance change of the whole stage in one jump sets bounds that need ≥ 4 sub-steps.
    let jump = StagePlan::new(
        1,
        amplification,
        Extrapolation::SingleJump { warn_fraction: 1.0 },
    );
    let whole = run_wear_stages(&mut [fresh.clone()], &jump, &mut runs)
        .map_err(|e| e.to_string())?
        .reports[0]
        .substeps[0]
        .max_change_fraction;
    let plan = StagePlan::new(
        1,
        amplification,
        Extrapolation::Controlled {
            tolerance: 0.05,
            min_fraction: whole / 8.0,
            max_fraction: whole / 4.0,
            max_runs: 100,
        },
    );
    let mut joints = vec![fresh];
    let stages = run_wear_stages(&mut joints, &plan, &mut runs).map_err(|e| e.to_string())?;
    let report = &stages.reports[0];
    let per_run = 1e-13 * MASS * 9.81 * SPEED * PIN_RADIUS * (T_END - WEAR_FROM);
    let volume = joints[0].worn_volume();
    let expected = amplification * per_run;
    eprintln!(
        "{} sub-steps, {} runs ({} rejected): worn volume {volume:.5e} m³, Archard \
         {expected:.5e} m³ ({:+.3} %)",
        report.substeps.len(),
        report.run_weights.len(),
        report.rejected_runs(),
        100.0 * (volume / expected - 1.0)
    );
    assert!(report.substeps.len() >= 4);
    assert_eq!(
        report.run_weights.len(),
        report.substeps.len() + 1 + report.rejected_runs()
    );
    assert_eq!(stages.halves_differences.len(), report.run_weights.len());
    // Runs on worn surfaces add the arc-to-chord excess of the deposit (the pressure spread
    // over the arc of a conforming contact, θ²/6): +0.2 % here, against +0.003 % for the single
    // jump, whose one run is on fresh surfaces.
    assert!((volume / expected - 1.0).abs() < 5e-3);
    // The halves were kept and weighted like the runs: they agree under the dead load.
    let halves = stages.stage_halves[0].ok_or("stage halves")?;
    assert!(halves.worn_volume < 0.01, "{halves:?}");
    for s in &report.substeps {
        assert!(s.error_estimate.is_some_and(|e| e <= 0.05), "{s:?}");
    }
    // Its noise cannot be levelled (the corrector shares each run between two sub-steps), so
    // none is given, rather than the jackknife's alone.
    assert!(stages.life_noise[0].iter().all(Option::is_none));
    assert_eq!(stages.stage_replicas[0][0].count(), 0);
    Ok(())
}
