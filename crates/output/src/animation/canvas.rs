//! What every part of a frame draws with: the frame's size, the colours (the GIF's palette is
//! built from them), the drawing area and its text.

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::plot::FONT;

/// Width and height of the animation, pixels.
pub const ANIMATION_SIZE: (u32, u32) = (720, 540);

/// Colours of the drawing; the GIF's palette is built from these and their blends with white.
pub(super) mod colours {
    use plotters::style::RGBColor;

    /// The links of the mechanism with clearance.
    pub const LINK: RGBColor = RGBColor(0, 114, 178);
    /// The ideal mechanism behind.
    pub const IDEAL: RGBColor = RGBColor(205, 205, 205);
    /// Ground marks, guides, frames of the insets.
    pub const GROUND: RGBColor = RGBColor(110, 110, 110);
    /// Clearance joints: their mark in the mechanism and their label.
    pub const JOINT: RGBColor = RGBColor(230, 159, 0);
    /// The journal-centre orbit.
    pub const TRAIL: RGBColor = RGBColor(86, 180, 233);
    /// The contact force.
    pub const FORCE: RGBColor = RGBColor(213, 94, 0);
    /// The worn bearing outline.
    pub const WORN: RGBColor = RGBColor(0, 158, 115);
    /// Every colour drawn (white and black included).
    pub const ALL: [RGBColor; 9] = [
        RGBColor(255, 255, 255),
        RGBColor(0, 0, 0),
        LINK,
        IDEAL,
        GROUND,
        JOINT,
        TRAIL,
        FORCE,
        WORN,
    ];
}

/// A frame, or a part of one, being drawn.
pub(super) type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;
/// What drawing on an [`Area`] returns.
pub(super) type DrawResult = Result<(), Box<dyn std::error::Error>>;

/// Writes `s` at `at` in the figures' font.
pub(super) fn text(
    area: &Area<'_>,
    s: &str,
    at: (i32, i32),
    size: u32,
    colour: RGBColor,
) -> DrawResult {
    area.draw(&Text::new(s, at, (FONT, size).into_font().color(&colour)))?;
    Ok(())
}
