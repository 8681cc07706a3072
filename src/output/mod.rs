//! Outputs of a run: `summary.json`, `history.csv`, VTK frames (`.vtu` + a `.pvd` collection),
//! and the progress display.

pub mod history;
pub mod progress;
pub mod summary;
pub mod vtk;

/// Creates an output folder (and its parents), or says which one could not be made and why.
pub fn create_folder(dir: &std::path::Path) -> Result<(), String> {
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("cannot create the output folder {} ({e})", dir.display()))
}
