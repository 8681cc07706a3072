//! VTK XML unstructured grids (`.vtu`, ASCII) and a ParaView collection (`.pvd`), written by
//! hand: the format is small and the crates for it are unmaintained.

use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

/// A named per-point or per-cell scalar field.
pub type Field<'a> = (&'a str, &'a [f32]);

/// Write points (r, z) in the plane y = 0 (x = r, z = z) as VTK vertices or triangles.
pub fn write_vtu(
    path: &Path,
    r: &[f32],
    z: &[f32],
    triangles: Option<&[[u32; 3]]>,
    point_fields: &[Field],
    cell_fields: &[Field],
) -> io::Result<()> {
    let n = r.len();
    let cells: Vec<Vec<u32>> = match triangles {
        Some(t) => t.iter().map(|c| c.to_vec()).collect(),
        None => (0..n as u32).map(|i| vec![i]).collect(),
    };
    let mut s = String::with_capacity(64 * n + 256);
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n");
    let _ = writeln!(
        s,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        n,
        cells.len()
    );
    s.push_str(
        "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for i in 0..n {
        let _ = writeln!(s, "{} 0 {}", r[i], z[i]);
    }
    s.push_str("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
    for c in &cells {
        let line: Vec<String> = c.iter().map(|v| v.to_string()).collect();
        s.push_str(&line.join(" "));
        s.push('\n');
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
    let mut off = 0;
    for c in &cells {
        off += c.len();
        let _ = write!(s, "{off} ");
    }
    s.push_str("\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for c in &cells {
        // 1 = VTK_VERTEX, 5 = VTK_TRIANGLE
        s.push_str(if c.len() == 3 { "5 " } else { "1 " });
    }
    s.push_str("\n</DataArray>\n</Cells>\n");
    write_fields(&mut s, "PointData", point_fields);
    write_fields(&mut s, "CellData", cell_fields);
    s.push_str("</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    super::write_whole(path, s.as_bytes())
}

fn write_fields(s: &mut String, tag: &str, fields: &[Field]) {
    let _ = writeln!(s, "<{tag}>");
    for (name, values) in fields {
        let _ = writeln!(
            s,
            "<DataArray type=\"Float32\" Name=\"{name}\" format=\"ascii\">"
        );
        for v in values.iter() {
            let _ = write!(s, "{v} ");
        }
        s.push_str("\n</DataArray>\n");
    }
    let _ = writeln!(s, "</{tag}>");
}

/// A `.pvd` collection: one entry per frame and part, rewritten whole after every frame so that
/// a run that stops early, or cannot write, still leaves a readable collection.
#[derive(Debug, Default)]
pub struct Collection {
    path: PathBuf,
    entries: Vec<(f64, usize, String)>,
}

impl Collection {
    pub fn new(path: PathBuf) -> Collection {
        Collection {
            path,
            entries: Vec::new(),
        }
    }

    /// A restarted run's collection: the `entries` its checkpoint kept, written out at once,
    /// so that frames a killed run wrote after the checkpoint are no longer listed.
    pub fn resume(path: PathBuf, entries: Vec<(f64, usize, String)>) -> io::Result<Collection> {
        let pvd = Collection { path, entries };
        pvd.write()?;
        Ok(pvd)
    }

    /// The entries so far: time (s), part (0 the target, 1 the projectile) and file name.
    pub fn entries(&self) -> &[(f64, usize, String)] {
        &self.entries
    }

    pub fn add(&mut self, time: f64, part: usize, file: &str) -> io::Result<()> {
        self.entries.push((time, part, file.to_string()));
        self.write()
    }

    fn write(&self) -> io::Result<()> {
        let mut s = String::from("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n");
        for (t, p, f) in &self.entries {
            let _ = writeln!(s, "<DataSet timestep=\"{t:e}\" part=\"{p}\" file=\"{f}\"/>");
        }
        s.push_str("</Collection>\n</VTKFile>\n");
        super::write_whole(&self.path, s.as_bytes())
    }
}
