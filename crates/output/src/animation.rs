//! The animated mechanism, `mechanism.gif`: one drive cycle after the start-up window, from
//! the poses a run records ([`sim::MechanismFrames`]).
//!
//! Each frame shows the bodies as links through their joint points (a bar for two points, a
//! polygon for more, a block for a slider), the ideal mechanism as a wide light-grey band
//! behind them, ground pivots and guides, and, for every clearance joint, an inset in the
//! bearing's frame where the clearance circle is drawn magnified (the factor is written in
//! the inset and returned in [`AnimationInfo::magnification`]: the clearance is drawn that
//! many times larger than the mechanism's scale). The inset holds the journal centre, its
//! orbit since the start of the cycle, the worn clearance after the last wear stage (in each
//! direction `c + (h_bearing + h_pin)/2`, the pin's cells facing that way as the pin has
//! turned at the frame) and the contact force on the pin as an arrow
//! from the journal centre towards the bearing centre, scaled to the cycle's peak (written
//! in kN); each frame stands for the output samples since the previous one, and its arrow is
//! their largest force, so an impact between frames still shows. The time and the fraction
//! of the cycle are written on every frame.
//!
//! The file stays small and quick to write: at most [`MAX_ANIMATION_FRAMES`] frames of
//! [`ANIMATION_SIZE`] pixels, encoded against one fixed palette (the few colours drawn and
//! their blends with white; every pixel maps to its nearest entry), so no frame is
//! quantized, and only the rectangle that changed from the previous frame is stored. The
//! same input gives the same bytes.

mod canvas;
mod encode;
mod inset;
mod layout;

use std::path::Path;

use plotters::prelude::*;

use crate::files::{OutputError, write_via_temp};
use crate::plot::register_fonts;
use scene::Scene;
use sim::{JointWearHistory, MechanismFrames, Response};

pub use sim::MAX_ANIMATION_FRAMES;

pub use canvas::ANIMATION_SIZE;
use canvas::{Area, DrawResult, colours, text};
use inset::Inset;
use layout::{Mechanism, View};

/// Time each frame shows, hundredths of a second (GIF's unit): a cycle of 72 frames loops in
/// about 4 s whatever its real period.
pub const FRAME_DELAY_CS: u16 = 6;

/// What [`write_animation`] drew, for the report's caption.
#[derive(Debug, Clone, PartialEq)]
pub struct AnimationInfo {
    /// Frames in the file.
    pub frames: usize,
    /// File size, bytes.
    pub bytes: u64,
    /// Per active clearance joint (name): the factor its clearance is magnified by in its
    /// inset, relative to the mechanism's scale.
    pub magnification: Vec<(String, f64)>,
}

/// Draws the animation of `response` (its recorded [`MechanismFrames`]) to `path` atomically;
/// `worn` holds the wear histories of the joints for a worn response (empty for the unworn
/// one), whose last stage's bearing outline the insets draw. Fails without recorded frames
/// (`run.animation = false`).
pub fn write_animation(
    path: &Path,
    scene: &Scene,
    response: &Response,
    worn: &[JointWearHistory],
    title: &str,
) -> Result<AnimationInfo, OutputError> {
    let plot_err = |reason: String| OutputError::Plot {
        path: path.to_path_buf(),
        reason,
    };
    let frames = response
        .frames
        .as_ref()
        .filter(|f| {
            !f.frames.is_empty()
                && f.poses.len() == f.frames.len()
                && f.ideal_poses.len() == f.frames.len()
                && f.frames.iter().all(|&k| k < response.times.len())
        })
        .ok_or_else(|| {
            plot_err("no mechanism frames recorded (run.animation = false, or an empty run)".into())
        })?;
    let mechanism = Mechanism::new(scene);
    let has_insets = response
        .contact
        .iter()
        .any(|c| scene.clearance_joints.iter().any(|j| j.name == c.name));
    let view = View::fit(&mechanism, frames, has_insets);
    let insets = inset::insets(scene, response, frames, worn, &view);
    let n = frames.frames.len().min(MAX_ANIMATION_FRAMES);
    register_fonts();
    let (w, h) = ANIMATION_SIZE;
    let period = scene.cycle_period().unwrap_or(f64::NAN);
    let scene_frame = |i| SceneFrame {
        title,
        mechanism: &mechanism,
        view: &view,
        insets: &insets,
        frames,
        response,
        period,
        i,
    };
    // Drawing and compressing the frames is most of the animation's cost and each frame
    // depends only on its own data: contiguous runs of frames are drawn and compressed on
    // their own threads (memory: one RGB buffer and two index buffers per worker, plus the
    // compressed frames), then written in order by this one, so the bytes stay the same.
    let workers = std::thread::available_parallelism()
        .map_or(1, usize::from)
        .clamp(1, MAX_WORKERS)
        .min(n.max(1));
    let chunk = n.div_ceil(workers);
    let workers = n.div_ceil(chunk);
    let encoded: Vec<Result<Vec<gif::Frame<'static>>, String>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..workers)
            .map(|k| {
                let range = k * chunk..((k + 1) * chunk).min(n);
                let scene_frame = &scene_frame;
                s.spawn(move || encode_frames(range, scene_frame))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
            })
            .collect()
    });
    let encoder = encode::Encoder::new(w, h, &colours::ALL, FRAME_DELAY_CS);
    write_via_temp(path, |tmp| {
        let mut gif = encoder.start(tmp).map_err(|e| plot_err(e.to_string()))?;
        for frames in encoded {
            for frame in frames.map_err(plot_err)? {
                encode::write_encoded(&mut gif, &frame).map_err(|e| plot_err(e.to_string()))?;
            }
        }
        encode::finish(gif).map_err(|e| plot_err(e.to_string()))
    })?;
    let bytes = std::fs::metadata(path)
        .map_err(|source| OutputError::Io {
            path: path.to_path_buf(),
            source,
        })?
        .len();
    Ok(AnimationInfo {
        frames: n,
        bytes,
        magnification: insets
            .iter()
            .map(|i| (i.name.clone(), i.magnification))
            .collect(),
    })
}

/// Threads that draw and compress an animation's frames at most: beyond a few, the extra
/// frame each draws to prime its encoder and the memory cost more than they save.
const MAX_WORKERS: usize = 4;

/// Draws and compresses the frames `range` (indices into the animation's frames), priming
/// the encoder with the frame before the first, so that the frames are those one encoder
/// drawing every frame in turn would make.
fn encode_frames<'a>(
    range: std::ops::Range<usize>,
    scene_frame: &(dyn Fn(usize) -> SceneFrame<'a> + Sync),
) -> Result<Vec<gif::Frame<'static>>, String> {
    let (w, h) = ANIMATION_SIZE;
    let mut encoder = encode::Encoder::new(w, h, &colours::ALL, FRAME_DELAY_CS);
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    let mut out = Vec::with_capacity(range.len());
    let first = range.start.checked_sub(1).unwrap_or(range.start);
    for i in first..range.end {
        {
            let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
            draw_frame(&root, &scene_frame(i))
                .and_then(|()| root.present().map_err(Into::into))
                .map_err(|e| e.to_string())?;
        }
        if i < range.start {
            encoder.prime(&rgb);
        } else {
            out.push(encoder.encode(&rgb));
        }
    }
    Ok(out)
}

/// Everything one frame needs.
struct SceneFrame<'a> {
    title: &'a str,
    mechanism: &'a Mechanism,
    view: &'a View,
    insets: &'a [Inset],
    frames: &'a MechanismFrames,
    response: &'a Response,
    period: f64,
    /// The frame, an index into `frames.frames`.
    i: usize,
}

fn draw_frame(root: &Area<'_>, f: &SceneFrame<'_>) -> DrawResult {
    root.fill(&WHITE)?;
    let (w, h) = ANIMATION_SIZE;
    let (w, h) = (w as i32, h as i32);
    text(root, f.title, (12, 8), 18, BLACK)?;
    // The mechanism, clipped to its part of the picture: the ideal one behind, wide and
    // light, then the one with clearance.
    let (part, _) = root.split_horizontally(f.view.width);
    let ideal = &f.frames.ideal_poses[f.i];
    let actual = &f.frames.poses[f.i];
    f.mechanism
        .draw_guides(&part, f.view, &[&f.frames.poses, &f.frames.ideal_poses])?;
    f.mechanism.draw_links(&part, f.view, ideal, true)?;
    f.mechanism.draw_pivots(&part, f.view)?;
    f.mechanism.draw_links(&part, f.view, actual, false)?;
    for inset in f.insets {
        inset.draw_mark(&part, f.view, actual)?;
    }
    for inset in f.insets {
        inset.draw(root, f.response, &f.frames.frames, f.i, actual)?;
    }
    let k = f.frames.frames[f.i];
    // Footer: time, fraction of the cycle, legend.
    let times = &f.response.times;
    let t = times[k];
    let t0 = times[f.frames.frames[0]];
    let cycle = if f.period > 0.0 {
        format!("  ·  cycle {:.2}", (t - t0) / f.period)
    } else {
        String::new()
    };
    text(
        root,
        &format!("t = {}{cycle}", time_label(t, f.period)),
        (12, h - 30),
        17,
        BLACK,
    )?;
    let legend = "grey: ideal mechanism  ·  insets in the bearing's frame";
    text(root, legend, (w - 400, h - 36), 13, colours::GROUND)?;
    let arrow = "arrow: largest contact force on the pin since the last frame";
    text(root, arrow, (w - 400, h - 19), 13, colours::GROUND)?;
    Ok(())
}

/// `t` in seconds with enough digits for frames `period/72` apart to differ.
fn time_label(t: f64, period: f64) -> String {
    let step = period / MAX_ANIMATION_FRAMES as f64;
    let digits = if step.is_finite() && step > 0.0 {
        (-step.log10()).ceil().clamp(1.0, 9.0) as usize + 1
    } else {
        4
    };
    format!("{t:.digits$} s")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_labels_resolve_a_frame() {
        assert_eq!(time_label(1.23456, 1.0), "1.235 s");
        assert_eq!(time_label(0.0071234, 0.012), "0.00712 s");
    }
}
