//! The elastic foundation's parameters: its layer, nodes and quadrature.

use serde::{Deserialize, Serialize};

use crate::error::{ContactError, positive};
use crate::material::Material;

/// Default overlap, as a fraction of the clearance, at which [`Foundation::hertz_matched`]
/// reproduces the conformal Hertz force: 4 %, the overlap of the LGRES start-up impacts
/// (20 µm at 0.5 mm).
pub const DEFAULT_REFERENCE_OVERLAP: f64 = 0.04;

/// Default number of nodes on the pin's outline (the wear grid's default cell count).
pub const DEFAULT_FOUNDATION_CELLS: usize = 1000;

/// Parameters of the elastic-foundation contact: the layer and the nodes on the pin.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Foundation {
    /// Layer modulus times hinge width, `k w` (Pa): the force per unit overlap and outline
    /// length.
    pub(in crate::joint) line_modulus: f64,
    /// Nodes on the pin's outline over 360°.
    pub(in crate::joint) cells: usize,
    /// The slowest onset velocity the layer's damping is scaled by (m/s; 0: the law's own
    /// floor).
    #[serde(default)]
    pub(in crate::joint) reference_speed: f64,
    /// How the energy is integrated between the nodes.
    #[serde(default)]
    pub(in crate::joint) quadrature: Quadrature,
}

/// How the layer's energy `(k w/2) ∫ d² ds` is integrated over the nodes' piecewise-linear
/// overlap.
///
/// Both integrate the positive part of each segment exactly, so the force is the exact
/// gradient of its discrete energy and C¹ as a zone edge crosses a node. Measured on the
/// default LGRES stage's worn surfaces against 10× the nodes (`lgres` example
/// `foundation_accuracy`, docs/performance.md): the trapezoid's force error falls as `N⁻²`
/// (joint B on 1000 nodes: 0.10 % median, 0.44 % at worst), Simpson's far faster (0.001 %,
/// 0.03 %).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Quadrature {
    /// The segments' energies summed (`V_h`): each node carries its own arc.
    Trapezoid,
    /// Richardson's combination `(4 V_h − V_2h)/3` of the segments' energies and those of the
    /// segments joining every other node (even indices): Simpson's weights in a zone's interior
    /// (nodes alternately `4/3` and `2/3` of their arc), its error `O(h⁴)` where the
    /// trapezoid's is `O(h²)`, on the same nodes. Needs an even node count. A node next to a
    /// zone edge may get a small negative weight: it then carries its elastic part only (no
    /// damping, no friction), so the energy stays exact. Wear deposits
    /// ([`crate::NodeLoad::normal_force`]) get the trapezoid's even loads scaled to the force's total
    /// (the negative weights' pull included), so a cell's deposit follows its own node and
    /// the Archard volume the load carried.
    #[default]
    Simpson,
}

impl Foundation {
    /// The layer that reproduces the model's conformal Hertz stiffness on round surfaces:
    /// `k w = E*/√2` with `E* = 1/(σ_i + σ_j)`, `σ = (1 − ν²)/E` (see the module docs), on
    /// [`DEFAULT_FOUNDATION_CELLS`] nodes.
    pub fn calibrated(bearing: &Material, pin: &Material) -> Self {
        let effective_modulus = 1.0 / (bearing.compliance() + pin.compliance());
        Self {
            line_modulus: effective_modulus / std::f64::consts::SQRT_2,
            cells: DEFAULT_FOUNDATION_CELLS,
            reference_speed: 0.0,
            quadrature: Quadrature::default(),
        }
    }

    /// The layer whose force on round surfaces (bearing radius `R_i`, pin radius `R_j`, in m)
    /// equals the conformal Hertz force `K δ^{3/2}` exactly at the overlap
    /// `δ_ref = reference × (R_i − R_j)`: the linear layer's force grows as
    /// `δ^{3/2}/√(c + δ)`, so one stiffness cannot match Hertz at every overlap, and this one
    /// matches it where the contact works. The force at `δ_ref` is integrated over the exact
    /// overlap of the two circles (4000 points across the contact arc). With `reference` =
    /// [`DEFAULT_REFERENCE_OVERLAP`], the LGRES joints are within 2 % of Hertz from 0 to 6 % of
    /// the clearance (the plain [`Foundation::calibrated`] is 2–4 % soft at their start-up
    /// impacts).
    pub fn hertz_matched(
        bearing: &Material,
        pin: &Material,
        bearing_radius: f64,
        pin_radius: f64,
        reference: f64,
    ) -> Result<Self, ContactError> {
        positive("bearing radius", bearing_radius)?;
        positive("pin radius", pin_radius)?;
        positive("reference overlap", reference)?;
        let clearance = bearing_radius - pin_radius;
        positive("clearance", clearance)?;
        let mut layer = Self::calibrated(bearing, pin);
        let delta = reference * clearance;
        let e = clearance + delta;
        // Half-angle of the overlap on the pin: |e + R_j u(α)| = R_i.
        let cos_half = (bearing_radius * bearing_radius - e * e - pin_radius * pin_radius)
            / (2.0 * e * pin_radius);
        let half = cos_half.clamp(-1.0, 1.0).acos();
        let points = 4000;
        let step = 2.0 * half / points as f64;
        let per_line_modulus: f64 = (0..points)
            .map(|k| {
                let alpha = -half + (k as f64 + 0.5) * step;
                let p = [e + pin_radius * alpha.cos(), pin_radius * alpha.sin()];
                let rho = p[0].hypot(p[1]);
                (rho - bearing_radius).max(0.0) * (p[0] / rho) * pin_radius * step
            })
            .sum();
        let hertz = 4.0 / (3.0 * (bearing.compliance() + pin.compliance()))
            * (bearing_radius * pin_radius / clearance).sqrt()
            * delta.powf(1.5);
        layer.line_modulus = hertz / per_line_modulus;
        positive("layer line modulus", layer.line_modulus)?;
        Ok(layer)
    }

    /// The layer whose conformal stiffness is Liu, Zhang & Yang's for a pin in a hole (Mech.
    /// Mach. Theory 42, 2007): a pin pressed `δ` into a groove it fits carries
    /// `(π/2) k w R_j δ` (`R_j` the pin radius, in m), and with `k w = E* w/(√2 R_j)` that is
    /// their law's conformal limit `(π/(2√2)) E* w δ`, proportional to the hinge width `w` (m)
    /// as a cylinder's force is. [`Foundation::calibrated`] is the same with `R_j` in place of
    /// `w`: the paper's Hertz law, which has no width in it.
    pub fn pin_in_hole(
        bearing: &Material,
        pin: &Material,
        pin_radius: f64,
        width: f64,
    ) -> Result<Self, ContactError> {
        positive("pin radius", pin_radius)?;
        positive("width", width)?;
        let mut layer = Self::calibrated(bearing, pin);
        layer.line_modulus *= width / pin_radius;
        positive("layer line modulus", layer.line_modulus)?;
        Ok(layer)
    }

    /// A layer of modulus `k` (Pa/m, > 0) over hinge width `w` (m, > 0).
    pub fn with_layer(layer_modulus: f64, width: f64) -> Result<Self, ContactError> {
        positive("layer_modulus", layer_modulus)?;
        positive("width", width)?;
        let line_modulus = layer_modulus * width;
        positive("layer_modulus × width", line_modulus)?;
        Ok(Self {
            line_modulus,
            cells: DEFAULT_FOUNDATION_CELLS,
            reference_speed: 0.0,
            quadrature: Quadrature::default(),
        })
    }

    /// The same layer on `cells` nodes (≥ 8; even for [`Quadrature::Simpson`]). A worn pin
    /// should use its wear grid's count, so the nodes sit at its cell centres.
    pub fn with_cells(mut self, cells: usize) -> Result<Self, ContactError> {
        if cells < 8 {
            return Err(ContactError::OutOfRange {
                parameter: "cells",
                value: cells as f64,
                expected: ">= 8",
            });
        }
        self.cells = cells;
        self.check_parity()
    }

    /// The same layer integrated by `quadrature` (default [`Quadrature::Simpson`]).
    pub fn with_quadrature(mut self, quadrature: Quadrature) -> Result<Self, ContactError> {
        self.quadrature = quadrature;
        self.check_parity()
    }

    /// How the energy is integrated between the nodes.
    pub fn quadrature(&self) -> Quadrature {
        self.quadrature
    }

    fn check_parity(self) -> Result<Self, ContactError> {
        if self.quadrature == Quadrature::Simpson && !self.cells.is_multiple_of(2) {
            return Err(ContactError::OutOfRange {
                parameter: "cells",
                value: self.cells as f64,
                expected: "an even count for Simpson's quadrature",
            });
        }
        Ok(self)
    }

    /// The same layer whose damping takes an onset velocity of at least `speed` (m/s, > 0),
    /// beyond the normal law's own floor: node `k` then carries
    /// `G_k (1 + χ ġ_k / max(|δ̇⁻|, v_ref))`. An impact at `v_ref` or faster keeps the law's
    /// restitution `c_e`; a slower one is damped less, as by a constant (Hunt–Crossley)
    /// dissipation coefficient `χ/v_ref` (for Lankarani–Nikravesh `1 − c² ≈ (1 − c_e²) v/v_ref`).
    /// Off by default: the paper's law keeps `c_e` at every speed, and the rate limit of the
    /// module docs already bounds the damping in persistent contact (docs/model.md §10.6).
    pub fn with_reference_speed(mut self, speed: f64) -> Result<Self, ContactError> {
        positive("reference_speed", speed)?;
        self.reference_speed = speed;
        Ok(self)
    }

    /// The slowest onset velocity the layer's damping is scaled by (m/s; 0: none beyond the
    /// normal law's floor).
    pub fn reference_speed(&self) -> f64 {
        self.reference_speed
    }

    /// `k w` (Pa).
    pub fn line_modulus(&self) -> f64 {
        self.line_modulus
    }

    /// The layer modulus `k` (Pa/m) over hinge width `width` (m).
    pub fn layer_modulus(&self, width: f64) -> f64 {
        self.line_modulus / width
    }

    /// Nodes on the pin's outline.
    pub fn cells(&self) -> usize {
        self.cells
    }
}
