//! The spanning tree of the ideal joints, its relative coordinates, and the forward kinematics
//! `z → (q, q̇, q̈)` along it.
//!
//! The tree grows breadth-first from the ground over the joints in model order; a body that
//! no ideal joint connects to the ground (directly or through other bodies) becomes the root of
//! its own subtree with a floating joint (`x, y, θ`). Each tree joint contributes relative
//! coordinates, each either a rotation of the child's subtree about a pivot or a translation
//! along a direction:
//! - revolute: the relative angle `θ_j − θ_i` of its two anchors' bodies (ground angle 0);
//! - prismatic: the slide `u·(P_slider − P_base)` of the joint's own driver convention, plus
//!   the relative angle `θ_slider − θ_base` unless the rotation is locked;
//! - floating: `x, y, θ` of the body.
//!
//! Joints left out of the tree close loops: their equations stay constraints with multipliers
//! (the mixed formulation), evaluated by the Cartesian constraint code on `q(z)`. A driver
//! prescribes a tree coordinate when its target is an affine function `offset + scale·z_k`
//! of one coordinate (a joint angle or slide of a tree joint; a coordinate of a body whose
//! tree joint from the ground moves it along that coordinate alone); otherwise it stays a
//! constraint too.

use crate::constraints::{ConstraintOwner, Constraints};
use crate::model::{Coordinate, DriveTarget, Joint, JointId, RotationLock};

use super::scalar::{Scalar, V2, add, lift, perp, rotate, scale, sub};

/// `(sin θ, cos θ)`.
fn sin_cos<T: Scalar>(theta: T) -> V2<T> {
    let (sin, cos) = theta.sin_cos();
    [sin, cos]
}

/// Position, velocity and acceleration of the material point at arm `d` from a point
/// `(p, v, a)` of a body turning at rate `w` with angular acceleration `al`.
fn offset<T: Scalar>(
    (p, v, a): (V2<T>, V2<T>, V2<T>),
    w: T,
    al: T,
    d: V2<T>,
) -> (V2<T>, V2<T>, V2<T>) {
    (
        add(p, d),
        add(v, scale(w, perp(d))),
        add(a, sub(scale(al, perp(d)), scale(w * w, d))),
    )
}

/// `R(θ) s` from `(sin θ, cos θ)`.
fn rotate_by<T: Scalar>(trig: V2<T>, s: [f64; 2]) -> V2<T> {
    let [sin, cos] = trig;
    let (x, y) = (T::constant(s[0]), T::constant(s[1]));
    [cos * x - sin * y, sin * x + cos * y]
}

/// How a tree joint places its child relative to its parent (points in the parent's frame,
/// or global when the parent is the ground).
#[derive(Debug, Clone, Copy)]
enum Link {
    /// One coordinate: the relative angle, `θ_child = θ_parent + sign·z`.
    Revolute {
        parent_point: [f64; 2],
        child_point: [f64; 2],
        sign: f64,
    },
    /// The slider is the child: coordinates slide, then the angle unless locked.
    Slider(Prismatic),
    /// The base (which carries the axis) is the child: the angle unless locked, then the slide.
    Base(Prismatic),
    /// `x, y, θ` of a body no ideal joint ties to the ground.
    Floating,
}

/// A prismatic tree joint's geometry, whichever of its bodies is the child: each point in the
/// frame of its body, the axis in the base's (global for the ground).
#[derive(Debug, Clone, Copy)]
struct Prismatic {
    base_point: [f64; 2],
    slider_point: [f64; 2],
    axis: [f64; 2],
    /// The relative angle `θ_slider − θ_base` where it is locked.
    lock: Option<f64>,
}

impl Prismatic {
    /// The relative angle `θ_slider − θ_base` and its rates: the locked one, else coordinate `k`.
    fn angle<T: Scalar>(&self, z: &[T], zd: &[T], zdd: &[T], k: usize) -> (T, T, T) {
        match self.lock {
            Some(angle) => (T::constant(angle), zero(), zero()),
            None => (z[k], zd[k], zdd[k]),
        }
    }
}

/// What one coordinate does to the bodies of its subtree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Motion {
    /// Turns them by `sign·dz` about the coordinate's pivot.
    Rotation { sign: f64 },
    /// Moves them by `dz` along the coordinate's direction.
    Translation,
}

#[derive(Debug, Clone)]
struct TreeJoint {
    parent: Option<usize>,
    child: usize,
    link: Link,
    /// Index of its first coordinate.
    first: usize,
}

/// A driver that prescribes a coordinate: `z = (f(t) − offset) / scale`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Prescribed {
    pub coordinate: usize,
    pub driver: usize,
    pub offset: f64,
    pub scale: f64,
}

/// The compiled tree.
#[derive(Debug, Clone)]
pub(crate) struct Tree {
    joints: Vec<TreeJoint>,
    /// Per coordinate: its motion and its tree joint.
    motions: Vec<Motion>,
    owner: Vec<usize>,
    /// Per tree joint: the bodies of the child's subtree (the child first).
    subtrees: Vec<Vec<usize>>,
    /// Coordinates the integrator carries, in coordinate order.
    pub free: Vec<usize>,
    pub prescribed: Vec<Prescribed>,
    /// Constraint equations kept (loop closures and drivers not prescribing a coordinate).
    pub kept: Vec<usize>,
    /// Coordinate count, free and prescribed.
    pub coordinates: usize,
}

/// Forward kinematics outputs, in the caller's storage.
pub(crate) struct Placement<'a, T> {
    pub q: &'a mut [T],
    pub qd: &'a mut [T],
    pub qdd: &'a mut [T],
    /// Per coordinate: the pivot of a rotation or the direction of a translation.
    pub axes: &'a mut [V2<T>],
    /// Per body: `(sin θ, cos θ)`, computed once and reused by its children.
    pub trig: &'a mut [V2<T>],
}

fn zero<T: Scalar>() -> T {
    T::constant(0.0)
}

impl Tree {
    /// Builds the tree of `joints` over `bodies` bodies and decides which constraint equations
    /// of `constraints` stay.
    pub fn new(bodies: usize, joints: &[Joint], constraints: &Constraints) -> Self {
        let ends = |joint: &Joint| match joint {
            Joint::Revolute { i, j, .. } => (i.body.map(|b| b.0), j.body.map(|b| b.0)),
            Joint::Prismatic { base, slider, .. } => {
                (base.body.map(|b| b.0), slider.body.map(|b| b.0))
            }
        };
        let mut placed = vec![false; bodies];
        let mut in_tree = vec![false; joints.len()];
        let mut tree_joints: Vec<TreeJoint> = Vec::with_capacity(bodies);
        let mut joint_of: Vec<Option<JointId>> = Vec::with_capacity(bodies);
        let mut motions = Vec::new();
        let mut queue = std::collections::VecDeque::from([None]);
        let push = |tree_joints: &mut Vec<TreeJoint>,
                    motions: &mut Vec<Motion>,
                    parent,
                    child,
                    link: Link| {
            let first = motions.len();
            match link {
                Link::Revolute { sign, .. } => motions.push(Motion::Rotation { sign }),
                Link::Slider(prismatic) => {
                    motions.push(Motion::Translation);
                    if prismatic.lock.is_none() {
                        motions.push(Motion::Rotation { sign: 1.0 });
                    }
                }
                Link::Base(prismatic) => {
                    if prismatic.lock.is_none() {
                        motions.push(Motion::Rotation { sign: -1.0 });
                    }
                    motions.push(Motion::Translation);
                }
                Link::Floating => {
                    motions.extend([
                        Motion::Translation,
                        Motion::Translation,
                        Motion::Rotation { sign: 1.0 },
                    ]);
                }
            }
            tree_joints.push(TreeJoint {
                parent,
                child,
                link,
                first,
            });
        };
        loop {
            while let Some(node) = queue.pop_front() {
                for (k, joint) in joints.iter().enumerate() {
                    if in_tree[k] {
                        continue;
                    }
                    let (a, b) = ends(joint);
                    let child = match (a, b) {
                        (a, Some(b)) if a == node && !placed[b] => b,
                        (Some(a), b) if b == node && !placed[a] => a,
                        _ => continue,
                    };
                    placed[child] = true;
                    in_tree[k] = true;
                    push(
                        &mut tree_joints,
                        &mut motions,
                        node,
                        child,
                        link(joint, child),
                    );
                    joint_of.push(Some(JointId(k)));
                    queue.push_back(Some(child));
                }
            }
            let Some(root) = placed.iter().position(|p| !p) else {
                break;
            };
            placed[root] = true;
            push(&mut tree_joints, &mut motions, None, root, Link::Floating);
            joint_of.push(None);
            queue.push_back(Some(root));
        }
        let coordinates = motions.len();
        let mut owner = vec![0; coordinates];
        for (t, joint) in tree_joints.iter().enumerate() {
            let next = tree_joints.get(t + 1).map_or(coordinates, |j| j.first);
            owner[joint.first..next].fill(t);
        }
        // Subtrees: every body belongs to the subtree of each tree joint on its way to a root.
        let mut tree_joint_of_body = vec![0; bodies];
        for (t, joint) in tree_joints.iter().enumerate() {
            tree_joint_of_body[joint.child] = t;
        }
        let mut subtrees = vec![Vec::new(); tree_joints.len()];
        for joint in &tree_joints {
            let body = joint.child;
            let mut t = tree_joint_of_body[body];
            loop {
                subtrees[t].push(body);
                match tree_joints[t].parent {
                    Some(parent) => t = tree_joint_of_body[parent],
                    None => break,
                }
            }
        }
        let mut tree = Self {
            joints: tree_joints,
            motions,
            owner,
            subtrees,
            free: Vec::new(),
            prescribed: Vec::new(),
            kept: Vec::new(),
            coordinates,
        };
        for (k, owner) in constraints.owners().iter().enumerate() {
            match owner {
                ConstraintOwner::Joint(id) => {
                    if !in_tree[id.0] {
                        tree.kept.push(k);
                    }
                }
                ConstraintOwner::Driver(id) => {
                    let target = constraints.drive_target(id.0);
                    match tree.prescription(target, &joint_of, &tree_joint_of_body) {
                        Some((coordinate, offset, scale))
                            if !tree.prescribed.iter().any(|p| p.coordinate == coordinate) =>
                        {
                            tree.prescribed.push(Prescribed {
                                coordinate,
                                driver: id.0,
                                offset,
                                scale,
                            });
                        }
                        _ => tree.kept.push(k),
                    }
                }
            }
        }
        tree.free = (0..coordinates)
            .filter(|c| !tree.prescribed.iter().any(|p| p.coordinate == *c))
            .collect();
        tree
    }

    /// `(coordinate, offset, scale)` when `target = offset + scale·z_coordinate` exactly.
    fn prescription(
        &self,
        target: DriveTarget,
        joint_of: &[Option<JointId>],
        tree_joint_of_body: &[usize],
    ) -> Option<(usize, f64, f64)> {
        match target {
            DriveTarget::JointAngle(id) | DriveTarget::JointSlide(id) => {
                let t = joint_of.iter().position(|j| *j == Some(id))?;
                let joint = &self.joints[t];
                // The joint's angle or slide coordinate is its own driver convention.
                let coordinate = match (target, joint.link) {
                    (DriveTarget::JointAngle(_), Link::Revolute { .. }) => joint.first,
                    (DriveTarget::JointSlide(_), Link::Slider(_)) => joint.first,
                    (DriveTarget::JointSlide(_), Link::Base(prismatic)) => {
                        joint.first + usize::from(prismatic.lock.is_none())
                    }
                    _ => return None,
                };
                Some((coordinate, 0.0, 1.0))
            }
            DriveTarget::Coordinate(body, which) => {
                let joint = &self.joints[tree_joint_of_body[body.0]];
                if joint.parent.is_some() {
                    return None;
                }
                let first = joint.first;
                match (joint.link, which) {
                    (Link::Floating, _) => Some((first + which as usize, 0.0, 1.0)),
                    (Link::Revolute { sign, .. }, Coordinate::Theta) => Some((first, 0.0, sign)),
                    (Link::Slider(Prismatic { lock: None, .. }), Coordinate::Theta) => {
                        Some((first + 1, 0.0, 1.0))
                    }
                    (Link::Base(Prismatic { lock: None, .. }), Coordinate::Theta) => {
                        Some((first, 0.0, -1.0))
                    }
                    (Link::Slider(prismatic), Coordinate::X | Coordinate::Y) => {
                        // r = P_base + z u − R(α) s_slider, u the (global) axis.
                        let angle = prismatic.lock?;
                        let c = which as usize;
                        let arm: V2<f64> = rotate(angle, prismatic.slider_point);
                        affine(prismatic.base_point[c] - arm[c], prismatic.axis[c], first)
                    }
                    (Link::Base(prismatic), Coordinate::X | Coordinate::Y) => {
                        // r = P_slider − z R(−α) axis − R(−α) s_base.
                        let angle = prismatic.lock?;
                        let c = which as usize;
                        let u: V2<f64> = rotate(-angle, prismatic.axis);
                        let arm: V2<f64> = rotate(-angle, prismatic.base_point);
                        affine(prismatic.slider_point[c] - arm[c], -u[c], first)
                    }
                    _ => None,
                }
            }
        }
    }

    pub fn motion(&self, coordinate: usize) -> Motion {
        self.motions[coordinate]
    }

    /// Bodies moved by `coordinate`.
    pub fn subtree(&self, coordinate: usize) -> &[usize] {
        &self.subtrees[self.owner[coordinate]]
    }

    /// Positions, velocities and accelerations of all bodies from all coordinates and their
    /// rates, parents before children; also each coordinate's pivot or direction.
    pub fn place<T: Scalar>(&self, z: &[T], zd: &[T], zdd: &[T], out: &mut Placement<'_, T>) {
        for joint in &self.joints {
            let (rp, thp, trig_p, vp, wp, ap, alp) = match joint.parent {
                Some(p) => (
                    [out.q[3 * p], out.q[3 * p + 1]],
                    out.q[3 * p + 2],
                    out.trig[p],
                    [out.qd[3 * p], out.qd[3 * p + 1]],
                    out.qd[3 * p + 2],
                    [out.qdd[3 * p], out.qdd[3 * p + 1]],
                    out.qdd[3 * p + 2],
                ),
                None => (
                    [zero(); 2],
                    zero(),
                    [zero(), T::constant(1.0)],
                    [zero(); 2],
                    zero(),
                    [zero(); 2],
                    zero(),
                ),
            };
            // Position, velocity and acceleration of the parent's material point at `rel`
            // from its centroid.
            let field = |rel: V2<T>| offset((rp, vp, ap), wp, alp, rel);
            let k = joint.first;
            let two = T::constant(2.0);
            // Child: angle, its rates, the point it hangs from (with velocity and
            // acceleration), and the arm `d` from that point to its centroid.
            let (th, trig, w, al, r, v, a);
            match joint.link {
                Link::Revolute {
                    parent_point,
                    child_point,
                    sign,
                } => {
                    let s = T::constant(sign);
                    let (p, vp_, ap_) = field(rotate_by(trig_p, parent_point));
                    out.axes[k] = p;
                    th = thp + s * z[k];
                    w = wp + s * zd[k];
                    al = alp + s * zdd[k];
                    trig = sin_cos(th);
                    let d = scale(T::constant(-1.0), rotate_by(trig, child_point));
                    (r, v, a) = offset((p, vp_, ap_), w, al, d);
                }
                Link::Slider(prismatic) => {
                    let u = rotate_by(trig_p, prismatic.axis);
                    out.axes[k] = u;
                    let rel = add(rotate_by(trig_p, prismatic.base_point), scale(z[k], u));
                    let (p, vp_, ap_) = field(rel);
                    let vs = add(vp_, scale(zd[k], u));
                    let as_ = add(ap_, add(scale(zdd[k], u), scale(two * wp * zd[k], perp(u))));
                    if prismatic.lock.is_none() {
                        out.axes[k + 1] = p;
                    }
                    let (phi, phid, phidd) = prismatic.angle(z, zd, zdd, k + 1);
                    th = thp + phi;
                    w = wp + phid;
                    al = alp + phidd;
                    trig = sin_cos(th);
                    let d = scale(T::constant(-1.0), rotate_by(trig, prismatic.slider_point));
                    (r, v, a) = offset((p, vs, as_), w, al, d);
                }
                Link::Base(prismatic) => {
                    let (p, vp_, ap_) = field(rotate_by(trig_p, prismatic.slider_point));
                    if prismatic.lock.is_none() {
                        out.axes[k] = p;
                    }
                    let (phi, phid, phidd) = prismatic.angle(z, zd, zdd, k);
                    let ks = k + usize::from(prismatic.lock.is_none());
                    th = thp - phi;
                    w = wp - phid;
                    al = alp - phidd;
                    trig = sin_cos(th);
                    let u = rotate_by(trig, prismatic.axis);
                    out.axes[ks] = scale(T::constant(-1.0), u);
                    let d = scale(
                        T::constant(-1.0),
                        add(scale(z[ks], u), rotate_by(trig, prismatic.base_point)),
                    );
                    let (rd, vd, ad) = offset((p, vp_, ap_), w, al, d);
                    r = rd;
                    v = sub(vd, scale(zd[ks], u));
                    a = sub(ad, add(scale(zdd[ks], u), scale(two * w * zd[ks], perp(u))));
                }
                Link::Floating => {
                    r = [z[k], z[k + 1]];
                    v = [zd[k], zd[k + 1]];
                    a = [zdd[k], zdd[k + 1]];
                    th = z[k + 2];
                    w = zd[k + 2];
                    al = zdd[k + 2];
                    trig = sin_cos(th);
                    out.axes[k] = lift([1.0, 0.0]);
                    out.axes[k + 1] = lift([0.0, 1.0]);
                    out.axes[k + 2] = r;
                }
            }
            out.trig[joint.child] = trig;
            let c = 3 * joint.child;
            out.q[c..c + 3].copy_from_slice(&[r[0], r[1], th]);
            out.qd[c..c + 3].copy_from_slice(&[v[0], v[1], w]);
            out.qdd[c..c + 3].copy_from_slice(&[a[0], a[1], al]);
        }
    }

    /// Column `∂q/∂z_coordinate` (length `3 × bodies`, zero outside the coordinate's subtree)
    /// from the positions and axes of [`Tree::place`].
    pub fn column<T: Scalar>(&self, coordinate: usize, q: &[T], axes: &[V2<T>], out: &mut [T]) {
        out.fill(zero());
        let axis = axes[coordinate];
        for &b in self.subtree(coordinate) {
            let column = &mut out[3 * b..3 * b + 3];
            match self.motions[coordinate] {
                Motion::Rotation { sign } => {
                    let s = T::constant(sign);
                    let arm = perp(sub([q[3 * b], q[3 * b + 1]], axis));
                    column.copy_from_slice(&[s * arm[0], s * arm[1], s]);
                }
                Motion::Translation => column.copy_from_slice(&[axis[0], axis[1], zero()]),
            }
        }
    }

    /// All coordinates and their rates read off a Cartesian state that satisfies the tree's
    /// joints (the inverse of [`Tree::place`] there).
    pub fn read(&self, q: &[f64], qd: &[f64], z: &mut [f64], zd: &mut [f64]) {
        let pose = |b: Option<usize>| match b {
            Some(b) => (
                [q[3 * b], q[3 * b + 1]],
                q[3 * b + 2],
                [qd[3 * b], qd[3 * b + 1]],
                qd[3 * b + 2],
            ),
            None => ([0.0; 2], 0.0, [0.0; 2], 0.0),
        };
        // Position and velocity of the point `s` (body frame) of body `b`.
        let point = |b: Option<usize>, s: [f64; 2]| {
            let (r, th, v, w) = pose(b);
            let arm: V2<f64> = rotate(th, s);
            (add(r, arm), add(v, scale(w, perp(arm))))
        };
        let dot = |a: V2<f64>, b: V2<f64>| a[0] * b[0] + a[1] * b[1];
        for joint in &self.joints {
            let (parent, child) = (joint.parent, Some(joint.child));
            let (_, thp, _, wp) = pose(parent);
            let (rc, thc, vc, wc) = pose(child);
            let k = joint.first;
            // The slide u·(P_s − P_b) and its rate, the axis turning with the base (angle
            // `th_base`, rate `w_base`).
            let slide = |base: Option<usize>, slider: Option<usize>, prismatic: Prismatic| {
                let (_, th_base, _, w_base) = pose(base);
                let u: V2<f64> = rotate(th_base, prismatic.axis);
                let (pb, vb) = point(base, prismatic.base_point);
                let (ps, vs) = point(slider, prismatic.slider_point);
                let gap = sub(ps, pb);
                (
                    dot(u, gap),
                    w_base * dot(perp(u), gap) + dot(u, sub(vs, vb)),
                )
            };
            match joint.link {
                Link::Revolute { sign, .. } => {
                    z[k] = sign * (thc - thp);
                    zd[k] = sign * (wc - wp);
                }
                Link::Slider(prismatic) => {
                    (z[k], zd[k]) = slide(parent, child, prismatic);
                    if prismatic.lock.is_none() {
                        z[k + 1] = thc - thp;
                        zd[k + 1] = wc - wp;
                    }
                }
                Link::Base(prismatic) => {
                    let ks = k + usize::from(prismatic.lock.is_none());
                    if prismatic.lock.is_none() {
                        z[k] = thp - thc;
                        zd[k] = wp - wc;
                    }
                    (z[ks], zd[ks]) = slide(child, parent, prismatic);
                }
                Link::Floating => {
                    z[k..k + 3].copy_from_slice(&[rc[0], rc[1], thc]);
                    zd[k..k + 3].copy_from_slice(&[vc[0], vc[1], wc]);
                }
            }
        }
    }
}

fn affine(offset: f64, scale: f64, coordinate: usize) -> Option<(usize, f64, f64)> {
    (scale.abs() > 1e-12).then_some((coordinate, offset, scale))
}

fn link(joint: &Joint, child: usize) -> Link {
    let is_child = |b: Option<crate::model::BodyId>| b.map(|b| b.0) == Some(child);
    match joint {
        Joint::Revolute { i, j, .. } => {
            if is_child(j.body) {
                Link::Revolute {
                    parent_point: i.point,
                    child_point: j.point,
                    sign: 1.0,
                }
            } else {
                Link::Revolute {
                    parent_point: j.point,
                    child_point: i.point,
                    sign: -1.0,
                }
            }
        }
        Joint::Prismatic {
            base,
            axis,
            slider,
            rotation,
            ..
        } => {
            let lock = match rotation {
                RotationLock::At(angle) => Some(*angle),
                RotationLock::Free => None,
            };
            let prismatic = Prismatic {
                base_point: base.point,
                slider_point: slider.point,
                axis: *axis,
                lock,
            };
            if is_child(slider.body) {
                Link::Slider(prismatic)
            } else {
                Link::Base(prismatic)
            }
        }
    }
}
