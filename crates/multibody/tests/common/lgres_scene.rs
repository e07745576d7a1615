//! The LGRES mechanism read from the shipped scene `crates/lgres/scenes/lgres.toml`, so that
//! multibody's tests and benches use the scene's numbers without a copy of them and without
//! depending on lgres: the bodies, the ideal joints, the guide and drive, gravity, and the
//! geometry of the clearance joints (for the caller to make ideal or compliant). Only what that
//! scene uses is understood; anything else panics naming the key.
#![allow(dead_code)]

use std::f64::consts::TAU;

use multibody::{Anchor, Body, BodyId, Coordinate, DriveTarget, Harmonic, Model, RotationLock};
use toml::Value;

/// The scene file, relative to this crate.
pub const PATH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../lgres/scenes/lgres.toml");

/// A clearance joint's bearing and pin centres (concentric in the scene's initial poses).
pub struct ClearanceGeometry {
    pub name: String,
    pub bearing: Anchor,
    pub pin: Anchor,
}

/// The scene's mechanism without its clearance joints.
pub struct Lgres {
    /// Bodies, ideal revolute and prismatic joints and the slide rod's drive.
    pub model: Model,
    /// Body names in scene order (`BodyId(k)` is the k-th).
    pub names: Vec<String>,
    /// Initial poses as written in the scene: x (m), y (m), θ (degrees).
    pub poses: Vec<[f64; 3]>,
    /// The clearance joints A and B.
    pub clearance_joints: Vec<ClearanceGeometry>,
    /// Gravitational acceleration (m/s²).
    pub gravity: [f64; 2],
}

fn number(table: &Value, key: &str) -> f64 {
    match table.get(key) {
        Some(Value::Float(x)) => *x,
        Some(Value::Integer(i)) => *i as f64,
        _ => panic!("{PATH}: `{key}` missing or not a number in {table}"),
    }
}

fn text<'a>(table: &'a Value, key: &str) -> &'a str {
    table
        .get(key)
        .and_then(Value::as_str)
        .unwrap_or_else(|| panic!("{PATH}: `{key}` missing or not a string in {table}"))
}

fn pair(table: &Value, key: &str) -> [f64; 2] {
    let values: Vec<f64> = table
        .get(key)
        .and_then(Value::as_array)
        .unwrap_or_else(|| panic!("{PATH}: `{key}` missing or not an array in {table}"))
        .iter()
        .map(|v| {
            v.as_float()
                .unwrap_or_else(|| panic!("{PATH}: `{key}` holds {v}"))
        })
        .collect();
    values
        .try_into()
        .unwrap_or_else(|v| panic!("{PATH}: `{key}` must have two entries, has {v:?}"))
}

fn list<'a>(scene: &'a Value, key: &str) -> &'a [Value] {
    scene
        .get(key)
        .and_then(Value::as_array)
        .map_or(&[], Vec::as_slice)
}

impl Lgres {
    /// The scene's mechanism with its drive at `rpm` (the scene's own is 60 rpm).
    pub fn load(rpm: f64) -> Self {
        let source =
            std::fs::read_to_string(PATH).unwrap_or_else(|e| panic!("reading {PATH}: {e}"));
        let scene = Value::Table(
            source
                .parse()
                .unwrap_or_else(|e| panic!("parsing {PATH}: {e}")),
        );
        let mut model = Model::new();
        let mut names = Vec::new();
        let mut poses = Vec::new();
        for b in list(&scene, "bodies") {
            let pose = [number(b, "x"), number(b, "y"), number(b, "theta_deg")];
            let body = Body::named(text(b, "name"))
                .with_mass(number(b, "mass"))
                .with_inertia(number(b, "inertia"))
                .with_pose([pose[0], pose[1], pose[2].to_radians()]);
            model.add_body(body).expect("the scene's bodies are valid");
            names.push(text(b, "name").to_string());
            poses.push(pose);
        }
        let find = |name: &str| -> Option<BodyId> {
            if name == "ground" {
                return None;
            }
            let k = names.iter().position(|n| n == name);
            Some(BodyId(
                k.unwrap_or_else(|| panic!("{PATH}: no body `{name}`")),
            ))
        };
        let anchor = |table: &Value, body: &str, point: &str| {
            let [x, y] = pair(table, point);
            match find(text(table, body)) {
                None => Anchor::ground(x, y),
                Some(id) => Anchor::on(id, x, y),
            }
        };
        let angle = |name: &str| find(name).map_or(0.0, |BodyId(k)| poses[k][2].to_radians());
        for j in list(&scene, "revolute_joints") {
            let (i, o) = (
                anchor(j, "body", "point"),
                anchor(j, "other", "other_point"),
            );
            model
                .add_revolute(text(j, "name"), i, o)
                .expect("the scene's joints are valid");
        }
        for j in list(&scene, "prismatic_joints") {
            let rotation = match j.get("lock_rotation").and_then(Value::as_bool) {
                Some(true) => RotationLock::At(angle(text(j, "body")) - angle(text(j, "other"))),
                _ => RotationLock::Free,
            };
            let (base, slider) = (
                anchor(j, "other", "other_point"),
                anchor(j, "body", "point"),
            );
            model
                .add_prismatic(
                    text(j, "name"),
                    base,
                    pair(j, "direction"),
                    slider,
                    rotation,
                )
                .expect("the scene's joints are valid");
        }
        for d in list(&scene, "drivers") {
            let part = |key| {
                d.get(key)
                    .unwrap_or_else(|| panic!("{PATH}: driver without `{key}`"))
            };
            let (target, law) = (part("target"), part("law"));
            assert_eq!(
                text(target, "kind"),
                "body-coordinate",
                "{PATH}: driver target"
            );
            assert_eq!(text(target, "coordinate"), "y", "{PATH}: driven coordinate");
            assert_eq!(text(law, "kind"), "harmonic", "{PATH}: drive law");
            let body = find(text(target, "body")).expect("the drive moves a body");
            let harmonic = Harmonic {
                offset: number(law, "offset"),
                amplitude: number(law, "amplitude"),
                omega: TAU * rpm / 60.0,
            };
            model
                .add_driver(
                    text(d, "name"),
                    DriveTarget::Coordinate(body, Coordinate::Y),
                    Box::new(harmonic),
                )
                .expect("the scene's driver is valid");
        }
        let clearance_joints = list(&scene, "clearance_joints")
            .iter()
            .map(|c| ClearanceGeometry {
                name: text(c, "name").to_string(),
                bearing: anchor(c, "bearing_body", "bearing_point"),
                pin: anchor(c, "pin_body", "pin_point"),
            })
            .collect();
        let gravity = pair(&scene, "gravity");
        Self {
            model,
            names,
            poses,
            clearance_joints,
            gravity,
        }
    }
}
