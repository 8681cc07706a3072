//! Projectile meshers: a tangent-ogive penetrator (optionally with a filled cavity) and a
//! flat-ended cylinder (Taylor bar), as linear axisymmetric triangles (physics.md §2).
//!
//! Both meshes are one structured block of quads. Rows run from the lowest outline (the nose
//! curve, or the impact face of a cylinder) to the tail face; columns run from the axis
//! (column 0, r = 0.0 exactly) to the outer surface. Every quad gets a centre node and is split
//! into four triangles, one per quad edge: the crossed-triangle pattern that keeps constant-strain
//! triangles from locking volumetrically in plastic flow (physics.md §2).
//!
//! The ogive nose is a transfinite (Coons) patch on the curved triangle axis / junction line /
//! ogive arc: the arc is split at a point M into two sides of the patch, so no cell collapses at
//! the tip and the spacing along the arc equals the element size. M is a straight (180°) corner
//! of the patch, which squashes the cells near it; Winslow smoothing and a local max-min
//! optimisation of the smallest altitude (which sets the stable time step) repair them.
//!
//! Longer than most files (about 820 lines) because the two layouts, the smoothing and the
//! assembly into triangles and master segments share one block structure; its tests live in
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
        .map(|l| l.topology().counts())
        .unwrap_or((0, 0)),
        ProjectileShape::Cylinder => {
            cylinder_layout(spec.diameter, spec.length, spec.element_size, spec.nose_z)
                .map(|(cols, rows)| {
                    Topology {
                        cells_z: rows.len() - 1,
                        cells_r: cols.len() - 1,
                        hole: None,
                    }
                    .counts()
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
    let rows = layout.corner_rows();
    let filler = match (cavity, layout.cavity) {
        (Some(spec), Some((rc, len))) => spec.filler_density * PI * rc * rc * len,
        _ => 0.0,
    };
    assemble(&rows, layout.topology(), density, filler)
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
    let topology = Topology {
        cells_z: rows_z.len() - 1,
        cells_r: cols.len() - 1,
        hole: None,
    };
    assemble(&rows, topology, density, 0.0)
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

/// A structured block of `cells_z × cells_r` quads, less an optional hole on the axis.
#[derive(Clone, Copy, Debug)]
struct Topology {
    cells_z: usize,
    cells_r: usize,
    hole: Option<Hole>,
}

impl Topology {
    fn cell_active(&self, g: usize, i: usize) -> bool {
        if g >= self.cells_z || i >= self.cells_r {
            return false;
        }
        match self.hole {
            Some(h) => !(g >= h.first_row && g < h.end_row && i < h.cols),
            None => true,
        }
    }

    /// A corner node exists when one of its (up to four) cells does.
    fn corner_used(&self, g: usize, i: usize) -> bool {
        let below = g.checked_sub(1);
        let left = i.checked_sub(1);
        let cell = |gg: Option<usize>, ii: Option<usize>| match (gg, ii) {
            (Some(gg), Some(ii)) => self.cell_active(gg, ii),
            _ => false,
        };
        cell(Some(g), Some(i)) || cell(Some(g), left) || cell(below, Some(i)) || cell(below, left)
    }

    /// (nodes, elements).
    fn counts(&self) -> (usize, usize) {
        let mut nodes = 0;
        let mut cells = 0;
        for g in 0..=self.cells_z {
            for i in 0..=self.cells_r {
                nodes += usize::from(self.corner_used(g, i));
                cells += usize::from(self.cell_active(g, i));
            }
        }
        (nodes + cells, 4 * cells)
    }
}

/// Discrete layout of the ogive mesh: everything but the node positions of the nose patch.
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
    /// Divisions of the axis and of the arc S→M.
    n_v: usize,
    /// Shank row heights from the junction to the tail face.
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
    let n_v = (((arc / h).round() as usize).saturating_sub(nr)).max(1);

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
                first_row: n_v + n_front,
                end_row: n_v + n_front + n_cav,
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
        n_v,
        shank_z,
        hole,
        cavity: meshed_cavity,
    })
}

impl OgiveLayout {
    fn topology(&self) -> Topology {
        Topology {
            cells_z: self.n_v + self.shank_z.len() - 1,
            cells_r: self.cols.len() - 1,
            hole: self.hole,
        }
    }

    /// Point of the nose arc at angle φ from the junction: r = s cos φ − (s − a) = R(x) with
    /// x = L_n − s sin φ the distance from the tip; the arc length from S is s·φ.
    fn arc(&self, phi: f64) -> (f64, f64) {
        (
            self.s * phi.cos() - (self.s - self.a),
            self.z_j - self.s * phi.sin(),
        )
    }

    /// Corner positions, row by row from the tip (row 0: the arc T→M) through the junction
    /// (row n_v) to the tail face, each row from the axis outward.
    fn corner_rows(&self) -> Vec<Vec<(f64, f64)>> {
        let nr = self.cols.len() - 1;
        let n_v = self.n_v;
        let phi_m = self.phi_tip * n_v as f64 / (n_v + nr) as f64;
        let o = (0.0, self.z_j);
        let sp = (self.a, self.z_j);
        let t = (0.0, self.z_j - self.nose_len);
        let m = self.arc(phi_m);
        // Sides of the patch, v = 0 at the junction and v = 1 at the arc T→M.
        let bottom = |i: usize| (self.cols[i], self.z_j);
        let top = |i: usize| {
            if i == 0 {
                t
            } else {
                self.arc(self.phi_tip - (self.phi_tip - phi_m) * i as f64 / nr as f64)
            }
        };
        let left = |v: f64| (0.0, self.z_j - self.nose_len * v);
        let right = |v: f64| self.arc(phi_m * v);

        let mut rows: Vec<Vec<(f64, f64)>> = Vec::with_capacity(n_v + self.shank_z.len());
        for g in 0..n_v {
            let v = (n_v - g) as f64 / n_v as f64;
            let row = (0..=nr)
                .map(|i| {
                    if g == 0 {
                        return top(i);
                    }
                    if i == 0 {
                        return left(v);
                    }
                    if i == nr {
                        return right(v);
                    }
                    // Patch parameter u blends the arc-length fractions of the bottom and top
                    // sides, so the interior follows the (graded) junction columns near the shank.
                    let ub = self.cols[i] / self.a;
                    let ut = i as f64 / nr as f64;
                    let u = ub + v * (ut - ub);
                    let (b, tp, l, rr) = (bottom(i), top(i), left(v), right(v));
                    let coons = |k: fn((f64, f64)) -> f64| {
                        (1.0 - v) * k(b) + v * k(tp) + (1.0 - u) * k(l) + u * k(rr)
                            - ((1.0 - u) * (1.0 - v) * k(o)
                                + u * (1.0 - v) * k(sp)
                                + (1.0 - u) * v * k(t)
                                + u * v * k(m))
                    };
                    (coons(|p| p.0), coons(|p| p.1))
                })
                .collect();
            rows.push(row);
        }
        for &z in &self.shank_z {
            rows.push(self.cols.iter().map(|&r| (r, z)).collect());
        }
        smooth_interior(&mut rows[..=n_v]);
        raise_min_altitude(&mut rows[..=n_v]);
        rows
    }
}

/// Smooths the interior corners of a structured patch whose boundary rows and columns stay
/// fixed, by Winslow's elliptic grid equations α x_ξξ − 2β x_ξη + γ x_ηη = 0 (Winslow 1966;
/// Thompson, Warsi & Mastin, "Numerical Grid Generation", 1985, ch. 6).
///
/// The nose patch has a straight (180°) corner at M, where transfinite interpolation (and a
/// plain Laplace smoother) squashes the cells along the arc; Winslow's equations keep the grid
/// lines there apart. Gauss–Seidel sweeps in a fixed order, starting from the Coons positions.
fn smooth_interior(rows: &mut [Vec<(f64, f64)>]) {
    let (n_g, n_i) = (rows.len(), rows[0].len());
    if n_g < 3 || n_i < 3 {
        return;
    }
    let scale = rows
        .iter()
        .flatten()
        .map(|p| p.0.abs().max(p.1.abs()))
        .fold(0.0, f64::max);
    for _ in 0..20_000 {
        let mut largest_move: f64 = 0.0;
        for g in 1..n_g - 1 {
            for i in 1..n_i - 1 {
                let (up, down) = (rows[g + 1][i], rows[g - 1][i]);
                let (left, right) = (rows[g][i - 1], rows[g][i + 1]);
                let (ul, ur) = (rows[g + 1][i - 1], rows[g + 1][i + 1]);
                let (dl, dr) = (rows[g - 1][i - 1], rows[g - 1][i + 1]);
                let xi = (0.5 * (right.0 - left.0), 0.5 * (right.1 - left.1));
                let eta = (0.5 * (up.0 - down.0), 0.5 * (up.1 - down.1));
                let alpha = eta.0 * eta.0 + eta.1 * eta.1;
                let beta = xi.0 * eta.0 + xi.1 * eta.1;
                let gamma = xi.0 * xi.0 + xi.1 * xi.1;
                let cross = |k: fn((f64, f64)) -> f64| 0.25 * (k(ur) - k(ul) - k(dr) + k(dl));
                let solve = |k: fn((f64, f64)) -> f64| {
                    (alpha * (k(right) + k(left)) + gamma * (k(up) + k(down))
                        - 2.0 * beta * cross(k))
                        / (2.0 * (alpha + gamma))
                };
                let target = (solve(|p| p.0), solve(|p| p.1));
                let p = &mut rows[g][i];
                largest_move = largest_move.max((target.0 - p.0).abs().max((target.1 - p.1).abs()));
                *p = target;
            }
        }
        if largest_move <= 1e-13 * scale {
            break;
        }
    }
}

/// Smallest altitude (2A over the longest side) of the four crossed triangles of the quad
/// `c` (counter-clockwise); negative when one is inverted.
fn crossed_min_altitude(c: [(f64, f64); 4]) -> f64 {
    let mid = (
        0.25 * (c[0].0 + c[1].0 + c[2].0 + c[3].0),
        0.25 * (c[0].1 + c[1].1 + c[2].1 + c[3].1),
    );
    (0..4)
        .map(|k| {
            let (p, q) = (c[k], c[(k + 1) % 4]);
            let twice_area = (q.0 - p.0) * (mid.1 - p.1) - (q.1 - p.1) * (mid.0 - p.0);
            let longest = [(p, q), (q, mid), (mid, p)]
                .iter()
                .map(|(x, y)| (y.0 - x.0).hypot(y.1 - x.1))
                .fold(0.0, f64::max);
            twice_area / longest
        })
        .fold(f64::INFINITY, f64::min)
}

/// Moves interior corners of a structured patch (boundary fixed) to raise the smallest
/// altitude of the crossed triangles around them: local max-min optimisation by compass
/// search (Freitag & Ollivier-Gooch 1997), in a fixed order, a few sweeps.
///
/// The nose patch has a straight (180°) corner at M: its cell is a triangle with M on one
/// side, and the Winslow grid leaves that cell's inner corner close to M, so its triangles'
/// altitudes — and the time step — fall to about h/10. The smallest altitude sets the stable
/// step of the whole projectile (physics.md §2), so it is worth raising.
fn raise_min_altitude(rows: &mut [Vec<(f64, f64)>]) {
    let (n_g, n_i) = (rows.len(), rows[0].len());
    if n_g < 3 || n_i < 3 {
        return;
    }
    let cell = |rows: &[Vec<(f64, f64)>], g: usize, i: usize| {
        crossed_min_altitude([
            rows[g][i],
            rows[g][i + 1],
            rows[g + 1][i + 1],
            rows[g + 1][i],
        ])
    };
    let around = |rows: &[Vec<(f64, f64)>], g: usize, i: usize| {
        cell(rows, g - 1, i - 1)
            .min(cell(rows, g - 1, i))
            .min(cell(rows, g, i - 1))
            .min(cell(rows, g, i))
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
        for g in 1..n_g - 1 {
            for i in 1..n_i - 1 {
                let p0 = rows[g][i];
                let size = (rows[g][i + 1].0 - p0.0).hypot(rows[g][i + 1].1 - p0.1);
                let mut best = around(rows, g, i);
                // Cells near the shape of a square keep their Winslow corners (a square cell's
                // crossed triangles have altitude size/2).
                if best > 0.35 * size {
                    continue;
                }
                let mut step = 0.2 * size;
                while step > 1e-3 * size {
                    let base = rows[g][i];
                    let mut improved = false;
                    for d in DIRECTIONS {
                        rows[g][i] = (base.0 + step * d.0, base.1 + step * d.1);
                        let q = around(rows, g, i);
                        if q > best * (1.0 + 1e-9) {
                            best = q;
                            improved = true;
                            break;
                        }
                        rows[g][i] = base;
                    }
                    if improved {
                        moved = true;
                    } else {
                        step *= 0.5;
                    }
                }
            }
        }
        if !moved {
            break;
        }
    }
}

/// Builds nodes, crossed-triangle elements, lumped masses and master segments from corner
/// positions `rows[g][i]` (column 0 on the axis) and lumps `filler_mass` on the walls of the
/// hole.
fn assemble(
    rows: &[Vec<(f64, f64)>],
    topo: Topology,
    density: f64,
    filler_mass: f64,
) -> Result<ProjectileMesh, MeshError> {
    let (n_nodes, n_elements) = topo.counts();
    let mut pos: Vec<(f64, f64)> = Vec::with_capacity(n_nodes);
    let width = topo.cells_r + 1;
    let mut corner = vec![u32::MAX; (topo.cells_z + 1) * width];
    let mut centre = vec![u32::MAX; topo.cells_z * topo.cells_r];
    // Row by row: the corners of a row, then the centres of the cells above it.
    for g in 0..=topo.cells_z {
        for i in 0..=topo.cells_r {
            if topo.corner_used(g, i) {
                corner[g * width + i] = pos.len() as u32;
                pos.push(rows[g][i]);
            }
        }
        for i in 0..topo.cells_r {
            if topo.cell_active(g, i) {
                centre[g * topo.cells_r + i] = pos.len() as u32;
                let p = [
                    rows[g][i],
                    rows[g][i + 1],
                    rows[g + 1][i + 1],
                    rows[g + 1][i],
                ];
                pos.push((
                    0.25 * p.iter().map(|q| q.0).sum::<f64>(),
                    0.25 * p.iter().map(|q| q.1).sum::<f64>(),
                ));
            }
        }
    }
    let mut elements = Vec::with_capacity(n_elements);
    for g in 0..topo.cells_z {
        for i in 0..topo.cells_r {
            if !topo.cell_active(g, i) {
                continue;
            }
            let c = [
                corner[g * width + i],
                corner[g * width + i + 1],
                corner[(g + 1) * width + i + 1],
                corner[(g + 1) * width + i],
            ];
            let mid = centre[g * topo.cells_r + i];
            for k in 0..4 {
                elements.push([c[k], c[(k + 1) % 4], mid]);
            }
        }
    }
    debug_assert_eq!((pos.len(), elements.len()), (n_nodes, n_elements));

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
