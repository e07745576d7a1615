//! Recorded frames.

/// States, accelerations and multipliers at a series of times (a simulation's output frames
/// or a kinematic analysis), stored flat: frame `i` of `q` is `q[i*n..(i+1)*n]`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Trajectory {
    pub times: Vec<f64>,
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
    /// Lagrange multipliers, `m` per frame, in the order of
    /// [`crate::System::constraint_labels`].
    pub lambda: Vec<f64>,
    pub coordinates: usize,
    pub constraints: usize,
}

impl Trajectory {
    pub fn len(&self) -> usize {
        self.times.len()
    }
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }
    pub fn q(&self, frame: usize) -> &[f64] {
        &self.q[frame * self.coordinates..(frame + 1) * self.coordinates]
    }
    pub fn qd(&self, frame: usize) -> &[f64] {
        &self.qd[frame * self.coordinates..(frame + 1) * self.coordinates]
    }
    pub fn qdd(&self, frame: usize) -> &[f64] {
        &self.qdd[frame * self.coordinates..(frame + 1) * self.coordinates]
    }
    pub fn lambda(&self, frame: usize) -> &[f64] {
        &self.lambda[frame * self.constraints..(frame + 1) * self.constraints]
    }
}
