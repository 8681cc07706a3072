//! VTK frames: a frame's parts, owned copies of the state's arrays, and their writing into a
//! run's folder and its `frames.pvd`.

use std::io;
use std::path::Path;

use super::vtk::{self, Collection, Vtu};

/// One frame: its number, the step and time it shows, and its parts.
pub struct Frame {
    pub number: usize,
    pub step: u64,
    /// s
    pub time: f64,
    pub parts: Vec<Part>,
}

/// A part of a frame: its file (`target_00003.vtu`), its part number in the collection, and
/// its grid.
pub struct Part {
    pub file: String,
    pub index: usize,
    pub grid: Vtu,
}

impl Frame {
    /// Writes each part into `dir` and lists it in `pvd`, stopping at the first refusal.
    pub fn write(&self, dir: &Path, pvd: &mut Collection) -> io::Result<()> {
        for part in &self.parts {
            vtk::write_vtu(&dir.join(&part.file), &part.grid)?;
            pvd.add(self.time, part.index, &part.file)?;
        }
        Ok(())
    }
}
