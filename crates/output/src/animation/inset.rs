//! The magnified clearance insets of an animation frame ([`Inset`]): per clearance joint, the
//! clearance circle in the bearing's frame with the journal centre, its orbit, the worn
//! clearance and the contact force.

use std::f64::consts::TAU;

use plotters::prelude::*;

use super::canvas::colours::{FORCE, GROUND, IDEAL, JOINT, LINK, TRAIL, WORN};
use super::canvas::{ANIMATION_SIZE, Area, DrawResult, text};
use super::layout::{FOOTER, INSETS, TITLE, View, global};
use scene::{BodyRef, Scene};
use sim::surfaces::cell_angle_deg;
use sim::{JointWearHistory, MechanismFrames, Response};

/// Most points of the orbit drawn over a cycle.
const TRAIL_POINTS: usize = 1500;
/// Height of the force line at the foot of an inset, pixels.
const FORCE_LINE: i32 = 22;

/// The largest of 1, 1.5, 2, 2.5, 3, 4, 5, 6 and 8 times a power of ten at most `x` (`x`
/// itself when it is not positive and finite).
fn nice_floor(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return x;
    }
    let decade = 10f64.powf(x.log10().floor());
    [8.0, 6.0, 5.0, 4.0, 3.0, 2.5, 2.0, 1.5, 1.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|v| *v <= x * (1.0 + 1e-12))
        .unwrap_or(decade)
}

/// A factor as written in the picture: `300`, `2.5`.
pub(super) fn factor_label(m: f64) -> String {
    if (m - m.round()).abs() < 1e-9 * m.max(1.0) {
        format!("{m:.0}")
    } else {
        format!("{}", (m * 1e6).round() / 1e6)
    }
}

/// One clearance joint's magnified inset.
pub(super) struct Inset {
    pub(super) name: String,
    /// The clearance is drawn this many times larger than the mechanism.
    pub(super) magnification: f64,
    /// Index into `Response::contact`.
    series: usize,
    /// The bearing centre: on a body (index, point in its frame) or fixed (global).
    bearing: Result<(usize, [f64; 2]), [f64; 2]>,
    /// The box, pixels (left, top, right, bottom), and the bearing centre in it.
    frame: (i32, i32, i32, i32),
    centre: (i32, i32),
    /// Pixels per metre of eccentricity.
    px_per_m: f64,
    /// Clearance circle radius, pixels.
    radius: f64,
    /// Archard depths of the worn bearing and pin per cell of their body frames, m (empty:
    /// unworn), and the indices of the bodies carrying them (`None`: the ground).
    bearing_depth: Vec<f64>,
    pin_depth: Vec<f64>,
    bodies: (Option<usize>, Option<usize>),
    /// Largest normal force over the cycle shown (from the start of the first frame's
    /// interval), N.
    peak: f64,
}

/// The insets of the active clearance joints of `response`, stacked right of the mechanism.
pub(super) fn insets(
    scene: &Scene,
    response: &Response,
    frames: &MechanismFrames,
    worn: &[JointWearHistory],
    view: &View,
) -> Vec<Inset> {
    let joints: Vec<_> = response
        .contact
        .iter()
        .enumerate()
        .filter_map(|(s, c)| {
            let joint = scene.clearance_joints.iter().find(|j| j.name == c.name)?;
            Some((s, c, joint))
        })
        .collect();
    if joints.is_empty() {
        return Vec::new();
    }
    let (w, h) = (ANIMATION_SIZE.0 as i32, ANIMATION_SIZE.1 as i32);
    let (left, right) = (w - INSETS + 4, w - 6);
    let height = (h - FOOTER - TITLE) / joints.len() as i32;
    let first = frames.frames[0];
    let last = *frames.frames.last().unwrap_or(&first);
    let (from, _) = interval(&frames.frames, 0);
    joints
        .into_iter()
        .enumerate()
        .map(|(k, (series, c, joint))| {
            let top = TITLE + k as i32 * height;
            let frame = (left, top, right, top + height - 6);
            let last_stage = worn
                .iter()
                .find(|j| j.name == c.name)
                .and_then(|j| j.stages.last());
            let bearing_depth = last_stage.map_or(Vec::new(), |s| s.bearing().depth().to_vec());
            let pin_depth = last_stage.map_or(Vec::new(), |s| s.pin().depth().to_vec());
            // The title (and the worn clearance's legend) above the circle, the force below.
            let header = if last_stage.is_none() { 26 } else { 42 };
            let free = height - 6 - header - FORCE_LINE;
            let room = f64::from((right - left) / 2 - 14).min(f64::from(free - 8) / 2.0);
            let finite = |v: &&f64| v.is_finite();
            let largest = |v: &[f64]| v.iter().filter(finite).fold(0.0, |a, b| f64::max(a, *b));
            let eccentricity = c.eccentricity.get(first..=last).map_or(0.0, largest);
            let extent = c
                .clearance
                .max(eccentricity)
                .max(c.clearance + 0.5 * (largest(&bearing_depth) + largest(&pin_depth)));
            let magnification = nice_floor(room.max(4.0) / (extent * view.scale));
            let px_per_m = magnification * view.scale;
            let centre = ((left + right) / 2, top + header + free / 2);
            let body = |name: &str| match scene.resolve(name) {
                Some(BodyRef::Body(b)) => Some(b),
                _ => None,
            };
            let bodies = (body(&joint.bearing_body), body(&joint.pin_body));
            let bearing = bodies
                .0
                .map(|b| (b, joint.bearing_point))
                .ok_or(joint.bearing_point);
            Inset {
                name: c.name.clone(),
                magnification,
                series,
                bearing,
                frame,
                centre,
                px_per_m,
                radius: px_per_m * c.clearance,
                bearing_depth,
                pin_depth,
                bodies,
                peak: c.normal_force.get(from..=last).map_or(0.0, largest),
            }
        })
        .collect()
}

/// The output samples frame `i` of `frames` stands for, `(from, to)` inclusive: those after
/// the previous frame up to its own (for the first frame, as many before it as lie between
/// the first two).
fn interval(frames: &[usize], i: usize) -> (usize, usize) {
    let k = frames[i];
    let from = match i {
        0 => match frames.get(1) {
            Some(next) => k.saturating_sub(next - k - 1),
            None => k,
        },
        _ => frames[i - 1] + 1,
    };
    (from.min(k), k)
}

/// Depth of the cell of `depth` (cells evenly over a turn of the body frame, cell 0 from 0)
/// holding body-frame angle `angle` (rad); 0 without cells.
fn depth_at(depth: &[f64], angle: f64) -> f64 {
    let n = depth.len();
    if n == 0 {
        return 0.0;
    }
    let k = (angle.rem_euclid(TAU) / TAU * n as f64) as usize;
    depth[k.min(n - 1)]
}

/// Directions at which the worn clearance is drawn.
const OUTLINE_POINTS: usize = 720;

/// Pixel at `(dx, dy)` pixels right of and above `centre`.
fn at(centre: (i32, i32), dx: f64, dy: f64) -> (i32, i32) {
    (centre.0 + dx.round() as i32, centre.1 - dy.round() as i32)
}

impl Inset {
    /// Marks the joint in the mechanism at `poses` and names it.
    pub(super) fn draw_mark(&self, area: &Area<'_>, view: &View, poses: &[[f64; 3]]) -> DrawResult {
        let p = match self.bearing {
            Ok((b, p)) => poses.get(b).map_or(p, |pose| global(pose, p)),
            Err(p) => p,
        };
        let (x, y) = view.px(p);
        area.draw(&Circle::new((x, y), 9, JOINT.stroke_width(3)))?;
        // Right of the mark, unless the name would run out of the mechanism's part.
        let width = 10 * self.name.chars().count() as i32;
        let left = if x + 11 + width > view.width as i32 {
            x - 11 - width
        } else {
            x + 11
        };
        text(area, &self.name, (left, y - 26), 17, JOINT)
    }

    /// The worn clearance at `poses`, pixels: in each direction `φ` of the bearing frame the
    /// clearance `c + (h_bearing(φ) + h_pin(φ'))/2`, `φ'` the same direction in the pin's
    /// frame (which turns against the bearing's). Empty when unworn.
    fn worn_outline(&self, poses: &[[f64; 3]]) -> Vec<(i32, i32)> {
        if self.bearing_depth.is_empty() && self.pin_depth.is_empty() {
            return Vec::new();
        }
        let angle = |b: Option<usize>| b.and_then(|b| poses.get(b)).map_or(0.0, |p| p[2]);
        let turn = angle(self.bodies.0) - angle(self.bodies.1);
        let c = self.radius / self.px_per_m;
        (0..=OUTLINE_POINTS)
            .map(|j| {
                let phi = cell_angle_deg(j % OUTLINE_POINTS, OUTLINE_POINTS).to_radians();
                let h = depth_at(&self.bearing_depth, phi) + depth_at(&self.pin_depth, phi + turn);
                let r = self.px_per_m * (c + 0.5 * h);
                at(self.centre, r * phi.cos(), r * phi.sin())
            })
            .collect()
    }

    /// The inset at frame `i` of `frames` (output samples; `poses` the bodies' then): the
    /// journal centre and its orbit at the frame's sample, the arrow the largest contact force
    /// of the samples since the previous frame (so an impact between frames shows), in its
    /// direction then.
    pub(super) fn draw(
        &self,
        area: &Area<'_>,
        response: &Response,
        frames: &[usize],
        i: usize,
        poses: &[[f64; 3]],
    ) -> DrawResult {
        let k = frames[i];
        let c = &response.contact[self.series];
        let (l, t, r, b) = self.frame;
        area.draw(&Rectangle::new([(l, t), (r, b)], IDEAL.stroke_width(1)))?;
        let label = format!(
            "{}: clearance ×{}",
            self.name,
            factor_label(self.magnification)
        );
        text(area, &label, (l + 6, t + 5), 14, JOINT)?;
        let (cx, cy) = self.centre;
        area.draw(&PathElement::new(
            vec![(cx - 4, cy), (cx + 4, cy)],
            GROUND.stroke_width(1),
        ))?;
        area.draw(&PathElement::new(
            vec![(cx, cy - 4), (cx, cy + 4)],
            GROUND.stroke_width(1),
        ))?;
        let circle: Vec<(i32, i32)> = (0..=120)
            .map(|d| {
                let phi = TAU * f64::from(d) / 120.0;
                at(
                    self.centre,
                    self.radius * phi.cos(),
                    self.radius * phi.sin(),
                )
            })
            .collect();
        area.draw(&PathElement::new(circle, BLACK.stroke_width(1)))?;
        let worn = self.worn_outline(poses);
        if !worn.is_empty() {
            area.draw(&PathElement::new(worn, WORN.stroke_width(2)))?;
            text(area, "worn: c + (h_b + h_p)/2", (l + 6, t + 23), 13, WORN)?;
        }
        let e = |j: usize| {
            let (x, y) = (c.ex_bearing[j], c.ey_bearing[j]);
            if x.is_finite() && y.is_finite() {
                (x, y)
            } else {
                (0.0, 0.0)
            }
        };
        let pixel = |(x, y): (f64, f64)| at(self.centre, self.px_per_m * x, self.px_per_m * y);
        let first = frames[0];
        let stride = (frames.last().unwrap_or(&first) - first)
            .div_ceil(TRAIL_POINTS)
            .max(1);
        let trail: Vec<(i32, i32)> = (first..k)
            .step_by(stride)
            .chain([k])
            .map(|j| pixel(e(j)))
            .collect();
        area.draw(&PathElement::new(trail, TRAIL.stroke_width(1)))?;
        let (ex, ey) = e(k);
        let pin = pixel((ex, ey));
        area.draw(&Circle::new(pin, 5, LINK.filled()))?;
        let (from, to) = interval(frames, i);
        let (force, j) = (from..=to)
            .filter(|&j| c.normal_force[j].is_finite())
            .map(|j| (c.normal_force[j], j))
            .fold((0.0, k), |best, f| if f.0 > best.0 { f } else { best });
        let (fx, fy) = e(j);
        let norm = fx.hypot(fy);
        if self.peak > 0.0 && force > 0.0 && norm > 0.0 {
            // The bearing pushes the pin towards its centre.
            let length = self.radius * (force / self.peak).min(1.0);
            let (ux, uy) = (-fx / norm, -fy / norm);
            let tip = at(pin, length * ux, length * uy);
            area.draw(&PathElement::new(vec![pin, tip], FORCE.stroke_width(3)))?;
            let head = 9.0_f64.min(0.6 * length);
            let side = |s: f64| {
                at(
                    tip,
                    -head * ux + s * 0.5 * head * uy,
                    -head * uy - s * 0.5 * head * ux,
                )
            };
            area.draw(&Polygon::new(
                vec![tip, side(1.0), side(-1.0)],
                FORCE.filled(),
            ))?;
        }
        let note = if self.peak > 0.0 {
            format!("F = {:.2} kN, peak {:.2} kN", force / 1e3, self.peak / 1e3)
        } else {
            "no contact in this cycle".to_string()
        };
        text(area, &note, (l + 6, b - FORCE_LINE + 2), 13, FORCE)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_intervals_tile_the_samples() {
        let frames = [10, 14, 18, 22];
        assert_eq!(interval(&frames, 0), (7, 10));
        assert_eq!(interval(&frames, 1), (11, 14));
        assert_eq!(interval(&frames, 3), (19, 22));
        assert_eq!(interval(&[2, 9], 0), (0, 2));
        assert_eq!(interval(&[5], 0), (5, 5));
    }

    #[test]
    fn depths_are_looked_up_by_cell() {
        let depth = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(depth_at(&depth, 0.1), 1.0);
        assert_eq!(depth_at(&depth, TAU / 4.0 + 0.01), 2.0);
        assert_eq!(depth_at(&depth, -0.01), 4.0);
        assert_eq!(depth_at(&depth, TAU + 0.01), 1.0);
        assert_eq!(depth_at(&[], 1.0), 0.0);
    }

    #[test]
    fn nice_factors() {
        assert_eq!(nice_floor(347.0), 300.0);
        assert_eq!(nice_floor(799.0), 600.0);
        assert_eq!(nice_floor(100.0), 100.0);
        assert_eq!(nice_floor(0.29), 0.25);
        assert_eq!(factor_label(250.0), "250");
        assert_eq!(factor_label(0.25), "0.25");
    }
}
