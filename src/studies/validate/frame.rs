//! The projectile's last VTK frame of a finished run (`projectile_<n>.vtu`, written by
//! `Simulation::write_frame`), read back for the damage maps: `solver::run` keeps its
//! `Simulation` to itself, and the last frame is its final state as written.

use std::path::Path;

/// The projectile mesh at the end of a run, with each element's damage.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    pub r: Vec<f64>,
    pub z: Vec<f64>,
    pub triangles: Vec<[usize; 3]>,
    pub damage: Vec<f64>,
}

/// The highest-numbered projectile frame in `dir`.
pub fn last_projectile_frame(dir: &Path) -> Result<Frame, String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let last = entries
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("projectile_") && n.ends_with(".vtu"))
        .max()
        .ok_or_else(|| format!("{}: no projectile frame (projectile_*.vtu)", dir.display()))?;
    let path = dir.join(&last);
    let text = super::run_files::read_run_file(&path)?;
    parse(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Reads the points, the triangles and the `damage` cell field of a frame.
fn parse(text: &str) -> Result<Frame, String> {
    let points = numbers(array(text, "<Points>", "<DataArray")?)?;
    if points.len() % 3 != 0 {
        return Err("the point coordinates do not come in threes".into());
    }
    let r: Vec<f64> = points.chunks(3).map(|p| p[0]).collect();
    let z: Vec<f64> = points.chunks(3).map(|p| p[2]).collect();
    let connectivity = numbers(array(text, "<Cells>", "Name=\"connectivity\"")?)?;
    if connectivity.len() % 3 != 0 {
        return Err("the cells are not all triangles".into());
    }
    let index = |x: f64| {
        let k = x as usize;
        (x >= 0.0 && x.fract() == 0.0 && k < r.len())
            .then_some(k)
            .ok_or_else(|| format!("connectivity entry {x} is not a point index"))
    };
    let triangles: Vec<[usize; 3]> = connectivity
        .chunks_exact(3)
        .map(|c| Ok([index(c[0])?, index(c[1])?, index(c[2])?]))
        .collect::<Result<_, String>>()?;
    let damage = numbers(array(text, "<CellData>", "Name=\"damage\"")?)?;
    if damage.len() != triangles.len() {
        return Err(format!(
            "{} damage values for {} triangles",
            damage.len(),
            triangles.len()
        ));
    }
    Ok(Frame {
        r,
        z,
        triangles,
        damage,
    })
}

/// The text of the first `DataArray` at `marker` after `section`.
fn array<'a>(text: &'a str, section: &str, marker: &str) -> Result<&'a str, String> {
    let missing = || format!("no {marker} in {section}");
    let from = text.find(section).ok_or_else(missing)?;
    let at = from + text[from..].find(marker).ok_or_else(missing)?;
    let open = at + text[at..].find('>').ok_or_else(missing)? + 1;
    let close = open + text[open..].find("</DataArray>").ok_or_else(missing)?;
    Ok(&text[open..close])
}

fn numbers(text: &str) -> Result<Vec<f64>, String> {
    text.split_whitespace()
        .map(|w| {
            w.parse::<f64>()
                .map_err(|_| format!("`{w}` is not a number"))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::vtk;

    /// What `vtk::write_vtu` writes for a projectile comes back.
    #[test]
    fn a_written_frame_reads_back() {
        let dir = std::env::temp_dir().join(format!("penetrate-frame-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (r, z) = (vec![0.0f32, 1.0, 0.0, 1.0], vec![0.0f32, 0.0, 1.0, 1.5]);
        let tri = [[0u32, 1, 2], [1, 3, 2]];
        for (n, damage) in [(0, [0.0f32, 0.0]), (1, [0.25, 1.0])] {
            vtk::write_vtu(
                &dir.join(format!("projectile_{n:05}.vtu")),
                &r,
                &z,
                Some(&tri),
                &[("v_r", &[0.0; 4])],
                &[("plastic_strain", &[0.5, 0.5]), ("damage", &damage)],
            )
            .unwrap();
        }
        let f = last_projectile_frame(&dir).unwrap();
        assert_eq!(f.r, vec![0.0, 1.0, 0.0, 1.0]);
        assert_eq!(f.z, vec![0.0, 0.0, 1.0, 1.5]);
        assert_eq!(f.triangles, vec![[0, 1, 2], [1, 3, 2]]);
        assert_eq!(f.damage, vec![0.25, 1.0]);
        let _ = std::fs::remove_dir_all(&dir);
        assert!(last_projectile_frame(&dir).is_err());
    }
}
