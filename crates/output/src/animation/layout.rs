//! What an animation frame draws of the mechanism: its links and ground marks from the
//! scene ([`Mechanism`]) and its placement in the picture ([`View`]).

use plotters::prelude::*;

use super::canvas::colours::{GROUND, IDEAL, LINK};
use super::canvas::{ANIMATION_SIZE, Area, DrawResult};
use scene::{BodyRef, Scene};
use sim::MechanismFrames;

/// Height of the title band, pixels.
pub(super) const TITLE: i32 = 36;
/// Height of the footer, pixels.
pub(super) const FOOTER: i32 = 42;
/// Width of the column of insets, pixels.
pub(super) const INSETS: i32 = 215;
/// Free margin around the mechanism, pixels.
const PAD: f64 = 26.0;

/// `p` (body frame) in the global frame of a body at `pose` `[x, y, θ]`.
pub(super) fn global(pose: &[f64; 3], p: [f64; 2]) -> [f64; 2] {
    let (s, c) = pose[2].sin_cos();
    [pose[0] + c * p[0] - s * p[1], pose[1] + s * p[0] + c * p[1]]
}

/// A guide line fixed to the ground and the body point that slides on it.
struct Guide {
    origin: [f64; 2],
    direction: [f64; 2],
    body: usize,
    point: [f64; 2],
}

/// How a body is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    /// A block on its centroid (a slider: at most one joint point).
    Block,
    /// A bar between two of its points (the others lie on it).
    Bar(usize, usize),
    /// A polygon through its points.
    Polygon,
}

impl Shape {
    /// The shape of a body with joint points `points` (distinct): a bar when they lie on one
    /// line (within a thousandth of the link's length).
    fn of(points: &[[f64; 2]]) -> Self {
        let dist = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
        let mut ends = (0, 0, 0.0);
        for (i, a) in points.iter().enumerate() {
            for (j, b) in points.iter().enumerate().skip(i + 1) {
                if dist(*a, *b) > ends.2 {
                    ends = (i, j, dist(*a, *b));
                }
            }
        }
        let (i, j, length) = ends;
        if length <= 0.0 {
            return Shape::Block;
        }
        let (a, b) = (points[i], points[j]);
        let off = |p: &[f64; 2]| {
            ((p[0] - a[0]) * (b[1] - a[1]) - (p[1] - a[1]) * (b[0] - a[0])).abs() / length
        };
        if points.iter().all(|p| off(p) <= 1e-3 * length) {
            Shape::Bar(i, j)
        } else {
            Shape::Polygon
        }
    }
}

/// The scene's bodies as links through their joint points, and its ground marks.
pub(super) struct Mechanism {
    /// Per body, its joint points in its frame: distinct, ordered around their centroid.
    links: Vec<Vec<[f64; 2]>>,
    shapes: Vec<Shape>,
    /// Ground pivots (global).
    pivots: Vec<[f64; 2]>,
    guides: Vec<Guide>,
}

impl Mechanism {
    pub(super) fn new(scene: &Scene) -> Self {
        let mut links = vec![Vec::new(); scene.bodies.len()];
        let mut pivots = Vec::new();
        let mut add = |body: &str, p: [f64; 2]| match scene.resolve(body) {
            Some(BodyRef::Body(k)) => links[k].push(p),
            Some(BodyRef::Ground) => pivots.push(p),
            None => {}
        };
        for j in &scene.revolute_joints {
            add(&j.body, j.point);
            add(&j.other, j.other_point);
        }
        for j in &scene.clearance_joints {
            add(&j.bearing_body, j.bearing_point);
            add(&j.pin_body, j.pin_point);
        }
        let mut guides = Vec::new();
        for j in &scene.prismatic_joints {
            let Some(BodyRef::Body(body)) = scene.resolve(&j.body) else {
                continue;
            };
            links[body].push(j.point);
            match scene.resolve(&j.other) {
                Some(BodyRef::Ground) => {
                    let n = j.direction[0].hypot(j.direction[1]);
                    if n > 0.0 {
                        guides.push(Guide {
                            origin: j.other_point,
                            direction: [j.direction[0] / n, j.direction[1] / n],
                            body,
                            point: j.point,
                        });
                    }
                }
                Some(BodyRef::Body(k)) => links[k].push(j.other_point),
                None => {}
            }
        }
        for points in &mut links {
            distinct_around_centroid(points);
        }
        distinct_around_centroid(&mut pivots);
        Self {
            shapes: links.iter().map(|p| Shape::of(p)).collect(),
            links,
            pivots,
            guides,
        }
    }

    /// Every point drawn at `poses` (link points and body centroids), global.
    fn points<'a>(&'a self, poses: &'a [[f64; 3]]) -> impl Iterator<Item = [f64; 2]> + 'a {
        self.links.iter().zip(poses).flat_map(|(points, pose)| {
            points
                .iter()
                .map(|p| global(pose, *p))
                .chain([[pose[0], pose[1]]])
        })
    }

    /// The guides fixed to the ground, over the travel of their slider in `sets`.
    pub(super) fn draw_guides(
        &self,
        area: &Area<'_>,
        view: &View,
        sets: &[&[Vec<[f64; 3]>]],
    ) -> DrawResult {
        for g in &self.guides {
            let along = |pose: &[f64; 3]| {
                let p = global(pose, g.point);
                (p[0] - g.origin[0]) * g.direction[0] + (p[1] - g.origin[1]) * g.direction[1]
            };
            let (lo, hi) = sets
                .iter()
                .flat_map(|set| set.iter())
                .filter_map(|poses| poses.get(g.body))
                .map(along)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
                    (a.min(t), b.max(t))
                });
            if lo > hi {
                continue;
            }
            let margin = (0.2 * (hi - lo)).max(30.0 / view.scale);
            let at = |t: f64| {
                view.px([
                    g.origin[0] + t * g.direction[0],
                    g.origin[1] + t * g.direction[1],
                ])
            };
            let line = vec![at(lo - margin), at(hi + margin)];
            area.draw(&PathElement::new(line, GROUND.stroke_width(2)))?;
        }
        Ok(())
    }

    /// The ground pivots.
    pub(super) fn draw_pivots(&self, area: &Area<'_>, view: &View) -> DrawResult {
        for p in &self.pivots {
            let (x, y) = view.px(*p);
            let base = GROUND.stroke_width(2);
            area.draw(&Polygon::new(
                vec![(x, y), (x - 8, y + 13), (x + 8, y + 13)],
                GROUND.mix(0.35).filled(),
            ))?;
            area.draw(&PathElement::new(
                vec![(x - 12, y + 13), (x + 12, y + 13)],
                base,
            ))?;
            for k in 0..4 {
                let x = x - 10 + 7 * k;
                area.draw(&PathElement::new(
                    vec![(x, y + 14), (x - 5, y + 19)],
                    GROUND.stroke_width(1),
                ))?;
            }
            area.draw(&Circle::new((x, y), 4, WHITE.filled()))?;
            area.draw(&Circle::new((x, y), 4, BLACK.stroke_width(1)))?;
        }
        Ok(())
    }

    /// The links at `poses`: `ideal` as wide light-grey bands, else as the coloured links
    /// with their joints.
    pub(super) fn draw_links(
        &self,
        area: &Area<'_>,
        view: &View,
        poses: &[[f64; 3]],
        ideal: bool,
    ) -> DrawResult {
        let (colour, width) = if ideal { (IDEAL, 13) } else { (LINK, 5) };
        let style = colour.stroke_width(width);
        for ((points, shape), pose) in self.links.iter().zip(&self.shapes).zip(poses) {
            let px: Vec<(i32, i32)> = points.iter().map(|p| view.px(global(pose, *p))).collect();
            let centre = view.px([pose[0], pose[1]]);
            match *shape {
                Shape::Block => {
                    // A slider: a block on its centroid, turned with the body.
                    let (a, b) = if ideal { (20.0, 13.0) } else { (16.0, 9.0) };
                    let (s, c) = pose[2].sin_cos();
                    let corner = |u: f64, v: f64| {
                        (
                            centre.0 + (c * u - s * v).round() as i32,
                            centre.1 - (s * u + c * v).round() as i32,
                        )
                    };
                    let block = vec![corner(a, b), corner(-a, b), corner(-a, -b), corner(a, -b)];
                    let fill = if ideal {
                        IDEAL.filled()
                    } else {
                        LINK.mix(0.3).filled()
                    };
                    area.draw(&Polygon::new(block.clone(), fill))?;
                    if !ideal {
                        let mut outline = block;
                        outline.push(outline[0]);
                        area.draw(&PathElement::new(outline, LINK.stroke_width(2)))?;
                    }
                    if let Some(p) = px.first().filter(|p| **p != centre) {
                        area.draw(&PathElement::new(vec![centre, *p], style))?;
                    }
                }
                Shape::Bar(a, b) => area.draw(&PathElement::new(vec![px[a], px[b]], style))?,
                Shape::Polygon => {
                    let fill = if ideal {
                        IDEAL.filled()
                    } else {
                        LINK.mix(0.25).filled()
                    };
                    area.draw(&Polygon::new(px.clone(), fill))?;
                    // Edge by edge: a wide path's mitred corners would spike.
                    for (k, p) in px.iter().enumerate() {
                        let q = px[(k + 1) % px.len()];
                        area.draw(&PathElement::new(vec![*p, q], style))?;
                    }
                }
            }
            let r = width / 2;
            for p in &px {
                if ideal {
                    area.draw(&Circle::new(*p, r, colour.filled()))?;
                } else {
                    area.draw(&Circle::new(*p, 4, WHITE.filled()))?;
                    area.draw(&Circle::new(*p, 4, BLACK.stroke_width(1)))?;
                }
            }
        }
        Ok(())
    }
}

/// Removes repeated points (within 1 nm) and orders three or more by angle around their
/// centroid, so they make a simple polygon.
fn distinct_around_centroid(points: &mut Vec<[f64; 2]>) {
    let mut distinct: Vec<[f64; 2]> = Vec::with_capacity(points.len());
    for p in points.iter() {
        if !distinct
            .iter()
            .any(|q| (p[0] - q[0]).abs() < 1e-9 && (p[1] - q[1]).abs() < 1e-9)
        {
            distinct.push(*p);
        }
    }
    if distinct.len() >= 3 {
        let n = distinct.len() as f64;
        let cx = distinct.iter().map(|p| p[0]).sum::<f64>() / n;
        let cy = distinct.iter().map(|p| p[1]).sum::<f64>() / n;
        let angle = |p: &[f64; 2]| (p[1] - cy).atan2(p[0] - cx);
        distinct.sort_by(|a, b| angle(a).total_cmp(&angle(b)));
    }
    *points = distinct;
}

/// Where the mechanism goes in the picture: one scale for both axes, y up.
pub(super) struct View {
    /// Pixels per metre.
    pub(super) scale: f64,
    /// Width of the mechanism's part of the picture (left of the insets), pixels.
    pub(super) width: u32,
    /// The world point drawn at `centre`.
    world: [f64; 2],
    centre: (f64, f64),
}

impl View {
    /// Fits every pose of `frames` (both mechanisms) and the ground pivots into the picture
    /// left of the insets (`insets`: whether there are any).
    pub(super) fn fit(mechanism: &Mechanism, frames: &MechanismFrames, insets: bool) -> Self {
        let (w, h) = (f64::from(ANIMATION_SIZE.0), f64::from(ANIMATION_SIZE.1));
        let right = if insets { w - f64::from(INSETS) } else { w };
        let (top, bottom) = (f64::from(TITLE), h - f64::from(FOOTER));
        let (lo, hi) = frames
            .poses
            .iter()
            .chain(&frames.ideal_poses)
            .flat_map(|poses| mechanism.points(poses))
            .chain(mechanism.pivots.iter().copied())
            .filter(|p| p[0].is_finite() && p[1].is_finite())
            .fold(
                ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]),
                |(lo, hi), p| {
                    (
                        [lo[0].min(p[0]), lo[1].min(p[1])],
                        [hi[0].max(p[0]), hi[1].max(p[1])],
                    )
                },
            );
        let world = if lo[0] <= hi[0] {
            [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])]
        } else {
            [0.0, 0.0]
        };
        let fit = |span: f64, pixels: f64| {
            if span > 0.0 {
                (pixels - 2.0 * PAD) / span
            } else {
                f64::INFINITY
            }
        };
        let scale = fit(hi[0] - lo[0], right).min(fit(hi[1] - lo[1], bottom - top));
        Self {
            scale: if scale.is_finite() { scale } else { 1000.0 },
            width: right as u32,
            world,
            centre: (0.5 * right, 0.5 * (top + bottom)),
        }
    }

    /// Pixel of world point `p`.
    pub(super) fn px(&self, p: [f64; 2]) -> (i32, i32) {
        let x = self.centre.0 + self.scale * (p[0] - self.world[0]);
        let y = self.centre.1 - self.scale * (p[1] - self.world[1]);
        (x.round() as i32, y.round() as i32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collinear_points_make_a_bar_between_the_ends() {
        assert_eq!(Shape::of(&[]), Shape::Block);
        assert_eq!(Shape::of(&[[0.1, 0.0]]), Shape::Block);
        assert_eq!(
            Shape::of(&[[0.6, 0.0], [-0.6, 0.0], [-0.4, 0.0]]),
            Shape::Bar(0, 1)
        );
        assert_eq!(
            Shape::of(&[[0.6, 0.0], [-0.6, 0.0], [0.0, 0.2]]),
            Shape::Polygon
        );
    }

    #[test]
    fn polygon_points_are_distinct_and_ordered() {
        let mut p = vec![[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [1.0, 0.0], [0.0, -1.0]];
        distinct_around_centroid(&mut p);
        // Counter-clockwise from the negative y axis (atan2 in (-π, π]).
        assert_eq!(p, vec![[0.0, -1.0], [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]]);
    }
}
