//! The diagnostics' running sums over an evaluation's nodes: energy, powers, resultants, the
//! deepest overlap and the contact zones, whose widths give the quadrature's resolution.

use super::layer::Quadrature;
use crate::diagnostics::ContactDiagnostics;
use crate::surface::{SurfaceProfile, wrap_angle};

/// Running sums for the diagnostics (plain values).
#[derive(Default)]
pub(in crate::joint) struct Books {
    pub(in crate::joint) energy: f64,
    pub(in crate::joint) damping_power: f64,
    pub(in crate::joint) friction_power: f64,
    pub(in crate::joint) friction_force: f64,
    pub(in crate::joint) normal_resultant: [f64; 2],
    /// `Σ G_k m_k` over the overlapping nodes, clamped ones included.
    pub(in crate::joint) elastic_resultant: [f64; 2],
    pub(in crate::joint) load: f64,
    pub(in crate::joint) load_sliding: f64,
    /// The deepest overlap seen (m), and the rate `ġ` of its node once computed.
    pub(in crate::joint) deepest: Option<f64>,
    pub(in crate::joint) deepest_rate: f64,
    pub(in crate::joint) cells: u32,
    pub(in crate::joint) zones: u32,
    /// Nodes around the pin (for zones through cell 0).
    pub(in crate::joint) grid: usize,
    /// The open zone: its last cell, its cells and its load.
    pub(in crate::joint) open: Option<(usize, u32, f64)>,
    /// The first [`MAX_ZONES`] closed zones' cells and loads.
    pub(in crate::joint) closed: [(u32, f64); MAX_ZONES],
    /// The quadrature, whose error the zones' resolution implies.
    pub(in crate::joint) quadrature: Quadrature,
    /// The loaded nodes' normal loads as the trapezoid weighs them (N; Simpson's deposits).
    pub(in crate::joint) trapezoid_load: f64,
    /// The normal loads of the nodes Simpson weighs negatively (N, ≤ 0; elastic only).
    pub(in crate::joint) pull: f64,
}

/// Zones whose width and load are kept for the narrowest-zone measure.
pub(in crate::joint) const MAX_ZONES: usize = 16;
/// Relative load a zone of one node misses by the linear interpolation between nodes; `n`
/// nodes miss this over `n²` (see [`Books::resolution_error`]).
pub(in crate::joint) const RESOLUTION_ERROR: f64 = 0.96;
/// The same bound for [`Quadrature::Simpson`], also over `n²`: a quarter of the trapezoid's.
/// Simpson's error falls faster (test `simpsons_quadrature_is_within_its_resolution_estimate`:
/// worst 3.3 % at zones of 2.5 nodes, 0.48 % at 5, 0.012 % at 10), so this overstates it
/// beyond a few nodes, where it is far below the validity limit anyway; it is tight where
/// the limit decides.
pub(in crate::joint) const SIMPSON_RESOLUTION_ERROR: f64 = 0.24;

impl Books {
    /// Counts one node's overlap for the deepest; `true` when it is the deepest so far.
    pub(in crate::joint) fn see_overlap(&mut self, g: f64) -> bool {
        let deepest = self.deepest.is_none_or(|d| g > d);
        if deepest {
            self.deepest = Some(g);
        }
        deepest
    }

    /// Adds node `cell` (overlap `g`, normal load `load`) to the zone bookkeeping; nodes come
    /// in order, and a zone is a run of consecutive overlapping cells.
    pub(in crate::joint) fn see_zone(&mut self, cell: usize, g: f64, load: f64) {
        let grid = self.grid.max(1);
        let continues = self
            .open
            .is_some_and(|(last, _, _)| (last + 1) % grid == cell);
        if g <= 0.0 || !continues {
            self.close_zone();
        }
        if g > 0.0 {
            self.cells += 1;
            let (_, width, carried) = self.open.unwrap_or((cell, 0, 0.0));
            self.open = Some((cell, width + 1, carried + load));
        }
    }

    pub(in crate::joint) fn close_zone(&mut self) {
        if let Some((_, width, load)) = self.open.take() {
            if (self.zones as usize) < MAX_ZONES {
                self.closed[self.zones as usize] = (width, load);
            }
            self.zones += 1;
        }
    }

    /// The relative error of the total normal load that the grid's resolution of each zone
    /// implies: linear interpolation across a smooth cap of `n` nodes misses `≈ 0.96/n²` of its
    /// load (measured on round surfaces: −0.24 % at 20 nodes, −0.025 % at 63, −0.009 % at 108,
    /// docs/model.md §10.2), weighted by each zone's share of the load.
    pub(in crate::joint) fn resolution_error(&mut self) -> f64 {
        self.close_zone();
        let kept = &self.closed[..(self.zones as usize).min(MAX_ZONES)];
        let total: f64 = kept.iter().map(|(_, load)| load).sum();
        if total <= 0.0 {
            return 0.0;
        }
        let miss = |width: u32| match self.quadrature {
            Quadrature::Trapezoid => RESOLUTION_ERROR / f64::from(width).powi(2),
            Quadrature::Simpson => SIMPSON_RESOLUTION_ERROR / f64::from(width).powi(2),
        };
        kept.iter()
            .map(|(width, load)| load / total * miss(*width))
            .sum()
    }

    /// Cells across the narrowest zone among those carrying at least a tenth of the load (all
    /// zones when none carries load); 0 without contact.
    pub(in crate::joint) fn narrowest(&mut self) -> u32 {
        self.close_zone();
        let kept = &self.closed[..(self.zones as usize).min(MAX_ZONES)];
        let total: f64 = kept.iter().map(|(_, load)| load).sum();
        kept.iter()
            .filter(|(_, load)| total <= 0.0 || *load >= 0.1 * total)
            .map(|(width, _)| *width)
            .min()
            .unwrap_or(0)
    }
}

/// Where a layer model's evaluation stood, for [`Books::diagnostics`]: the plain values of the
/// pose the books were summed at.
pub(in crate::joint) struct LayerPose {
    /// `|e|`, the eccentricity's length (m).
    pub rho: f64,
    /// The eccentricity, pin centre minus bearing centre (m).
    pub e: [f64; 2],
    /// The bearing centre in the world (m).
    pub centre: [f64; 2],
    /// The bearing's and the pin's angles (rad).
    pub angles: (f64, f64),
    /// The paper's sliding rate `φ̇` (rad/s).
    pub phi_rate: f64,
    /// The rate of the centres' distance (m/s).
    pub centre_rate: f64,
    /// The model's bound on the outlines' gap when no node was computed (m, negative: free).
    pub free_gap: f64,
}

impl Books {
    /// The diagnostics the layer models (the foundation, the thin gap) report from their books:
    /// the contact direction is the resultant normal force on the bearing when loaded, else the
    /// line of centres; the deepest overlap and its rate, or, free, a negative distance between
    /// the outlines (or the model's bound on it) and the rate of the centres' distance.
    pub(in crate::joint) fn diagnostics<B: SurfaceProfile, P: SurfaceProfile>(
        &mut self,
        bearing: &B,
        pin: &P,
        pose: LayerPose,
    ) -> ContactDiagnostics {
        let loaded = self.load > 0.0;
        let direction = if loaded {
            self.normal_resultant
        } else {
            pose.e
        };
        let contact_angle = if direction == [0.0, 0.0] {
            0.0
        } else {
            direction[1].atan2(direction[0])
        };
        let (theta_bearing, theta_pin) = pose.angles;
        let bearing_angle = wrap_angle(contact_angle - theta_bearing);
        let pin_angle = wrap_angle(contact_angle - theta_pin);
        let bearing_sample = bearing.sample(bearing_angle);
        let pin_sample = pin.sample(pin_angle);
        let (sin, cos) = contact_angle.sin_cos();
        let (penetration, normal_velocity) = match self.deepest {
            Some(g) if g > 0.0 => (g, self.deepest_rate),
            Some(g) => (g, pose.centre_rate),
            None => (pose.free_gap, pose.centre_rate),
        };
        ContactDiagnostics {
            in_contact: penetration > 0.0,
            penetration,
            eccentricity: pose.rho,
            contact_angle,
            bearing_angle,
            pin_angle,
            bearing_radius: bearing_sample.radius,
            pin_radius: pin_sample.radius,
            normal_velocity,
            tangential_velocity: if loaded {
                self.load_sliding / self.load
            } else {
                0.0
            },
            geometric_sliding_velocity: penetration.max(0.0) * pose.phi_rate,
            normal_force: self.normal_resultant[0].hypot(self.normal_resultant[1]),
            elastic_force: self.elastic_resultant[0].hypot(self.elastic_resultant[1]),
            friction_force: self.friction_force,
            contact_point: [
                pose.centre[0] + bearing_sample.radius * cos,
                pose.centre[1] + bearing_sample.radius * sin,
            ],
            elastic_energy: self.energy,
            damping_power: self.damping_power,
            friction_power: self.friction_power,
            bearing_slope: bearing_sample.slope,
            pin_slope: pin_sample.slope,
            bearing_curvature: bearing_sample.curvature,
            pin_curvature: pin_sample.curvature,
            contact_cells: self.cells,
            contact_zones: self.zones,
            narrowest_zone_cells: self.narrowest(),
            resolution_error: self.resolution_error(),
            neglected_terms: 0.0,
        }
    }
}
