//! The animated mechanism: the poses a run records for it (one period after the start-up
//! window, the ideal mechanism's joints closed, the clearance's within the clearance) and the
//! GIF drawn from them (well formed, bounded, deterministic), and the `run.animation` switch.

mod common;

use std::path::{Path, PathBuf};

use output::animation::{AnimationInfo, MAX_ANIMATION_FRAMES, write_animation};
use scene::{BodyRef, Scene, load_str};
use sim::{MechanismFrames, RunOutcome};

/// The slider-crank over two drive cycles (0.024 s), no wear.
const SLIDER_CRANK: &str = "extends = \"slider-crank\"\n[run]\ncycles = 2\nwear_stages = 0\n";

fn temp_dir(tag: &str) -> PathBuf {
    common::temp_dir("anim", tag)
}

fn run(text: &str) -> RunOutcome {
    common::run(text, "test")
}

/// What the GIF's block structure says: screen size, and per image its rectangle and delay.
struct GifFile {
    size: (u16, u16),
    frames: Vec<((u16, u16, u16, u16), u16)>,
}

/// Walks the blocks of a GIF (header, screen descriptor, colour tables, extensions, images,
/// trailer), failing on anything malformed or on bytes after the trailer.
fn parse_gif(bytes: &[u8]) -> GifFile {
    assert_eq!(&bytes[..6], b"GIF89a", "not a GIF89a file");
    let u16_at = |k: usize| u16::from_le_bytes([bytes[k], bytes[k + 1]]);
    let size = (u16_at(6), u16_at(8));
    let table = |flags: u8| {
        if flags & 0x80 != 0 {
            3 << ((flags & 7) + 1)
        } else {
            0
        }
    };
    let mut k = 13 + table(bytes[10]);
    let skip_sub_blocks = |mut k: usize| {
        loop {
            let n = usize::from(bytes[k]);
            k += 1 + n;
            if n == 0 {
                return k;
            }
        }
    };
    let mut frames = Vec::new();
    let mut delay = 0;
    loop {
        match bytes[k] {
            0x21 => {
                if bytes[k + 1] == 0xF9 {
                    delay = u16_at(k + 4);
                }
                k = skip_sub_blocks(k + 2);
            }
            0x2C => {
                let rect = (u16_at(k + 1), u16_at(k + 3), u16_at(k + 5), u16_at(k + 7));
                k += 10 + table(bytes[k + 9]);
                // LZW minimum code size, then the image data.
                k = skip_sub_blocks(k + 1);
                frames.push((rect, delay));
            }
            0x3B => {
                assert_eq!(k + 1, bytes.len(), "bytes after the trailer");
                return GifFile { size, frames };
            }
            b => panic!("unexpected block {b:#04x} at byte {k}"),
        }
    }
}

/// Where body `name`'s point `p` (or the ground point) is at `poses`.
fn point(scene: &Scene, poses: &[[f64; 3]], name: &str, p: [f64; 2]) -> [f64; 2] {
    match scene.resolve(name).unwrap() {
        BodyRef::Ground => p,
        BodyRef::Body(k) => {
            let [x, y, th] = poses[k];
            let (s, c) = th.sin_cos();
            [x + c * p[0] - s * p[1], y + s * p[0] + c * p[1]]
        }
    }
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn frames(outcome: &RunOutcome) -> &MechanismFrames {
    outcome.response.frames.as_ref().expect("frames recorded")
}

#[test]
fn the_frames_span_one_period_after_the_window() {
    let outcome = run(SLIDER_CRANK);
    let scene = &outcome.scene;
    let f = frames(&outcome);
    let times = &outcome.response.times;
    let period = scene.cycle_period().unwrap();
    let dt = scene.solver.output_interval;
    // 1200 samples a period: every frame is a distinct sample.
    assert_eq!(f.frames.len(), MAX_ANIMATION_FRAMES);
    assert_eq!(f.poses.len(), f.frames.len());
    assert_eq!(f.ideal_poses.len(), f.frames.len());
    assert!(
        f.poses
            .iter()
            .chain(&f.ideal_poses)
            .all(|p| p.len() == scene.bodies.len())
    );
    // The first frame is the first output time at or after the window.
    let first = f.frames[0];
    let window = scene.run.transient_window;
    assert!(times[first] >= window - 1e-12 && times[first - 1] < window);
    // Evenly spaced over one period, the time closing the cycle left out.
    let step = period / MAX_ANIMATION_FRAMES as f64;
    for (j, &k) in f.frames.iter().enumerate() {
        let expected = times[first] + j as f64 * step;
        assert!((times[k] - expected).abs() <= 0.5 * dt + 1e-12, "frame {j}");
    }
    let span = times[*f.frames.last().unwrap()] - times[first];
    assert!(span < period && span > period - 2.0 * step, "span {span}");
    // The poses are the run's: the recorded body's centroid at the frames' samples.
    let body = scene.response_body().unwrap();
    for (i, &k) in f.frames.iter().enumerate() {
        assert_eq!(f.poses[i][body][0], outcome.response.motion.x[k]);
        assert_eq!(f.poses[i][body][1], outcome.response.motion.y[k]);
        assert_eq!(f.ideal_poses[i][body][0], outcome.response.ideal.x[k]);
        assert_eq!(f.ideal_poses[i][body][1], outcome.response.ideal.y[k]);
    }
}

#[test]
fn ideal_joints_close_and_the_clearance_poses_stay_within_the_clearance() {
    let outcome = run(SLIDER_CRANK);
    let scene = &outcome.scene;
    let f = frames(&outcome);
    let joint = &scene.clearance_joints[0];
    let c = joint.clearance;
    let mut largest_offset: f64 = 0.0;
    for (ideal, actual) in f.ideal_poses.iter().zip(&f.poses) {
        for j in &scene.revolute_joints {
            let gap = |poses: &[[f64; 3]]| {
                distance(
                    point(scene, poses, &j.body, j.point),
                    point(scene, poses, &j.other, j.other_point),
                )
            };
            assert!(gap(ideal) < 1e-9, "ideal {}: {:e}", j.name, gap(ideal));
            assert!(gap(actual) < 1e-6, "{}: {:e}", j.name, gap(actual));
        }
        let bearing =
            |poses: &[[f64; 3]]| point(scene, poses, &joint.bearing_body, joint.bearing_point);
        let pin = |poses: &[[f64; 3]]| point(scene, poses, &joint.pin_body, joint.pin_point);
        // The ideal mechanism's clearance joint is an ideal revolute joint.
        assert!(distance(bearing(ideal), pin(ideal)) < 1e-9);
        // With clearance the pin stays in its bearing (up to a small penetration) and the
        // joint's sides move from the ideal by about the clearance.
        let eccentricity = distance(bearing(actual), pin(actual));
        assert!(eccentricity < 1.1 * c, "eccentricity {eccentricity:e}");
        for (now, ideal) in [(bearing(actual), bearing(ideal)), (pin(actual), pin(ideal))] {
            let offset = distance(now, ideal);
            largest_offset = largest_offset.max(offset);
            assert!(offset < 3.0 * c, "offset {offset:e} from the ideal");
        }
    }
    // ... and they do move: the clearance shows.
    assert!(
        largest_offset > 0.1 * c,
        "largest offset {largest_offset:e}"
    );
}

fn check_gif(path: &Path, info: &AnimationInfo) -> Vec<u8> {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(info.bytes, bytes.len() as u64);
    assert!(bytes.len() < 3_000_000, "{} bytes", bytes.len());
    let gif = parse_gif(&bytes);
    assert_eq!(gif.frames.len(), info.frames);
    assert!(
        info.frames <= MAX_ANIMATION_FRAMES && info.frames >= 24,
        "{}",
        info.frames
    );
    let (w, h) = output::animation::ANIMATION_SIZE;
    assert_eq!(gif.size, (w as u16, h as u16));
    assert_eq!(
        gif.frames[0].0,
        (0, 0, w as u16, h as u16),
        "the first frame is whole"
    );
    for ((left, top, fw, fh), delay) in &gif.frames {
        assert!(u32::from(left + fw) <= w && u32::from(top + fh) <= h);
        assert_eq!(*delay, output::animation::FRAME_DELAY_CS);
    }
    bytes
}

#[test]
fn the_gif_is_bounded_well_formed_and_deterministic() {
    let outcome = run(SLIDER_CRANK);
    let dir = temp_dir("gif");
    let path = dir.join("mechanism.gif");
    let title = "slider-crank";
    let info = write_animation(&path, &outcome.scene, &outcome.response, &[], title).unwrap();
    let bytes = check_gif(&path, &info);
    assert_eq!(info.frames, MAX_ANIMATION_FRAMES);
    // One magnification per clearance joint, enough to see a 0.5 mm clearance.
    assert_eq!(info.magnification.len(), 1);
    assert_eq!(info.magnification[0].0, "rod-slider");
    assert!(info.magnification[0].1 >= 10.0, "{:?}", info.magnification);
    // Frames after the first store only what changed, and something does change.
    let gif = parse_gif(&bytes);
    assert!(
        gif.frames[1..]
            .iter()
            .any(|(r, _)| u32::from(r.2) * u32::from(r.3) > 1)
    );
    // Nothing but the file is left, and the same input gives the same bytes.
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    let again = dir.join("again.gif");
    write_animation(&again, &outcome.scene, &outcome.response, &[], title).unwrap();
    assert!(bytes == std::fs::read(&again).unwrap(), "not deterministic");
}

#[test]
fn the_worn_response_draws_with_its_wear() {
    let outcome = run(&common::worn_slider_crank("", 2, 1, ""));
    let worn = outcome.worn_response.as_ref().expect("worn response");
    assert!(worn.frames.is_some());
    let dir = temp_dir("worn");
    let path = dir.join("mechanism_worn.gif");
    let info = write_animation(&path, &outcome.scene, worn, &outcome.wear, "worn").unwrap();
    check_gif(&path, &info);
    let unworn = write_animation(
        &dir.join("mechanism.gif"),
        &outcome.scene,
        &outcome.response,
        &[],
        "unworn",
    )
    .unwrap();
    // The worn bearing widens what the inset must hold: never a larger magnification.
    assert!(info.magnification[0].1 <= unworn.magnification[0].1 * 1.5);
}

#[test]
fn without_animation_nothing_is_recorded_or_drawn() {
    let outcome = run(&format!("{SLIDER_CRANK}animation = false\n"));
    assert!(!outcome.scene.run.animation);
    assert!(outcome.response.frames.is_none());
    let dir = temp_dir("none");
    let path = dir.join("mechanism.gif");
    let e = write_animation(&path, &outcome.scene, &outcome.response, &[], "none").unwrap_err();
    assert!(e.to_string().contains("run.animation"), "{e}");
    assert!(!path.exists());
}

#[test]
fn a_scene_without_active_clearance_animates_its_ideal_mechanism() {
    let outcome = run(&format!(
        "{SLIDER_CRANK}[[clearance_joints]]\nname = \"rod-slider\"\nideal = true\n"
    ));
    let f = frames(&outcome);
    assert_eq!(f.poses, f.ideal_poses);
    let dir = temp_dir("ideal");
    let path = dir.join("mechanism.gif");
    let info = write_animation(&path, &outcome.scene, &outcome.response, &[], "ideal").unwrap();
    check_gif(&path, &info);
    assert!(info.magnification.is_empty());
}

#[test]
fn the_animation_field_round_trips_and_defaults_to_true() {
    let scene = load_str(
        "extends = \"slider-crank\"\n",
        "default",
        lgres::scenes::BUILTINS,
    )
    .unwrap();
    assert!(scene.run.animation);
    let off = scene
        .clone()
        .edit("no animation", |s| s.run.animation = false)
        .unwrap();
    let text = off.to_toml();
    assert!(text.contains("animation = false"), "{text}");
    let back = load_str(&text, "round trip", lgres::scenes::BUILTINS).unwrap();
    assert_eq!(back, off);
    assert_eq!(
        load_str(&scene.to_toml(), "round trip", lgres::scenes::BUILTINS).unwrap(),
        scene
    );
}
