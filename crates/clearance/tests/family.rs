//! The mechanism family of any size: it builds, assembles and runs in every formulation and
//! linear solver, and refuses sizes below the smallest chain.

use clearance::family::{Chain, ChainParams, FamilyError, chain};
use multibody::{Formulation, Harmonic, LinearSolverKind, OutputTimes, SimulationOptions};

/// The chain assembles with one driven rocker and runs in each formulation, following its
/// drive with small drift and a closed energy balance; the sparse iteration solver retraces
/// the dense one's trajectory.
#[test]
fn a_small_chain_runs_the_same_with_either_linear_solver() {
    let params = ChainParams::default();
    let mut finals = Vec::new();
    let cases = [
        (Formulation::Cartesian, LinearSolverKind::Dense),
        (Formulation::Cartesian, LinearSolverKind::SparseFaer),
        (Formulation::JointCoordinates, LinearSolverKind::Dense),
    ];
    for (formulation, solver) in cases {
        let Chain {
            mut system,
            revolutes,
            clearances,
        } = chain(11, 5, &params).expect("builds");
        // 16 joints in chain order (6 pivots, 10 pins): joints 5, 10 and 15 have clearance.
        assert_eq!((revolutes, clearances), (13, 3));
        let (q, qd) = system.initial_guess();
        let start = system.assemble(0.0, &q, &qd).expect("assembles");
        let mut options = SimulationOptions::until(0.05);
        options.output = OutputTimes::At(vec![0.05]);
        options.formulation = formulation;
        options.linear_solver = solver;
        let run = system.simulate(&start, &options, &mut ()).expect("runs");
        let energy = run.energy.expect("audited");
        eprintln!(
            "{formulation:?}, {solver:?}: {} steps, drift {:.2e} m, energy residual {:.2e}",
            run.statistics.steps,
            run.drift.position,
            energy.relative_residual()
        );
        // Baumgarte-stabilised drift during impacts stays below 1 % of the clearance.
        assert!(run.drift.position < 1e-6, "drift {}", run.drift.position);
        assert!(energy.relative_residual() < 1e-3, "{energy:?}");
        let drive = Harmonic {
            offset: -std::f64::consts::FRAC_PI_2,
            amplitude: params.amplitude,
            omega: params.omega,
        };
        let angle = run.final_state.q[2];
        let expected = drive_value(&drive, run.final_state.t);
        assert!((angle - expected).abs() < 1e-6, "{angle} vs {expected}");
        finals.push(run.final_state.q);
    }
    // The impacts make the runs part at the tolerances' scale, whatever solves them.
    let difference = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    for other in &finals[1..] {
        let d = difference(&finals[0], other);
        assert!(d < 1e-5, "final coordinates differ by {d:e}");
    }
}

/// Without impacts the sparse solver retraces the dense one: the same equations solved
/// in two pivoting orders, so the Newton iterates differ at round-off only.
#[test]
fn the_sparse_solver_retraces_the_dense_trajectory() {
    let mut runs = Vec::new();
    for solver in [LinearSolverKind::Dense, LinearSolverKind::SparseFaer] {
        // A period longer than the chain: every joint is ideal.
        let mut system = chain(11, 100, &ChainParams::default())
            .expect("builds")
            .system;
        let (q, qd) = system.initial_guess();
        let start = system.assemble(0.0, &q, &qd).expect("assembles");
        let mut options = SimulationOptions::until(0.5);
        options.output = OutputTimes::Every(0.05);
        options.linear_solver = solver;
        runs.push(system.simulate(&start, &options, &mut ()).expect("runs"));
    }
    let (dense, sparse) = (&runs[0], &runs[1]);
    let d = dense
        .trajectory
        .q
        .iter()
        .zip(&sparse.trajectory.q)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "steps {} vs {}, largest difference {d:e}",
        dense.statistics.steps, sparse.statistics.steps
    );
    assert_eq!(dense.trajectory.q.len(), sparse.trajectory.q.len());
    assert!(d < 1e-12, "dense vs sparse: {d:e}");
}

fn drive_value(drive: &Harmonic, t: f64) -> f64 {
    use multibody::DriveFunction;
    drive.value(t)
}

#[test]
fn sizes_below_the_smallest_chain_are_errors() {
    assert!(matches!(
        chain(1, 5, &ChainParams::default()),
        Err(FamilyError::Size { .. })
    ));
    assert!(matches!(
        chain(5, 1, &ChainParams::default()),
        Err(FamilyError::Size { .. })
    ));
}
