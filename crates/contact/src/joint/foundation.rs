//! The elastic-foundation contact: a Winkler layer over the true outlines of pin and bearing.
//!
//! A worn bearing is a groove with dents and flanks, and a worn pin touches it over an arc, at
//! times over two; a line-of-centres contact sees one point. Here every point of the pin's
//! outline presses into a thin elastic layer on the bearing (Mukras et al., J. Tribol. 2010,
//! used it for revolute-joint wear).
//!
//! # Overlap
//! The pin's outline is sampled at `N` nodes fixed in the pin's frame, at the centres of its
//! cells `α_k = (k + ½) 2π/N` (the wear grid's), at its own (worn) radius `r_k`. Node `k` sits at
//! `P_k = r_j + A(θ_j)(s_j + r_k u(α_k))`. Its overlap with the bearing's outline is measured
//! radially from the bearing centre `C_i`: with `D_k = P_k − C_i`, `ρ_k = |D_k|` and
//! `ψ_k = atan2(D_k)`, `g_k = ρ_k − R_i(ψ_k − θ_i)`, the bearing's (worn) radius in that
//! direction. This is exact geometry for any eccentricity: nothing is linearised about the
//! line of centres.
//!
//! # Energy and force
//! The layer stores `V = (k w/2) ∫ d² ds` over the pin's outline (`d = max(0, g)`, `k` the layer
//! modulus in Pa/m, `w` the hinge width, `ds = R_j0 dα`). Between nodes `g` is taken linear and
//! the positive part is integrated exactly:
//! `∫₀¹ max(0, a + (b − a)s)² ds` is `(a² + ab + b²)/3` for `a, b ≥ 0` and `a³/(3(a − b))` when
//! only `a > 0`. This is C² in `(a, b)` as a node crosses the edge of a contact zone, so the
//! force is C¹: the integrator sees no kink when a zone grows or shrinks by a cell. The
//! segments' sum is the trapezoid rule, with an error `O(h²)`; by default ([`Quadrature`]) the
//! energy is Richardson's `(4 V_h − V_2h)/3`, `V_2h` the same sum over the segments joining every
//! other node: Simpson's rule on the same nodes, `O(h⁴)` inside a zone, as exact a gradient
//! and as smooth.
//!
//! The elastic force is exactly `−∇V`: with `G_k = ∂V/∂g_k ≥ 0` and
//! `∇g_k = m_k·∂D_k/∂q + R_i' ∂θ_i/∂q`, `m_k = n_k − (R_i'/ρ_k) t_k`, node `k` pushes the pin
//! with `−G_k m_k` at `P_k` and the bearing with `+G_k m_k` at the same point (its moment about
//! the bearing centre carries the `R_i'` term). So an elastic worn joint conserves energy on
//! any shape, and the pair of forces has no net moment.
//!
//! # Damping and friction, per node
//! Each node's load is `L_k = G_k φ(ġ_k)`, where `φ` is the joint's normal law's hysteresis
//! factor (for Lankarani–Nikravesh `1 + 3(1 − c_e²)/4 · ġ/δ̇⁻`, clamped at zero so the layer
//! never pulls) and `ġ_k = ∇g_k·q̇`, held within `±δ̇⁻` (the law's floored onset velocity, or
//! the layer's reference speed if larger). Within that range, the rates one impact spans, the
//! law is unchanged: on round surfaces `ġ_k ≈ δ̇` across the small contact arc, so the total is
//! the law's force and an impact rebounds with its `c_e` at any speed. Beyond it the factor is
//! held at `1 ± χ`: a pin that settled gently into a worn groove (`δ̇⁻` at the floor) and then
//! slides along its flanks would otherwise carry `χ ġ_k/δ̇⁻`, tens to hundreds of times its
//! elastic load; held, the damping adds at most what an impact's onset adds. Damping
//! dissipates `Σ (L_k − G_k) ġ_k ≥ 0` either way. Friction
//! acts at each node along the local tangent `t̂_k ⟂ m_k`, with the law evaluated on the node's
//! load `L_k |m_k|` and its material sliding velocity (the pin's material point at `P_k`
//! relative to the bearing's), or the paper's `d_k φ̇` where the joint chooses it.
//!
//! # Calibration
//! For a round pin of radius `R − c` in a round bearing of radius `R`, penetration `δ`, the
//! integral gives to leading order `F = (4√2/3) k w √(R R_j) δ^{3/2}/√(c + δ)`. With
//! `k w = E*/√2`, `E* = 1/(σ_i + σ_j)`, this is the model's conformal Hertz force
//! `K δ^{3/2}`, `K = (4/3) E* √(R_i R_j/c)`, times `√(c/(c + δ))` ([`Foundation::calibrated`]);
//! the tests check it against an independent quadrature. [`Foundation::hertz_matched`] makes
//! it exact at a chosen overlap instead (the scenes' default: 4 % of the clearance).
//!
//! # Cost
//! Only nodes that can touch are visited. The pin's nodes are grouped in 64 sectors; a sector
//! is skipped when its farthest reach from the bearing centre (its largest radius, at the angle
//! nearest the eccentricity `e`) stays inside the bearing's smallest radius over the sector of
//! the bearing it can land on ([`SurfaceProfile::radius_bounds_between`], exact for worn
//! profiles). In free flight (`|e| + R_j⁺ ≤ R_i⁻`) no node is visited, and the deepest overlap
//! (the event function) is then the skipped sectors' bound. The Jacobian runs the same code on
//! dual numbers, only on the nodes next to an overlap. A node's ray angle `ψ_k` is not an
//! `atan2` but its own direction `θ_j + α_k` plus the small angle between the two (within
//! `asin(|e|/r_k)`), summed from its series to rounding.
//!
//! Between evaluations the joint moves little (a step's Newton iterations, the next step), so
//! plain evaluations also remember the overlaps they found and the pose they found them at
//! (the overlap memory, in the [`FoundationWorkspace`] the caller passes in): a node whose remembered gap stays negative by more than the distance it
//! can have moved since (plus the bearing's slope bound times the angle that subtends), and out
//! of contact below the remembered deepest node's, is not computed; the event function starts
//! from the remembered deepest node, so that its bound passes over the rest. This changes no
//! result, bit for bit; on the worn LGRES cycle it saves 40 % of the instructions
//! (docs/performance.md).

pub(in crate::joint) mod books;
mod evaluate;
pub(in crate::joint) mod geometry;
mod layer;
mod memory;
mod nodes;
pub(in crate::joint) mod stream;
mod window;

pub use layer::{DEFAULT_FOUNDATION_CELLS, DEFAULT_REFERENCE_OVERLAP, Foundation, Quadrature};
pub use memory::FoundationWorkspace;
pub use window::NodeWindow;

use books::{Books, LayerPose};
use geometry::{Body, Node, angle_near, cross, dot, offset};
use stream::{NodeQueue, Output, Pending, apply, segment};

use super::dual::Real;
use super::model::NodeLoad;
use super::pair::ContactPair;
use super::types::SlidingVelocity;
use crate::diagnostics::ContactDiagnostics;
use crate::friction::FrictionLaw;
use crate::normal::NormalLaw;
use crate::surface::{SurfaceProfile, wrap_angle};
use memory::{Noted, Pose, Remembered, Skip};

/// What the foundation evaluates on: the pair, and its node window for the pair's outlines.
struct Kernel<'k, B, P, N, F> {
    pair: &'k ContactPair<B, P, N, F>,
    window: &'k NodeWindow,
}

/// What one evaluation holds fixed while it streams the nodes.
struct Pass<T> {
    cells: usize,
    /// Half the layer's stiffness per node, `k w · arc/2` (N/m).
    weight: f64,
    simpson: bool,
    /// The impact's onset velocity as the law reads it (m/s): a node's rate counts within ±.
    onset: f64,
    /// The paper's sliding rate `φ̇ = t·ė/|e|`.
    phi_rate: T,
    theta_bearing: T,
    theta_pin: f64,
    pin_centre_arm: [T; 2],
    line_modulus: f64,
}

/// The two bodies in the evaluation's arithmetic and in plain numbers (for the look-ahead).
struct Bodies<T> {
    bearing: Body<T>,
    pin: Body<T>,
    bearing_centre_arm: [T; 2],
    plain: (Body<f64>, Body<f64>),
    plain_arm: [f64; 2],
}

/// Where the loaded nodes go: the visitor of accepted steps, and Simpson's loads held until
/// the evaluation's totals are known.
pub(in crate::joint) struct Sink<'v, 'd> {
    pub(in crate::joint) visit: Option<&'v mut dyn FnMut(&NodeLoad)>,
    /// The workspace's buffer, emptied for this evaluation.
    pub(in crate::joint) deposits: &'d mut Vec<NodeLoad>,
}

/// The overlap memory as one evaluation uses it: what it rules out (`skip`), whether the
/// evaluation renews it (`recording`), and how many nodes were computed in full.
struct MemoryUse<'m> {
    mem: Option<&'m mut Remembered>,
    skip: Option<Skip>,
    recording: bool,
    computed: usize,
}

impl Sink<'_, '_> {
    /// Hands Simpson's held wear loads to the visitor. Simpson's weights alternate along a zone
    /// (4/3, 2/3 of a node's arc): the wear gets the trapezoid's even loads, scaled to the
    /// force's total so that the Archard volume follows the load the joint carries.
    pub(in crate::joint) fn deposit(&mut self, books: &Books) {
        if let Some(visit) = self.visit.as_mut() {
            let scale = if books.trapezoid_load > 0.0 {
                ((books.load + books.pull) / books.trapezoid_load).max(0.0)
            } else {
                0.0
            };
            for load in self.deposits.iter_mut() {
                load.normal_force *= scale;
                visit(load);
            }
        }
    }
}

/// The overlap memory an evaluation holds: its notes, and the pose it is evaluated at.
type HeldMemory<'m> = (&'m mut Remembered, Pose);

/// The line of centres at one state: the direction of the free joint's diagnostics.
struct Centres<T> {
    /// The pin centre from the bearing centre, `e` (m).
    e_value: [f64; 2],
    /// `|e|` (m).
    rho: f64,
    /// The paper's sliding rate `φ̇ = t·ė/|e|` (rad/s), in the evaluation's arithmetic.
    phi_rate: T,
    /// The rate the centres move apart along `e` (m/s).
    centre_rate: f64,
}

/// [`Centres`] of the two bodies, given their centres' arms.
fn centres<T: Real>(
    bearing: &Body<T>,
    pin: &Body<T>,
    bearing_centre_arm: &[T; 2],
    pin_centre_arm: &[T; 2],
) -> Centres<T> {
    let e = offset(pin, pin_centre_arm, bearing, bearing_centre_arm);
    let e_value = [e[0].value(), e[1].value()];
    let rho = e_value[0].hypot(e_value[1]);
    let e_rate = {
        let p = pin.point_velocity(pin_centre_arm);
        let b = bearing.point_velocity(bearing_centre_arm);
        [p[0] - b[0], p[1] - b[1]]
    };
    let e_norm = dot(&e, &e).sqrt();
    let phi_rate = if rho > 0.0 {
        cross(&e, &e_rate) / (e_norm * e_norm)
    } else {
        T::constant(0.0)
    };
    let centre_rate = if rho > 0.0 {
        (e_value[0] * e_rate[0].value() + e_value[1] * e_rate[1].value()) / rho
    } else {
        0.0
    };
    Centres {
        e_value,
        rho,
        phi_rate,
        centre_rate,
    }
}

impl<B: SurfaceProfile, P: SurfaceProfile, N: NormalLaw, F: FrictionLaw> Kernel<'_, B, P, N, F> {
    /// The kernel: forces on both bodies, diagnostics, and each loaded node to `visit` if any;
    /// what it passes over by the overlap memory and renews it with, in `workspace`.
    fn foundation_eval<T: Real>(
        &self,
        foundation: &Foundation,
        workspace: &mut FoundationWorkspace,
        bearing_state: [T; 6],
        pin_state: [T; 6],
        onset_velocity: Option<f64>,
        visit: Option<&mut dyn FnMut(&NodeLoad)>,
    ) -> Output<T> {
        let cells = foundation.cells;
        let bearing = Body::new(bearing_state);
        let pin = Body::new(pin_state);
        let bearing_centre_arm =
            bearing.rotate([self.pair.bearing_centre.x, self.pair.bearing_centre.y]);
        let pin_centre_arm = pin.rotate([self.pair.pin_centre.x, self.pair.pin_centre.y]);
        let Centres {
            e_value,
            rho,
            phi_rate,
            centre_rate,
        } = centres(&bearing, &pin, &bearing_centre_arm, &pin_centre_arm);
        // The impact's onset velocity as the law reads it (floored), and at least the layer's
        // reference speed when one is set (`Foundation::with_reference_speed`). A node's rate
        // counts only within ± this: the range one impact spans (`Foundation`'s docs).
        let onset = self.pair.normal_law.effective_onset(
            onset_velocity
                .unwrap_or(centre_rate)
                .abs()
                .max(foundation.reference_speed),
        );
        let theta_bearing = bearing_state[2];
        let theta_pin = pin_state[2].value();

        let zero = T::constant(0.0);
        let mut out = Output {
            bearing: [zero; 3],
            pin: [zero; 3],
            diagnostics: ContactDiagnostics::default(),
        };
        let mut books = Books {
            grid: cells,
            quadrature: foundation.quadrature,
            ..Books::default()
        };
        let weight = 0.5 * foundation.line_modulus * self.window.node_arc;
        let simpson = foundation.quadrature == Quadrature::Simpson;
        let candidates = self.candidates(
            cells,
            e_value,
            (theta_pin, theta_bearing.value()),
            if simpson { 2 } else { 1 },
        );

        let FoundationWorkspace { memory, deposits } = workspace;
        let (mut memory, mut skip, recording) =
            self.overlap_memory(memory, &bearing, cells, e_value, theta_pin);
        let mem: Option<&mut Remembered> = memory.as_mut().map(|(m, pose)| {
            if recording && m.renew(*pose).is_none() {
                skip = None;
            }
            &mut **m
        });
        let pass = Pass {
            cells,
            weight,
            simpson,
            onset,
            phi_rate,
            theta_bearing,
            theta_pin,
            pin_centre_arm,
            line_modulus: foundation.line_modulus,
        };
        let bodies = Bodies {
            plain: (
                Body::new(bearing_state.map(Real::value)),
                Body::new(pin_state.map(Real::value)),
            ),
            plain_arm: [bearing_centre_arm[0].value(), bearing_centre_arm[1].value()],
            bearing,
            pin,
            bearing_centre_arm,
        };
        deposits.clear();
        let mut sink = Sink { visit, deposits };
        let mut memory_use = MemoryUse {
            mem,
            skip,
            recording,
            computed: 0,
        };
        for &run in &candidates.runs[..candidates.count] {
            self.stream_run(
                &pass,
                run,
                &bodies,
                &mut books,
                &mut out,
                &mut sink,
                &mut memory_use,
            );
        }
        let computed = memory_use.computed;
        sink.deposit(&books);
        if let Some((m, _)) = memory {
            Self::keep_memory(m, recording, computed);
        }
        if books.deepest.is_none_or(|d| d < candidates.outside_bound) {
            books.deepest = Some(candidates.outside_bound);
        }
        let rho_free = rho + self.window.pin_max.min(1e300) - self.window.bearing_min;
        out.diagnostics = books.diagnostics(
            &self.pair.bearing_profile,
            &self.pair.pin_profile,
            LayerPose {
                rho,
                e: e_value,
                centre: [
                    bearing_state[0].value() + bearing_centre_arm[0].value(),
                    bearing_state[1].value() + bearing_centre_arm[1].value(),
                ],
                angles: (theta_bearing.value(), theta_pin),
                phi_rate: phi_rate.value(),
                centre_rate,
                free_gap: rho_free,
            },
        );
        out
    }

    /// The overlap memory this evaluation uses, what it rules out and whether it renews it.
    /// Plain evaluations pass over the nodes the memory rules out (`Skip`), and renew it with
    /// the overlaps they find when it has nothing to say or has gone stale. (No memory, no
    /// pose: nothing of it runs for round bearings, dual numbers or an empty workspace.)
    fn overlap_memory<'m, T: Real>(
        &self,
        memory: &'m mut Remembered,
        bearing: &Body<T>,
        cells: usize,
        e_value: [f64; 2],
        theta_pin: f64,
    ) -> (Option<HeldMemory<'m>>, Option<Skip>, bool) {
        let usable =
            T::PLAIN && self.window.bearing_slope.is_some() && memory.overlap.len() == cells;
        let memory = usable.then(|| {
            let (s, c) = bearing.theta_sin_cos;
            let pose = Pose::new(e_value, (s.value(), c.value()), bearing.theta, theta_pin);
            (memory, pose)
        });
        let skip = memory
            .as_ref()
            .filter(|(m, _)| m.deepest > f64::NEG_INFINITY)
            .and_then(|(m, pose)| Some(Skip::new(m, self.window.drift(m.pose, *pose)?)));
        // A memory whose deepest node surely still overlaps is only read; otherwise (and when
        // stale) this evaluation renews it, passing over what the old notes rule out and
        // carrying their bounds (plus the drift) into the new ones.
        let recording = memory.is_some()
            && !(skip.is_some_and(|s| s.overlapping)
                && memory.as_ref().is_some_and(|(m, _)| !m.stale));
        (memory, skip, recording)
    }

    /// Keeps the memory for the next evaluation: a renewed one with the count of nodes it
    /// computed, a read one marked stale once it saves less than half of that.
    fn keep_memory(memory: &mut Remembered, recording: bool, computed: usize) {
        if recording {
            memory.computed = computed;
        } else {
            memory.stale = 2 * computed > memory.computed;
        }
    }

    /// A closed node's share: its elastic load `G_k` (the energy's gradient over the node), the
    /// damping and friction on it, their forces on both bodies, the books, and its wear load
    /// (held in `sink` under Simpson's rule, else handed to the visitor). Returns the node's
    /// normal load (N).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn carry<T: Real>(
        &self,
        pass: &Pass<T>,
        node: &Node<T>,
        load_gradient: T,
        deposit_gradient: f64,
        books: &mut Books,
        out: &mut Output<T>,
        sink: &mut Sink<'_, '_>,
    ) -> f64 {
        let g_k = load_gradient * pass.weight;
        if g_k.value() < 0.0 {
            // A negative Simpson pass.weight next to a zone edge: the energy's own gradient,
            // elastic only (no damping, no friction, no wear).
            let force_on_pin = [-(g_k * node.m[0]), -(g_k * node.m[1])];
            books.elastic_resultant[0] += g_k.value() * node.m[0].value();
            books.elastic_resultant[1] += g_k.value() * node.m[1].value();
            books.pull += g_k.value() * dot(&node.m, &node.m).sqrt().value();
            apply(out, node, force_on_pin);
            return 0.0;
        }
        if g_k.value() == 0.0 {
            return 0.0;
        }
        books.elastic_resultant[0] += g_k.value() * node.m[0].value();
        books.elastic_resultant[1] += g_k.value() * node.m[1].value();
        let rate = node.g_rate.value();
        let (factor, d_factor) = self
            .pair
            .normal_law
            .hysteresis(rate.clamp(-pass.onset, pass.onset), pass.onset);
        // Beyond the impact's range the factor is held: no partial in the rate.
        let d_factor = if rate.abs() > pass.onset {
            0.0
        } else {
            d_factor
        };
        if factor <= 0.0 {
            // Clamped: the layer does not pull; its elastic load is released as damping.
            books.damping_power -= g_k.value() * node.g_rate.value();
            return 0.0;
        }
        let load = g_k * node.g_rate.chain(factor, d_factor);
        let m_norm = dot(&node.m, &node.m).sqrt();
        let t_hat = [-node.m[1] / m_norm, node.m[0] / m_norm];
        let normal = load * m_norm;
        let material = dot(&node.relative_velocity, &t_hat);
        let paper = if node.g.value() > 0.0 {
            node.g * pass.phi_rate
        } else {
            T::constant(0.0)
        };
        let sliding = match self.pair.friction_sliding {
            SlidingVelocity::Material => material,
            SlidingVelocity::Paper => paper,
        };
        let friction = self
            .pair
            .friction_law
            .evaluate(sliding.value(), normal.value());
        let friction_force = sliding.chain2(
            normal,
            friction.force,
            friction.d_velocity,
            friction.d_normal_force,
        );
        let force_on_pin = [
            -(load * node.m[0]) - friction_force * t_hat[0],
            -(load * node.m[1]) - friction_force * t_hat[1],
        ];
        apply(out, node, force_on_pin);

        let (load_v, normal_v, material_v) = (load.value(), normal.value(), material.value());
        books.damping_power += (load_v - g_k.value()) * node.g_rate.value();
        books.friction_power += friction.force * material_v;
        books.friction_force += friction.force;
        books.normal_resultant[0] += load_v * node.m[0].value();
        books.normal_resultant[1] += load_v * node.m[1].value();
        books.load += normal_v;
        books.load_sliding += normal_v * material_v;
        let Some(visit) = sink.visit.as_mut() else {
            return normal_v;
        };
        let node_load = |normal_force| NodeLoad {
            cell: node.cell,
            pin_angle: node.alpha,
            bearing_angle: wrap_angle(node.bearing_angle.unwrap_or_else(|| {
                let w = [
                    node.pin_arm[0].value() - pass.pin_centre_arm[0].value(),
                    node.pin_arm[1].value() - pass.pin_centre_arm[1].value(),
                ];
                angle_near(node.ray, w, pass.theta_pin + node.alpha) - pass.theta_bearing.value()
            })),
            normal_force,
            arc: self.window.node_arc,
            material_sliding: material_v,
            paper_sliding: paper.value(),
            stiffness: pass.line_modulus * self.window.node_arc * factor * m_norm.value(),
        };
        if pass.simpson {
            // Held until the evaluation's totals are known (the quadrature's docs).
            let trapezoid = deposit_gradient * pass.weight * factor * m_norm.value();
            if trapezoid > 0.0 {
                books.trapezoid_load += trapezoid;
                sink.deposits.push(node_load(trapezoid));
            }
        } else {
            visit(&node_load(normal_v));
        }
        normal_v
    }

    /// Every computed node passes here in order, once all its segments are seen: its load, and
    /// the zone it belongs to.
    #[inline]
    fn emit<T: Real>(
        &self,
        pass: &Pass<T>,
        pending: &Pending<T>,
        books: &mut Books,
        out: &mut Output<T>,
        sink: &mut Sink<'_, '_>,
    ) {
        let (gradient, deposit) = if pass.simpson {
            (
                pending.fine * (4.0 / 3.0) - pending.coarse / 3.0,
                pending.fine.value(),
            )
        } else {
            (pending.fine, pending.fine.value())
        };
        let normal = self.carry(pass, &pending.node, gradient, deposit, books, out, sink);
        books.see_zone(pending.node.cell, pending.node.overlap, normal);
    }

    /// Streams one run of candidate nodes, `first..=last` (signed, wrapping), closing each
    /// node's load once all its segments are seen: its neighbours' and, for Simpson, the even
    /// nodes' two neighbours two apart. A node none of whose segments can be loaded (its overlap
    /// and those of the nodes it joins ≤ 0) carries nothing: only its plain overlap is
    /// computed, not the node in `T`. (A whole-circle window starts opposite the contact, so no
    /// segment closes the circle.)
    #[allow(clippy::too_many_arguments)]
    fn stream_run<T: Real>(
        &self,
        pass: &Pass<T>,
        (first, last): (i64, i64),
        bodies: &Bodies<T>,
        books: &mut Books,
        out: &mut Output<T>,
        sink: &mut Sink<'_, '_>,
        memory: &mut MemoryUse<'_>,
    ) {
        let n = pass.cells as i64;
        let node_at = |k: i64| {
            self.node(
                k.rem_euclid(n) as usize,
                &bodies.bearing,
                &bodies.pin,
                &bodies.bearing_centre_arm,
                pass.theta_bearing,
            )
        };
        let mut queue = NodeQueue::<T>::default();
        // Overlaps behind (`k − 1`, `k − 2`) and ahead (`k + 1`, `k + 2`; the second only for
        // Simpson) of node `k`.
        let mut behind = [f64::NEG_INFINITY; 2];
        // Plain arithmetic would compute a node's overlap twice (here and in `node_at`), so
        // it looks ahead with the node's distance from the bearing centre: below the
        // bearing's smallest radius that is the overlap `node_at` gives, bit for bit, and
        // above it the node may overlap (+∞) and is computed in full, unless the memory
        // remembers it apart: then its gap alone, again bit for bit `node_at`'s.
        // A node the memory rules out looks ahead as −∞: not computed unless a node it
        // joins may overlap, exactly as a node below the bearing's smallest radius.
        // (A method, not a closure: called from several places, a closure is not inlined.)
        let theta = pass.theta_bearing.value();
        macro_rules! look {
            ($k:expr) => {{
                let k: i64 = $k;
                if k > last {
                    (f64::NEG_INFINITY, Noted::Nothing)
                } else {
                    self.look_ahead(
                        k.rem_euclid(n) as usize,
                        T::PLAIN,
                        &bodies.plain,
                        &bodies.plain_arm,
                        theta,
                        memory.skip.zip(memory.mem.as_deref()),
                    )
                }
            }};
        }
        let nothing = (f64::NEG_INFINITY, Noted::Nothing);
        let mut here = look!(first);
        let mut ahead = [
            look!(first + 1),
            if pass.simpson {
                look!(first + 2)
            } else {
                nothing
            },
        ];
        for k in first..=last {
            let (overlap_here, noted_here) = here;
            let coarse_node = pass.simpson && k.rem_euclid(2) == 0;
            let joins_overlap = overlap_here > 0.0
                || behind[0] > 0.0
                || ahead[0].0 > 0.0
                || (coarse_node && (behind[1] > 0.0 || ahead[1].0 > 0.0));
            let early = (!T::PLAIN || overlap_here <= 0.0).then(|| books.see_overlap(overlap_here));
            if joins_overlap {
                let node = node_at(k);
                memory.computed += 1;
                if let Some(m) = memory.mem.as_deref_mut().filter(|_| memory.recording) {
                    m.note(node.cell, node.overlap, node.beyond);
                }
                if early.unwrap_or_else(|| books.see_overlap(node.overlap)) {
                    books.deepest_rate = node.g_rate.value();
                }
                let mut entry = Pending {
                    index: k,
                    node,
                    fine: T::constant(0.0),
                    coarse: T::constant(0.0),
                };
                if let Some(left) = queue.at(k - 1) {
                    let (q, dq_a, dq_b) = segment(left.node.g, entry.node.g);
                    books.energy +=
                        pass.weight * q.value() * if pass.simpson { 4.0 / 3.0 } else { 1.0 };
                    left.fine = left.fine + dq_a;
                    entry.fine = dq_b;
                }
                if coarse_node && let Some(left) = queue.at(k - 2) {
                    // The every-other-node segment spans two arcs: twice the pass.weight.
                    let (q, dq_a, dq_b) = segment(left.node.g, entry.node.g);
                    books.energy -= pass.weight * q.value() * (2.0 / 3.0);
                    left.coarse = left.coarse + dq_a * 2.0;
                    entry.coarse = dq_b * 2.0;
                }
                queue.push(entry);
                // Close what has seen all its segments, in order.
                while queue.front().is_some_and(|front| {
                    front.index < k
                        && (!pass.simpson || front.index.rem_euclid(2) == 1 || front.index + 2 <= k)
                }) && let Some(done) = queue.pop()
                {
                    self.emit(pass, &done, books, out, sink);
                }
            } else {
                if let Some(m) = memory.mem.as_deref_mut().filter(|_| memory.recording) {
                    let cell = k.rem_euclid(n) as usize;
                    match (noted_here, memory.skip) {
                        (Noted::Below, _) => m.note(cell, overlap_here, false),
                        (Noted::Gap, _) => m.note(cell, overlap_here, true),
                        (Noted::Carried, Some(skip)) => {
                            m.note(cell, skip.gap_bound(m, cell), false);
                        }
                        _ => {}
                    }
                }
                // Nothing left to join for the nodes waiting: their remaining segments meet
                // overlaps ≤ 0 (else this node would have been computed).
                while let Some(done) = queue.pop() {
                    self.emit(pass, &done, books, out, sink);
                }
            }
            behind = [overlap_here, behind[0]];
            here = ahead[0];
            // The trapezoid looks one node ahead only.
            ahead = if pass.simpson {
                [ahead[1], look!(k + 3)]
            } else {
                [look!(k + 2), nothing]
            };
        }
        while let Some(done) = queue.pop() {
            self.emit(pass, &done, books, out, sink);
        }
    }
}
