//! The pictures `penetrate plot` makes of a run's outputs: its history against time (depth,
//! velocity, deceleration, contact force) from `history.csv`, and the final fields (damage
//! and pressure of the concrete and of the projectile, in the r–z plane) from the last frame
//! `frames.pvd` lists.

use std::path::{Path, PathBuf};

use super::plot::{Chart, FieldMap, Mark, Square};
use super::run_files;
use super::vtk::{self, Vtu};

/// The curves, from `history.csv`.
pub const CURVES: [&str; 4] = [
    "depth.png",
    "velocity.png",
    "deceleration.png",
    "contact-force.png",
];

/// The final fields, from the last frame.
pub const FIELDS: [&str; 2] = ["damage.png", "pressure.png"];

/// Standard gravity (m/s², 3rd CGPM 1901): decelerations are given in g, as a penetrator's
/// accelerometer records them.
const STANDARD_GRAVITY: f64 = 9.80665;

/// Why the pictures could not be made.
#[derive(Debug)]
pub enum PlotError {
    /// The run's folder or one of its files is missing or malformed: which, and why.
    Input(String),
    /// A picture could not be written: which, and why.
    Output(String),
}

/// What [`plot_run`] wrote.
#[derive(Debug)]
pub struct Plotted {
    pub written: Vec<PathBuf>,
    /// Why there are no field pictures, when there are none (a run with `--no-vtk`).
    pub no_fields: Option<String>,
}

/// Draws the pictures of the run in `dir` into `out`.
pub fn plot_run(dir: &Path, out: &Path) -> Result<Plotted, PlotError> {
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => return Err(PlotError::Input(format!("{}: not a folder", dir.display()))),
        Err(e) => return Err(PlotError::Input(format!("{}: {e}", dir.display()))),
    }
    let columns = [
        "time_s",
        "depth_m",
        "projectile_velocity_m_s",
        "contact_force_N",
        "nose_force_N",
    ];
    let history = run_files::history(dir, &columns).map_err(PlotError::Input)?;
    let [time, depth, velocity, force, nose] = &history[..] else {
        unreachable!("one column per name asked for")
    };
    // Read before anything is written: a malformed frame leaves no half set of pictures.
    let last = last_frame(dir)?;
    super::create_folder(out).map_err(|e| PlotError::Output(e.to_string()))?;
    let ms: Vec<f64> = time.iter().map(|t| t * 1e3).collect();
    let series = |values: &[f64], scale: f64| -> Vec<(f64, f64)> {
        ms.iter()
            .zip(values)
            .map(|(&t, &v)| (t, v * scale))
            .collect()
    };
    let charts = [
        Chart::new("Depth of penetration", "time (ms)", "depth (mm)").series(
            "depth",
            series(depth, 1e3),
            Mark::Line,
        ),
        Chart::new("Projectile velocity", "time (ms)", "velocity (m/s)").series(
            "velocity",
            series(velocity, 1.0),
            Mark::Line,
        ),
        Chart::new("Projectile deceleration", "time (ms)", "deceleration (g)").series(
            "-dv/dt between rows",
            deceleration(&ms, time, velocity),
            Mark::Line,
        ),
        Chart::new("Axial contact force", "time (ms)", "force (kN)")
            .series("whole projectile", series(force, 1e-3), Mark::Line)
            .series("nose", series(nose, 1e-3), Mark::Line),
    ];
    let mut written = Vec::new();
    for (chart, file) in charts.iter().zip(CURVES) {
        written.push(write(out, file, |path| chart.write_png(path))?);
    }
    let no_fields = match last {
        Err(why) => Some(why),
        Ok((t, grids)) => {
            for (map, file) in field_maps(t, &grids).iter().zip(FIELDS) {
                written.push(write(out, file, |path| map.write_png(path))?);
            }
            None
        }
    };
    Ok(Plotted { written, no_fields })
}

fn write(
    out: &Path,
    file: &str,
    draw: impl FnOnce(&Path) -> std::io::Result<()>,
) -> Result<PathBuf, PlotError> {
    let path = out.join(file);
    draw(&path).map_err(|e| PlotError::Output(format!("{}: {e}", path.display())))?;
    Ok(path)
}

/// The mean deceleration over each row's interval, in g, at the row's time (as
/// `contact_force_N` is the mean force over it); none on the first row.
fn deceleration(ms: &[f64], time: &[f64], velocity: &[f64]) -> Vec<(f64, f64)> {
    (1..time.len())
        .filter(|&k| time[k] > time[k - 1])
        .map(|k| {
            let a = (velocity[k - 1] - velocity[k]) / (time[k] - time[k - 1]);
            (ms[k], a / STANDARD_GRAVITY)
        })
        .collect()
}

/// The time and the grids of the last frame `frames.pvd` lists (every part listed at that
/// time); `Ok(Err(why))` for a run without frames.
type LastFrame = Result<(f64, Vec<Vtu>), String>;

fn last_frame(dir: &Path) -> Result<LastFrame, PlotError> {
    let pvd = dir.join("frames.pvd");
    if !pvd.exists() {
        return Ok(Err(format!(
            "no {}: field pictures need frames (a run without --no-vtk)",
            pvd.display()
        )));
    }
    let listed = vtk::read_pvd(&pvd).map_err(PlotError::Input)?;
    let Some(last) = listed.last() else {
        return Ok(Err(format!(
            "{} lists no frame: field pictures need frames",
            pvd.display()
        )));
    };
    let grids = listed
        .iter()
        .filter(|d| d.time == last.time)
        .map(|d| vtk::read_vtu(&dir.join(&d.file)))
        .collect::<Result<_, _>>()
        .map_err(PlotError::Input)?;
    Ok(Ok((last.time, grids)))
}

/// Damage and pressure at time `t` (s) of `grids`: particles as squares of their share of the
/// plane, meshes as their triangles; r across, z up, in mm.
fn field_maps(t: f64, grids: &[Vtu]) -> [FieldMap; 2] {
    let map = |title: &str, label: &str, name: &str, scale: f64| {
        let mut map = FieldMap {
            title: format!("{title} at t = {:.1} µs", t * 1e6),
            x_label: "r (mm)".into(),
            y_label: "z (mm)".into(),
            value_label: label.into(),
            triangles: Vec::new(),
            values: Vec::new(),
            squares: Vec::new(),
            range: (0.0, 1.0),
        };
        for grid in grids {
            let at = |k: usize| [grid.r[k] as f64 * 1e3, grid.z[k] as f64 * 1e3];
            match &grid.triangles {
                Some(triangles) => {
                    let values = grid.cell_field(name).unwrap_or_default();
                    for (k, t) in triangles.iter().enumerate() {
                        map.triangles.push(t.map(|c| at(c as usize)));
                        map.values
                            .push(values.get(k).map_or(f64::NAN, |&v| v as f64 * scale));
                    }
                }
                None => {
                    let values = grid.point_field(name).unwrap_or_default();
                    let side = particle_side(grid) * 1e3;
                    map.squares.extend((0..grid.r.len()).map(|k| Square {
                        centre: at(k),
                        side,
                        value: values.get(k).map_or(f64::NAN, |&v| v as f64 * scale),
                    }));
                }
            }
        }
        map
    };
    let damage = map("Damage", "damage", "damage", 1.0);
    let mut pressure = map("Pressure", "pressure (MPa)", "pressure", 1e-6);
    let span = |values: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = values
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        (lo <= hi).then_some((lo, hi))
    };
    // The concrete's range where there is concrete: the steel's GPa would leave the target one
    // colour. The projectile's pressures beyond it take the scale's end colours.
    let concrete = span(&mut pressure.squares.iter().map(|s| s.value));
    let all = span(&mut pressure.values.iter().copied());
    if let Some(range) = concrete.or(all) {
        pressure.range = range;
        if concrete.is_some() && !pressure.triangles.is_empty() {
            pressure.value_label = "pressure (MPa), the concrete's range".into();
        }
    }
    [damage, pressure]
}

/// The side (m) of a square as large as a particle's share of the r–z plane: the median over
/// the particles of √(m̃/ρ), the ring mass `mass` = 2π r m̃ (state.rs); where the frame lacks
/// them, the side of an equal share of the particles' bounding box.
fn particle_side(grid: &Vtu) -> f64 {
    let n = grid.r.len();
    if let (Some(mass), Some(rho)) = (grid.point_field("mass"), grid.point_field("density")) {
        let mut sides: Vec<f64> = (0..n)
            .map(|k| {
                let m_tilde = mass[k] as f64 / (std::f64::consts::TAU * grid.r[k] as f64);
                (m_tilde / rho[k] as f64).sqrt()
            })
            .filter(|s| s.is_finite() && *s > 0.0)
            .collect();
        if !sides.is_empty() {
            let middle = sides.len() / 2;
            return *sides.select_nth_unstable_by(middle, f64::total_cmp).1;
        }
    }
    let span = |v: &[f32]| {
        let finite = v.iter().map(|&x| x as f64).filter(|x| x.is_finite());
        let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        });
        (hi - lo).max(0.0)
    };
    (span(&grid.r) * span(&grid.z) / n.max(1) as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deceleration is the velocity's fall between rows over their time, in g; rows at one time
    /// give none.
    #[test]
    fn deceleration_is_the_mean_between_rows() {
        let time = [0.0, 1e-3, 1e-3, 3e-3];
        let ms = [0.0, 1.0, 1.0, 3.0];
        let velocity = [
            300.0,
            300.0 - STANDARD_GRAVITY,
            0.0,
            -2.0 * STANDARD_GRAVITY,
        ];
        let a = deceleration(&ms, &time, &velocity);
        assert_eq!(a.len(), 2);
        assert_eq!(a[0].0, 1.0);
        assert!((a[0].1 - 1000.0).abs() < 1e-9, "{a:?}");
        assert!((a[1].1 - 1000.0).abs() < 1e-9, "{a:?}");
    }

    /// The pressure's colours span the concrete's range, not the steel's GPa; a frame of the
    /// projectile alone spans its own.
    #[test]
    fn the_pressure_scale_is_the_concrete_s() {
        let particles = Vtu {
            r: vec![0.01, 0.02],
            z: vec![0.0, 0.0],
            point_data: vec![("pressure".into(), vec![-1.0e6, 40.0e6])],
            ..Vtu::default()
        };
        let projectile = Vtu {
            r: vec![0.0, 0.01, 0.0],
            z: vec![0.0, 0.0, 0.01],
            triangles: Some(vec![[0, 1, 2]]),
            cell_data: vec![("pressure".into(), vec![2.0e9])],
            ..Vtu::default()
        };
        let [_, both] = field_maps(0.0, &[particles, projectile.clone()]);
        assert_eq!(both.range, (-1.0, 40.0));
        assert!(both.value_label.contains("the concrete's range"));
        let [_, alone] = field_maps(0.0, &[projectile]);
        assert_eq!(alone.range, (2000.0, 2000.0));
        assert_eq!(alone.value_label, "pressure (MPa)");
    }

    /// A particle's square has its share of the plane: side s for ring mass 2π r ρ s².
    #[test]
    fn a_particle_square_has_its_share_of_the_plane() {
        let (s, rho) = (2.5e-3f64, 2400.0f64);
        let r = vec![1.25e-3f32, 3.75e-3, 6.25e-3];
        let mass: Vec<f32> = r
            .iter()
            .map(|&r| (std::f64::consts::TAU * r as f64 * rho * s * s) as f32)
            .collect();
        let grid = Vtu {
            z: vec![0.0; 3],
            point_data: vec![
                ("mass".into(), mass),
                ("density".into(), vec![rho as f32; 3]),
            ],
            r,
            ..Vtu::default()
        };
        assert!((particle_side(&grid) - s).abs() < 1e-6 * s);
        let bare = Vtu {
            r: vec![0.0, 1.0, 0.0, 1.0],
            z: vec![0.0, 0.0, 1.0, 1.0],
            ..Vtu::default()
        };
        assert_eq!(particle_side(&bare), 0.5);
    }
}
