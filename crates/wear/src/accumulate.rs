//! Archard wear accumulated over one stage's accepted integration steps ([`StageWear`]), and
//! the joint's side of a stage ([`WornJoint::start_stage`], [`WornJoint::apply`] and the bounds
//! on what applying a record would change): a record is built on a joint, so it sits above
//! `joint`, which knows nothing of it.

use std::f64::consts::TAU;

use contact::{ContactDiagnostics, NodeLoad, SlidingVelocity};

use crate::error::{WearError, finite, non_negative, positive};
use crate::implicit::{self, ContactZone, ZoneBook};
use crate::joint::{ContactArc, ShapeBound, WornJoint};
use crate::profile::{ArcDeposit, check_increment, layer_volume};

/// The wear depth a joint gathers during one stage, kept apart from its surfaces.
///
/// Within a stage the geometry the contact sees is frozen: steps add to these buffers, and
/// only [`WornJoint::apply`] moves them (amplified) into the surfaces. Feed it **accepted**
/// steps only; rejected steps and Newton iterations must not call it. Per step it neither
/// allocates nor touches more than the cells of the two contact arcs.
#[derive(Clone, Debug, PartialEq)]
pub struct StageWear {
    wear_coefficient: f64,
    sliding: SlidingVelocity,
    hinge_width: f64,
    bearing_radius: f64,
    pin_radius: f64,
    bearing: Vec<f64>,
    pin: Vec<f64>,
    /// Per cell, how much of the gap's overlap the record's wear closes per unit of overlap
    /// (dimensionless, see [`relaxation`](Self::bearing_relaxation)).
    bearing_relaxation: Vec<f64>,
    pin_relaxation: Vec<f64>,
    /// The contact zones of the record's steps: the wear process's Jacobian
    /// ([`implicit`](Self::implicit)); gathered only when asked.
    zones: ZoneBook,
    gather_zones: bool,
    archard_volume: f64,
    /// Cell weights of the last arc on each surface (see [`ArcDeposit`]).
    bearing_arc: ArcDeposit,
    pin_arc: ArcDeposit,
}

impl StageWear {
    /// An empty record for `joint`'s grids.
    pub fn new(joint: &WornJoint) -> Self {
        Self {
            wear_coefficient: joint.wear_coefficient(),
            sliding: joint.sliding(),
            hinge_width: joint.hinge_width(),
            bearing_radius: joint.bearing().nominal_radius(),
            pin_radius: joint.pin().nominal_radius(),
            bearing: vec![0.0; joint.bearing().cells()],
            pin: vec![0.0; joint.pin().cells()],
            bearing_relaxation: vec![0.0; joint.bearing().cells()],
            pin_relaxation: vec![0.0; joint.pin().cells()],
            zones: ZoneBook::default(),
            gather_zones: false,
            archard_volume: 0.0,
            bearing_arc: ArcDeposit::default(),
            pin_arc: ArcDeposit::default(),
        }
    }

    /// A record with given cell depths (m), for callers that compute wear their own way
    /// (and for tests). Depths must match the joint's grids and be finite and ≥ 0.
    pub fn from_depths(
        joint: &WornJoint,
        bearing: Vec<f64>,
        pin: Vec<f64>,
    ) -> Result<Self, WearError> {
        check_increment("bearing wear", joint.bearing(), &bearing)?;
        check_increment("pin wear", joint.pin(), &pin)?;
        let mut wear = Self::new(joint);
        wear.bearing = bearing;
        wear.pin = pin;
        Ok(wear)
    }

    /// The same record with given relaxations per cell (dimensionless, finite and ≥ 0, one per
    /// cell of each grid; see [`bearing_relaxation`](Self::bearing_relaxation)), for callers
    /// that compute wear their own way (and for tests).
    pub fn with_relaxation(mut self, bearing: Vec<f64>, pin: Vec<f64>) -> Result<Self, WearError> {
        for (name, mine, given) in [
            ("bearing relaxation", &self.bearing, &bearing),
            ("pin relaxation", &self.pin, &pin),
        ] {
            if mine.len() != given.len() {
                return Err(WearError::GridMismatch {
                    name,
                    expected: mine.len(),
                    found: given.len(),
                });
            }
            for &x in given {
                non_negative(name, x)?;
            }
        }
        self.bearing_relaxation = bearing;
        self.pin_relaxation = pin;
        Ok(self)
    }

    /// The same record with `zones` added to its contact zones (for callers that compute
    /// wear their own way, and for tests): what [`implicit`](Self::implicit) reads. Zones with
    /// no node or a relaxation that is not positive are left out.
    pub fn with_zones(mut self, zones: impl IntoIterator<Item = ContactZone>) -> Self {
        let (pin, bearing) = (self.pin.len(), self.bearing.len());
        for zone in zones {
            self.zones.add(zone, pin, bearing);
        }
        self
    }

    /// The same record gathering (or not) the contact zones of the steps it is fed, which
    /// [`implicit`](Self::implicit) needs (default: not; they cost memory and time for a
    /// stage stepped explicitly).
    pub fn gathering_zones(mut self, on: bool) -> Self {
        self.gather_zones = on;
        self
    }

    /// The contact zones gathered so far (merged where they meet the same cells).
    pub fn zones(&self) -> &[ContactZone] {
        self.zones.zones()
    }

    /// Clears the record for reuse in the next stage without reallocating.
    pub fn reset(&mut self) {
        self.bearing.fill(0.0);
        self.pin.fill(0.0);
        self.bearing_relaxation.fill(0.0);
        self.pin_relaxation.fill(0.0);
        self.zones.clear();
        self.archard_volume = 0.0;
    }

    /// Adds the wear of one accepted step of length `dt` (s) that went from state `start` to
    /// state `end`.
    ///
    /// Quadrature: per-endpoint trapezoid. Each end deposits `K_d p |v_t| · dt/2` over its own
    /// contact arc (on both surfaces, at its own body-frame angles), with the mean pressure
    /// `p = F_n / (AB · w)` distributed across the arc elliptically (Hertz), the arc from
    /// [`ContactArc`] and `v_t` the joint's chosen sliding velocity ([`WornJoint::sliding`]). An end that is out of contact or
    /// carries no force contributes nothing, so a step where contact begins or ends gets half
    /// a step of wear from the loaded end (first-order at the onset; steps there are short).
    /// Edge cells get the part of the distribution that falls on them.
    ///
    /// Errors name the first non-finite diagnostic field of a loaded end, or a bad `dt`; the
    /// record is unchanged when the step is rejected this way.
    pub fn accumulate_step(
        &mut self,
        start: &ContactDiagnostics,
        end: &ContactDiagnostics,
        dt: f64,
    ) -> Result<(), WearError> {
        non_negative("dt", dt)?;
        let a = self.rate(start)?;
        let b = self.rate(end)?;
        for (d, loaded) in [(start, a), (end, b)] {
            if let Some((arc, rate, archard_rate)) = loaded {
                let amount = rate * 0.5 * dt;
                self.pin_arc
                    .deposit(&mut self.pin, d.pin_angle, arc.pin_half_angle, amount);
                self.bearing_arc.deposit(
                    &mut self.bearing,
                    d.bearing_angle,
                    arc.bearing_half_angle,
                    amount,
                );
                self.archard_volume += archard_rate * 0.5 * dt;
            }
        }
        Ok(())
    }

    /// Adds the wear of one accepted step of length `dt` (s) of an elastic-foundation contact,
    /// from the loaded nodes at its start and at its end (`contact::NodeLoad`, as the contact
    /// model reported them).
    ///
    /// Archard per node, from the pressure the force used: depth `h = K_d p |v_s| dt/2` per end
    /// (trapezoid), with `p = F_k/(arc · w)` the node's normal force over its share of the
    /// outline and `v_s` the joint's chosen sliding velocity. Each surface takes `h/2` in
    /// radius over the node's arc: on the pin at the node's own angle, on the bearing where the
    /// node meets it, each spread over the two nearest cell centres (linear weights, so the
    /// deposit moves continuously with the contact). The worn volume of the step is then
    /// exactly `K_d Σ F_k |v_s| dt`, Archard's ([`archard_volume`](Self::archard_volume)).
    ///
    /// Errors name the first non-finite or negative node field, or a bad `dt`; the record is
    /// unchanged then.
    pub fn accumulate_nodes(
        &mut self,
        start: &[NodeLoad],
        end: &[NodeLoad],
        dt: f64,
    ) -> Result<(), WearError> {
        non_negative("dt", dt)?;
        for node in start.iter().chain(end) {
            non_negative("node normal_force", node.normal_force)?;
            positive("node arc", node.arc)?;
            finite("node sliding", node.sliding(self.sliding))?;
            finite("node pin_angle", node.pin_angle)?;
            finite("node bearing_angle", node.bearing_angle)?;
            non_negative("node stiffness", node.stiffness)?;
        }
        // The nodes of a joint share one arc: its spread factors are computed once. A node's
        // angle spans as many pin cells as its pin spread factor; on the bearing's grid the same
        // angle spans `bearing_span` cells (at the pin's radius).
        let mut spread = (f64::NAN, 0.0, 0.0);
        let mut bearing_span = 0.0;
        for node in start.iter().chain(end) {
            let speed = node.sliding(self.sliding).abs();
            let archard_rate = self.wear_coefficient * node.normal_force * speed;
            // Depth h over the node's arc; each surface's cells hold h/2 of radius over their
            // own width at their nominal radius (`layer_volume`).
            let depth = archard_rate * 0.5 * dt / (node.arc * self.hinge_width);
            if node.arc != spread.0 {
                spread = (
                    node.arc,
                    spread_factor(node.arc, self.pin_radius, self.pin.len()),
                    spread_factor(node.arc, self.bearing_radius, self.bearing.len()),
                );
                bearing_span = spread_factor(node.arc, self.pin_radius, self.bearing.len());
            }
            let (_, pin_cells, bearing_cells) = spread;
            // The relaxation is spread like the depth, so a cell holds the mean over the nodes
            // that reach it.
            let relaxation = self.node_relaxation(node, dt);
            deposit_over(
                [&mut self.pin, &mut self.pin_relaxation],
                node.pin_angle,
                [depth * pin_cells, relaxation * pin_cells],
                pin_cells,
            );
            deposit_over(
                [&mut self.bearing, &mut self.bearing_relaxation],
                node.bearing_angle,
                [depth * bearing_cells, relaxation * bearing_cells],
                bearing_span,
            );
            self.archard_volume += archard_rate * 0.5 * dt;
        }
        // Each end's contact zones, for the wear process's Jacobian (the nodes' shared arc and
        // its spread factors from the loop above).
        let (pin_cells, bearing_cells) = (self.pin.len(), self.bearing.len());
        let (arc, pin_share, bearing_share) = spread;
        if self.gather_zones && arc.is_finite() {
            let node_count = (TAU * self.pin_radius / arc).round() as usize;
            let share = 0.5 * (pin_share + bearing_share);
            for nodes in [start, end] {
                let mut zones = std::mem::take(&mut self.zones);
                implicit::zones_of(
                    nodes,
                    node_count,
                    share,
                    |node| self.node_relaxation(node, dt),
                    |zone| zones.add(zone, pin_cells, bearing_cells),
                );
                self.zones = zones;
            }
        }
        Ok(())
    }

    /// How much of a node's overlap its deposit over half of a step `dt` closes per unit of
    /// overlap: the depth's derivative in the gap, `K_d (∂F/∂g) |v_s| (dt/2)/(arc w)`
    /// ([`bearing_relaxation`](Self::bearing_relaxation)).
    fn node_relaxation(&self, node: &NodeLoad, dt: f64) -> f64 {
        self.wear_coefficient * node.stiffness * node.sliding(self.sliding).abs() * 0.5 * dt
            / (node.arc * self.hinge_width)
    }

    /// For a loaded state: its arc, depth rate `K_d p |v_t|` (m/s) and Archard volume rate
    /// `K_d F_n |v_t|` (m³/s). `None` when nothing wears.
    fn rate(&self, d: &ContactDiagnostics) -> Result<Option<(ContactArc, f64, f64)>, WearError> {
        if !d.in_contact || d.normal_force == 0.0 {
            return Ok(None);
        }
        let force = non_negative("normal_force", d.normal_force)?;
        let speed = match self.sliding {
            SlidingVelocity::Material => finite("tangential_velocity", d.tangential_velocity)?,
            SlidingVelocity::Paper => {
                finite("geometric_sliding_velocity", d.geometric_sliding_velocity)?
            }
        }
        .abs();
        finite("eccentricity", d.eccentricity)?;
        finite("pin_angle", d.pin_angle)?;
        finite("bearing_angle", d.bearing_angle)?;
        positive("pin_radius", d.pin_radius)?;
        positive("bearing_radius", d.bearing_radius)?;
        let Some(arc) = ContactArc::new(d.eccentricity, d.bearing_radius, d.pin_radius) else {
            return Ok(None);
        };
        let archard_rate = self.wear_coefficient * force * speed;
        let rate = archard_rate / (arc.chord * self.hinge_width);
        Ok(Some((arc, rate, archard_rate)))
    }

    /// Smooths the gathered depths of both surfaces with a periodic Gaussian of standard
    /// deviation `sigma` radians of the surface (normalised, so the worn volume is unchanged;
    /// `sigma ≤ 0` does nothing). An angle, so the smoothing is the same on any grid.
    ///
    /// Why: the wear of K simulated cycles of a chaotic mechanism is a noisy sample of the
    /// expected wear field of the millions of cycles a stage stands for; amplified, its
    /// cell-scale noise becomes cell-scale ridges no real life would leave. Smoothing over a
    /// few cells (far less than a contact zone spans) estimates that field; the halves check
    /// and the convergence study measure how well.
    pub fn smooth(&mut self, sigma: f64) {
        if sigma > 0.0 && sigma.is_finite() {
            for cells in [
                &mut self.bearing,
                &mut self.pin,
                &mut self.bearing_relaxation,
                &mut self.pin_relaxation,
            ] {
                let per_cell = TAU / cells.len() as f64;
                smooth_periodic(cells, sigma / per_cell);
            }
        }
    }

    /// Each of this record's four grids (depths and relaxations, bearing and pin) beside
    /// `other`'s of the same kind.
    fn grids_beside<'a>(
        &'a mut self,
        other: &'a StageWear,
    ) -> [(&'a mut Vec<f64>, &'a Vec<f64>); 4] {
        [
            (&mut self.bearing, &other.bearing),
            (&mut self.pin, &other.pin),
            (&mut self.bearing_relaxation, &other.bearing_relaxation),
            (&mut self.pin_relaxation, &other.pin_relaxation),
        ]
    }

    /// Adds `other`'s depths to this record, cell by cell: `other` must be a record of the same
    /// joint (same grids), e.g. another trajectory of an ensemble on the same surfaces.
    pub fn add(&mut self, other: &StageWear) {
        for (mine, theirs) in self.grids_beside(other) {
            for (h, o) in mine.iter_mut().zip(theirs) {
                *h += o;
            }
        }
        let (pin, bearing) = (self.pin.len(), self.bearing.len());
        self.zones.merge(&other.zones, pin, bearing);
        self.archard_volume += other.archard_volume;
    }

    /// Multiplies every depth (and the Archard volume) by `factor` (≥ 0): with [`add`](Self::add),
    /// the mean of two records of the same joint.
    pub fn scale(&mut self, factor: f64) {
        for h in self
            .bearing
            .iter_mut()
            .chain(self.pin.iter_mut())
            .chain(self.bearing_relaxation.iter_mut())
            .chain(self.pin_relaxation.iter_mut())
        {
            *h *= factor;
        }
        self.zones.scale(factor);
        self.archard_volume *= factor;
    }

    /// Removes `other`'s depths from this record, cell by cell (clamped at 0 against round-off):
    /// with `other` the first half of the same run, what remains is the second half.
    pub fn subtract(&mut self, other: &StageWear) {
        for (mine, theirs) in self.grids_beside(other) {
            for (h, o) in mine.iter_mut().zip(theirs) {
                *h = (*h - o).max(0.0);
            }
        }
        // The zones of a difference are not known: the remainder steps explicitly. Dropped,
        // not cleared: a stage keeps every run's halves, and the capacity would stay with each.
        self.zones = ZoneBook::default();
        self.archard_volume -= other.archard_volume;
    }

    /// Bearing cell depths gathered so far (m, before amplification).
    pub fn bearing(&self) -> &[f64] {
        &self.bearing
    }

    /// Pin cell depths gathered so far (m, before amplification).
    pub fn pin(&self) -> &[f64] {
        &self.pin
    }

    /// Per bearing cell, the part of the gap's overlap the record's wear closes per unit of
    /// overlap (dimensionless; 0 where nothing pressed, and with contacts that do not report a
    /// layer stiffness, i.e. the line-of-centres contact).
    ///
    /// A node pressing with `F(g)` deposits `K_d F |v_s| dt/(arc w)`; wearing both surfaces by
    /// that depth closes its overlap `g` by as much (each surface takes half in radius), so the
    /// deposit's derivative in `g`, `λ = K_d (∂F/∂g) |v_s| dt/(arc w)`, is the rate (per unit
    /// amplification) at which wear relaxes the cell's overlap: a cell that wore `Δh` more
    /// presses `λ Δh` less. On a Winkler layer `∂F/∂g = k w arc`, so `λ = K_d k s` with `s`
    /// the sliding distance while the cell is loaded. A diagnostic: the sub-steps report
    /// `a λ` weighted by the wear ([`JointSubstep::wear_stiffness`](crate::JointSubstep)).
    pub fn bearing_relaxation(&self) -> &[f64] {
        &self.bearing_relaxation
    }

    /// Per pin cell, as [`bearing_relaxation`](Self::bearing_relaxation).
    pub fn pin_relaxation(&self) -> &[f64] {
        &self.pin_relaxation
    }

    /// The relaxation averaged over the cells with the record's depths as weights, the larger
    /// of the two surfaces (0 without wear): the `λ` that the bulk of the wear sees.
    pub fn relaxation_weighted(&self) -> f64 {
        let weighted = |depth: &[f64], relaxation: &[f64]| {
            let total: f64 = depth.iter().sum();
            if total > 0.0 {
                depth
                    .iter()
                    .zip(relaxation)
                    .map(|(h, l)| h * l)
                    .sum::<f64>()
                    / total
            } else {
                0.0
            }
        };
        weighted(&self.bearing, &self.bearing_relaxation)
            .max(weighted(&self.pin, &self.pin_relaxation))
    }

    /// The depths per unit amplification that a linearly implicit sub-step of
    /// `amplification` applies (relaxations and zones kept; the Archard volume scaled with the
    /// worn volume), and the conjugate-gradient iterations it took.
    ///
    /// Why: within a contact zone the wear rate falls where a surface wore more (a cell that
    /// wore `Δh` more presses `λ Δh` less), while the pin moves to keep carrying its load. So
    /// the shape of a wear pattern within the zones relaxes toward a steady one at about `λ`
    /// per unit amplification, and the explicit update `a·w` multiplies such a pattern by
    /// `1 − aλ`: unstable past `aλ = 2`, inaccurate well before. This step applies `a·w̃`
    /// with `(I − aJ) w̃ = w`, `J` the rate's Jacobian in the depths gathered from the
    /// record's contact zones (`crate::implicit`'s module docs): backward Euler for the
    /// zones' shapes, while every pattern that is a translation over each zone that saw it
    /// (a turning pin's even wear, a groove that fits the pin) passes unchanged. Negative
    /// depths, which the projection can give at a zone's edge, are clamped to 0 (depths only
    /// grow). Without zones (line-of-centres contacts, halves) the result is this record.
    pub fn implicit(&self, amplification: f64) -> (StageWear, usize) {
        let mut out = self.clone();
        if self.zones.is_empty() || !(amplification > 0.0 && amplification.is_finite()) {
            return (out, 0);
        }
        let before = out.worn_volume();
        let nb = self.bearing.len();
        let stacked: Vec<f64> = self.bearing.iter().chain(&self.pin).copied().collect();
        let (solved, iterations) = implicit::solve(
            self.zones.zones(),
            nb,
            self.pin.len(),
            amplification,
            &stacked,
        );
        for (o, x) in out.bearing.iter_mut().chain(out.pin.iter_mut()).zip(solved) {
            *o = x.max(0.0);
        }
        let after = out.worn_volume();
        if before > 0.0 {
            out.archard_volume *= after / before;
        }
        (out, iterations)
    }

    /// Largest cell depth on either surface (m).
    pub fn max_depth(&self) -> f64 {
        self.bearing
            .iter()
            .chain(&self.pin)
            .copied()
            .fold(0.0, f64::max)
    }

    /// Archard's volume `K_d ∫ F_n |v_t| dt` over the steps fed so far (m³), by the same
    /// quadrature: the reference for [`worn_volume`](Self::worn_volume).
    pub fn archard_volume(&self) -> f64 {
        self.archard_volume
    }

    /// Volume in the depth buffers, `Σ h/2 · R Δθ · w` over both surfaces (m³).
    ///
    /// It exceeds [`archard_volume`](Self::archard_volume) by the arc-to-chord ratio
    /// `θ/sin θ ≈ 1 + θ²/6` of the contact half-angles: docs/model.md spreads the pressure
    /// `F_n/(AB·w)` over the arc, not the chord (0.2 % for a 6° half-arc, 5 % for 30°).
    pub fn worn_volume(&self) -> f64 {
        layer_volume(&self.bearing, self.bearing_radius, self.hinge_width)
            + layer_volume(&self.pin, self.pin_radius, self.hinge_width)
    }
}

/// The joint's side of a stage: starting a record, bounding what applying it would change, and
/// applying it (amplified) to the surfaces.
impl WornJoint {
    /// An empty wear record for one stage on this joint (allocates its two depth buffers).
    pub fn start_stage(&self) -> StageWear {
        StageWear::new(self)
    }

    /// Upper bound on the relative change of the local clearance, in any contact direction,
    /// that applying `wear` with amplification 1 would cause.
    ///
    /// A bearing cell with depth `h_i` meets the pin where the clearance is at least
    /// `c0 + h_i/2`, so its share is `(Δh_i/2)/(c0 + h_i/2)`; likewise for the pin. The sum of
    /// the two surfaces' largest shares bounds `Δc/c` for every pairing of cells, whatever
    /// the bodies' relative rotation. It is linear in the amplification.
    pub fn clearance_change_per_amplification(&self, wear: &StageWear) -> Result<f64, WearError> {
        self.check(wear)?;
        let c0 = self.nominal_clearance();
        Ok(self.bearing().relative_opening(wear.bearing(), c0)
            + self.pin().relative_opening(wear.pin(), c0))
    }

    /// How much applying `wear` with amplification 1 changes the shape of the local clearance
    /// `c = R_i − R_j`, relative to the shape it has: the change of its slope, `|Δc'|`, over
    /// `c0 + |c'|`, and of its curvature, `|Δc''|`, over `c0 + |c''|` (largest values over the
    /// cells, the two surfaces' added; angles in radians). Like the clearance-change bound, a
    /// limit on these lets a sub-step change the profile's shape by a bounded fraction, so the
    /// linear extrapolation of the wear stays credible while the dents deepen. Linear in the
    /// amplification.
    pub fn shape_change_per_amplification(
        &self,
        wear: &StageWear,
    ) -> Result<(f64, f64), WearError> {
        // With both bounds relative to c0: |Δc'|/(c0 + |c'|) = rate/(1 + now).
        let [now, rate] = self.shape_bounds(wear)?;
        Ok((
            rate.slope / (1.0 + now.slope),
            rate.curvature / (1.0 + now.curvature),
        ))
    }

    /// The worn clearance's shape now and its growth per unit amplification of `wear` (in that
    /// order), as
    /// bounds relative to the nominal clearance: `((max|R_i'| + max|R_j'|)/c0,
    /// (max|R_i''| + max|R_j''|)/c0)` and the same for the increment (see
    /// [`crate::GeometryLimits`]).
    pub fn shape_bounds(&self, wear: &StageWear) -> Result<[ShapeBound; 2], WearError> {
        self.check(wear)?;
        let c0 = self.nominal_clearance();
        let bound = |(bs, bc): (f64, f64), (ps, pc): (f64, f64)| ShapeBound {
            slope: (bs + ps) / c0,
            curvature: (bc + pc) / c0,
        };
        Ok([
            bound(self.bearing().shape(), self.pin().shape()),
            bound(
                self.bearing().shape_change(wear.bearing()),
                self.pin().shape_change(wear.pin()),
            ),
        ])
    }

    /// Ends a stage: adds `amplification ×` the stage's depths to the surfaces and returns
    /// the clearance-change bound of this update (see
    /// [`clearance_change_per_amplification`](Self::clearance_change_per_amplification)).
    ///
    /// Depths only grow, so the clearance only opens. Fails, leaving the joint untouched,
    /// for a foreign wear record, `amplification ≤ 0`, or a pin that would be worn through.
    pub fn apply(&mut self, wear: &StageWear, amplification: f64) -> Result<f64, WearError> {
        let fraction = self.check_apply(wear, amplification)?;
        let (bearing, pin) = self.surfaces_mut();
        bearing.add_scaled(wear.bearing(), amplification);
        pin.add_scaled(wear.pin(), amplification);
        Ok(fraction)
    }

    /// Everything [`apply`](Self::apply) checks, without changing the joint; returns the
    /// same clearance-change bound. Lets several joints be checked before any is updated.
    pub fn check_apply(&self, wear: &StageWear, amplification: f64) -> Result<f64, WearError> {
        positive("amplification", amplification)?;
        let fraction = amplification * self.clearance_change_per_amplification(wear)?;
        let pin_depth = self.pin().max_half_depth_after(wear.pin(), amplification);
        if pin_depth >= self.pin().nominal_radius() {
            return Err(WearError::PinWornThrough {
                radius: self.pin().nominal_radius(),
                depth: pin_depth,
            });
        }
        Ok(fraction)
    }

    fn check(&self, wear: &StageWear) -> Result<(), WearError> {
        check_increment("bearing wear", self.bearing(), wear.bearing())?;
        check_increment("pin wear", self.pin(), wear.pin())
    }
}

/// How many cells of a surface of radius `radius` and `cells` cells an arc of length `arc`
/// covers: a depth spread over the arc becomes this times the depth in one cell.
fn spread_factor(arc: f64, radius: f64, cells: usize) -> f64 {
    arc / (radius * TAU / cells as f64)
}

/// Adds `amounts[m]` (a depth times cells) to `grids[m]` (grids of one surface, of equal
/// length, sharing the node's coverage) for a node spanning `span` cells of angle around
/// body-frame angle `angle`: for a node no wider than a cell, split between the two nearest
/// cell centres ([`deposit_linear`]); for a wider one (nodes coarser than the wear grid), over
/// the cells its angle covers, in proportion to the part of each it covers, so that nodes side
/// by side under an even load wear their cells evenly.
fn deposit_over<const M: usize>(grids: [&mut [f64]; M], angle: f64, amounts: [f64; M], span: f64) {
    if span <= 1.0 {
        for (cells, amount) in grids.into_iter().zip(amounts) {
            deposit_linear(cells, angle, amount);
        }
        return;
    }
    let Some(n) = grids.first().map(|cells| cells.len()) else {
        return;
    };
    debug_assert!(grids.iter().all(|cells| cells.len() == n));
    if n == 0 {
        return;
    }
    let depths = amounts.map(|amount| amount / span);
    // The arc from `start` to `end` in cell units (cell k spans [k, k + 1)).
    let centre = contact::wrap_angle(angle) * n as f64 / TAU;
    let (start, end) = (centre - 0.5 * span, centre + 0.5 * span);
    let first = contact::floor(start) as i64;
    let last = contact::floor(end) as i64;
    // The grid's index of cell `first`, then stepped with a wrap (no division a cell).
    let mut index = first.rem_euclid(n as i64) as usize;
    let mut grids = grids;
    for k in first..=last {
        let covered = (end.min((k + 1) as f64) - start.max(k as f64)).max(0.0);
        for (cells, depth) in grids.iter_mut().zip(depths) {
            cells[index] += depth * covered;
        }
        index += 1;
        if index == n {
            index = 0;
        }
    }
}

/// Adds `amount` to the cells around body-frame angle `angle`, split between the two nearest
/// cell centres in proportion to closeness (all in one cell when `angle` is a centre).
fn deposit_linear(cells: &mut [f64], angle: f64, amount: f64) {
    let n = cells.len();
    let u = contact::wrap_angle(angle) * n as f64 / TAU - 0.5;
    let base = contact::floor(u);
    let t = u - base;
    let i = (base as i64).rem_euclid(n as i64) as usize;
    cells[i] += amount * (1.0 - t);
    if t > 0.0 {
        cells[(i + 1) % n] += amount * t;
    }
}

/// Periodic convolution of `cells` with a Gaussian of `sigma` cells, truncated at 4σ and
/// normalised to sum 1.
fn smooth_periodic(cells: &mut [f64], sigma: f64) {
    let n = cells.len();
    let reach = ((4.0 * sigma).ceil() as usize).min(n / 2);
    let weights: Vec<f64> = (0..=reach)
        .map(|k| (-0.5 * (k as f64 / sigma).powi(2)).exp())
        .collect();
    let total = weights[0] + 2.0 * weights[1..].iter().sum::<f64>();
    let source = cells.to_vec();
    for (i, out) in cells.iter_mut().enumerate() {
        let mut sum = weights[0] * source[i];
        for (k, w) in weights.iter().enumerate().skip(1) {
            sum += w * (source[(i + k) % n] + source[(i + n - k % n) % n]);
        }
        *out = sum / total;
    }
}
