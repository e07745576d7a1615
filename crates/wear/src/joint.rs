//! A worn clearance joint: wear parameters, the bearing and pin surfaces, the contact arc.
//!
//! What a stage's wear does to a joint ([`WornJoint::start_stage`], [`WornJoint::apply`],
//! [`WornJoint::check_apply`] and the change bounds) is in `accumulate`, next to the record
//! ([`crate::StageWear`]) it reads.

use contact::SlidingVelocity;
use serde::{Deserialize, Serialize};

use crate::error::{WearError, non_negative, positive};
use crate::profile::{Side, WornProfile};

/// Default number of cells per surface (the paper's grid).
pub const DEFAULT_CELLS: usize = 1000;

/// Archard wear parameters of one joint.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct WearParams {
    /// Dimensional wear coefficient `K_d = K_w / H` (m²/N). `0` means wear off.
    pub wear_coefficient: f64,
    /// Hinge width `w` (m): the contact area is `chord · w`.
    pub hinge_width: f64,
    /// Cells per surface over 360°.
    pub cells: usize,
}

impl WearParams {
    /// Parameters with dimensional wear coefficient `K_d` (m²/N; 0: wear off) and the default
    /// grid ([`DEFAULT_CELLS`]); the hinge width is still to be given with
    /// [`WearParams::with_hinge_width`] (validation rejects it unset):
    /// `WearParams::archard(1.8e-13).with_hinge_width(0.1)` reads without the argument order.
    /// Validated where used ([`WornJoint::new`]) or by [`WearParams::validate`].
    pub fn archard(wear_coefficient: f64) -> Self {
        Self {
            wear_coefficient,
            hinge_width: f64::NAN,
            cells: DEFAULT_CELLS,
        }
    }

    /// The same parameters with hinge width `w` (m).
    pub fn with_hinge_width(mut self, hinge_width: f64) -> Self {
        self.hinge_width = hinge_width;
        self
    }

    /// The same parameters with `cells` cells per surface.
    pub fn with_cells(mut self, cells: usize) -> Self {
        self.cells = cells;
        self
    }

    /// Validated parameters: `K_d` finite and ≥ 0, `w` finite and > 0, `cells ≥ 1`.
    pub fn new(wear_coefficient: f64, hinge_width: f64, cells: usize) -> Result<Self, WearError> {
        let params = Self {
            wear_coefficient,
            hinge_width,
            cells,
        };
        params.validate()?;
        Ok(params)
    }

    /// Checks the parameters (for values built or deserialized field by field).
    pub fn validate(&self) -> Result<(), WearError> {
        non_negative("wear_coefficient", self.wear_coefficient)?;
        positive("hinge_width", self.hinge_width)?;
        if self.cells == 0 {
            return Err(WearError::ZeroCells);
        }
        Ok(())
    }

    /// Whether these parameters produce any wear (`K_d > 0`).
    pub fn is_on(&self) -> bool {
        self.wear_coefficient > 0.0
    }
}

/// The geometry of a penetrating contact: where the pin and bearing circles intersect.
///
/// The intersection points A and B lie at `R_j` from the pin centre and `R_i` from the bearing
/// centre, `|e|` apart. In the triangle (bearing centre, pin centre, A) the law of cosines gives
/// the angle `α` at the pin centre (docs/model.md §3), and the angle `γ` at the bearing centre:
///
/// `cos α = (|e|² + R_j² − R_i²) / (2|e|R_j)`,  `cos γ = (|e|² + R_i² − R_j²) / (2|e|R_i)`.
///
/// The contact direction `n` points from the bearing centre through the pin centre, so the
/// pin's arc spans `±(π − α)` about `n` and the bearing's `±γ` about `n`; the chord is
/// `AB = 2R_j sin(π − α) = 2R_i sin γ` (law of sines). Both angles are computed in the
/// cancellation-free half-angle form, with `δ = |e| − (R_i − R_j)`:
///
/// `sin²((π − α)/2) = δ (|e| + R_i + R_j) / (4|e|R_j)`,  `sin²(γ/2) = δ (R_i + R_j − |e|) / (4|e|R_i)`,
///
/// which stay accurate for micrometre penetrations where the cosine forms lose digits.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactArc {
    /// Half-angle of the arc on the pin, `π − α` (rad).
    pub pin_half_angle: f64,
    /// Half-angle of the arc on the bearing, `γ` (rad).
    pub bearing_half_angle: f64,
    /// Chord `AB` (m).
    pub chord: f64,
}

impl ContactArc {
    /// The arc for eccentricity `|e|` and local radii; `None` unless the pin penetrates
    /// (`δ > 0`) with positive radii.
    pub fn new(eccentricity: f64, bearing_radius: f64, pin_radius: f64) -> Option<Self> {
        let (e, ri, rj) = (eccentricity, bearing_radius, pin_radius);
        let delta = e - (ri - rj);
        if !(delta > 0.0 && ri > 0.0 && rj > 0.0 && e.is_finite()) {
            return None;
        }
        let half = |s2: f64| 2.0 * s2.clamp(0.0, 1.0).sqrt().asin();
        let pin_half_angle = half(delta * (e + ri + rj) / (4.0 * e * rj));
        let bearing_half_angle = half(delta * (ri + rj - e) / (4.0 * e * ri));
        let chord = 2.0 * rj * pin_half_angle.sin();
        (chord > 0.0).then_some(Self {
            pin_half_angle,
            bearing_half_angle,
            chord,
        })
    }
}

/// Bounds on the shape of a worn clearance relative to the nominal clearance `c0` (see
/// [`WornJoint::shape_bounds`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeBound {
    /// `(max|R_i'| + max|R_j'|)/c0`, 1/rad.
    pub slope: f64,
    /// `(max|R_i''| + max|R_j''|)/c0`, 1/rad².
    pub curvature: f64,
}

/// A clearance joint with worn surfaces: the bearing (hole, on one body) and the pin
/// (journal, on the other), each a body-fixed [`WornProfile`], plus the wear parameters.
///
/// Serializes whole, so a stage can be saved, inspected and resumed; deserialization
/// re-validates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "JointData")]
pub struct WornJoint {
    wear_coefficient: f64,
    hinge_width: f64,
    bearing: WornProfile,
    pin: WornProfile,
    /// Which sliding velocity drives Archard wear.
    #[serde(default)]
    sliding: SlidingVelocity,
}

#[derive(Deserialize)]
struct JointData {
    wear_coefficient: f64,
    hinge_width: f64,
    bearing: WornProfile,
    pin: WornProfile,
    #[serde(default)]
    sliding: SlidingVelocity,
}

impl TryFrom<JointData> for WornJoint {
    type Error = WearError;
    fn try_from(d: JointData) -> Result<Self, WearError> {
        WornJoint::from_profiles(d.wear_coefficient, d.hinge_width, d.bearing, d.pin)
            .map(|joint| joint.with_sliding(d.sliding))
    }
}

impl WornJoint {
    /// An unworn joint with bearing radius `R_i` and pin radius `R_j < R_i` (m). A joint value
    /// always wears, so `K_d = 0` is an error here; for parameters that may say "wear off" use
    /// [`WornJoint::if_wearing`].
    pub fn new(
        params: &WearParams,
        bearing_radius: f64,
        pin_radius: f64,
    ) -> Result<Self, WearError> {
        params.validate()?;
        check_radii(bearing_radius, pin_radius)?;
        Self::from_profiles(
            params.wear_coefficient,
            params.hinge_width,
            WornProfile::new(Side::Bearing, bearing_radius, params.cells)?,
            WornProfile::new(Side::Pin, pin_radius, params.cells)?,
        )
    }

    /// [`WornJoint::new`], or `Ok(None)` when `params` turn wear off (`K_d = 0`, e.g. read from a
    /// scene): the caller keeps an `Option<WornJoint>` and with `None` allocates no grid and
    /// calls no wear code (it uses `contact::CircularProfile` for the surfaces). Parameters and
    /// radii are validated either way.
    pub fn if_wearing(
        params: &WearParams,
        bearing_radius: f64,
        pin_radius: f64,
    ) -> Result<Option<Self>, WearError> {
        if params.is_on() {
            return Self::new(params, bearing_radius, pin_radius).map(Some);
        }
        params.validate()?;
        check_radii(bearing_radius, pin_radius)?;
        Ok(None)
    }

    /// A joint from existing (possibly worn) surfaces, e.g. loaded from a previous stage.
    /// `wear_coefficient` must be > 0 here: a joint value always means wear on.
    pub fn from_profiles(
        wear_coefficient: f64,
        hinge_width: f64,
        bearing: WornProfile,
        pin: WornProfile,
    ) -> Result<Self, WearError> {
        positive("wear_coefficient", wear_coefficient)?;
        positive("hinge_width", hinge_width)?;
        for (name, profile, side) in [
            ("bearing", &bearing, Side::Bearing),
            ("pin", &pin, Side::Pin),
        ] {
            if profile.side() != side {
                return Err(WearError::WrongSide { name });
            }
        }
        check_radii(bearing.nominal_radius(), pin.nominal_radius())?;
        Ok(Self {
            wear_coefficient,
            hinge_width,
            bearing,
            pin,
            sliding: SlidingVelocity::Material,
        })
    }

    /// The same joint with wear driven by `sliding` (default: the material sliding velocity;
    /// [`SlidingVelocity::Paper`] reproduces the paper's `δ φ̇`, about 30× less wear).
    pub fn with_sliding(mut self, sliding: SlidingVelocity) -> Self {
        self.sliding = sliding;
        self
    }

    /// Which sliding velocity drives the wear.
    pub fn sliding(&self) -> SlidingVelocity {
        self.sliding
    }

    /// `K_d` (m²/N).
    pub fn wear_coefficient(&self) -> f64 {
        self.wear_coefficient
    }

    /// Hinge width `w` (m).
    pub fn hinge_width(&self) -> f64 {
        self.hinge_width
    }

    /// The bearing surface (implements `contact::SurfaceProfile`).
    pub fn bearing(&self) -> &WornProfile {
        &self.bearing
    }

    /// The pin surface (implements `contact::SurfaceProfile`).
    pub fn pin(&self) -> &WornProfile {
        &self.pin
    }

    /// The bearing and pin surfaces, for a stage's update ([`WornJoint::apply`]).
    pub(crate) fn surfaces_mut(&mut self) -> (&mut WornProfile, &mut WornProfile) {
        (&mut self.bearing, &mut self.pin)
    }

    /// Initial clearance `c0 = R_i − R_j` (m).
    pub fn nominal_clearance(&self) -> f64 {
        self.bearing.nominal_radius() - self.pin.nominal_radius()
    }

    /// Local clearance `c = R_i*(θ_i) − R_j*(θ_j) = c0 + (h_i + h_j)/2 ≥ c0` (m) for a contact
    /// direction at body-frame angles `bearing_angle` and `pin_angle`.
    pub fn local_clearance(&self, bearing_angle: f64, pin_angle: f64) -> f64 {
        self.nominal_clearance()
            + 0.5 * (self.bearing.wear_depth(bearing_angle).0 + self.pin.wear_depth(pin_angle).0)
    }

    /// Largest local clearance (m): `c0 + (max h_i + max h_j)/2`, the clearance where the
    /// deepest dents of bearing and pin face each other (cell depths; the interpolated profile
    /// never exceeds its deepest cell, so this bounds [`local_clearance`](Self::local_clearance)
    /// in every direction, and the bodies' relative rotation reaches it when it aligns the two
    /// peaks).
    pub fn max_local_clearance(&self) -> f64 {
        self.nominal_clearance() + 0.5 * (self.bearing.peak().depth + self.pin.peak().depth)
    }

    /// Material removed from both surfaces so far (m³).
    pub fn worn_volume(&self) -> f64 {
        self.bearing.worn_volume(self.hinge_width) + self.pin.worn_volume(self.hinge_width)
    }
}

fn check_radii(bearing_radius: f64, pin_radius: f64) -> Result<(), WearError> {
    positive("bearing_radius", bearing_radius)?;
    positive("pin_radius", pin_radius)?;
    if pin_radius >= bearing_radius {
        return Err(WearError::RadiiInconsistent {
            pin: pin_radius,
            bearing: bearing_radius,
        });
    }
    Ok(())
}
