//! Validation: every value of a parsed scene checked, each problem an [`Issue`](super::Issue) naming its
//! field path; contact laws and materials are checked by `contact` itself.

use contact::ContactError;
use std::collections::HashSet;

use super::error::Validator;
use super::limits::MAX_K_D_SCATTER;
use super::{
    BodyRef, ClearanceJointSpec, DriverTarget, GROUND, MAX_WEAR_CELLS, Scene, SceneError, Solver,
    TimeLaw,
};

impl Scene {
    /// Check every value; `origin` names the scene in the error.
    pub fn validate(&self, origin: &str) -> Result<(), SceneError> {
        let mut v = Validator::default();
        v.scene(self);
        super::limits::check(&mut v, self);
        if v.issues.is_empty() {
            Ok(())
        } else {
            Err(SceneError::Invalid {
                origin: origin.to_string(),
                issues: v.issues,
            })
        }
    }
}

impl Validator {
    fn vector(&mut self, path: &str, v: [f64; 2]) {
        for (k, x) in v.iter().enumerate() {
            self.number(&format!("{path}[{k}]"), *x, false);
        }
    }

    fn body_name(&mut self, scene: &Scene, path: &str, name: &str) {
        if scene.resolve(name).is_none() {
            self.push(path, name, format!("no body of this name (nor `{GROUND}`)"));
        }
    }

    fn unique<'a>(&mut self, seen: &mut HashSet<&'a str>, path: &str, name: &'a str) {
        if name.trim().is_empty() {
            self.push(path, name, "must not be empty");
        } else if !seen.insert(name) {
            self.push(path, name, "duplicate name");
        }
    }

    fn scene(&mut self, s: &Scene) {
        self.vector("gravity", s.gravity);
        if s.bodies.is_empty() {
            self.push("bodies", "[]", "a scene needs at least one body");
        }
        let mut seen = HashSet::new();
        for (k, b) in s.bodies.iter().enumerate() {
            let p = format!("bodies[{k}]");
            if b.name == GROUND {
                self.push(format!("{p}.name"), &b.name, "`ground` is reserved");
            }
            self.unique(&mut seen, &format!("{p}.name"), &b.name);
            self.number(&format!("{p}.mass"), b.mass, true);
            self.number(&format!("{p}.inertia"), b.inertia, true);
            self.number(&format!("{p}.x"), b.x, false);
            self.number(&format!("{p}.y"), b.y, false);
            self.number(&format!("{p}.theta_deg"), b.theta.deg(), false);
            self.vector(&format!("{p}.velocity"), b.velocity);
            self.number(&format!("{p}.omega"), b.omega, false);
        }
        let mut joints = HashSet::new();
        for (k, j) in s.revolute_joints.iter().enumerate() {
            let p = format!("revolute_joints[{k}]");
            self.unique(&mut joints, &format!("{p}.name"), &j.name);
            self.pair(
                s,
                &p,
                ("body", &j.body, j.point),
                ("other", &j.other, j.other_point),
            );
        }
        for (k, j) in s.prismatic_joints.iter().enumerate() {
            let p = format!("prismatic_joints[{k}]");
            self.unique(&mut joints, &format!("{p}.name"), &j.name);
            self.pair(
                s,
                &p,
                ("body", &j.body, j.point),
                ("other", &j.other, j.other_point),
            );
            self.vector(&format!("{p}.direction"), j.direction);
            if j.direction.iter().all(|x| *x == 0.0) {
                self.push(format!("{p}.direction"), j.direction, "must not be zero");
            }
        }
        for (k, c) in s.clearance_joints.iter().enumerate() {
            let p = format!("clearance_joints[{k}]");
            self.unique(&mut joints, &format!("{p}.name"), &c.name);
            self.clearance_joint(s, &p, c);
            // Output files are named after the joint: two names must not make the same file.
            for (i, other) in s.clearance_joints[..k].iter().enumerate() {
                if other.name == c.name {
                    continue;
                }
                if let Some(file) = super::file_names::colliding_file(&other.name, &c.name) {
                    self.push(
                        format!("{p}.name"),
                        &c.name,
                        format!(
                            "both it and clearance_joints[{i}].name = {:?} would write {file}: \
                             choose names that do not extend each other this way",
                            other.name
                        ),
                    );
                }
            }
        }
        let mut drivers = HashSet::new();
        for (k, d) in s.drivers.iter().enumerate() {
            let p = format!("drivers[{k}]");
            self.unique(&mut drivers, &format!("{p}.name"), &d.name);
            match &d.target {
                DriverTarget::BodyCoordinate { body, .. } => {
                    if !matches!(s.resolve(body), Some(BodyRef::Body(_))) {
                        self.push(format!("{p}.target.body"), body, "no body of this name");
                    }
                }
                DriverTarget::JointAngle { joint } => {
                    if !s.revolute_joints.iter().any(|j| &j.name == joint) {
                        self.push(
                            format!("{p}.target.joint"),
                            joint,
                            "no revolute joint of this name",
                        );
                    }
                }
            }
            self.law(&format!("{p}.law"), &d.law);
        }
        self.solver(&s.solver);
        self.run(s);
    }

    fn pair(
        &mut self,
        s: &Scene,
        p: &str,
        (bkey, body, point): (&str, &str, [f64; 2]),
        (okey, other, other_point): (&str, &str, [f64; 2]),
    ) {
        self.body_name(s, &format!("{p}.{bkey}"), body);
        self.body_name(s, &format!("{p}.{okey}"), other);
        if body == other {
            self.push(
                format!("{p}.{okey}"),
                other,
                format!("same body as `{bkey}`"),
            );
        }
        self.vector(&format!("{p}.point"), point);
        self.vector(&format!("{p}.other_point"), other_point);
    }

    fn law(&mut self, p: &str, law: &TimeLaw) {
        match law {
            TimeLaw::Constant { value } => {
                self.number(&format!("{p}.value"), *value, false);
            }
            TimeLaw::Ramp { value, rate } => {
                self.number(&format!("{p}.value"), *value, false);
                self.number(&format!("{p}.rate"), *rate, false);
            }
            TimeLaw::Harmonic {
                offset,
                amplitude,
                rpm,
                omega,
            } => {
                self.number(&format!("{p}.offset"), *offset, false);
                self.number(&format!("{p}.amplitude"), *amplitude, false);
                match (rpm, omega) {
                    (Some(r), None) => {
                        self.number(&format!("{p}.rpm"), *r, true);
                    }
                    (None, Some(w)) => {
                        self.number(&format!("{p}.omega"), *w, true);
                    }
                    (None, None) => self.push(p, "{}", "give `rpm` or `omega`"),
                    (Some(r), Some(w)) => self.push(
                        p,
                        (r, w),
                        "give `rpm` or `omega`, not both (rpm, omega shown)",
                    ),
                }
            }
        }
    }

    fn clearance_joint(&mut self, s: &Scene, p: &str, c: &ClearanceJointSpec) {
        self.body_name(s, &format!("{p}.bearing_body"), &c.bearing_body);
        self.body_name(s, &format!("{p}.pin_body"), &c.pin_body);
        if c.bearing_body == c.pin_body {
            self.push(
                format!("{p}.pin_body"),
                &c.pin_body,
                "same body as the bearing",
            );
        }
        self.vector(&format!("{p}.bearing_point"), c.bearing_point);
        self.vector(&format!("{p}.pin_point"), c.pin_point);
        let radius_ok = self.number(&format!("{p}.bearing_radius"), c.bearing_radius, true);
        if self.number(&format!("{p}.clearance"), c.clearance, true)
            && radius_ok
            && c.clearance >= c.bearing_radius
        {
            self.push(
                format!("{p}.clearance"),
                c.clearance,
                format!(
                    "must be smaller than bearing_radius ({} m): the pin radius is their difference",
                    c.bearing_radius
                ),
            );
        }
        for (side, m) in [("bearing", c.bearing_material), ("pin", c.pin_material)] {
            self.contact(
                &format!("{p}.{side}_material"),
                contact::Material::try_from(m),
            );
        }
        self.contact(
            &format!("{p}.normal_law"),
            contact::NormalLawKind::from_params(c.normal_law),
        );
        self.contact(
            &format!("{p}.friction"),
            contact::FrictionLawKind::from_params(c.friction),
        );
        c.contact.check(self, p, c, &s.run);
        if let Some(w) = &c.wear {
            let q = format!("{p}.wear");
            self.number(&format!("{q}.k_d"), w.k_d, true);
            if let Some(h) = w.hardness {
                self.number(&format!("{q}.hardness"), h, true);
            }
            self.number(&format!("{q}.width"), w.width, true);
            if self.number(&format!("{q}.k_d_scatter"), w.k_d_scatter, false)
                && !(0.0..=MAX_K_D_SCATTER).contains(&w.k_d_scatter)
            {
                self.push(
                    format!("{q}.k_d_scatter"),
                    w.k_d_scatter,
                    format!(
                        "must lie in [0, {MAX_K_D_SCATTER}] (the standard deviation of ln k_d; \
                         {MAX_K_D_SCATTER} already spreads k_d by a factor of 20 either way)"
                    ),
                );
            }
            if !(8..=MAX_WEAR_CELLS).contains(&w.cells) {
                self.push(
                    format!("{q}.cells"),
                    w.cells,
                    format!("must lie in 8..={MAX_WEAR_CELLS}"),
                );
            }
        }
    }

    /// Records `contact`'s verdict on a law or material (its ranges are defined once, there)
    /// under the field path of the parameter it names.
    fn contact<T>(&mut self, q: &str, checked: Result<T, ContactError>) {
        match checked {
            Ok(_) => {}
            Err(ContactError::NonFinite { parameter, value }) => {
                self.push(format!("{q}.{parameter}"), value, "must be a finite number");
            }
            Err(ContactError::OutOfRange {
                parameter,
                value,
                expected,
            }) => self.push(
                format!("{q}.{parameter}"),
                value,
                format!("must be {expected}"),
            ),
            Err(other) => self.push(q, "…", other.to_string()),
        }
    }

    fn solver(&mut self, s: &Solver) {
        if self.number("solver.rtol", s.rtol, true) && s.rtol >= 1.0 {
            self.push("solver.rtol", s.rtol, "must be below 1");
        }
        if let Some(a) = s.atol_position {
            self.number("solver.atol_position", a, true);
        }
        if let Some(a) = s.atol_angle {
            self.number("solver.atol_angle", a, true);
        }
        self.number("solver.atol_velocity", s.atol_velocity, true);
        self.number("solver.output_interval", s.output_interval, true);
        self.number("solver.baumgarte_alpha", s.baumgarte_alpha, false);
        self.number("solver.baumgarte_beta", s.baumgarte_beta, false);
        if s.max_steps == Some(0) {
            self.push("solver.max_steps", 0, "must be at least 1");
        }
        if let Some(t) = s.max_wall_time {
            self.number("solver.max_wall_time", t, true);
        }
    }

    /// `run.until_limit` and what it needs: the limit, a cycle budget and wear; `max_cycles`
    /// only with it.
    fn until_limit(&mut self, s: &Scene) {
        let r = &s.run;
        if let Some(max) = r.max_cycles
            && self.number("run.max_cycles", max, true)
            && !r.until_limit
        {
            self.push(
                "run.max_cycles",
                max,
                "only bounds a run with run.until_limit = true (drop it, or set that)",
            );
        }
        if !r.until_limit {
            return;
        }
        if r.clearance_limit.is_none() {
            self.push(
                "run.until_limit",
                true,
                "needs run.clearance_limit, the largest local clearance to run to (m)",
            );
        }
        if r.max_cycles.is_none() {
            self.push(
                "run.max_cycles",
                "none",
                "required with run.until_limit = true: the most drive cycles the stages may \
                 stand for, so that a joint that wears slowly does not run without end",
            );
        }
        let wears = s.active_clearance_joints().any(|c| c.wear.is_some());
        if r.wear_stages == 0 || !wears {
            self.push(
                "run.until_limit",
                true,
                "needs wear: run.wear_stages at least 1 and a clearance joint with a wear table",
            );
        }
    }

    /// An optional setting in `(0, 1]` that only sub-steps use: refused outside that interval,
    /// and with the single jump (`adaptive` false), which has no sub-steps to `purpose`.
    /// Returns the value where it passed, for the setting's own further checks.
    fn sub_step_setting(
        &mut self,
        path: &str,
        value: Option<f64>,
        adaptive: bool,
        purpose: &str,
    ) -> Option<f64> {
        let v = value.filter(|v| self.number(path, *v, true))?;
        if v > 1.0 {
            self.push(path, v, "must lie in (0, 1]");
            None
        } else if !adaptive {
            self.push(
                path,
                v,
                format!(
                    "needs run.adaptive_extrapolation = true (the single jump has no sub-steps \
                     to {purpose})"
                ),
            );
            None
        } else {
            Some(v)
        }
    }

    fn run(&mut self, s: &Scene) {
        let r = &s.run;
        if let Some(t) = r.period {
            self.number("run.period", t, true);
        }
        if (r.cycles > 0 || r.wear_stages > 0) && s.cycle_period().is_none() {
            self.push(
                "run.period",
                "none",
                "no driver has a periodic law (harmonic, or a ramp on an angle); give run.period",
            );
        }
        if r.wear_stages > 0 && r.cycles_per_stage == 0 {
            self.push(
                "run.cycles_per_stage",
                0,
                "must be positive when wear_stages > 0",
            );
        }
        // That they divide K is checked by the run, once K's override is known.
        if r.trajectories == 0 {
            self.push("run.trajectories", 0, "must be at least 1");
        }
        self.number("run.amplification", r.amplification, true);
        let f = r.max_clearance_change;
        if self.number("run.max_clearance_change", f, true) && f > 1.0 {
            self.push("run.max_clearance_change", f, "must lie in (0, 1]");
        }
        if self.number("run.wear_smoothing_deg", r.wear_smoothing_deg, false)
            && !(0.0..=30.0).contains(&r.wear_smoothing_deg)
        {
            self.push(
                "run.wear_smoothing_deg",
                r.wear_smoothing_deg,
                "must lie in [0, 30] degrees (0: no smoothing; a Gaussian wider than a contact \
                 zone would erase the wear pattern)",
            );
        }
        self.sub_step_setting(
            "run.forming_clearance_change",
            r.forming_clearance_change,
            r.adaptive_extrapolation,
            "bound",
        );
        if let Some(depth) = r.forming_depth
            && self.number("run.forming_depth", depth, true)
        {
            if depth > 1.0 {
                self.push(
                    "run.forming_depth",
                    depth,
                    "must lie in (0, 1] (a fraction of the joint's nominal clearance)",
                );
            } else if r.forming_clearance_change.is_none() {
                self.push(
                    "run.forming_depth",
                    depth,
                    "has no effect without run.forming_clearance_change (the finer bound it \
                     ends; set both, or neither)",
                );
            }
        }
        if let Some(bound) = r.max_slope_change {
            self.number("run.max_slope_change", bound, true);
        }
        if let Some(bound) = r.max_curvature_change {
            self.number("run.max_curvature_change", bound, true);
        }
        if let Some(tolerance) = self.sub_step_setting(
            "run.wear_tolerance",
            r.wear_tolerance,
            r.adaptive_extrapolation,
            "control",
        ) && r.wear_stepping == wear::WearStepping::LinearlyImplicit
        {
            self.push(
                "run.wear_tolerance",
                tolerance,
                "cannot be combined with run.wear_stepping = \"linearly-implicit\" \
                 (error-controlled sub-steps are an explicit predictor-corrector; drop one)",
            );
        }
        if let Some(target) = self.sub_step_setting(
            "run.wear_noise",
            r.wear_noise,
            r.adaptive_extrapolation,
            "size",
        ) && r.wear_tolerance.is_some()
        {
            self.push(
                "run.wear_noise",
                target,
                "cannot be combined with run.wear_tolerance (error-controlled sub-steps \
                 size themselves; drop one)",
            );
        }
        if r.max_substeps == 0 {
            self.push("run.max_substeps", 0, "must be at least 1");
        }
        if let Some(name) = &r.response_body
            && !matches!(s.resolve(name), Some(BodyRef::Body(_)))
        {
            self.push("run.response_body", name, "no body of this name");
        }
        if let Some(limit) = r.clearance_limit
            && self.number("run.clearance_limit", limit, true)
        {
            for (k, c) in s.clearance_joints.iter().enumerate() {
                if !c.ideal && c.clearance.is_finite() && limit <= c.clearance {
                    self.push(
                        "run.clearance_limit",
                        limit,
                        format!(
                            "must exceed the initial clearance of every clearance joint: \
                             clearance_joints[{k}] ({}) starts at {} m",
                            c.name, c.clearance
                        ),
                    );
                }
            }
        }
        self.until_limit(s);
        if self.number("run.transient_window", r.transient_window, false)
            && r.transient_window < 0.0
        {
            self.push(
                "run.transient_window",
                r.transient_window,
                "must not be negative",
            );
        }
    }
}
