//! SPH target lattice (physics.md §3): a square lattice of spacing Δ filling the concrete
//! cylinder r ∈ [0, R], z ∈ [−T, 0]. Particles sit at cell centres, so the first column is at
//! r = Δ/2 and no particle lies on the axis (the axis is handled by mirror ghosts).

use std::f64::consts::PI;

use super::{MeshError, TargetLattice};

/// (columns, rows) of the lattice `lattice` would build: round(radius/Δ), round(thickness/Δ).
/// Allocates nothing, so memory can be estimated up front; non-finite or non-positive input
/// gives 0 (or saturates) and `lattice` rejects it.
pub fn lattice_count(radius: f64, thickness: f64, spacing: f64) -> (usize, usize) {
    (
        (radius / spacing).round() as usize,
        (thickness / spacing).round() as usize,
    )
}

/// Target particles at r = (i + ½)Δ, z = −(k + ½)Δ, with ring mass ρ₀ · 2π r Δ² (physics.md §3).
/// `rear` marks the last row, `lateral` the last column. They are stored along the Z-order curve
/// of (i, k) ([`z_order`]), and keep that order through a run: particles near in index are near
/// in space, so a GPU warp's neighbours lie in about half the cache lines they span when stored
/// row by row (docs/performance.md, "The neighbour lists: skin and particle order").
pub fn lattice(
    radius: f64,
    thickness: f64,
    spacing: f64,
    density: f64,
) -> Result<TargetLattice, MeshError> {
    for (name, value) in [
        ("radius", radius),
        ("thickness", thickness),
        ("spacing", spacing),
        ("density", density),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(MeshError(format!(
                "target {name} must be a positive finite number, got {value}"
            )));
        }
    }
    let (cols, rows) = lattice_count(radius, thickness, spacing);
    if cols < 2 || rows < 2 {
        return Err(MeshError(format!(
            "target lattice of {cols} columns × {rows} rows is too small: radius and \
             thickness must each hold at least 2 particle spacings; make spacing smaller"
        )));
    }
    // The sites are numbered row by row (k · cols + i) in u32; `check` refuses such a lattice
    // long before this for its memory.
    let count = cols
        .checked_mul(rows)
        .and_then(|n| u32::try_from(n).ok())
        .ok_or_else(|| {
            MeshError(format!(
                "target lattice of {cols} columns × {rows} rows has more than {} particles: \
                 make spacing larger",
                u32::MAX
            ))
        })?;
    let n = count as usize;
    let mut t = TargetLattice {
        r: Vec::with_capacity(n),
        z: Vec::with_capacity(n),
        mass: Vec::with_capacity(n),
        rear: Vec::with_capacity(n),
        lateral: Vec::with_capacity(n),
        site: Vec::with_capacity(n),
    };
    let mut sites: Vec<u32> = (0..count).collect();
    sites.sort_unstable_by_key(|&s| z_order(s as usize % cols, s as usize / cols));
    for site in sites {
        let (k, i) = (site as usize / cols, site as usize % cols);
        let r = (i as f64 + 0.5) * spacing;
        t.r.push(r as f32);
        t.z.push((-(k as f64 + 0.5) * spacing) as f32);
        t.mass
            .push((density * 2.0 * PI * r * spacing * spacing) as f32);
        t.rear.push(k + 1 == rows);
        t.lateral.push(i + 1 == cols);
        t.site.push(site);
    }
    Ok(t)
}

/// The position of lattice site (column i, row k) along the Z-order (Morton) curve: the bits of
/// i and k interleaved, i's in the even places. Every aligned block of 2ᵐ × 2ᵐ sites is a run of
/// consecutive keys.
fn z_order(i: usize, k: usize) -> u64 {
    /// Spreads the low 32 bits of x into the even bit places.
    fn spread(x: usize) -> u64 {
        let mut x = x as u64 & 0xffff_ffff;
        x = (x | (x << 16)) & 0x0000_ffff_0000_ffff;
        x = (x | (x << 8)) & 0x00ff_00ff_00ff_00ff;
        x = (x | (x << 4)) & 0x0f0f_0f0f_0f0f_0f0f;
        x = (x | (x << 2)) & 0x3333_3333_3333_3333;
        (x | (x << 1)) & 0x5555_5555_5555_5555
    }
    spread(i) | (spread(k) << 1)
}

/// The lattice column (r = (i + ½)Δ) nearest to radius `r`, and how far outside `r` it lies
/// (negative: inside). `penetrate check` reports it for the projectile's shank: a column that
/// grazes the shank is met by the contact or not as round-off decides (docs/limitations.md,
/// "Round-off and single runs").
pub fn nearest_column(r: f64, spacing: f64) -> (f64, f64) {
    let i = (r / spacing - 0.5).round().max(0.0);
    let column = (i + 0.5) * spacing;
    (column, column - r)
}

/// Whether a particle at (r, z) lies in a lead hole `depth` deep and `diameter` wide.
fn in_hole(r: f32, z: f32, depth: f64, diameter: f64) -> bool {
    f64::from(r) < 0.5 * diameter && f64::from(z) > -depth
}

/// How many particles [`drill`] leaves out of the [`lattice`] of these sizes, counted without
/// building it (`penetrate check`): the columns in the hole times the rows in it. Each is found
/// by bisection on the f32 centres, so a lattice far too fine to build is counted at once (its
/// memory estimate refuses it).
pub fn drilled_count(
    radius: f64,
    thickness: f64,
    spacing: f64,
    depth: f64,
    diameter: f64,
) -> usize {
    let (cols, rows) = lattice_count(radius, thickness, spacing);
    let centre = |i: usize| ((i as f64 + 0.5) * spacing) as f32;
    let in_cols = leading(cols, |i| in_hole(centre(i), 0.0, f64::INFINITY, diameter));
    let in_rows = leading(rows, |k| in_hole(0.0, -centre(k), depth, f64::INFINITY));
    in_cols.saturating_mul(in_rows)
}

/// The number of leading indices of 0..n for which `inside` holds, for a predicate true on a
/// prefix (the centres grow with the index, so a hole's columns and rows are a prefix).
fn leading(n: usize, inside: impl Fn(usize) -> bool) -> usize {
    let (mut lo, mut hi) = (0, n);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if inside(mid) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Drills a lead hole into the front face along the axis: leaves out every particle whose centre
/// lies at r < diameter/2 and z > −depth. `depth = 0` leaves the lattice as it is. Returns how
/// many particles were left out.
pub fn drill(t: &mut TargetLattice, depth: f64, diameter: f64) -> usize {
    let keep: Vec<bool> =
        t.r.iter()
            .zip(&t.z)
            .map(|(&r, &z)| !in_hole(r, z, depth, diameter))
            .collect();
    fn retain<T>(v: &mut Vec<T>, keep: &[bool]) {
        let mut k = keep.iter();
        v.retain(|_| *k.next().unwrap());
    }
    retain(&mut t.r, &keep);
    retain(&mut t.z, &keep);
    retain(&mut t.mass, &keep);
    retain(&mut t.rear, &keep);
    retain(&mut t.lateral, &keep);
    retain(&mut t.site, &keep);
    keep.iter().filter(|&&k| !k).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_positions_and_flags() {
        let d = 0.01;
        assert_eq!(lattice_count(0.1, 0.05, d), (10, 5));
        // round(): 0.104 / 0.01 → 10, 0.056 / 0.01 → 6.
        assert_eq!(lattice_count(0.104, 0.056, d), (10, 6));
        let t = lattice(0.1, 0.05, d, 2370.0).unwrap();
        assert_eq!(t.r.len(), 50);
        assert_eq!(t.mass.len(), 50);
        // Every site once, with its flags and mass.
        let mut seen = [false; 50];
        for p in 0..50 {
            let i = (t.r[p] as f64 / d - 0.5).round() as usize;
            let k = (-t.z[p] as f64 / d - 0.5).round() as usize;
            assert_eq!(
                (t.r[p], t.z[p]),
                (
                    ((i as f64 + 0.5) * d) as f32,
                    (-(k as f64 + 0.5) * d) as f32
                )
            );
            assert!(
                !std::mem::replace(&mut seen[k * 10 + i], true),
                "site {i}, {k} twice"
            );
            assert_eq!(t.rear[p], k == 4, "rear flag of {p}");
            assert_eq!(t.lateral[p], i == 9, "lateral flag of {p}");
            assert_eq!(t.site[p] as usize, k * 10 + i, "site of {p}");
            let m = 2370.0 * 2.0 * PI * (i as f64 + 0.5) * d * d * d;
            assert!(((t.mass[p] as f64 - m) / m).abs() < 1e-6);
        }
        assert!(t.r.iter().all(|&r| r > 0.0));
    }

    /// Stored along the Z-order curve: the corner's 2 × 2 block first, in the order (0, 0),
    /// (1, 0), (0, 1), (1, 1), then the next block along the row; and every aligned 4 × 4 block
    /// of a lattice is a run of 16 consecutive particles.
    #[test]
    fn particles_near_in_index_are_near_in_space() {
        let d = 0.01;
        let t = lattice(0.16, 0.08, d, 2370.0).unwrap();
        let site = |p: usize| {
            (
                (t.r[p] as f64 / d - 0.5).round() as usize,
                (-t.z[p] as f64 / d - 0.5).round() as usize,
            )
        };
        let first: Vec<_> = (0..6).map(site).collect();
        assert_eq!(first, [(0, 0), (1, 0), (0, 1), (1, 1), (2, 0), (3, 0)]);
        for block in 0..t.r.len() / 16 {
            let (i0, k0) = site(16 * block);
            assert_eq!(
                (i0 % 4, k0 % 4),
                (0, 0),
                "block {block} starts at {i0}, {k0}"
            );
            for p in 16 * block..16 * (block + 1) {
                let (i, k) = site(p);
                assert!(
                    (i0..i0 + 4).contains(&i) && (k0..k0 + 4).contains(&k),
                    "particle {p} at {i}, {k} off its block"
                );
            }
        }
    }

    #[test]
    fn total_mass_is_the_cylinder_mass() {
        let (radius, thickness, d, rho) = (0.75, 0.5, 0.0025, 2370.0);
        let t = lattice(radius, thickness, d, rho).unwrap();
        let (cols, rows) = lattice_count(radius, thickness, d);
        assert_eq!((cols, rows), (300, 200));
        assert_eq!(t.r.len(), cols * rows);
        let total: f64 = t.mass.iter().map(|&m| m as f64).sum();
        let exact = rho * PI * radius * radius * thickness;
        assert!(((total - exact) / exact).abs() < 0.01, "{total} vs {exact}");
    }

    #[test]
    fn drill_leaves_out_the_hole_only() {
        let d = 0.01;
        let mut t = lattice(0.1, 0.1, d, 2370.0).unwrap();
        let whole = t.clone();
        assert_eq!(drill(&mut t, 0.0, 0.05), 0);
        assert_eq!(t, whole);
        // Columns at r = 5, 15 mm (< 20 mm) in rows at z = −5 … −35 mm (> −40 mm): 2 × 4.
        assert_eq!(drilled_count(0.1, 0.1, d, 0.04, 0.04), 8);
        assert_eq!(drill(&mut t, 0.04, 0.04), 8);
        assert_eq!(t.r.len(), 100 - 8);
        for p in 0..t.r.len() {
            assert!(
                t.r[p] > 0.02 || t.z[p] < -0.04,
                "particle {p} left in the hole"
            );
            assert_eq!(t.mass[p], whole.mass[whole_index(&whole, t.r[p], t.z[p])]);
        }
        assert_eq!(t.rear.iter().filter(|&&f| f).count(), 10);
        assert_eq!(t.lateral.iter().filter(|&&f| f).count(), 10);
    }

    /// The count `check` reports is the count a run drills, at sizes whose hole edges fall on,
    /// between and next to particle centres (f32 centres).
    #[test]
    fn drilled_count_is_what_drill_leaves_out() {
        for &(spacing, depth, diameter) in &[
            (0.004, 0.1, 0.0269),
            (0.004, 0.2, 0.016),
            (0.003, 0.0015, 0.003),
            (0.008, 0.3, 0.0086),
            (0.006, 0.0, 0.05),
            (0.004, 0.7, 0.6),
        ] {
            let mut t = lattice(0.3, 0.76, spacing, 2370.0).unwrap();
            let counted = drilled_count(0.3, 0.76, spacing, depth, diameter);
            assert_eq!(
                drill(&mut t, depth, diameter),
                counted,
                "spacing {spacing}, depth {depth}, diameter {diameter}"
            );
        }
    }

    /// A spacing far too fine to build is counted at once, not column by column (a linear walk
    /// over its 10²⁸ columns hung `penetrate check`).
    #[test]
    fn drilled_count_of_an_absurd_lattice_is_immediate() {
        assert_eq!(drilled_count(0.04, 0.05, 1e-30, 0.0, 0.02), 0);
        assert_eq!(drilled_count(0.04, 0.05, 1e-30, 0.01, 0.02), usize::MAX);
        // 1e-9 m: 4e7 columns, 2e6 of them in the hole; 5e7 rows, 1e7 in it.
        assert_eq!(
            drilled_count(0.04, 0.05, 1e-9, 0.01, 0.004),
            2_000_000 * 10_000_000
        );
    }

    fn whole_index(t: &TargetLattice, r: f32, z: f32) -> usize {
        (0..t.r.len())
            .find(|&i| t.r[i] == r && t.z[i] == z)
            .unwrap()
    }

    #[test]
    fn nearest_column_to_the_shank() {
        let close = |(a, b): (f64, f64), (c, d): (f64, f64)| {
            assert!((a - c).abs() < 1e-12 && (b - d).abs() < 1e-12, "{a} {b}")
        };
        // The Forrestal shank (r = 13.45 mm): at Δ = 3 mm the column at 13.5 mm grazes it.
        close(nearest_column(0.01345, 0.003), (0.0135, 0.00005));
        close(nearest_column(0.01345, 0.0031), (0.01395, 0.0005));
        close(nearest_column(0.01345, 0.0029), (0.01305, -0.0004));
        close(nearest_column(0.01345, 0.004), (0.014, 0.00055));
        // Every column a lattice builds is one (i + ½)Δ, and none is nearer.
        let t = lattice(0.1, 0.02, 0.003, 2370.0).unwrap();
        let (col, gap) = nearest_column(0.01345, 0.003);
        let best =
            t.r.iter()
                .map(|&r| (r as f64 - 0.01345).abs())
                .fold(1.0, f64::min);
        assert!((best - gap.abs()).abs() < 1e-8 && t.r.contains(&(col as f32)));
        // A radius inside the first column gives the first column.
        close(nearest_column(0.0001, 0.003), (0.0015, 0.0014));
    }

    #[test]
    fn rejects_bad_input() {
        assert!(lattice(0.1, 0.05, 0.0, 2370.0).is_err());
        assert!(lattice(0.1, f64::INFINITY, 0.01, 2370.0).is_err());
        assert!(lattice(-0.1, 0.05, 0.01, 2370.0).is_err());
        assert!(lattice(0.1, 0.05, 0.01, f64::NAN).is_err());
        // One row only.
        assert!(lattice(0.1, 0.012, 0.01, 2370.0).is_err());
        assert!(lattice(0.014, 0.1, 0.01, 2370.0).is_err());
        assert_eq!(lattice_count(f64::NAN, 0.1, 0.01).0, 0);
        // More sites than u32 numbers (10⁵ × 10⁵), refused before anything is allocated.
        let e = lattice(1.0, 1.0, 1e-5, 2370.0).unwrap_err();
        assert!(e.0.contains("more than 4294967295 particles"), "{}", e.0);
    }
}
