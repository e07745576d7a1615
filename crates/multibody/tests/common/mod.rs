//! Mechanisms shared by the integration tests.
#![allow(dead_code)]

pub mod lgres_scene;

use multibody::{
    Anchor, Body, BodyId, DriveFunction, DriveTarget, ElementId, ForceElement, ForcePartials,
    Gravity, JointId, Model, RotationLock, State, System,
};

pub const G: f64 = 9.81;

/// Adds a uniform bar of `mass` and `length` (centroidal inertia `m l² / 12`) at `pose`.
pub fn bar(model: &mut Model, name: &str, mass: f64, length: f64, pose: [f64; 3]) -> BodyId {
    model
        .add_body(Body::new(name, mass, mass * length * length / 12.0, pose))
        .expect("valid body")
}

/// Largest `|a_i − b_i|`.
pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The near and far ends (`∓length/2` along its x axis) of a bar of `length`.
pub fn ends(body: BodyId, length: f64) -> (Anchor, Anchor) {
    (
        Anchor::on(body, -0.5 * length, 0.0),
        Anchor::on(body, 0.5 * length, 0.0),
    )
}

/// Adds a revolute joint making the anchors `i` and `j` coincide.
pub fn pin(model: &mut Model, name: &str, i: Anchor, j: Anchor) -> JointId {
    model.add_revolute(name, i, j).expect("valid joint")
}

/// Slider-crank: crank length `r` pinned at the origin, rod length `l`, slider on the x axis
/// (rotation locked). Bodies: crank, rod, slider. Returns the model and the crank joint.
pub struct SliderCrank {
    pub r: f64,
    pub l: f64,
}

impl SliderCrank {
    pub const STANDARD: Self = Self { r: 0.1, l: 0.3 };

    /// Closed-form coordinates `(crank, rod, slider)` for crank angle `phi`.
    pub fn positions(&self, phi: f64) -> [f64; 9] {
        let (r, l) = (self.r, self.l);
        let tip = [r * phi.cos(), r * phi.sin()];
        let psi = -(r * phi.sin() / l).asin();
        let x_slider = tip[0] + l * psi.cos();
        [
            0.5 * tip[0],
            0.5 * tip[1],
            phi,
            tip[0] + 0.5 * l * psi.cos(),
            tip[1] + 0.5 * l * psi.sin(),
            psi,
            x_slider,
            0.0,
            0.0,
        ]
    }

    pub fn model(&self, phi: f64) -> (Model, JointId) {
        let q = self.positions(phi);
        let mut model = Model::new();
        let crank = bar(&mut model, "crank", 1.0, self.r, [q[0], q[1], q[2]]);
        let rod = bar(&mut model, "rod", 2.0, self.l, [q[3], q[4], q[5]]);
        let slider = model
            .add_body(Body::new("slider", 3.0, 0.01, [q[6], q[7], q[8]]))
            .expect("valid body");
        let (crank_near, crank_far) = ends(crank, self.r);
        let (rod_near, rod_far) = ends(rod, self.l);
        let pivot = pin(&mut model, "O", Anchor::ground(0.0, 0.0), crank_near);
        pin(&mut model, "A", crank_far, rod_near);
        pin(&mut model, "B", rod_far, Anchor::on(slider, 0.0, 0.0));
        model
            .add_prismatic(
                "guide",
                Anchor::ground(0.0, 0.0),
                [1.0, 0.0],
                Anchor::on(slider, 0.0, 0.0),
                RotationLock::At(0.0),
            )
            .expect("valid joint");
        (model, pivot)
    }
}

/// Crank-rocker four-bar: ground pivots at (0,0) and (d,0); crank a, coupler b, rocker c.
pub struct FourBar {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub d: f64,
}

impl FourBar {
    pub const STANDARD: Self = Self {
        a: 0.2,
        b: 0.5,
        c: 0.4,
        d: 0.45,
    };

    /// Closed-form coordinates for crank angle `phi` (open assembly, coupler above).
    pub fn positions(&self, phi: f64) -> [f64; 9] {
        let p_a = [self.a * phi.cos(), self.a * phi.sin()];
        let o4 = [self.d, 0.0];
        let delta = [o4[0] - p_a[0], o4[1] - p_a[1]];
        let e = delta[0].hypot(delta[1]);
        // Circle intersection: B at distance b from A and c from O4, above the line A→O4.
        let along = (self.b * self.b - self.c * self.c + e * e) / (2.0 * e);
        let height = (self.b * self.b - along * along).sqrt();
        let u = [delta[0] / e, delta[1] / e];
        let p_b = [
            p_a[0] + along * u[0] - height * u[1],
            p_a[1] + along * u[1] + height * u[0],
        ];
        let coupler = (p_b[1] - p_a[1]).atan2(p_b[0] - p_a[0]);
        let rocker = (p_b[1] - o4[1]).atan2(p_b[0] - o4[0]);
        [
            0.5 * p_a[0],
            0.5 * p_a[1],
            phi,
            0.5 * (p_a[0] + p_b[0]),
            0.5 * (p_a[1] + p_b[1]),
            coupler,
            0.5 * (o4[0] + p_b[0]),
            0.5 * (o4[1] + p_b[1]),
            rocker,
        ]
    }

    pub fn model(&self, phi: f64) -> (Model, JointId) {
        self.model_at(&self.positions(phi))
    }

    /// The four-bar with its bodies at the poses `q` (which need not close the loop, e.g. for
    /// lengths that cannot assemble).
    pub fn model_at(&self, q: &[f64]) -> (Model, JointId) {
        let mut model = Model::new();
        let pose = |k: usize| [q[k], q[k + 1], q[k + 2]];
        let crank = bar(&mut model, "crank", 1.0, self.a, pose(0));
        let coupler = bar(&mut model, "coupler", 2.0, self.b, pose(3));
        let rocker = bar(&mut model, "rocker", 1.5, self.c, pose(6));
        let (crank_near, crank_far) = ends(crank, self.a);
        let (coupler_near, coupler_far) = ends(coupler, self.b);
        let (rocker_near, rocker_far) = ends(rocker, self.c);
        let pivot = pin(&mut model, "O2", Anchor::ground(0.0, 0.0), crank_near);
        pin(&mut model, "A", crank_far, coupler_near);
        pin(&mut model, "B", coupler_far, rocker_far);
        pin(&mut model, "O4", Anchor::ground(self.d, 0.0), rocker_near);
        (model, pivot)
    }
}

/// A uniform rod of length `length` pinned at one end to the ground origin, hanging at angle
/// `theta` (−π/2 = straight down).
pub fn pendulum(mass: f64, length: f64, theta: f64) -> Model {
    let mut model = Model::new();
    let pose = [
        0.5 * length * theta.cos(),
        0.5 * length * theta.sin(),
        theta,
    ];
    let rod = bar(&mut model, "rod", mass, length, pose);
    pin(
        &mut model,
        "pin",
        Anchor::ground(0.0, 0.0),
        Anchor::on(rod, -0.5 * length, 0.0),
    );
    model
}

/// Adds gravity (−y) to a compiled system built from `model`'s bodies.
pub fn with_gravity(model: Model) -> System {
    let gravity = Gravity::new(&model, [0.0, -G]);
    let mut system = System::new(model).expect("valid model");
    system.add_element(Box::new(gravity));
    system
}

/// `system`'s initial guess assembled at `t = 0`.
pub fn assembled(system: &System) -> State {
    let (q, qd) = system.initial_guess();
    system.assemble(0.0, &q, &qd).expect("assembles")
}

/// [`with_gravity`] and `spring`: a system whose forces have partials in both q and q̇.
pub fn with_gravity_and_spring(model: Model, spring: SpringDamper) -> System {
    let mut system = with_gravity(model);
    system.add_element(Box::new(spring));
    system
}

/// A linear spring-damper from a point on a body to a ground point, with geometric
/// nonlinearity through the body's rotation: a force element with nonzero partials in both q
/// and q̇, reported through the two-body 6×12 layout.
pub struct SpringDamper {
    pub body: BodyId,
    pub point: [f64; 2],
    pub anchor: [f64; 2],
    pub stiffness: f64,
    pub damping: f64,
}

impl SpringDamper {
    /// A stiff spring-damper on body 1 (the four-bar's coupler), anchored far from it.
    pub const STIFF: Self = Self {
        body: BodyId(1),
        point: [0.1, 0.05],
        anchor: [0.3, 0.6],
        stiffness: 150.0,
        damping: 7.0,
    };

    /// A softer one on body 1 (the slider-crank's rod or the four-bar's coupler).
    pub const SOFT: Self = Self {
        body: BodyId(1),
        point: [0.1, 0.0],
        anchor: [0.2, 0.3],
        stiffness: 80.0,
        damping: 3.0,
    };

    /// Lever arm `a = A(θ)s`, force `F` and `∂a/∂θ = a⊥`.
    fn evaluate(&self, q: &[f64], qd: &[f64]) -> ([f64; 2], [f64; 2]) {
        let k = 3 * self.body.0;
        let (s, c) = q[k + 2].sin_cos();
        let a = [
            c * self.point[0] - s * self.point[1],
            s * self.point[0] + c * self.point[1],
        ];
        let omega = qd[k + 2];
        let position = [
            q[k] + a[0] - self.anchor[0],
            q[k + 1] + a[1] - self.anchor[1],
        ];
        let velocity = [qd[k] - omega * a[1], qd[k + 1] + omega * a[0]];
        let force = [
            -self.stiffness * position[0] - self.damping * velocity[0],
            -self.stiffness * position[1] - self.damping * velocity[1],
        ];
        (a, force)
    }
}

impl ForceElement for SpringDamper {
    fn name(&self) -> &str {
        "spring-damper"
    }

    fn add_forces(&self, _t: f64, q: &[f64], qd: &[f64], forces: &mut [f64]) {
        let (a, f) = self.evaluate(q, qd);
        let k = 3 * self.body.0;
        forces[k] += f[0];
        forces[k + 1] += f[1];
        forces[k + 2] += a[0] * f[1] - a[1] * f[0];
    }

    fn add_partials(&self, _t: f64, q: &[f64], qd: &[f64], partials: &mut ForcePartials<'_>) {
        let (a, f) = self.evaluate(q, qd);
        let omega = qd[3 * self.body.0 + 2];
        let (kk, cc) = (self.stiffness, self.damping);
        let a_perp = [-a[1], a[0]];
        // Columns: x, y, θ of F (two rows), then the moment row.
        let df_dq = [
            [-kk, 0.0, -kk * a_perp[0] + cc * omega * a[0]],
            [0.0, -kk, -kk * a_perp[1] + cc * omega * a[1]],
        ];
        let df_dqd = [[-cc, 0.0, -cc * a_perp[0]], [0.0, -cc, -cc * a_perp[1]]];
        let mut jacobian = [[0.0; 12]; 6];
        for col in 0..3 {
            jacobian[0][col] = df_dq[0][col];
            jacobian[1][col] = df_dq[1][col];
            jacobian[2][col] = a[0] * df_dq[1][col] - a[1] * df_dq[0][col];
            jacobian[0][6 + col] = df_dqd[0][col];
            jacobian[1][6 + col] = df_dqd[1][col];
            jacobian[2][6 + col] = a[0] * df_dqd[1][col] - a[1] * df_dqd[0][col];
        }
        // The lever arm turns with θ: ∂(a × F)/∂θ gains a⊥ × F.
        jacobian[2][2] += a_perp[0] * f[1] - a_perp[1] * f[0];
        partials.add_pair([Some(self.body), None], &jacobian);
    }
}

/// A drive that replays a recorded motion exactly at its sample times (the kinematic
/// analysis only asks at those times).
pub struct Replay {
    pub samples: Vec<(f64, f64, f64, f64)>,
}

impl Replay {
    fn nearest(&self, t: f64) -> (f64, f64, f64, f64) {
        self.samples
            .iter()
            .copied()
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
            .unwrap_or((t, 0.0, 0.0, 0.0))
    }
}

impl DriveFunction for Replay {
    fn value(&self, t: f64) -> f64 {
        self.nearest(t).1
    }
    fn velocity(&self, t: f64) -> f64 {
        self.nearest(t).2
    }
    fn acceleration(&self, t: f64) -> f64 {
        self.nearest(t).3
    }
}

pub fn angle_driver(model: &mut Model, joint: JointId, drive: Box<dyn DriveFunction>) {
    model
        .add_driver("crank drive", DriveTarget::JointAngle(joint), drive)
        .expect("valid driver");
}

pub fn first_element() -> ElementId {
    ElementId(0)
}
