//! Projectile meshers: a tangent-ogive penetrator (optionally with a filled cavity) and a
//! flat-ended cylinder (Taylor bar), as linear axisymmetric triangles (physics.md §2).
//!
//! Both meshes are made of cells, each split into triangles around a centre node, one per cell
//! edge: the crossed-triangle pattern that keeps constant-strain triangles from locking
//! volumetrically in plastic flow (physics.md §2). A cylinder and an ogive's shank are one
//! structured block of quads; rows run toward the tail face, columns from the axis (column 0,
//! r = 0.0 exactly) to the outer surface.
//!
//! The ogive nose is meshed in layers between straight lines from the axis to the arc, one
//! element apart along both. A line carries as many cells as its length holds elements, so the
//! count falls from the shank's columns toward the tip; where it falls, a cell of the layer is a
//! pentagon (two edges below, one above), split into five triangles around its centre. The last
//! line has two edges and closes at the tip in one kite. A structured block with the shank's
//! columns all the way to the tip squeezed them into slivers a quarter of an element high, and
//! the smallest altitude sets the stable step of the whole coupled run (physics.md §2, §5).
//! Laplace smoothing and a local max-min optimisation of the smallest altitude place the nose's
//! interior nodes.
//!
//! Longer than most files (about 830 lines) because the two layouts, the smoothing and the
//! assembly into triangles and master segments share one cell structure; its tests live in
//! `projectile/tests.rs`.

use std::collections::HashMap;
use std::f64::consts::{FRAC_1_SQRT_2, PI};

use super::{MasterSegment, MeshError, ProjectileMesh};
use crate::scene::{CavitySpec, ProjectileShape, ProjectileSpec};

/// Meshes the projectile of a scene: dispatches on its shape, density from its material.
pub fn build(spec: &ProjectileSpec) -> Result<ProjectileMesh, MeshError> {
    let density = spec.material.density;
    match spec.shape {
        ProjectileShape::Ogive { crh } => ogive(
            spec.diameter,
            spec.length,
            crh,
            spec.element_size,
            spec.cavity.as_ref(),
            density,
            spec.nose_z,
        ),
        ProjectileShape::Cylinder => {
            if spec.cavity.is_some() {
                return Err(MeshError(
                    "projectile: a cavity is only meshed in an ogive projectile; remove \
                     [projectile.cavity] or use shape = \"ogive\""
                        .into(),
                ));
            }
            cylinder(
                spec.diameter,
                spec.length,
                spec.element_size,
                density,
                spec.nose_z,
            )
        }
    }
}

/// Node and element counts the mesh of `spec` will have, without building it (for `check` and
/// memory estimates). Exact for valid specs; (0, 0) when the spec cannot be meshed (`build`
/// says why).
pub fn estimate_counts(spec: &ProjectileSpec) -> (usize, usize) {
    match spec.shape {
        ProjectileShape::Ogive { crh } => ogive_layout(
            spec.diameter,
            spec.length,
            crh,
            spec.element_size,
            spec.cavity.as_ref(),
            spec.nose_z,
        )
        .map(|l| l.cells().counts())
        .unwrap_or((0, 0)),
        ProjectileShape::Cylinder => {
            cylinder_layout(spec.diameter, spec.length, spec.element_size, spec.nose_z)
                .map(|(cols, rows)| {
                    let rows: Vec<Vec<(f64, f64)>> = rows
                        .iter()
                        .map(|&z| cols.iter().map(|&r| (r, z)).collect())
                        .collect();
                    let mut mesh = CellMesh::default();
                    mesh.push_block(&rows, None, &[]);
                    mesh.counts()
                })
                .unwrap_or((0, 0))
        }
    }
}

/// Tangent-ogive projectile: a nose of ogive radius s = crh·diameter on a cylindrical shank of
/// radius a = diameter/2, nose tip at (0, `nose_z`), tail face at z = `nose_z + length`.
///
/// Nose length L_n = sqrt(s² − (s − a)²); outer radius at distance x from the tip
/// R(x) = sqrt(s² − (L_n − x)²) − (s − a). The optional cavity is a coaxial cylinder of radius
/// `cavity.diameter/2` whose rear end lies `cavity.rear_wall` below the tail face; its filler
/// mass is lumped on the cavity-wall nodes.
///
/// The shank has nr = max(2, round(a/element_size)) columns. With a cavity the columns are
/// graded (uniform inside and outside the cavity radius) so that one falls exactly on the
/// cavity wall, and the shank rows are spaced so that two fall exactly on its ends: the meshed
/// cavity is the specified one, and so is the projectile's mass.
///
/// Masters run along the outline from the nose tip to the tail centre. Errors: a non-positive
/// or non-finite size or density, crh < 0.5, no shank (length ≤ L_n), or a cavity that does not
/// fit: narrower than half a column, leaving no column of steel outside it, or with a front
/// (toward the nose junction) or rear wall thinner than half an element.
pub fn ogive(
    diameter: f64,
    length: f64,
    crh: f64,
    element_size: f64,
    cavity: Option<&CavitySpec>,
    density: f64,
    nose_z: f64,
) -> Result<ProjectileMesh, MeshError> {
    positive("density", density)?;
    let layout = ogive_layout(diameter, length, crh, element_size, cavity, nose_z)?;
    let mut mesh = layout.cells();
    mesh.smooth();
    let filler = match (cavity, layout.cavity) {
        (Some(spec), Some((rc, len))) => spec.filler_density * PI * rc * rc * len,
        _ => 0.0,
    };
    assemble(&mesh, density, filler)
}

/// Flat-ended solid cylinder (Taylor bar) of radius a = diameter/2 occupying
/// z ∈ [`bottom_z`, `bottom_z + length`], r ∈ [0, a]: a structured crossed-triangle grid of
/// max(2, round(a/element_size)) columns and max(1, round(length/element_size)) rows.
/// Masters run from the impact face at the axis round to the tail centre.
pub fn cylinder(
    diameter: f64,
    length: f64,
    element_size: f64,
    density: f64,
    bottom_z: f64,
) -> Result<ProjectileMesh, MeshError> {
    positive("density", density)?;
    let (cols, rows_z) = cylinder_layout(diameter, length, element_size, bottom_z)?;
    let rows: Vec<Vec<(f64, f64)>> = rows_z
        .iter()
        .map(|&z| cols.iter().map(|&r| (r, z)).collect())
        .collect();
    let mut mesh = CellMesh::default();
    mesh.push_block(&rows, None, &[]);
    assemble(&mesh, density, 0.0)
}

fn positive(name: &str, value: f64) -> Result<(), MeshError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(MeshError(format!(
            "projectile {name} must be a positive finite number, got {value}"
        )))
    }
}

fn finite(name: &str, value: f64) -> Result<(), MeshError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(MeshError(format!(
            "projectile {name} must be finite, got {value}"
        )))
    }
}

/// Number of intervals of about `h` in a length `len` (at least 1).
fn divisions(len: f64, h: f64) -> usize {
    ((len / h).round() as usize).max(1)
}

/// `n` equal intervals from `x0` to `x1`, both ends exact, appended to `out` without `x0`.
fn push_spaced(out: &mut Vec<f64>, x0: f64, x1: f64, n: usize) {
    for k in 1..n {
        out.push(x0 + (x1 - x0) * k as f64 / n as f64);
    }
    out.push(x1);
}

/// Column radii and row heights of a solid cylinder.
fn cylinder_layout(
    diameter: f64,
    length: f64,
    element_size: f64,
    bottom_z: f64,
) -> Result<(Vec<f64>, Vec<f64>), MeshError> {
    positive("diameter", diameter)?;
    positive("length", length)?;
    positive("element_size", element_size)?;
    finite("nose_z", bottom_z)?;
    let a = 0.5 * diameter;
    let mut cols = vec![0.0];
    push_spaced(&mut cols, 0.0, a, divisions(a, element_size).max(2));
    let mut rows = vec![bottom_z];
    push_spaced(
        &mut rows,
        bottom_z,
        bottom_z + length,
        divisions(length, element_size),
    );
    Ok((cols, rows))
}

/// Rectangle of removed cells (the cavity): rows `first_row..end_row`, columns `0..cols`.
#[derive(Clone, Copy, Debug)]
struct Hole {
    first_row: usize,
    end_row: usize,
    cols: usize,
}

/// Corners and counter-clockwise polygonal cells (quads, and pentagons where the nose's cell
/// count falls), before each cell is split into triangles around its centre; `free` marks the
/// corners that smoothing may move (inside the nose, off every boundary).
#[derive(Debug, Default)]
struct CellMesh {
    corners: Vec<(f64, f64)>,
    cells: Vec<Vec<u32>>,
    free: Vec<bool>,
}

impl CellMesh {
    fn corner(&mut self, p: (f64, f64), free: bool) -> u32 {
        self.corners.push(p);
        self.free.push(free);
        (self.corners.len() - 1) as u32
    }

    /// Appends the structured block of corner rows `rows[g][i]` (z rising with g, column 0 on
    /// the axis) less `hole`; row 0 reuses the corners `first` where given (the nose's junction
    /// line).
    fn push_block(&mut self, rows: &[Vec<(f64, f64)>], hole: Option<Hole>, first: &[u32]) {
        let (cells_z, cells_r) = (rows.len() - 1, rows[0].len() - 1);
        let active = |g: usize, i: usize| {
            g < cells_z
                && i < cells_r
                && !hole.is_some_and(|h| g >= h.first_row && g < h.end_row && i < h.cols)
        };
        // A corner exists when one of its (up to four) cells does.
        let used = |g: usize, i: usize| {
            let (below, left) = (g.checked_sub(1), i.checked_sub(1));
            active(g, i)
                || left.is_some_and(|l| active(g, l))
                || below.is_some_and(|b| active(b, i))
                || below.zip(left).is_some_and(|(b, l)| active(b, l))
        };
        let mut index = vec![vec![u32::MAX; cells_r + 1]; cells_z + 1];
        for (g, row) in rows.iter().enumerate() {
            for (i, &p) in row.iter().enumerate() {
                if g == 0 && !first.is_empty() {
                    index[g][i] = first[i];
                } else if used(g, i) {
                    index[g][i] = self.corner(p, false);
                }
            }
        }
        for g in 0..cells_z {
            for i in 0..cells_r {
                if active(g, i) {
                    self.cells.push(vec![
                        index[g][i],
                        index[g][i + 1],
                        index[g + 1][i + 1],
                        index[g + 1][i],
                    ]);
                }
            }
        }
    }

    /// (nodes, elements): a node per corner and per cell centre, a triangle per cell edge.
    fn counts(&self) -> (usize, usize) {
        (
            self.corners.len() + self.cells.len(),
            self.cells.iter().map(Vec::len).sum(),
        )
    }

    /// Places the free corners: Laplace smoothing (each the mean of the corners it shares a
    /// cell edge with), then a local max-min optimisation of the smallest altitude around each
    /// (Freitag & Ollivier-Gooch 1997), since that altitude sets the stable step of the whole
    /// projectile (physics.md §2). Gauss–Seidel sweeps in a fixed order: deterministic.
    fn smooth(&mut self) {
        let n = self.corners.len();
        let mut joined: Vec<Vec<u32>> = vec![Vec::new(); n];
        let mut cells_of: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (c, cell) in self.cells.iter().enumerate() {
            for k in 0..cell.len() {
                let (a, b) = (cell[k], cell[(k + 1) % cell.len()]);
                for (x, y) in [(a, b), (b, a)] {
                    if !joined[x as usize].contains(&y) {
                        joined[x as usize].push(y);
                    }
                }
                cells_of[a as usize].push(c);
            }
        }
        let free: Vec<usize> = (0..n).filter(|&k| self.free[k]).collect();
        if free.is_empty() {
            return;
        }
        let scale = self
            .corners
            .iter()
            .map(|p| p.0.abs().max(p.1.abs()))
            .fold(0.0, f64::max);
        for _ in 0..1000 {
            let mut largest_move: f64 = 0.0;
            for &k in &free {
                let m = joined[k].len() as f64;
                let target = joined[k].iter().fold((0.0, 0.0), |acc, &j| {
                    let q = self.corners[j as usize];
                    (acc.0 + q.0 / m, acc.1 + q.1 / m)
                });
                let p = &mut self.corners[k];
                largest_move = largest_move.max((target.0 - p.0).abs().max((target.1 - p.1).abs()));
                *p = target;
            }
            if largest_move <= 1e-12 * scale {
                break;
            }
        }

        let around = |mesh: &CellMesh, k: usize| {
            cells_of[k]
                .iter()
                .map(|&c| {
                    let corners: Vec<(f64, f64)> = mesh.cells[c]
                        .iter()
                        .map(|&j| mesh.corners[j as usize])
                        .collect();
                    crossed_min_altitude(&corners)
                })
                .fold(f64::INFINITY, f64::min)
        };
        const D: f64 = FRAC_1_SQRT_2;
        const DIRECTIONS: [(f64, f64); 8] = [
            (1.0, 0.0),
            (0.0, 1.0),
            (-1.0, 0.0),
            (0.0, -1.0),
            (D, D),
            (-D, D),
            (-D, -D),
            (D, -D),
        ];
        for _ in 0..20 {
            let mut moved = false;
            for &k in &free {
                let p0 = self.corners[k];
                let size = joined[k]
                    .iter()
                    .map(|&j| {
                        let q = self.corners[j as usize];
                        (q.0 - p0.0).hypot(q.1 - p0.1)
                    })
                    .fold(f64::INFINITY, f64::min);
                let mut best = around(self, k);
                let mut step = 0.2 * size;
                while step > 1e-3 * size {
                    let base = self.corners[k];
                    let mut improved = false;
                    for d in DIRECTIONS {
                        self.corners[k] = (base.0 + step * d.0, base.1 + step * d.1);
                        let q = around(self, k);
                        if q > best * (1.0 + 1e-9) {
                            best = q;
                            improved = true;
                            break;
                        }
                        self.corners[k] = base;
                    }
                    if improved {
                        moved = true;
                    } else {
                        step *= 0.5;
                    }
                }
            }
            if !moved {
                break;
            }
        }
    }
}

/// Smallest altitude (2A over the longest side) of the triangles a counter-clockwise cell is
/// split into around its centre (the mean of its corners); negative when one is inverted.
fn crossed_min_altitude(c: &[(f64, f64)]) -> f64 {
    let n = c.len() as f64;
    let mid = c
        .iter()
        .fold((0.0, 0.0), |acc, p| (acc.0 + p.0 / n, acc.1 + p.1 / n));
    (0..c.len())
        .map(|k| {
            let (p, q) = (c[k], c[(k + 1) % c.len()]);
            let twice_area = (q.0 - p.0) * (mid.1 - p.1) - (q.1 - p.1) * (mid.0 - p.0);
            let longest = [(p, q), (q, mid), (mid, p)]
                .iter()
                .map(|(x, y)| (y.0 - x.0).hypot(y.1 - x.1))
                .fold(0.0, f64::max);
            twice_area / longest
        })
        .fold(f64::INFINITY, f64::min)
}

/// Discrete layout of the ogive mesh: everything but the positions of the nose's interior
/// corners.
struct OgiveLayout {
    /// Shank radius a.
    a: f64,
    /// Ogive radius s.
    s: f64,
    /// Nose length L_n.
    nose_len: f64,
    /// Arc angle of the nose, from the junction (φ = 0) to the tip: cos φ_tip = (s − a)/s.
    phi_tip: f64,
    /// z of the nose–shank junction.
    z_j: f64,
    /// Column radii, shared by the junction line and every shank row: r[0] = 0, r[nr] = a.
    cols: Vec<f64>,
    /// Element size asked for.
    h: f64,
    /// Divisions of the nose's axis and of its arc, at least 2: evenly spaced but for the one at
    /// the tip, `tip_divisions` times as long.
    n_nose: usize,
    /// Length of the tip's division in the others': 1/sin θ for a tip of half-angle θ, within
    /// [1, 2], so the tip's kite is wide enough for a fair altitude.
    tip_divisions: f64,
    /// Shank row heights from the junction to the tail face; the hole's rows count from it.
    shank_z: Vec<f64>,
    hole: Option<Hole>,
    /// Meshed cavity (radius, length).
    cavity: Option<(f64, f64)>,
}

fn ogive_layout(
    diameter: f64,
    length: f64,
    crh: f64,
    h: f64,
    cavity: Option<&CavitySpec>,
    nose_z: f64,
) -> Result<OgiveLayout, MeshError> {
    positive("diameter", diameter)?;
    positive("length", length)?;
    positive("element_size", h)?;
    finite("nose_z", nose_z)?;
    if !(crh.is_finite() && crh >= 0.5) {
        return Err(MeshError(format!(
            "projectile crh must be at least 0.5 (a hemispherical nose), got {crh}"
        )));
    }
    let a = 0.5 * diameter;
    let s = crh * diameter;
    let nose_len = (s * s - (s - a) * (s - a)).sqrt();
    if length <= nose_len {
        return Err(MeshError(format!(
            "projectile length {length} m leaves no shank behind the {nose_len:.6} m nose of \
             crh {crh}; make the projectile longer or the crh smaller"
        )));
    }
    let phi_tip = ((s - a) / s).acos();
    let z_j = nose_z + nose_len;
    let z_tail = nose_z + length;
    let nr = divisions(a, h).max(2);
    let arc = s * phi_tip;
    // The tip's half-angle is φ_tip, the arc's turn from the junction.
    let tip_divisions = (1.7 / phi_tip.sin()).clamp(1.0, 3.0);
    let n_nose = ((arc / h - tip_divisions + 1.0).round() as usize).max(2);

    let mut cols = vec![0.0];
    let mut shank_z = vec![z_j];
    let mut hole = None;
    let mut meshed_cavity = None;
    match cavity {
        None => {
            push_spaced(&mut cols, 0.0, a, nr);
            push_spaced(&mut shank_z, z_j, z_tail, divisions(z_tail - z_j, h));
        }
        Some(c) => {
            positive("cavity diameter", c.diameter)?;
            positive("cavity length", c.length)?;
            positive("cavity rear_wall", c.rear_wall)?;
            if !(c.filler_density.is_finite() && c.filler_density >= 0.0) {
                return Err(MeshError(format!(
                    "projectile cavity filler_density must be zero or positive, got {}",
                    c.filler_density
                )));
            }
            let rc = 0.5 * c.diameter;
            // The cavity wall takes the column nearest to it; the columns on each side of it are
            // spaced evenly, so the wall lies exactly at rc.
            let ic = (rc / (a / nr as f64)).round() as usize;
            if ic == 0 {
                return Err(MeshError(format!(
                    "projectile cavity diameter {} m is below one element ({h} m); make \
                     element_size smaller",
                    c.diameter
                )));
            }
            if ic >= nr {
                return Err(MeshError(format!(
                    "projectile cavity diameter {} m leaves a side wall of {:.6} m, thinner than \
                     one element ({h} m); make element_size smaller or the cavity narrower",
                    c.diameter,
                    a - rc
                )));
            }
            push_spaced(&mut cols, 0.0, rc, ic);
            push_spaced(&mut cols, rc, a, nr - ic);

            let z_c1 = z_tail - c.rear_wall;
            let z_c0 = z_c1 - c.length;
            let wall = |name: &str, thickness: f64| -> Result<usize, MeshError> {
                let n = (thickness / h).round();
                if n >= 1.0 {
                    Ok(n as usize)
                } else {
                    Err(MeshError(format!(
                        "projectile cavity {name} wall is {thickness:.6} m thick, less than \
                         half an element ({h} m); make element_size smaller or move the cavity"
                    )))
                }
            };
            let n_front = wall("front (toward the nose junction)", z_c0 - z_j)?;
            let n_rear = wall("rear", c.rear_wall)?;
            let n_cav = divisions(c.length, h);
            push_spaced(&mut shank_z, z_j, z_c0, n_front);
            push_spaced(&mut shank_z, z_c0, z_c1, n_cav);
            push_spaced(&mut shank_z, z_c1, z_tail, n_rear);
            hole = Some(Hole {
                first_row: n_front,
                end_row: n_front + n_cav,
                cols: ic,
            });
            meshed_cavity = Some((rc, z_c1 - z_c0));
        }
    }
    Ok(OgiveLayout {
        a,
        s,
        nose_len,
        phi_tip,
        z_j,
        cols,
        h,
        n_nose,
        tip_divisions,
        shank_z,
        hole,
        cavity: meshed_cavity,
    })
}

impl OgiveLayout {
    /// Point of the nose arc at angle φ from the junction: r = s cos φ − (s − a) = R(x) with
    /// x = L_n − s sin φ the distance from the tip; the arc length from S is s·φ.
    fn arc(&self, phi: f64) -> (f64, f64) {
        (
            self.s * phi.cos() - (self.s - self.a),
            self.z_j - self.s * phi.sin(),
        )
    }

    /// The cells, from the tip to the tail face, with the nose's interior corners where lines
    /// place them (`CellMesh::smooth` moves them).
    ///
    /// Nose line j (0 < j < n) runs straight from the axis at z_j − L_n·j/n to the arc at
    /// φ_tip·j/n, so the axis and the arc are split evenly; line 0 is the junction row of the
    /// shank. A line takes as many edges as its length holds elements, never more than the line
    /// behind it nor fewer than half (each cell of a layer spans one or two edges of the line
    /// behind), and line n − 1 takes two, the kite at the tip closing it.
    fn cells(&self) -> CellMesh {
        let n = self.n_nose;
        let nr = self.cols.len() - 1;
        let t = |j: usize| j as f64 / (n as f64 - 1.0 + self.tip_divisions);
        let axis = |j: usize| (0.0, self.z_j - self.nose_len * t(j));
        let on_arc = |j: usize| self.arc(self.phi_tip * t(j));
        let mut edges = vec![nr; n];
        for j in 1..n {
            let (p, q) = (axis(j), on_arc(j));
            let fits = ((q.0 - p.0).hypot(q.1 - p.1) / self.h).round() as usize;
            // At most 2^(n − j) edges, so the lines can halve down to two at line n − 1.
            let cap = 1usize.checked_shl((n - j) as u32).unwrap_or(usize::MAX);
            edges[j] = if j == n - 1 {
                2
            } else {
                fits.max(1)
                    .max(edges[j - 1].div_ceil(2))
                    .min(edges[j - 1])
                    .min(cap)
            };
        }

        let mut mesh = CellMesh::default();
        let tip = mesh.corner((0.0, self.z_j - self.nose_len), false);
        let mut lines: Vec<Vec<u32>> = vec![Vec::new(); n];
        for j in (1..n).rev() {
            let (p, q) = (axis(j), on_arc(j));
            let m = edges[j];
            lines[j] = (0..=m)
                .map(|k| {
                    let point = match k {
                        0 => p,
                        _ if k == m => q,
                        _ => {
                            let f = k as f64 / m as f64;
                            (p.0 + f * (q.0 - p.0), p.1 + f * (q.1 - p.1))
                        }
                    };
                    mesh.corner(point, k != 0 && k != m)
                })
                .collect();
        }
        lines[0] = self
            .cols
            .iter()
            .map(|&r| mesh.corner((r, self.z_j), false))
            .collect();

        let last = &lines[n - 1];
        mesh.cells.push(vec![tip, last[2], last[1], last[0]]);
        for j in (0..n - 1).rev() {
            let (lower, upper) = (&lines[j + 1], &lines[j]);
            let (cl, cu) = (edges[j + 1], edges[j]);
            // Each edge k of the line with fewer meets edges s(k)..s(k + 1) of the other: one,
            // or two in a pentagon.
            let (few, many) = (cl.min(cu), cl.max(cu));
            let s = |k: usize| (2 * k * many + few) / (2 * few);
            for k in 0..few {
                let cell = if cl <= cu {
                    let mut cell = vec![lower[k], lower[k + 1]];
                    cell.extend((s(k)..=s(k + 1)).rev().map(|u| upper[u]));
                    cell
                } else {
                    let mut cell: Vec<u32> = (s(k)..=s(k + 1)).map(|l| lower[l]).collect();
                    cell.extend([upper[k + 1], upper[k]]);
                    cell
                };
                mesh.cells.push(cell);
            }
        }

        let rows: Vec<Vec<(f64, f64)>> = self
            .shank_z
            .iter()
            .map(|&z| self.cols.iter().map(|&r| (r, z)).collect())
            .collect();
        mesh.push_block(&rows, self.hole, &lines[0]);
        mesh
    }
}

/// Builds nodes (the corners, then a centre per cell at the mean of its corners),
/// crossed-triangle elements (one per cell edge), lumped masses and master segments, and lumps
/// `filler_mass` on the walls of the hole.
fn assemble(mesh: &CellMesh, density: f64, filler_mass: f64) -> Result<ProjectileMesh, MeshError> {
    let (n_nodes, n_elements) = mesh.counts();
    let mut pos: Vec<(f64, f64)> = Vec::with_capacity(n_nodes);
    pos.extend_from_slice(&mesh.corners);
    let mut elements = Vec::with_capacity(n_elements);
    for cell in &mesh.cells {
        let n = cell.len() as f64;
        let mid = pos.len() as u32;
        pos.push(cell.iter().fold((0.0, 0.0), |acc, &k| {
            let p = mesh.corners[k as usize];
            (acc.0 + p.0 / n, acc.1 + p.1 / n)
        }));
        for k in 0..cell.len() {
            elements.push([cell[k], cell[(k + 1) % cell.len()], mid]);
        }
    }

    // Lumped ring masses: ρ₀V₀/3 per node and element, V₀ = 2π r̄ A (physics.md §2).
    let mut mass = vec![0.0f64; pos.len()];
    let mut steel = 0.0;
    for (e, el) in elements.iter().enumerate() {
        let twice_area = twice_area(&pos, el);
        if twice_area <= 0.0 {
            return Err(MeshError(format!(
                "projectile mesh folded: element {e} has area {:e} m²; make element_size smaller",
                0.5 * twice_area
            )));
        }
        let r_mean = el.iter().map(|&n| pos[n as usize].0).sum::<f64>() / 3.0;
        let m = density * PI * r_mean * twice_area;
        steel += m;
        for &n in el {
            mass[n as usize] += m / 3.0;
        }
    }

    let (outer, walls) = boundary_chains(&pos, &elements)?;
    if filler_mass > 0.0 {
        // Filler lumped on the cavity-wall nodes by the ring area each represents: half of
        // 2π r̄ |AB| from each wall edge it ends.
        let mut share = vec![0.0f64; pos.len()];
        for seg in &walls {
            let (pa, pb) = (pos[seg.a as usize], pos[seg.b as usize]);
            let ring = PI * (pa.0 + pb.0) * (pb.0 - pa.0).hypot(pb.1 - pa.1);
            share[seg.a as usize] += 0.5 * ring;
            share[seg.b as usize] += 0.5 * ring;
        }
        let total: f64 = share.iter().sum();
        if total <= 0.0 {
            return Err(MeshError(
                "projectile cavity has no wall to carry its filler mass".into(),
            ));
        }
        for (m, s) in mass.iter_mut().zip(&share) {
            *m += filler_mass * s / total;
        }
    }

    Ok(ProjectileMesh {
        node_r: pos.iter().map(|p| p.0 as f32).collect(),
        node_z: pos.iter().map(|p| p.1 as f32).collect(),
        node_mass: mass.iter().map(|&m| m as f32).collect(),
        elements,
        masters: outer,
        total_mass: steel + filler_mass,
        filler_mass,
    })
}

/// 2A = Σ r_i b_i, b_i = z_j − z_m (cyclic).
fn twice_area(pos: &[(f64, f64)], el: &[u32; 3]) -> f64 {
    (0..3)
        .map(|k| {
            let r = pos[el[k] as usize].0;
            let zj = pos[el[(k + 1) % 3] as usize].1;
            let zm = pos[el[(k + 2) % 3] as usize].1;
            r * (zj - zm)
        })
        .sum()
}

/// Boundary edges (used by exactly one triangle) off the axis, split into the outer outline,
/// walked from the nose tip (or the impact face at the axis) to the tail centre, and the rest
/// (cavity walls). Each edge keeps its element's counter-clockwise order, so the material is on
/// its left.
fn boundary_chains(
    pos: &[(f64, f64)],
    elements: &[[u32; 3]],
) -> Result<(Vec<MasterSegment>, Vec<MasterSegment>), MeshError> {
    let mut uses: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * elements.len());
    for el in elements {
        for k in 0..3 {
            let (a, b) = (el[k], el[(k + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut edges = Vec::new();
    for (e, el) in elements.iter().enumerate() {
        for k in 0..3 {
            let (a, b, c) = (el[k], el[(k + 1) % 3], el[(k + 2) % 3]);
            let on_axis = pos[a as usize].0 == 0.0 && pos[b as usize].0 == 0.0;
            if uses[&(a.min(b), a.max(b))] == 1 && !on_axis {
                edges.push(MasterSegment {
                    element: e as u32,
                    a,
                    b,
                    c,
                });
            }
        }
    }
    let mut from: HashMap<u32, usize> = HashMap::with_capacity(edges.len());
    for (k, seg) in edges.iter().enumerate() {
        if from.insert(seg.a, k).is_some() {
            return Err(MeshError(format!(
                "projectile mesh boundary is not manifold at node {}",
                seg.a
            )));
        }
    }
    let ends: std::collections::HashSet<u32> = edges.iter().map(|s| s.b).collect();
    // Open chains start where no edge ends (at the axis); whatever is left forms closed loops.
    let mut starts: Vec<usize> = (0..edges.len())
        .filter(|&k| !ends.contains(&edges[k].a))
        .collect();
    starts.extend(0..edges.len());
    let mut visited = vec![false; edges.len()];
    let mut chains: Vec<Vec<usize>> = Vec::new();
    for start in starts {
        let mut chain = Vec::new();
        let mut k = start;
        while !visited[k] {
            visited[k] = true;
            chain.push(k);
            match from.get(&edges[k].b) {
                Some(&next) => k = next,
                None => break,
            }
        }
        if !chain.is_empty() {
            chains.push(chain);
        }
    }
    // The outline is the chain through the outermost node.
    let r_max = pos.iter().map(|p| p.0).fold(0.0, f64::max);
    let outer = chains
        .iter()
        .position(|ch| {
            ch.iter().any(|&k| {
                pos[edges[k].a as usize].0 == r_max || pos[edges[k].b as usize].0 == r_max
            })
        })
        .ok_or_else(|| MeshError("projectile mesh has no outer boundary".into()))?;
    let mut masters = Vec::new();
    let mut walls = Vec::new();
    for (n, chain) in chains.iter().enumerate() {
        let dest = if n == outer { &mut masters } else { &mut walls };
        dest.extend(chain.iter().map(|&k| edges[k]));
    }
    Ok((masters, walls))
}

#[cfg(test)]
mod tests;
