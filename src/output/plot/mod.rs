//! PNG plots for the validation report and `penetrate plot`: series on linear or log axes
//! ([`Chart`]) and a scalar field on triangles and squares ([`FieldMap`], e.g. the damage of
//! each projectile element and each target particle in the r–z plane).
//!
//! Dependency-light on purpose: a plain RGB canvas, the `png` encoder and the public-domain
//! `font8x8` glyphs, so a report renders wherever the solver builds (no font files, no system
//! libraries). Every image is 800×560 px. Bad data (NaN, inf, empty, huge values) is skipped,
//! never a panic; only file errors are returned.
//!
//! Split by concern: the public charts and colour scales here, axes and ticks in `axes`, the
//! raster, its 8x8 text and the PNG encoding in `canvas`.

mod axes;
mod canvas;

use std::io;
use std::path::Path;

use axes::{box_left, short, Axis, Edges, Frame, Rect};
use canvas::{text_width, widest, Canvas};

const WIDTH: i64 = 800;
const HEIGHT: i64 = 560;
/// Least height of a field map's colour bar (px).
const COLOUR_BAR_MIN: i64 = 160;
/// Plot box limits (px): room above for the title, below for tick labels and the x label.
const BOX_TOP: f64 = 44.0;
const BOX_BOTTOM: f64 = 500.0;
const BOX_RIGHT: f64 = 780.0;
/// font8x8 glyph cell (px) at 1×.
const GLYPH: i64 = 8;
/// Largest magnitude of a linear axis coordinate, so that spans and margins stay finite.
const COORD_LIMIT: f64 = f64::MAX / 4.0;

type Rgb = [u8; 3];
const WHITE: Rgb = [255; 3];
const BLACK: Rgb = [0; 3];
const GRID: Rgb = [228; 3];
/// Colour of a non-finite field value: grey is outside the colour map.
const MISSING: Rgb = [150; 3];

/// Okabe & Ito (2008) colour-blind-safe palette; black is left out (it draws the axes) and
/// yellow comes last (it is weak on white).
const PALETTE: [Rgb; 7] = [
    [0, 114, 178],
    [213, 94, 0],
    [0, 158, 115],
    [230, 159, 0],
    [204, 121, 167],
    [86, 180, 233],
    [240, 228, 66],
];

/// Viridis (van der Walt & Smith, matplotlib's default map) at 9 even stops, interpolated
/// linearly: monotonic in lightness, so it reads in grey print and for colour-blind readers.
const VIRIDIS: [Rgb; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];

/// How an axis maps data values to distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scale {
    /// Distance proportional to the value.
    Linear,
    /// Distance proportional to log10 of the value; values ≤ 0 are not drawn.
    Log,
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mark {
    /// Segments between consecutive points, broken where a point cannot be drawn.
    Line,
    /// A dot at each point.
    Points,
    /// Segments and dots.
    LinePoints,
}

/// One labelled data set of a [`Chart`].
pub struct Series {
    /// Legend text.
    pub label: String,
    /// (x, y) in data units, joined in this order.
    pub points: Vec<(f64, f64)>,
    /// Line, dots or both.
    pub mark: Mark,
}

/// An x–y chart of one or more series; colours follow the series order.
pub struct Chart {
    /// Text above the plot box.
    pub title: String,
    /// Text under the x axis.
    pub x_label: String,
    /// Text beside the y axis, read bottom to top.
    pub y_label: String,
    /// Linear or log x axis.
    pub x_scale: Scale,
    /// Linear or log y axis.
    pub y_scale: Scale,
    /// Data sets, drawn in order (later ones on top).
    pub series: Vec<Series>,
}

impl Chart {
    /// Linear axes, no series.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Chart {
        Chart {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: Vec::new(),
        }
    }

    /// The same chart with a log x axis.
    pub fn log_x(self) -> Chart {
        Chart {
            x_scale: Scale::Log,
            ..self
        }
    }

    /// The same chart with a log y axis.
    pub fn log_y(self) -> Chart {
        Chart {
            y_scale: Scale::Log,
            ..self
        }
    }

    /// The same chart with one more series.
    pub fn series(mut self, label: &str, points: Vec<(f64, f64)>, mark: Mark) -> Chart {
        let label = label.to_string();
        self.series.push(Series {
            label,
            points,
            mark,
        });
        self
    }

    /// Renders the chart to an 800×560 RGB PNG; "no data" when no point can be drawn.
    pub fn write_png(&self, path: &Path) -> io::Result<()> {
        self.render().write_png(path)
    }

    /// Axis coordinates of a point, None where it cannot be drawn on these scales.
    fn coords(&self, (x, y): (f64, f64)) -> Option<(f64, f64)> {
        Some((self.x_scale.coord(x)?, self.y_scale.coord(y)?))
    }

    /// Axes covering every drawable point; None without one.
    fn frame(&self) -> Option<Frame> {
        let points = || self.series.iter().flat_map(|s| s.points.iter());
        let drawable = || points().filter_map(|&p| self.coords(p));
        let x = Axis::covering(self.x_scale, drawable().map(|c| c.0))?;
        let y = Axis::covering(self.y_scale, drawable().map(|c| c.1))?;
        let left = box_left(&y);
        let rect = Rect::new(left, BOX_TOP, BOX_RIGHT - left, BOX_BOTTOM - BOX_TOP);
        Some(Frame { x, y, rect })
    }

    fn render(&self) -> Canvas {
        let mut canvas = Canvas::new();
        canvas.title(&self.title);
        let Some(frame) = self.frame() else {
            canvas.no_data(&self.x_label, &self.y_label);
            return canvas;
        };
        frame.draw_axes(&mut canvas, true, &self.x_label, &self.y_label);
        let mut dots = Vec::new();
        for (series, &colour) in self.series.iter().zip(PALETTE.iter().cycle()) {
            let pixel = |&p| self.coords(p).map(|c| round(frame.pixel(c)));
            let pixels: Vec<_> = series.points.iter().map(pixel).collect();
            if series.mark != Mark::Points {
                for pair in pixels.windows(2) {
                    if let [Some(a), Some(b)] = *pair {
                        canvas.line(a, b, colour);
                    }
                }
            }
            if series.mark != Mark::Line {
                for &p in pixels.iter().flatten() {
                    canvas.dot(p, colour);
                }
            }
            dots.extend(pixels.into_iter().flatten());
        }
        self.draw_legend(&mut canvas, frame.rect.edges(), &dots);
        canvas
    }

    /// A legend box in the corner of the plot box that hides the fewest data points.
    fn draw_legend(&self, canvas: &mut Canvas, plot: Edges, dots: &[(i64, i64)]) {
        const ROW: i64 = 14;
        const INSET: i64 = 10;
        let labels = self.series.iter().map(|s| s.label.as_str());
        let (width, height) = (48 + widest(labels), 8 + ROW * self.series.len() as i64);
        let (x0, x1) = (plot.0 + INSET, plot.2 - INSET - width);
        let (y0, y1) = (plot.1 + INSET, plot.3 - INSET - height);
        let corners = [(x1, y0), (x0, y0), (x1, y1), (x0, y1)];
        let hidden = |&&(x, y): &&(i64, i64)| {
            let covers =
                |d: &&(i64, i64)| (x..=x + width).contains(&d.0) && (y..=y + height).contains(&d.1);
            dots.iter().filter(covers).count()
        };
        let Some(&(x, y)) = corners.iter().min_by_key(hidden) else {
            return;
        };
        canvas.fill(x, y, width, height, WHITE);
        canvas.outline((x, y, x + width, y + height), [120; 3]);
        let colours = PALETTE.iter().cycle();
        for (i, (series, &colour)) in self.series.iter().zip(colours).enumerate() {
            let row = y + 4 + ROW * i as i64 + ROW / 2;
            if series.mark != Mark::Points {
                canvas.line((x + 8, row), (x + 30, row), colour);
            }
            if series.mark != Mark::Line {
                canvas.dot((x + 19, row), colour);
            }
            canvas.text(x + 40, row - GLYPH / 2, &series.label, 1, BLACK);
        }
    }
}

/// A square of a [`FieldMap`] (an SPH particle's share of the plane), coloured by its value.
#[derive(Clone, Copy, Debug)]
pub struct Square {
    pub centre: [f64; 2],
    /// In the axes' length unit; drawn at least 1 px wide.
    pub side: f64,
    /// A non-finite value is drawn grey.
    pub value: f64,
}

/// A scalar field on triangles and squares in a plane (e.g. the damage of each projectile
/// element and each target particle in the r–z plane), coloured by value.
pub struct FieldMap {
    /// Text above the map.
    pub title: String,
    /// Text under the x axis.
    pub x_label: String,
    /// Text beside the y axis, read bottom to top.
    pub y_label: String,
    /// Text beside the colour bar.
    pub value_label: String,
    /// Corners (x, y) of each triangle, in the same length unit on both axes.
    pub triangles: Vec<[[f64; 2]; 3]>,
    /// One value per triangle; a missing or non-finite value is drawn grey.
    pub values: Vec<f64>,
    /// Squares, drawn under the triangles.
    pub squares: Vec<Square>,
    /// Colour scale limits (value_min, value_max); values are clamped into it.
    pub range: (f64, f64),
}

impl FieldMap {
    /// Renders the map to an RGB PNG 800 px wide with equal scales on both axes and a colour
    /// bar, as tall as the map needs (at most 560 px; a slender map leaves no blank band);
    /// "no data" when no triangle or square has finite corners.
    pub fn write_png(&self, path: &Path) -> io::Result<()> {
        self.render().write_png(path)
    }

    fn range_labels(&self) -> [String; 2] {
        [short(self.range.0), short(self.range.1)]
    }

    /// Axes covering every finite triangle and square, scaled so that a unit of x is as long
    /// as a unit of y, leaving room on the right for the colour bar; None without one.
    fn frame(&self) -> Option<Frame> {
        let finite = |t: &[[f64; 2]; 3]| t.iter().flatten().all(|v| v.is_finite());
        let squares = self.squares.iter().map(|s| {
            let h = 0.5 * s.side;
            let [x, y] = s.centre;
            [[x - h, y - h], [x + h, y + h], [x + h, y + h]]
        });
        let shapes = self.triangles.iter().copied().chain(squares);
        let corners: Vec<[f64; 2]> = shapes.filter(finite).flatten().collect();
        let along = |k: usize| {
            corners
                .iter()
                .filter_map(move |c| Scale::Linear.coord(c[k]))
        };
        let x = Axis::covering(Scale::Linear, along(0))?;
        let y = Axis::covering(Scale::Linear, along(1))?;
        let left = box_left(&y);
        let labels = self.range_labels();
        let bar_room = 82 + widest(labels.iter().map(String::as_str));
        let room_x = WIDTH as f64 - bar_room as f64 - left;
        let scale = (room_x / (x.hi - x.lo)).min((BOX_BOTTOM - BOX_TOP) / (y.hi - y.lo));
        let rect = Rect::new(left, BOX_TOP, (x.hi - x.lo) * scale, (y.hi - y.lo) * scale);
        Some(Frame { x, y, rect })
    }

    /// Colour of a value: viridis over `range`, grey where the value is missing or not finite.
    fn colour(&self, value: Option<f64>) -> Rgb {
        let Some(v) = value.filter(|v| v.is_finite()) else {
            return MISSING;
        };
        let t = (v - self.range.0) / (self.range.1 - self.range.0);
        // A zero or non-finite range leaves t undefined: the middle of the map.
        viridis(if t.is_nan() { 0.5 } else { t.clamp(0.0, 1.0) })
    }

    fn render(&self) -> Canvas {
        let Some(frame) = self.frame() else {
            let mut canvas = Canvas::new();
            canvas.title(&self.title);
            canvas.no_data(&self.x_label, &self.y_label);
            return canvas;
        };
        // Room under the map for the tick labels and the x label, and beside it for the
        // colour bar (at least COLOUR_BAR_MIN tall).
        let edges = frame.rect.edges();
        let (_, top, _, bottom) = edges;
        let height = (bottom + 44).max(top + COLOUR_BAR_MIN + 12).min(HEIGHT);
        let mut canvas = Canvas::with_height(height);
        canvas.title(&self.title);
        frame.draw_axes(&mut canvas, false, &self.x_label, &self.y_label);
        for square in &self.squares {
            let h = 0.5 * square.side;
            let [x, y] = square.centre;
            let corners = [frame.pixel((x - h, y - h)), frame.pixel((x + h, y + h))];
            canvas.rectangle(corners, edges, self.colour(Some(square.value)));
        }
        for (i, triangle) in self.triangles.iter().enumerate() {
            let corners = triangle.map(|[x, y]| frame.pixel((x, y)));
            canvas.triangle(corners, edges, self.colour(self.values.get(i).copied()));
        }
        canvas.outline(edges, BLACK);
        self.draw_colour_bar(&mut canvas, edges);
        canvas
    }

    /// Colour bar right of the map, max at the top, with its limits and `value_label`.
    fn draw_colour_bar(&self, canvas: &mut Canvas, (_, top, right, bottom): Edges) {
        let (x, height) = (right + 36, (bottom - top).max(COLOUR_BAR_MIN));
        for row in 0..height {
            let t = 1.0 - row as f64 / (height - 1) as f64;
            canvas.fill(x, top + row, 18, 1, viridis(t));
        }
        canvas.outline((x, top, x + 18, top + height), BLACK);
        let [min, max] = self.range_labels();
        canvas.text(x + 24, top, &max, 1, BLACK);
        canvas.text(x + 24, top + height - GLYPH, &min, 1, BLACK);
        let label_x = x + 34 + widest([min.as_str(), max.as_str()].into_iter());
        let middle = top + height / 2 + text_width(&self.value_label, 1) / 2;
        canvas.text_up(label_x, middle, &self.value_label, BLACK);
    }
}

fn round((x, y): (f64, f64)) -> (i64, i64) {
    (x.round() as i64, y.round() as i64)
}

/// Viridis at `t` in 0..=1.
fn viridis(t: f64) -> Rgb {
    let s = t * (VIRIDIS.len() - 1) as f64;
    let i = (s.floor() as usize).min(VIRIDIS.len() - 2);
    let (a, b, f) = (VIRIDIS[i], VIRIDIS[i + 1], s - i as f64);
    std::array::from_fn(|k| (a[k] as f64 + f * (b[k] as f64 - a[k] as f64)).round() as u8)
}

#[cfg(test)]
mod tests {
    use std::fs;

    use super::*;

    /// A fresh directory under the system temp dir, unique to this process and test.
    fn temp_dir(name: &str) -> std::path::PathBuf {
        let name = format!("penetrate-plot-{}-{name}", std::process::id());
        let dir = std::env::temp_dir().join(name);
        fs::create_dir_all(&dir).expect("create temp dir");
        dir
    }

    /// Width, height and RGB bytes of a PNG written here.
    fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
        let decoder = png::Decoder::new(fs::File::open(path).expect("open png"));
        let mut reader = decoder.read_info().expect("png header");
        let mut rgb = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut rgb).expect("png frame");
        assert_eq!(info.color_type, png::ColorType::Rgb);
        assert_eq!(info.bit_depth, png::BitDepth::Eight);
        rgb.truncate(info.buffer_size());
        (info.width, info.height, rgb)
    }

    fn pixel(rgb: &[u8], (x, y): (i64, i64)) -> Rgb {
        let i = 3 * (y * WIDTH + x) as usize;
        [rgb[i], rgb[i + 1], rgb[i + 2]]
    }

    #[test]
    fn charts_draw_every_series_and_their_text() {
        let dir = temp_dir("charts");
        let parabola = (0..50)
            .map(|i| (0.1 * i as f64, (0.1 * i as f64).powi(2)))
            .collect();
        let measured = vec![(1.0, 3.0), (2.0, 5.0), (4.0, 12.0)];
        let linear = Chart::new("Depth of penetration", "time (ms)", "depth (mm)")
            .series("parabola", parabola, Mark::Line)
            .series("measured", measured, Mark::Points);
        let power = (0..40).map(|i| (10f64.powf(0.1 * i as f64), 10f64.powf(-0.2 * i as f64)));
        let log_log = Chart::new("Convergence", "particles", "error")
            .log_x()
            .log_y()
            .series("h^2", power.collect(), Mark::LinePoints)
            .series("h", vec![(1.0, 1.0), (1e3, 1e-3)], Mark::Line);
        for (name, chart) in [("linear", &linear), ("log-log", &log_log)] {
            let path = dir.join(format!("{name}.png"));
            chart.write_png(&path).expect("write chart");
            let (width, height, rgb) = decode(&path);
            assert_eq!((width, height), (WIDTH as u32, HEIGHT as u32), "{name}");
            for colour in &PALETTE[..2] {
                let found = rgb.chunks(3).any(|p| p == colour);
                assert!(found, "{name}: no pixel of series colour {colour:?}");
            }
            let (left, top, right, bottom) = chart.frame().expect("drawable points").rect.edges();
            let all = (0..HEIGHT).flat_map(|y| (0..WIDTH).map(move |x| (x, y)));
            let outside = |&(x, y): &(i64, i64)| x < left || x > right || y < top || y > bottom;
            let inked = all
                .filter(outside)
                .filter(|&p| pixel(&rgb, p) != WHITE)
                .count();
            assert!(
                inked > 500,
                "{name}: only {inked} pixels of text around the box"
            );
        }
        fs::remove_dir_all(dir).expect("remove temp dir");
    }

    #[test]
    fn bad_points_and_empty_plots_still_write() {
        let dir = temp_dir("bad");
        let (nan, inf, max) = (f64::NAN, f64::INFINITY, f64::MAX);
        let bad = vec![
            (nan, 1.0),
            (1.0, inf),
            (-1.0, -2.0),
            (0.0, 0.0),
            (2.0, 3.0),
            (max, -max),
        ];
        let chart = |title: &str| Chart::new(title, "x", "y");
        let charts = [
            chart(""),
            chart("empty series").series("none", Vec::new(), Mark::LinePoints),
            chart("bad").series("bad", bad.clone(), Mark::LinePoints),
            chart("bad log")
                .log_x()
                .log_y()
                .series("bad", bad, Mark::LinePoints),
            chart("not positive")
                .log_y()
                .series("-", vec![(1.0, -1.0), (2.0, 0.0)], Mark::Line),
            chart("huge").series("huge", vec![(-max, 1e-308), (max, 5e-324)], Mark::Line),
            chart("one point")
                .log_x()
                .series("one", vec![(1e-300, 0.0)], Mark::Points),
        ];
        for (i, chart) in charts.iter().enumerate() {
            let path = dir.join(format!("{i}.png"));
            chart.write_png(&path).expect("write chart");
            assert_eq!(decode(&path).0, WIDTH as u32);
        }
        let map = FieldMap {
            title: "bad map".into(),
            x_label: "r".into(),
            y_label: "z".into(),
            value_label: "D".into(),
            triangles: vec![
                [[0.0, 0.0], [nan, 1.0], [1.0, 1.0]],
                [[0.0, 0.0], [1.0, 0.0], [1.0, 0.0]],
            ],
            values: vec![nan],
            squares: vec![
                Square {
                    centre: [nan, 0.0],
                    side: 1.0,
                    value: 0.5,
                },
                Square {
                    centre: [0.0, 0.0],
                    side: inf,
                    value: nan,
                },
                Square {
                    centre: [max, -max],
                    side: max,
                    value: 0.5,
                },
            ],
            range: (nan, inf),
        };
        map.write_png(&dir.join("map.png")).expect("write map");
        let empty = FieldMap {
            triangles: Vec::new(),
            squares: Vec::new(),
            ..map
        };
        empty
            .write_png(&dir.join("empty.png"))
            .expect("write empty map");
        fs::remove_dir_all(dir).expect("remove temp dir");
    }

    #[test]
    fn field_map_colours_each_triangle_by_its_value() {
        let dir = temp_dir("map");
        let map = FieldMap {
            title: "Damage".into(),
            x_label: "r (m)".into(),
            y_label: "z (m)".into(),
            value_label: "damage".into(),
            triangles: vec![
                [[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]],
                [[1.0, 0.0], [1.0, 2.0], [0.0, 2.0]],
            ],
            values: vec![0.0, 1.0],
            squares: vec![Square {
                centre: [1.5, 1.0],
                side: 0.5,
                value: 0.5,
            }],
            range: (0.0, 1.0),
        };
        let path = dir.join("map.png");
        map.write_png(&path).expect("write map");
        let (_, _, rgb) = decode(&path);
        let Frame { x, y, rect } = map.frame().expect("finite triangles");
        let (x_scale, y_scale) = (rect.width / (x.hi - x.lo), rect.height / (y.hi - y.lo));
        assert!(
            (x_scale / y_scale - 1.0).abs() < 1e-12,
            "aspect {x_scale} vs {y_scale} px/m"
        );
        let frame = Frame { x, y, rect };
        for (triangle, &value) in map.triangles.iter().zip(&map.values) {
            let sum = |k: usize| triangle.iter().map(|c| c[k]).sum::<f64>();
            let (px, py) = frame.pixel((sum(0) / 3.0, sum(1) / 3.0));
            let at = (px.floor() as i64, py.floor() as i64);
            assert_eq!(pixel(&rgb, at), viridis(value), "value {value}");
        }
        let (px, py) = frame.pixel((1.5, 1.0));
        let at = (px.floor() as i64, py.floor() as i64);
        assert_eq!(pixel(&rgb, at), viridis(0.5), "the square");

        // A slender map (10:1) gets a canvas only as tall as it and its colour bar need, with
        // the x axis's label still on it.
        let slender = FieldMap {
            triangles: vec![[[0.0, 0.0], [10.0, 0.0], [0.0, 1.0]]],
            values: vec![0.5],
            squares: Vec::new(),
            ..map
        };
        let path = dir.join("slender.png");
        slender.write_png(&path).expect("write slender map");
        let (width, height, rgb) = decode(&path);
        assert_eq!(width, WIDTH as u32);
        let (_, top, _, bottom) = slender.frame().expect("finite").rect.edges();
        let height = i64::from(height);
        assert!(height < HEIGHT / 2, "{height} px tall");
        assert!(height >= top + COLOUR_BAR_MIN && height >= bottom + 34);
        let label_rows = (bottom + 20..height).flat_map(|y| (0..WIDTH).map(move |x| (x, y)));
        let inked = label_rows.filter(|&p| pixel(&rgb, p) != WHITE).count();
        assert!(inked > 20, "no x label under the map ({inked} px)");
        fs::remove_dir_all(dir).expect("remove temp dir");
    }
}
