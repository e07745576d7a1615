//! Archard accumulation against closed-form pin-on-bearing wear.

mod common;

use approx::assert_relative_eq;
use common::*;
use contact::ContactDiagnostics;
use std::f64::consts::TAU;
use wear::{ContactArc, WearError};

/// Half-angles straight from docs/model.md's law of cosines (independent of the crate's form).
fn arc_by_cosines(e: f64, ri: f64, rj: f64) -> (f64, f64) {
    let alpha = ((e * e + rj * rj - ri * ri) / (2.0 * e * rj)).acos();
    let gamma = ((e * e + ri * ri - rj * rj) / (2.0 * e * ri)).acos();
    (std::f64::consts::PI - alpha, gamma)
}

#[test]
fn contact_arc_matches_law_of_cosines_and_sines() {
    for delta in [1e-6, 1e-5, 5e-5, 2e-4] {
        let e = CLEARANCE + delta;
        let arc = ContactArc::new(e, R_BEARING, R_PIN).unwrap();
        let (pin, bearing) = arc_by_cosines(e, R_BEARING, R_PIN);
        assert_relative_eq!(arc.pin_half_angle, pin, max_relative = 1e-6);
        assert_relative_eq!(arc.bearing_half_angle, bearing, max_relative = 1e-6);
        // Same chord seen from both centres.
        assert_relative_eq!(
            arc.chord,
            2.0 * R_BEARING * arc.bearing_half_angle.sin(),
            max_relative = 1e-12
        );
        assert_relative_eq!(arc.chord, 2.0 * R_PIN * pin.sin(), max_relative = 1e-6);
    }
    assert!(ContactArc::new(CLEARANCE - 1e-6, R_BEARING, R_PIN).is_none());
}

/// A pin held still under constant load; the bearing turns at `omega` under it.
#[test]
fn pin_on_turning_bearing_matches_archard() {
    let cells = 1000;
    let (force, omega, delta) = (3000.0, 0.5, 10e-6);
    let speed = omega * R_BEARING;
    let (pin_angle, bearing_start) = (1.0, 3.0);
    let (dt, steps) = (1e-3, 2000);
    let total = dt * steps as f64;
    let state = |t: f64| loaded(force, speed, delta, pin_angle, bearing_start - omega * t);

    let mut stage = joint(cells).start_stage();
    for s in 0..steps {
        let t = s as f64 * dt;
        stage
            .accumulate_step(&state(t), &state(t + dt), dt)
            .unwrap();
    }

    let (a, gamma) = arc_by_cosines(CLEARANCE + delta, R_BEARING, R_PIN);
    let chord = 2.0 * R_PIN * a.sin();
    let rate = K_D * force / (chord * WIDTH) * speed;
    let dtheta = TAU / cells as f64;
    let centre = |k: usize| (k as f64 + 0.5) * dtheta;

    // Pin: cells inside the fixed arc wear for the whole time, with the elliptic (Hertzian)
    // pressure distribution (4/π) p̄ √(1 − u²) across the arc; the cell average of that weight
    // differs from its centre value by < 1e-3 away from the arc's ends.
    let mut inside = 0;
    for (k, &h) in stage.pin().iter().enumerate() {
        let off = (centre(k) - pin_angle).abs();
        if off < 0.8 * a {
            let weight = 4.0 / std::f64::consts::PI * (1.0 - (off / a).powi(2)).sqrt();
            assert_relative_eq!(h, rate * total * weight, max_relative = 1e-3);
            inside += 1;
        } else if off > a + dtheta {
            assert_eq!(h, 0.0, "pin cell {k} outside the arc");
        }
    }
    assert!(
        inside >= 40,
        "the arc should cover many cells, got {inside}"
    );

    // Bearing: cells the whole arc swept over wear for 2γ/ω.
    let end = bearing_start - omega * total;
    let mut swept = 0;
    for (k, &h) in stage.bearing().iter().enumerate() {
        let th = centre(k);
        if th > end + gamma + dtheta && th < bearing_start - gamma - dtheta {
            assert_relative_eq!(h, rate * 2.0 * gamma / omega, max_relative = 1e-3);
            swept += 1;
        } else if th < end - gamma - dtheta || th > bearing_start + gamma + dtheta {
            assert_eq!(h, 0.0, "bearing cell {k} never under the arc");
        }
    }
    assert!(swept > 50);

    // Volume: both halves together equal K_d F s (up to the arc/chord ratio, < 1 %).
    let archard = K_D * force * speed * total;
    assert_relative_eq!(stage.archard_volume(), archard, max_relative = 1e-12);
    let worn = stage.worn_volume();
    assert!(
        (worn / archard - 1.0).abs() < 0.01,
        "worn/archard = {}",
        worn / archard
    );
    // ... and exactly by that ratio.
    let pin_half = 0.5 * archard * a / a.sin();
    let bearing_half = 0.5 * archard * gamma / gamma.sin();
    assert_relative_eq!(worn, pin_half + bearing_half, max_relative = 1e-6);
}

#[test]
fn contact_onset_gets_half_a_step_from_the_loaded_end() {
    let joint = joint(1000);
    let mut stage = joint.start_stage();
    let free = ContactDiagnostics::default();
    let end = loaded(2000.0, 0.1, 5e-6, 2.0, 4.0);
    let dt = 1e-4;
    stage.accumulate_step(&free, &end, dt).unwrap();
    let archard = K_D * 2000.0 * 0.1;
    assert_relative_eq!(
        stage.archard_volume(),
        archard * dt / 2.0,
        max_relative = 1e-12
    );
    // Contact ending: symmetric.
    let mut ending = joint.start_stage();
    ending.accumulate_step(&end, &free, dt).unwrap();
    assert_eq!(ending.pin(), stage.pin());
    assert_eq!(ending.bearing(), stage.bearing());
    // In contact but unloaded (force clamped to zero while separating): no wear.
    let mut unloaded = joint.start_stage();
    let mut zero = end;
    zero.normal_force = 0.0;
    unloaded.accumulate_step(&zero, &zero, dt).unwrap();
    assert_eq!(unloaded.max_depth(), 0.0);
}

#[test]
fn surfaces_stay_frozen_until_the_stage_is_applied() {
    let mut joint = joint(1000);
    let before = joint.clone();
    let mut stage = joint.start_stage();
    let s = loaded(2000.0, 0.1, 5e-6, 2.0, 4.0);
    stage.accumulate_step(&s, &s, 1e-2).unwrap();
    assert!(stage.max_depth() > 0.0);
    assert_eq!(joint, before);
    joint.apply(&stage, 10.0).unwrap();
    let wear::Peak {
        depth: peak, angle, ..
    } = joint.pin().peak();
    assert_relative_eq!(peak, 10.0 * stage.pin().iter().copied().fold(0.0, f64::max));
    // The peak lies on the loaded arc of the pin.
    let arc = ContactArc::new(s.eccentricity, R_BEARING, R_PIN).unwrap();
    assert!((angle - 2.0).abs() <= arc.pin_half_angle);
    // Reset reuses the buffers.
    stage.reset();
    assert_eq!(stage.max_depth(), 0.0);
    assert_eq!(stage.archard_volume(), 0.0);
}

#[test]
fn bad_diagnostics_and_steps_name_the_field() {
    let mut stage = joint(100).start_stage();
    let good = loaded(2000.0, 0.1, 5e-6, 2.0, 4.0);
    let named = |r: Result<(), WearError>| match r {
        Err(WearError::InvalidParameter { name, .. }) => name,
        other => panic!("expected a named error, got {other:?}"),
    };
    assert_eq!(named(stage.accumulate_step(&good, &good, -1.0)), "dt");
    assert_eq!(named(stage.accumulate_step(&good, &good, f64::NAN)), "dt");
    let mut bad = good;
    bad.tangential_velocity = f64::INFINITY;
    assert_eq!(
        named(stage.accumulate_step(&good, &bad, 1e-3)),
        "tangential_velocity"
    );
    let mut bad = good;
    bad.normal_force = f64::NAN;
    assert_eq!(
        named(stage.accumulate_step(&bad, &good, 1e-3)),
        "normal_force"
    );
    let mut bad = good;
    bad.pin_angle = f64::NAN;
    assert_eq!(named(stage.accumulate_step(&bad, &good, 1e-3)), "pin_angle");
    // Nothing was deposited by the rejected calls.
    assert_eq!(stage.max_depth(), 0.0);
}

#[test]
fn paper_sliding_wears_with_the_geometric_contact_point_speed() {
    use contact::SlidingVelocity;
    let material = joint(1000);
    let paper = joint(1000).with_sliding(SlidingVelocity::Paper);
    assert_eq!(paper.sliding(), SlidingVelocity::Paper);
    let mut s = loaded(2000.0, 0.1, 5e-6, 2.0, 4.0);
    s.geometric_sliding_velocity = -0.004;
    let (mut a, mut b) = (material.start_stage(), paper.start_stage());
    a.accumulate_step(&s, &s, 1e-3).unwrap();
    b.accumulate_step(&s, &s, 1e-3).unwrap();
    assert_relative_eq!(
        b.archard_volume(),
        0.04 * a.archard_volume(),
        max_relative = 1e-12
    );
    assert_relative_eq!(b.max_depth(), 0.04 * a.max_depth(), max_relative = 1e-12);
}

/// Foundation node loads: the worn volume of every step is Archard's `K_d Σ F |v| dt` to
/// round-off, whatever the nodes' angles (between cell centres or on them) and grid sizes.
#[test]
fn node_deposits_carry_the_archard_volume_exactly() {
    use contact::NodeLoad;
    for (cells, node_cells) in [(1000, 1000), (720, 1000), (1000, 360)] {
        let joint = joint(cells);
        let mut stage = joint.start_stage();
        let arc = R_PIN * TAU / node_cells as f64;
        let node = |k: usize, force: f64, speed: f64| NodeLoad {
            bearing_angle: 1.234 + 0.0137 * k as f64,
            ..node(k, node_cells, force, speed)
        };
        let start: Vec<NodeLoad> = (10..40).map(|k| node(k, 50.0 + k as f64, -0.3)).collect();
        let end: Vec<NodeLoad> = (12..45).map(|k| node(k, 80.0 - k as f64, 0.25)).collect();
        let dt = 1e-4;
        stage.accumulate_nodes(&start, &end, dt).unwrap();
        let expected: f64 = start
            .iter()
            .chain(&end)
            .map(|n| 1.8e-13 * n.normal_force * n.material_sliding.abs() * 0.5 * dt)
            .sum();
        assert_relative_eq!(stage.archard_volume(), expected, max_relative = 1e-14);
        assert_relative_eq!(stage.worn_volume(), expected, max_relative = 1e-12);
        // The pin cells under matching grids hold the closed-form depth K_d p |v| dt/2 ...
        if cells == node_cells {
            let p = start[0].normal_force / (arc * 0.1);
            assert_relative_eq!(
                stage.pin()[10],
                1.8e-13 * p * 0.3 * 0.5 * dt,
                max_relative = 1e-12
            );
        }
        // ... and nothing is deposited away from the nodes.
        assert_eq!(stage.pin()[cells / 2 + 100], 0.0);
    }
    // A NaN node is refused and leaves the record as it was.
    let mut stage = joint(100).start_stage();
    let bad = NodeLoad {
        normal_force: f64::NAN,
        arc: 1e-3,
        ..NodeLoad::default()
    };
    assert!(stage.accumulate_nodes(&[bad], &[], 1e-4).is_err());
    assert_eq!(stage.max_depth(), 0.0);
}

/// Nodes coarser than the wear grid (a node's arc over 2, 4 and 2.78 cells) under one even
/// load all around wear every cell alike, at the closed-form depth `K_d p |v| dt/2` of each
/// end: each node covers the cells under its own arc. (Split between the two nearest cell
/// centres, as for nodes finer than the cells, four cells a node left half the cells bare.)
#[test]
fn nodes_coarser_than_the_cells_wear_an_even_load_evenly() {
    use contact::NodeLoad;
    for (cells, node_cells) in [(1000, 500), (1000, 250), (1000, 360)] {
        let mut stage = joint(cells).start_stage();
        let arc = R_PIN * TAU / node_cells as f64;
        let nodes: Vec<NodeLoad> = (0..node_cells)
            .map(|k| node(k, node_cells, 40.0, 0.2))
            .collect();
        let dt = 1e-4;
        stage.accumulate_nodes(&nodes, &nodes, dt).unwrap();
        // Both ends; each surface holds half the depth over its own radius (`layer_volume`).
        let depth = 2.0 * 1.8e-13 * 40.0 / (arc * 0.1) * 0.2 * 0.5 * dt;
        for d in stage.pin() {
            assert_relative_eq!(*d, depth, max_relative = 1e-9);
        }
        for d in stage.bearing() {
            assert_relative_eq!(*d, depth * R_PIN / R_BEARING, max_relative = 1e-9);
        }
    }
}

/// Smoothing a stage's wear keeps its volume, spreads a one-cell spike into a Gaussian of the
/// given width (periodic across 0/2π), and leaves a uniform layer alone.
#[test]
fn smoothing_keeps_the_volume_and_spreads_a_spike() {
    use wear::StageWear;
    let joint = joint(200);
    let mut spike = vec![0.0; 200];
    spike[1] = 1e-6;
    let mut wear = StageWear::from_depths(&joint, spike.clone(), vec![2e-7; 200]).unwrap();
    let before = wear.worn_volume();
    wear.smooth(3.0 * TAU / 200.0); // three cells
    assert_relative_eq!(wear.worn_volume(), before, max_relative = 1e-12);
    // Peak height 1/(σ√(2π)) of the spike, centred on its cell; the tail wraps through 0.
    assert_relative_eq!(
        wear.bearing()[1],
        1e-6 / (3.0 * TAU.sqrt()),
        max_relative = 1e-3
    );
    assert_relative_eq!(wear.bearing()[199], wear.bearing()[3], max_relative = 1e-12);
    assert!(wear.pin().iter().all(|h| (h - 2e-7).abs() < 1e-18));
    // No smoothing: unchanged.
    let mut same = StageWear::from_depths(&joint, spike.clone(), vec![0.0; 200]).unwrap();
    same.smooth(0.0);
    assert_eq!(same.bearing(), &spike[..]);
}

#[test]
fn node_deposits_carry_their_relaxation_and_a_whole_circle_zone_relaxes_even_wear() {
    use contact::NodeLoad;
    // Nodes on every pin cell centre, meeting the bearing at the same angle, all alike.
    let cells = 200;
    let joint = joint(cells);
    let arc = R_PIN * TAU / cells as f64;
    let (stiffness, speed, dt) = (4e9, 0.3, 1e-4);
    // A turning pin: its even wear comes from nodes all around (here all at once).
    let nodes: Vec<NodeLoad> = (0..cells)
        .map(|k| NodeLoad {
            stiffness,
            ..node(k, cells, 100.0, speed)
        })
        .collect();
    let mut stage = joint.start_stage().gathering_zones(true);
    stage.accumulate_nodes(&nodes, &nodes, dt).unwrap();
    // Two ends of K_d S |v| (dt/2)/(arc w): the depth's derivative in the overlap.
    let lambda = 1.8e-13 * stiffness * speed * dt / (arc * 0.1);
    assert_relative_eq!(stage.pin_relaxation()[60], lambda, max_relative = 1e-12);
    // The bearing's wider cells hold the node's share, as its depths do.
    assert_relative_eq!(
        stage.bearing_relaxation()[60],
        lambda * R_PIN / R_BEARING,
        max_relative = 1e-9
    );
    assert_relative_eq!(stage.relaxation_weighted(), lambda, max_relative = 1e-9);
    // One zone of all 200 nodes at once: even wear all around is no translation of it, so
    // the implicit step relaxes it like any shape, by 1/(1 + aλ) with aλ ≈ 1 here.
    let (implicit, iterations) = stage.implicit(1.0 / lambda);
    assert!(iterations > 0);
    // Exactly: the zone's λ is the mean of the two surfaces' shares (R_pin/R_bearing on the
    // bearing), and the even parts c_b, c_p solve [1 + μ, μ; μ, 1 + μ] c̃ = c, μ = aλ/2
    // (equal depths would be halved).
    let mu = 0.5 * 0.5 * (1.0 + R_PIN / R_BEARING);
    for k in [0, 60, 199] {
        let (cb, cp) = (stage.bearing()[k], stage.pin()[k]);
        let expected = ((1.0 + mu) * cp - mu * cb) / (1.0 + 2.0 * mu);
        assert_relative_eq!(implicit.pin()[k], expected, max_relative = 1e-6);
        assert!(implicit.pin()[k] < 0.51 * cp);
    }
}

#[test]
fn a_turning_pins_even_wear_passes_the_implicit_step() {
    use contact::NodeLoad;
    // The load stays at the bearing's bottom while the pin turns a cell per instant: a zone
    // of 10 nodes meets the same bearing cells each time, and every pin cell once in each of
    // the zone's places. The pin wears evenly (steady), the bearing a flat patch.
    let cells = 200;
    let joint = joint(cells);
    let per_cell = TAU / cells as f64;
    let arc = R_PIN * per_cell;
    let mut stage = joint.start_stage().gathering_zones(true);
    for t in 0..cells {
        let nodes: Vec<NodeLoad> = (0..10)
            .map(|m| {
                let k = (t + m) % cells;
                NodeLoad {
                    cell: k,
                    pin_angle: (k as f64 + 0.5) * per_cell,
                    bearing_angle: (145 + m) as f64 * per_cell,
                    normal_force: 100.0,
                    arc,
                    material_sliding: 0.3,
                    paper_sliding: 0.0,
                    stiffness: 4e9,
                }
            })
            .collect();
        stage.accumulate_nodes(&nodes, &nodes, 1e-4).unwrap();
    }
    let lambda = stage.relaxation_weighted();
    let (implicit, _) = stage.implicit(4.0 / lambda);
    let even = stage.pin()[17];
    for k in 0..cells {
        assert_relative_eq!(stage.pin()[k], even, max_relative = 1e-9);
        // Within the zone's curvature (a flat patch is a translation over 0.31 rad to 1 %).
        let ratio = implicit.pin()[k] / even;
        assert!((ratio - 1.0).abs() < 0.02, "pin cell {k}: ×{ratio}");
    }
    eprintln!(
        "aλ = 4 (pin λ {:.3e} per unit): even pin wear ×{:.4} (frame-fixed step: ×0.2), {} zone(s)",
        lambda,
        implicit.pin()[17] / even,
        stage.zones().len()
    );
}
