//! Outputs of a run: `summary.json`, `history.csv`, VTK frames (`.vtu` + a `.pvd` collection),
//! and the progress display.

pub mod history;
pub mod progress;
pub mod summary;
pub mod vtk;
