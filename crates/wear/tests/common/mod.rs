//! Shared fixtures: LGRES joint B geometry and synthetic contact states.
#![allow(dead_code)]

use contact::{ContactDiagnostics, NodeLoad};
use std::f64::consts::TAU;
use wear::{WearParams, WornJoint};

pub const R_BEARING: f64 = 0.080;
pub const CLEARANCE: f64 = 0.0005;
pub const R_PIN: f64 = R_BEARING - CLEARANCE;
pub const WIDTH: f64 = 0.1;
pub const K_D: f64 = 1.8e-13;

pub fn joint(cells: usize) -> WornJoint {
    let params = WearParams::new(K_D, WIDTH, cells).unwrap();
    WornJoint::new(&params, R_BEARING, R_PIN).unwrap()
}

/// A loaded contact state with penetration `delta` on the nominal geometry.
pub fn loaded(
    force: f64,
    speed: f64,
    delta: f64,
    pin_angle: f64,
    bearing_angle: f64,
) -> ContactDiagnostics {
    ContactDiagnostics {
        in_contact: true,
        penetration: delta,
        eccentricity: CLEARANCE + delta,
        bearing_radius: R_BEARING,
        pin_radius: R_PIN,
        normal_force: force,
        tangential_velocity: speed,
        pin_angle,
        bearing_angle,
        ..Default::default()
    }
}

/// Node `k` of `nodes` around the pin at its cell's centre, carrying its arc `R_j 2π/nodes`,
/// meeting the bearing at the same angle: normal force `force` (N), material sliding `speed`
/// (m/s), stiffness 1e9 N/m.
pub fn node(k: usize, nodes: usize, force: f64, speed: f64) -> NodeLoad {
    let angle = (k as f64 + 0.5) * TAU / nodes as f64;
    NodeLoad {
        cell: k,
        pin_angle: angle,
        bearing_angle: angle,
        normal_force: force,
        arc: R_PIN * TAU / nodes as f64,
        material_sliding: speed,
        paper_sliding: 0.0,
        stiffness: 1e9,
    }
}
