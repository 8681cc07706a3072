//! The projectile's last VTK frame of a finished run (`projectile_<n>.vtu`, written by
//! `solver::run`), read back for the damage maps: `solver::run` keeps its
//! `Simulation` to itself, and the last frame is its final state as written.

use std::path::Path;

use crate::output::vtk;

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
    let vtu = vtk::read_vtu(&path)?;
    let fail = |why: &str| format!("{}: {why}", path.display());
    let triangles = vtu.triangles.as_ref().ok_or_else(|| fail("no triangles"))?;
    let damage = vtu
        .cell_field("damage")
        .ok_or_else(|| fail("no damage cell field"))?;
    let wide = |v: &[f32]| v.iter().map(|&x| x as f64).collect();
    Ok(Frame {
        r: wide(&vtu.r),
        z: wide(&vtu.z),
        triangles: triangles.iter().map(|t| t.map(|k| k as usize)).collect(),
        damage: wide(damage),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::vtk::Vtu;

    /// What `vtk::write_vtu` writes for a projectile comes back; a frame that is not a file is
    /// named.
    #[test]
    fn a_written_frame_reads_back() {
        let dir = std::env::temp_dir().join(format!("penetrate-frame-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (r, z) = (vec![0.0f32, 1.0, 0.0, 1.0], vec![0.0f32, 0.0, 1.0, 1.5]);
        let tri = [[0u32, 1, 2], [1, 3, 2]];
        for (n, damage) in [(0, [0.0f32, 0.0]), (1, [0.25, 1.0])] {
            let grid = Vtu {
                r: r.clone(),
                z: z.clone(),
                triangles: Some(tri.to_vec()),
                point_data: vec![("v_r".into(), vec![0.0; 4])],
                cell_data: vec![
                    ("plastic_strain".into(), vec![0.5, 0.5]),
                    ("damage".into(), damage.to_vec()),
                ],
            };
            vtk::write_vtu(&dir.join(format!("projectile_{n:05}.vtu")), &grid).unwrap();
        }
        let f = last_projectile_frame(&dir).unwrap();
        assert_eq!(f.r, vec![0.0, 1.0, 0.0, 1.0]);
        assert_eq!(f.z, vec![0.0, 0.0, 1.0, 1.5]);
        assert_eq!(f.triangles, vec![[0, 1, 2], [1, 3, 2]]);
        assert_eq!(f.damage, vec![0.25, 1.0]);
        let vtu = dir.join("projectile_00007.vtu");
        std::os::unix::fs::symlink("/dev/zero", &vtu).unwrap();
        let e = last_projectile_frame(&dir).unwrap_err();
        assert!(
            e.contains("projectile_00007.vtu: not a regular file"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
        assert!(last_projectile_frame(&dir).is_err());
    }
}
