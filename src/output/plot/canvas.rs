//! The raster a plot is drawn on: an RGB canvas with lines, dots, triangles and 8x8 bitmap
//! text (`font8x8`), encoded as PNG.

use std::path::Path;
use std::{fs, io};

use font8x8::{UnicodeFonts, BASIC_FONTS, GREEK_FONTS, LATIN_FONTS};

use super::axes::{axis_labels, Edges};
use super::{Rgb, BLACK, BOX_BOTTOM, BOX_RIGHT, BOX_TOP, GLYPH, HEIGHT, WIDTH};

/// The font8x8 glyph of a character: basic, Latin-1 or Greek; dashes as '-', others as '?'.
fn glyph(ch: char) -> [u8; 8] {
    let ch = if matches!(ch, '–' | '—' | '−') {
        '-'
    } else {
        ch
    };
    let found = BASIC_FONTS.get(ch).or_else(|| LATIN_FONTS.get(ch));
    let found = found.or_else(|| GREEK_FONTS.get(ch));
    found.or_else(|| BASIC_FONTS.get('?')).unwrap_or_default()
}

/// Lit pixels of `text` at 1×, as (x, y) from its top-left corner.
fn ink(text: &str) -> impl Iterator<Item = (i64, i64)> + '_ {
    text.chars().enumerate().flat_map(|(i, ch)| {
        let rows = glyph(ch).into_iter().enumerate();
        rows.flat_map(move |(row, bits)| {
            let lit = (0..8).filter(move |col| bits >> col & 1 == 1);
            lit.map(move |col| (i as i64 * GLYPH + col, row as i64))
        })
    })
}

pub(super) fn text_width(text: &str, scale: i64) -> i64 {
    text.chars().count() as i64 * GLYPH * scale
}

/// Width (px) of the widest of `texts` at 1×.
pub(super) fn widest<'a>(texts: impl Iterator<Item = &'a str>) -> i64 {
    texts.map(|t| text_width(t, 1)).max().unwrap_or(0)
}

/// An RGB image 800 px wide and 560 (or `height`) tall, white to start; drawing outside it is
/// ignored.
pub(super) struct Canvas {
    rgb: Vec<u8>,
    height: i64,
}

impl Canvas {
    pub(super) fn new() -> Canvas {
        Canvas::with_height(HEIGHT)
    }

    pub(super) fn with_height(height: i64) -> Canvas {
        Canvas {
            rgb: vec![255; (WIDTH * height * 3) as usize],
            height,
        }
    }

    pub(super) fn set(&mut self, x: i64, y: i64, colour: Rgb) {
        if (0..WIDTH).contains(&x) && (0..self.height).contains(&y) {
            let i = 3 * (y * WIDTH + x) as usize;
            self.rgb[i..i + 3].copy_from_slice(&colour);
        }
    }

    pub(super) fn fill(&mut self, x: i64, y: i64, width: i64, height: i64, colour: Rgb) {
        for y in y.max(0)..y.saturating_add(height).min(self.height) {
            for x in x.max(0)..x.saturating_add(width).min(WIDTH) {
                self.set(x, y, colour);
            }
        }
    }

    /// A 1 px frame on the edge pixels.
    pub(super) fn outline(&mut self, (left, top, right, bottom): Edges, colour: Rgb) {
        let (width, height) = (right - left + 1, bottom - top + 1);
        self.fill(left, top, width, 1, colour);
        self.fill(left, bottom, width, 1, colour);
        self.fill(left, top, 1, height, colour);
        self.fill(right, top, 1, height, colour);
    }

    /// A 2 px wide Bresenham line.
    pub(super) fn line(&mut self, (x0, y0): (i64, i64), (x1, y1): (i64, i64), colour: Rgb) {
        // Endpoints lie on the canvas by construction; this only bounds the loop otherwise.
        if [x0, y0, x1, y1]
            .iter()
            .any(|v| !(-WIDTH..2 * WIDTH).contains(v))
        {
            return;
        }
        let (dx, dy) = ((x1 - x0).abs(), -(y1 - y0).abs());
        let (sx, sy) = ((x1 - x0).signum(), (y1 - y0).signum());
        let (mut x, mut y, mut err) = (x0, y0, dx + dy);
        loop {
            self.fill(x, y, 2, 2, colour);
            if (x, y) == (x1, y1) {
                return;
            }
            let e2 = 2 * err;
            if e2 >= dy {
                err += dy;
                x += sx;
            }
            if e2 <= dx {
                err += dx;
                y += sy;
            }
        }
    }

    /// A filled dot of radius 3 px.
    pub(super) fn dot(&mut self, (x, y): (i64, i64), colour: Rgb) {
        for dy in -3..=3_i64 {
            for dx in -3..=3_i64 {
                if dx * dx + dy * dy <= 10 {
                    self.set(x + dx, y + dy, colour);
                }
            }
        }
    }

    /// Fills the pixels inside `clip` whose centres lie in the triangle (corners in px).
    pub(super) fn triangle(&mut self, [a, b, c]: [(f64, f64); 3], clip: Edges, colour: Rgb) {
        let edge = |p: (f64, f64), q: (f64, f64), s: (f64, f64)| {
            (q.0 - p.0) * (s.1 - p.1) - (q.1 - p.1) * (s.0 - p.0)
        };
        let area = edge(a, b, c);
        if area == 0.0 || area.is_nan() {
            return;
        }
        let bounds = |u: [f64; 3]| {
            let (lo, hi) = (u[0].min(u[1]).min(u[2]), u[0].max(u[1]).max(u[2]));
            (lo.floor() as i64, hi.ceil() as i64)
        };
        let ((x0, x1), (y0, y1)) = (bounds([a.0, b.0, c.0]), bounds([a.1, b.1, c.1]));
        for y in y0.max(clip.1)..=y1.min(clip.3) {
            for x in x0.max(clip.0)..=x1.min(clip.2) {
                let p = (x as f64 + 0.5, y as f64 + 0.5);
                let sides = [edge(b, c, p), edge(c, a, p), edge(a, b, p)];
                if sides.iter().all(|w| w * area >= 0.0) {
                    self.set(x, y, colour);
                }
            }
        }
    }

    /// Fills the pixels inside `clip` between two opposite corners (px), at least one pixel.
    pub(super) fn rectangle(&mut self, [a, b]: [(f64, f64); 2], clip: Edges, colour: Rgb) {
        let span = |p: f64, q: f64, lo: i64, hi: i64| {
            let (p, q) = (p.min(q), p.max(q));
            if !(p.is_finite() && q.is_finite()) {
                return (1, 0);
            }
            let first = (p.round() as i64).max(lo);
            (
                first,
                (q.round() as i64).saturating_sub(1).max(first).min(hi),
            )
        };
        let (x0, x1) = span(a.0, b.0, clip.0, clip.2);
        let (y0, y1) = span(a.1, b.1, clip.1, clip.3);
        for y in y0..=y1 {
            for x in x0..=x1 {
                self.set(x, y, colour);
            }
        }
    }

    /// Text with its top-left corner at (x, y), glyphs scaled by `scale`.
    pub(super) fn text(&mut self, x: i64, y: i64, text: &str, scale: i64, colour: Rgb) {
        for (dx, dy) in ink(text) {
            self.fill(x + dx * scale, y + dy * scale, scale, scale, colour);
        }
    }

    /// Text turned 90° counter-clockwise (read bottom to top), its bottom-left corner at (x, y).
    pub(super) fn text_up(&mut self, x: i64, y: i64, text: &str, colour: Rgb) {
        for (dx, dy) in ink(text) {
            self.set(x + dy, y - 1 - dx, colour);
        }
    }

    /// The title centred on top: 2× where it fits, else 1×.
    pub(super) fn title(&mut self, title: &str) {
        let fits = text_width(title, 2) <= WIDTH - 20;
        let scale = if fits { 2 } else { 1 };
        self.text(
            (WIDTH - text_width(title, scale)) / 2,
            14,
            title,
            scale,
            BLACK,
        );
    }

    /// An empty plot box saying "no data".
    pub(super) fn no_data(&mut self, x_label: &str, y_label: &str) {
        let edges = (60, BOX_TOP as i64, BOX_RIGHT as i64, BOX_BOTTOM as i64);
        self.outline(edges, BLACK);
        axis_labels(self, edges, x_label, y_label);
        let x = (edges.0 + edges.2 - text_width("no data", 2)) / 2;
        self.text(x, (edges.1 + edges.3) / 2 - GLYPH, "no data", 2, BLACK);
    }

    pub(super) fn write_png(&self, path: &Path) -> io::Result<()> {
        // Encoded in memory, so that every error writing the file reaches the caller.
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, WIDTH as u32, self.height as u32);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(&self.rgb)?;
        writer.finish()?;
        fs::write(path, bytes)
    }
}
