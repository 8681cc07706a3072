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

/// Removes what an earlier run left in `dir` that this one may not overwrite: its
/// `summary.json` and `history.csv` (a run refused or killed before writing its own must not
/// show the last one's) and its frames (`frames.pvd`, `target_NNNNN.vtu`,
/// `projectile_NNNNN.vtu`: a shorter run, or one without frames, would otherwise sit beside the
/// last one's). Nothing else is touched.
pub fn clear_previous_run(dir: &std::path::Path) -> std::io::Result<()> {
    let frame = |name: &str| {
        ["target_", "projectile_"].iter().any(|prefix| {
            name.strip_prefix(prefix)
                .and_then(|rest| rest.strip_suffix(".vtu"))
                .is_some_and(|n| n.len() >= 5 && n.bytes().all(|b| b.is_ascii_digit()))
        })
    };
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let ours = ["summary.json", "history.csv", "frames.pvd"].contains(&name);
        if (ours || frame(name)) && entry.file_type()?.is_file() {
            std::fs::remove_file(entry.path())?;
        }
    }
    Ok(())
}
