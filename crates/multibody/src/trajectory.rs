//! Recorded frames.

/// States, accelerations and multipliers at a series of times (a simulation's output frames
/// or a kinematic analysis), stored flat: frame `i` of `q` is `q[i*n..(i+1)*n]`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Trajectory {
    /// Frame times (s).
    pub times: Vec<f64>,
    /// Coordinates `q`, `n` per frame (m, rad).
    pub q: Vec<f64>,
    /// Velocities `q̇`, `n` per frame (m/s, rad/s).
    pub qd: Vec<f64>,
    /// Accelerations `q̈`, `n` per frame (m/s², rad/s²).
    pub qdd: Vec<f64>,
    /// Lagrange multipliers, `m` per frame, in the order of
    /// [`crate::System::constraint_labels`].
    pub lambda: Vec<f64>,
    /// `n`, the stride of `q`, `qd` and `qdd`.
    pub coordinates: usize,
    /// `m`, the stride of `lambda`.
    pub constraints: usize,
}

impl Trajectory {
    /// Number of frames.
    pub fn len(&self) -> usize {
        self.times.len()
    }
    /// Whether no frame was recorded.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }
    /// Coordinates of frame `frame` (panics if out of range, like slice indexing).
    pub fn q(&self, frame: usize) -> &[f64] {
        &self.q[frame * self.coordinates..(frame + 1) * self.coordinates]
    }
    /// Velocities of frame `frame`.
    pub fn qd(&self, frame: usize) -> &[f64] {
        &self.qd[frame * self.coordinates..(frame + 1) * self.coordinates]
    }
    /// Accelerations of frame `frame`.
    pub fn qdd(&self, frame: usize) -> &[f64] {
        &self.qdd[frame * self.coordinates..(frame + 1) * self.coordinates]
    }
    /// Multipliers of frame `frame`.
    pub fn lambda(&self, frame: usize) -> &[f64] {
        &self.lambda[frame * self.constraints..(frame + 1) * self.constraints]
    }
}
