//! The Cartesian state of a mechanism and the tolerances it is integrated to: the values both
//! formulations, the system and the integration loop share (nothing here imports the rest of
//! the crate).

/// A configuration that satisfies the constraints: positions and velocities at time `t`.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Time (s).
    pub t: f64,
    /// Coordinates `(x, y, θ)` per body (m, rad).
    pub q: Vec<f64>,
    /// Velocities (m/s, rad/s).
    pub qd: Vec<f64>,
}

/// Absolute tolerances per kind of state variable. Positions should be scaled to the
/// smallest length that matters (e.g. a joint clearance, docs/model.md §8), not to the coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AbsoluteTolerances {
    /// m
    pub position: f64,
    /// rad
    pub angle: f64,
    /// m/s
    pub velocity: f64,
    /// rad/s
    pub angular_velocity: f64,
}

impl Default for AbsoluteTolerances {
    /// 1e-8 m, 1e-8 rad, 1e-6 m/s, 1e-6 rad/s: well below the micrometre scale of clearance
    /// penetrations for mechanisms about a metre in size.
    fn default() -> Self {
        Self {
            position: 1e-8,
            angle: 1e-8,
            velocity: 1e-6,
            angular_velocity: 1e-6,
        }
    }
}

impl AbsoluteTolerances {
    /// The same tolerance for every variable.
    pub fn uniform(value: f64) -> Self {
        Self {
            position: value,
            angle: value,
            velocity: value,
            angular_velocity: value,
        }
    }
}
