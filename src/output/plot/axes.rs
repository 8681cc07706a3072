//! Axes of a plot: data values to pixels, round ticks on linear and log scales, and the box
//! with its ticks and labels drawn on a [`Canvas`].

use super::canvas::{text_width, widest, Canvas};
use super::{Scale, BLACK, COORD_LIMIT, GLYPH, GRID};

impl Scale {
    /// Axis coordinate of a data value (the value, or its log10); None where it cannot be drawn.
    pub(super) fn coord(self, v: f64) -> Option<f64> {
        match self {
            Scale::Linear => v.is_finite().then(|| v.clamp(-COORD_LIMIT, COORD_LIMIT)),
            Scale::Log => (v.is_finite() && v > 0.0).then(|| v.log10()),
        }
    }
}

/// One axis: its scale and its limits in axis coordinates (values, or log10 of values).
#[derive(Clone, Copy, Debug)]
pub(super) struct Axis {
    pub(super) scale: Scale,
    pub(super) lo: f64,
    pub(super) hi: f64,
}

impl Axis {
    /// The axis covering `coords` with a 5 % margin; a zero span is widened so that it still has
    /// ticks. None without a coordinate.
    pub(super) fn covering(scale: Scale, coords: impl Iterator<Item = f64>) -> Option<Axis> {
        let limits = (f64::INFINITY, f64::NEG_INFINITY);
        let (lo, hi) = coords.fold(limits, |(lo, hi), c| (lo.min(c), hi.max(c)));
        if lo > hi {
            return None;
        }
        let (lo, hi) = if hi - lo > 1e-9 * lo.abs().max(hi.abs()) {
            let margin = 0.05 * (hi - lo);
            (lo - margin, hi + margin)
        } else {
            let mid = 0.5 * lo + 0.5 * hi;
            let pad = match scale {
                Scale::Log => 0.5,
                Scale::Linear if mid.abs() > 1e-150 => 0.1 * mid.abs(),
                Scale::Linear => 1.0,
            };
            (mid - pad, mid + pad)
        };
        Some(Axis { scale, lo, hi })
    }

    /// Fraction of the way from `lo` to `hi`.
    pub(super) fn unit(&self, c: f64) -> f64 {
        (c - self.lo) / (self.hi - self.lo)
    }

    /// Tick positions (axis coordinates) with their labels.
    pub(super) fn ticks(&self) -> Vec<(f64, String)> {
        match self.scale {
            Scale::Linear => linear_ticks(self.lo, self.hi),
            Scale::Log => log_ticks(self.lo, self.hi),
        }
    }
}

/// Ticks at multiples of a 1, 2 or 5 × 10^k step, the step giving closest to 4–8 ticks.
fn linear_ticks(lo: f64, hi: f64) -> Vec<(f64, String)> {
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        return Vec::new();
    }
    // First and last multiple of `step` inside lo..hi, with slack for rounding.
    let indices = |step: f64| ((lo / step - 1e-9).ceil(), (hi / step + 1e-9).floor());
    let misfit = |step: f64| {
        let (first, last) = indices(step);
        let n = last - first + 1.0;
        ((4.0 - n).max(n - 8.0).max(0.0), (n - 6.0).abs())
    };
    let k = span.log10().floor() as i32;
    let steps = (k - 1..=k).flat_map(|e| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(e)));
    let best = steps.filter(|s| s.is_normal()).min_by(|&a, &b| {
        let ((fit_a, off_a), (fit_b, off_b)) = (misfit(a), misfit(b));
        fit_a.total_cmp(&fit_b).then(off_a.total_cmp(&off_b))
    });
    let Some(step) = best else {
        return Vec::new();
    };
    let (first, last) = indices(step);
    let scientific = lo.abs().max(hi.abs()) >= 1e5 || step < 1e-3;
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let label = |v: f64| match v {
        _ if v == 0.0 => "0".to_string(),
        _ if scientific => {
            let digits = (v.abs().log10().floor() - step.log10().floor()).clamp(0.0, 15.0);
            format!("{:.*e}", digits as usize, v)
        }
        _ => format!("{v:.decimals$}"),
    };
    let values = (0..=(last - first) as i64).map(|i| (first + i as f64) * step);
    values.map(|v| (v, label(v))).collect()
}

/// Ticks at decades (every n-th where there are more than 8); under four decades at 1, 3 or
/// 1, 2, 5 × 10^k, and where even those are too few, linear ticks of the values.
fn log_ticks(lo: f64, hi: f64) -> Vec<(f64, String)> {
    if !(lo.is_finite() && hi.is_finite() && hi > lo) {
        return Vec::new();
    }
    let (first, last) = ((lo - 1e-9).ceil() as i32, (hi + 1e-9).floor() as i32);
    if last - first >= 3 {
        let stride = (last - first + 8) / 8;
        let start = first + (stride - first.rem_euclid(stride)) % stride;
        let decades = (start..=last).step_by(stride as usize);
        return decades.map(|e| (e as f64, power_label(1, e))).collect();
    }
    let within = |mantissas: &[u32]| -> Vec<(f64, String)> {
        let candidates = (first - 1..=last).flat_map(|e| mantissas.iter().map(move |&m| (m, e)));
        let placed = candidates.map(|(m, e)| ((m as f64).log10() + e as f64, power_label(m, e)));
        placed
            .filter(|&(c, _)| c >= lo - 1e-9 && c <= hi + 1e-9)
            .collect()
    };
    let (thirds, fifths) = (within(&[1, 3]), within(&[1, 2, 5]));
    if thirds.len() >= 4 {
        return thirds;
    }
    if fifths.len() >= 2 {
        return fifths;
    }
    let linear = linear_ticks(10f64.powf(lo), 10f64.powf(hi)).into_iter();
    linear
        .filter(|t| t.0 > 0.0)
        .map(|(v, label)| (v.log10(), label))
        .collect()
}

/// `m` × 10^`e` as plain decimals between 0.01 and 9000, else as `2e-5`.
fn power_label(m: u32, e: i32) -> String {
    match e {
        -2..=-1 => format!("{:.*}", e.unsigned_abs() as usize, m as f64 * 10f64.powi(e)),
        0..=3 => format!("{}", m * 10u32.pow(e as u32)),
        _ => format!("{m}e{e}"),
    }
}

/// A value in about 4 significant digits, for labels that are not ticks.
pub(super) fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    if !(1e-3..1e5).contains(&v.abs()) {
        return format!("{v:.3e}");
    }
    let decimals = (3.0 - v.abs().log10().floor()).max(0.0) as usize;
    let text = format!("{v:.decimals$}");
    match text.contains('.') {
        true => text.trim_end_matches('0').trim_end_matches('.').to_string(),
        false => text,
    }
}

/// Left edge of the plot box: room for the rotated y label and the widest y tick label.
pub(super) fn box_left(y: &Axis) -> f64 {
    let ticks = y.ticks();
    (34 + widest(ticks.iter().map(|t| t.1.as_str()))).max(60) as f64
}

/// Left, top, right and bottom pixel of a box, all inclusive.
pub(super) type Edges = (i64, i64, i64, i64);

/// A rectangle on the canvas (px).
#[derive(Clone, Copy, Debug)]
pub(super) struct Rect {
    pub(super) left: f64,
    pub(super) top: f64,
    pub(super) width: f64,
    pub(super) height: f64,
}

impl Rect {
    pub(super) fn new(left: f64, top: f64, width: f64, height: f64) -> Rect {
        Rect {
            left,
            top,
            width,
            height,
        }
    }

    pub(super) fn edges(&self) -> Edges {
        let (right, bottom) = (self.left + self.width, self.top + self.height);
        let (left, top) = (self.left.round() as i64, self.top.round() as i64);
        (left, top, right.round() as i64, bottom.round() as i64)
    }
}

/// The plot box and the axes it shows.
pub(super) struct Frame {
    pub(super) x: Axis,
    pub(super) y: Axis,
    pub(super) rect: Rect,
}

impl Frame {
    /// Pixel position of a point given in axis coordinates.
    pub(super) fn pixel(&self, (cx, cy): (f64, f64)) -> (f64, f64) {
        let r = &self.rect;
        let y = r.top + (1.0 - self.y.unit(cy)) * r.height;
        (r.left + self.x.unit(cx) * r.width, y)
    }

    /// Box, ticks with labels (thinned where labels would overlap), grid lines at the ticks
    /// where asked, and the axis labels.
    pub(super) fn draw_axes(&self, canvas: &mut Canvas, grid: bool, x_label: &str, y_label: &str) {
        let edges @ (left, top, right, bottom) = self.rect.edges();
        let at = |ticks: Vec<(f64, String)>, pixel: &dyn Fn(f64) -> f64| -> Vec<(i64, String)> {
            ticks
                .into_iter()
                .map(|(c, label)| (pixel(c).round() as i64, label))
                .collect()
        };
        let x_ticks = at(self.x.ticks(), &|c| self.pixel((c, 0.0)).0);
        let y_ticks = at(self.y.ticks(), &|c| self.pixel((0.0, c)).1);
        let need = widest(x_ticks.iter().map(|t| t.1.as_str())) + 6;
        for (x, label) in x_ticks.iter().step_by(stride(&x_ticks, need)) {
            if grid {
                canvas.fill(*x, top, 1, bottom - top, GRID);
            }
            canvas.fill(*x, bottom - 5, 1, 5, BLACK);
            canvas.text(x - text_width(label, 1) / 2, bottom + 7, label, 1, BLACK);
        }
        for (y, label) in y_ticks.iter().step_by(stride(&y_ticks, 2 * GLYPH)) {
            if grid {
                canvas.fill(left, *y, right - left, 1, GRID);
            }
            canvas.fill(left, *y, 5, 1, BLACK);
            let x = left - 6 - text_width(label, 1);
            canvas.text(x, y - GLYPH / 2, label, 1, BLACK);
        }
        canvas.outline(edges, BLACK);
        axis_labels(canvas, edges, x_label, y_label);
    }
}

/// Every how-many-th tick keeps neighbouring labels at least `need` px apart.
fn stride(ticks: &[(i64, String)], need: i64) -> usize {
    let gaps = ticks.windows(2).map(|w| (w[1].0 - w[0].0).abs());
    match gaps.min() {
        Some(gap) if gap > 0 => ((need + gap - 1) / gap).max(1) as usize,
        _ => 1,
    }
}

/// The x label centred under a box, the y label read bottom to top at the left edge.
pub(super) fn axis_labels(
    canvas: &mut Canvas,
    (left, top, right, bottom): Edges,
    x_label: &str,
    y_label: &str,
) {
    let x = (left + right - text_width(x_label, 1)) / 2;
    canvas.text(x, bottom + 26, x_label, 1, BLACK);
    let y = (top + bottom + text_width(y_label, 1)) / 2;
    canvas.text_up(8, y, y_label, BLACK);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn positions(ticks: &[(f64, String)]) -> Vec<f64> {
        ticks.iter().map(|t| t.0).collect()
    }

    fn labels(ticks: &[(f64, String)]) -> Vec<&str> {
        ticks.iter().map(|t| t.1.as_str()).collect()
    }

    #[test]
    fn ticks_are_round_values_and_decades() {
        let unit = linear_ticks(0.0, 1.0);
        let expected = [0.0, 0.2, 0.4, 0.6, 0.8, 1.0];
        assert_eq!(unit.len(), expected.len());
        assert!(unit
            .iter()
            .zip(expected)
            .all(|(t, e)| (t.0 - e).abs() < 1e-12));
        assert_eq!(labels(&unit), ["0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
        assert_eq!(positions(&linear_ticks(-3.0, 17.0)), [0.0, 5.0, 10.0, 15.0]);
        let big = linear_ticks(0.0, 3e6);
        assert_eq!(
            labels(&big),
            ["0", "5e5", "1.0e6", "1.5e6", "2.0e6", "2.5e6", "3.0e6"]
        );

        let decades = log_ticks(-3.0, 2.0);
        assert_eq!(positions(&decades), [-3.0, -2.0, -1.0, 0.0, 1.0, 2.0]);
        assert_eq!(labels(&decades), ["1e-3", "0.01", "0.1", "1", "10", "100"]);
        let many = positions(&log_ticks(-10.0, 20.0));
        assert_eq!(many, [-8.0, -4.0, 0.0, 4.0, 8.0, 12.0, 16.0, 20.0]);
        assert_eq!(
            labels(&log_ticks(-3.1, -1.4)),
            ["1e-3", "3e-3", "0.01", "0.03"]
        );
        assert_eq!(labels(&log_ticks(0.1, 0.9)), ["2", "5"]);
        assert!(log_ticks(3f64.log10(), 4.5f64.log10()).len() >= 2);
    }
}
