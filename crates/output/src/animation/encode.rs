//! GIF encoding against one fixed palette: the colours drawn, their blends with white (the
//! anti-aliased edges of lines and text) and a grey ramp; every pixel maps to its nearest
//! entry, memoized, so no frame is quantized and the result is deterministic. After the first
//! frame only the rectangle that changed is stored, its unchanged pixels transparent.

use std::borrow::Cow;
use std::collections::HashMap;
use std::error::Error;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use gif::{DisposalMethod, Frame, Repeat};
use plotters::style::RGBColor;

/// The GIF being written.
pub(super) type Gif = gif::Encoder<BufWriter<File>>;

/// Blends of each drawn colour with white, counting the colour itself.
const BLEND_STEPS: u8 = 8;
/// Levels of the grey ramp, black and white included.
const GREY_LEVELS: u8 = 16;

/// Maps RGB frames to a fixed palette and writes them.
pub(super) struct Encoder {
    width: u16,
    height: u16,
    palette: Vec<[u8; 3]>,
    /// Index of the transparent entry (after every drawn colour).
    transparent: u8,
    cache: HashMap<[u8; 3], u8>,
    previous: Option<Vec<u8>>,
    current: Vec<u8>,
    delay: u16,
}

impl Encoder {
    /// An encoder for `width × height` frames drawn in `colours` (on white), each shown
    /// `delay` hundredths of a second.
    pub(super) fn new(width: u32, height: u32, colours: &[RGBColor], delay: u16) -> Self {
        let mut palette: Vec<[u8; 3]> = vec![[255, 255, 255]];
        let mut add = |c: [u8; 3]| {
            if palette.len() < 255 && !palette.contains(&c) {
                palette.push(c);
            }
        };
        for g in 0..GREY_LEVELS {
            let v = (u32::from(g) * 255 / u32::from(GREY_LEVELS - 1)) as u8;
            add([v, v, v]);
        }
        for c in colours {
            for k in 1..=BLEND_STEPS {
                let blend = |v: u8| {
                    let w = u32::from(BLEND_STEPS - k);
                    ((u32::from(v) * u32::from(k) + 255 * w) / u32::from(BLEND_STEPS)) as u8
                };
                add([blend(c.0), blend(c.1), blend(c.2)]);
            }
        }
        let transparent = palette.len() as u8;
        let pixels = usize::from(width as u16) * usize::from(height as u16);
        Self {
            width: width as u16,
            height: height as u16,
            palette,
            transparent,
            cache: HashMap::new(),
            previous: None,
            current: vec![0; pixels],
            delay,
        }
    }

    /// Creates the file at `path` and writes the header and the palette.
    pub(super) fn start(&self, path: &Path) -> Result<Gif, Box<dyn Error>> {
        let file = BufWriter::new(File::create(path)?);
        let mut rgb: Vec<u8> = self.palette.iter().flatten().copied().collect();
        // The transparent entry: magenta, never drawn.
        rgb.extend([255, 0, 255]);
        let mut gif = gif::Encoder::new(file, self.width, self.height, &rgb)?;
        gif.set_repeat(Repeat::Infinite)?;
        Ok(gif)
    }

    /// Palette entry nearest to `c`.
    fn index(&mut self, c: [u8; 3]) -> u8 {
        let palette = &self.palette;
        *self.cache.entry(c).or_insert_with(|| {
            let d = |p: &[u8; 3]| {
                p.iter()
                    .zip(c)
                    .map(|(a, b)| (i32::from(*a) - i32::from(b)).pow(2))
                    .sum::<i32>()
            };
            // Ties go to the first entry: deterministic.
            (0..palette.len())
                .min_by_key(|&k| (d(&palette[k]), k))
                .unwrap_or(0) as u8
        })
    }

    /// Maps one frame (RGB, 3 bytes a pixel, rows top to bottom) to the palette and makes it
    /// the previous frame, without encoding it: a worker that starts in the middle of the
    /// animation primes itself with the frame before its first, so its first changed
    /// rectangle is the one a single encoder would store.
    pub(super) fn prime(&mut self, rgb: &[u8]) {
        let current = self.map(rgb);
        self.advance(current);
    }

    /// One frame (RGB, 3 bytes a pixel, rows top to bottom) as the GIF stores it: after the
    /// first, only the rectangle that changed from the previous frame, already LZW-compressed
    /// (for [`write_encoded`]) so that workers can compress frames in parallel; the bytes are
    /// those `gif::Encoder::write_frame` would write.
    pub(super) fn encode(&mut self, rgb: &[u8]) -> Frame<'static> {
        let current = self.map(rgb);
        let (w, h) = (usize::from(self.width), usize::from(self.height));
        let mut frame = Frame {
            delay: self.delay,
            dispose: DisposalMethod::Keep,
            width: self.width,
            height: self.height,
            ..Frame::default()
        };
        frame.buffer = match &self.previous {
            None => Cow::Owned(current.clone()),
            Some(prev) => {
                let rect = changed_rect(prev, &current, w, h);
                // Nothing changed: one transparent pixel keeps the frame (and its delay).
                let (x0, y0, x1, y1) = rect.unwrap_or((0, 0, 0, 0));
                let mut sub = Vec::with_capacity((x1 - x0 + 1) * (y1 - y0 + 1));
                for y in y0..=y1 {
                    let row = y * w + x0..=y * w + x1;
                    if rect.is_some() {
                        sub.extend(
                            current[row.clone()]
                                .iter()
                                .zip(&prev[row])
                                .map(|(&c, &p)| if c != p { c } else { self.transparent }),
                        );
                    } else {
                        sub.extend(row.map(|_| self.transparent));
                    }
                }
                frame.left = x0 as u16;
                frame.top = y0 as u16;
                frame.width = (x1 - x0 + 1) as u16;
                frame.height = (y1 - y0 + 1) as u16;
                frame.transparent = Some(self.transparent);
                Cow::Owned(sub)
            }
        };
        self.advance(current);
        frame.make_lzw_pre_encoded();
        // The compressed frame is kept until written, in a buffer reserved at half the
        // uncompressed size: about ten times what it holds.
        if let Cow::Owned(compressed) = &mut frame.buffer {
            compressed.shrink_to_fit();
        }
        frame
    }

    /// The palette indices of `rgb`, in the buffer the frame before last used.
    fn map(&mut self, rgb: &[u8]) -> Vec<u8> {
        let (w, h) = (usize::from(self.width), usize::from(self.height));
        let mut current = std::mem::take(&mut self.current);
        current.resize(w * h, 0);
        let mut last: Option<([u8; 3], u8)> = None;
        for (out, px) in current.iter_mut().zip(rgb.chunks_exact(3)) {
            let c = [px[0], px[1], px[2]];
            *out = match last {
                Some((l, k)) if l == c => k,
                _ => {
                    let k = self.index(c);
                    last = Some((c, k));
                    k
                }
            };
        }
        current
    }

    /// `current` becomes the previous frame; the old previous one's buffer is reused.
    fn advance(&mut self, current: Vec<u8>) {
        self.current = self.previous.replace(current).unwrap_or_default();
    }
}

/// Writes a frame made by [`Encoder::encode`].
pub(super) fn write_encoded(gif: &mut Gif, frame: &Frame<'_>) -> Result<(), Box<dyn Error>> {
    gif.write_lzw_pre_encoded_frame(frame)?;
    Ok(())
}

/// The smallest rectangle `(x0, y0, x1, y1)` (inclusive) holding every pixel that differs,
/// `None` when none does.
fn changed_rect(a: &[u8], b: &[u8], w: usize, h: usize) -> Option<(usize, usize, usize, usize)> {
    let row = |y: usize| a[y * w..(y + 1) * w] != b[y * w..(y + 1) * w];
    let y0 = (0..h).find(|&y| row(y))?;
    let y1 = (0..h).rev().find(|&y| row(y))?;
    let (mut x0, mut x1) = (w, 0);
    for y in y0..=y1 {
        let (ra, rb) = (&a[y * w..(y + 1) * w], &b[y * w..(y + 1) * w]);
        if let Some(x) = (0..w).find(|&x| ra[x] != rb[x]) {
            x0 = x0.min(x);
            x1 = x1.max((0..w).rev().find(|&x| ra[x] != rb[x]).unwrap_or(x));
        }
    }
    Some((x0, y0, x1, y1))
}

/// Writes the trailer and flushes the file.
pub(super) fn finish(gif: Gif) -> Result<(), Box<dyn Error>> {
    let mut file = gif.into_inner()?;
    file.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_changed_rectangle_is_tight() {
        let a = vec![0u8; 20];
        let mut b = a.clone();
        assert_eq!(changed_rect(&a, &b, 5, 4), None);
        b[5 + 3] = 1; // (3, 1)
        b[2 * 5 + 1] = 1; // (1, 2)
        assert_eq!(changed_rect(&a, &b, 5, 4), Some((1, 1, 3, 2)));
    }

    #[test]
    fn drawn_colours_map_to_themselves() {
        let colour = RGBColor(0, 114, 178);
        let mut e = Encoder::new(4, 4, &[colour], 5);
        let k = e.index([0, 114, 178]);
        assert_eq!(e.palette[usize::from(k)], [0, 114, 178]);
        let white = e.index([255, 255, 255]);
        assert_eq!(e.palette[usize::from(white)], [255, 255, 255]);
        // A colour never drawn maps to the nearest entry, never to the transparent one.
        assert!(e.index([1, 2, 250]) < e.transparent);
        assert!(e.palette.len() < 255);
    }
}
