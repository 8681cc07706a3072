//! Outputs of a run: `summary.json`, `history.csv`, VTK frames (`.vtu` + a `.pvd` collection,
//! written off the stepping thread by [`frames`]), the progress display, and PNG plots of what
//! a run or a study wrote ([`plot`]), read back through [`run_files`] and [`vtk::read_vtu`].

pub mod frames;
pub mod history;
pub mod plot;
pub mod progress;
pub mod run_files;
pub mod run_plots;
pub mod summary;
pub mod vtk;

/// Creates an output folder (and its parents), or says which one could not be made and why.
pub fn create_folder(dir: &std::path::Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| {
        let message = format!("cannot create the output folder {} ({e})", dir.display());
        std::io::Error::new(e.kind(), message)
    })
}

/// A run's checkpoint in its output folder (`penetrate run --checkpoint-every`).
pub const RESTART_FILE: &str = "restart.bin";

/// The files a run writes besides its frames and `scene.toml`.
const RUN_FILES: [&str; 4] = ["summary.json", "history.csv", "frames.pvd", RESTART_FILE];

/// Removes what an earlier run left in `dir` that this one may not overwrite: its
/// `summary.json` and `history.csv` (a run refused or killed before writing its own must not
/// show the last one's), its frames (`frames.pvd`, `target_NNNNN.vtu`, `projectile_NNNNN.vtu`:
/// a shorter run, or one without frames, would otherwise sit beside the last one's), its
/// checkpoint (`restart.bin`, which continues that run's history, not this one's), the
/// pictures `penetrate plot` drew of it ([`run_plots`]), and any of these a killed run left
/// half-written (`<name>.partial`, [`write_whole`]). Nothing else is touched.
pub fn clear_previous_run(dir: &std::path::Path) -> std::io::Result<()> {
    remove_outputs(dir, |name, _| {
        RUN_FILES.contains(&name)
            || frame_number(name).is_some()
            || run_plots::CURVES.contains(&name)
            || run_plots::FIELDS.contains(&name)
    })
}

/// Removes what a run killed after its checkpoint wrote that a restart from it writes again:
/// `summary.json` (of an earlier end of the run), the frames from number `frames` on, and
/// what was left half-written. The checkpoint itself stays until the restart writes its next.
pub fn clear_after_checkpoint(dir: &std::path::Path, frames: usize) -> std::io::Result<()> {
    remove_outputs(dir, |name, partial| {
        name == "summary.json"
            || frame_number(name).is_some_and(|n| n >= frames as u64)
            || (partial && (RUN_FILES.contains(&name) || frame_number(name).is_some()))
    })
}

/// The number of a frame file, `target_NNNNN.vtu` or `projectile_NNNNN.vtu` (one past any
/// run's frames where it has more digits than a u64 holds).
fn frame_number(name: &str) -> Option<u64> {
    ["target_", "projectile_"].iter().find_map(|prefix| {
        name.strip_prefix(prefix)
            .and_then(|rest| rest.strip_suffix(".vtu"))
            .filter(|n| n.len() >= 5 && n.bytes().all(|b| b.is_ascii_digit()))
            .map(|n| n.parse().unwrap_or(u64::MAX))
    })
}

/// Removes the plain files of `dir` that `doomed` picks by name, `.partial` taken off (and
/// whether it was there).
fn remove_outputs(
    dir: &std::path::Path,
    doomed: impl Fn(&str, bool) -> bool,
) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let (name, partial) = match name.strip_suffix(".partial") {
            Some(name) => (name, true),
            None => (name, false),
        };
        if doomed(name, partial) && entry.file_type()?.is_file() {
            std::fs::remove_file(entry.path())?;
        }
    }
    Ok(())
}

/// Writes `bytes` to `path` whole or not at all: into `<path>.partial` first, renamed over
/// `path` once complete. On failure (a full disk) the partial file is removed, so the folder
/// keeps what it had and the bytes are free again for `summary.json`, and the error names the
/// file.
pub fn write_whole(path: &std::path::Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut partial = path.as_os_str().to_owned();
    partial.push(".partial");
    let partial = std::path::PathBuf::from(partial);
    let written = std::fs::write(&partial, bytes).and_then(|()| std::fs::rename(&partial, path));
    written.map_err(|e| {
        let _ = std::fs::remove_file(&partial);
        named(path, e)
    })
}

/// Writes `header` and `rows` to `path` as CSV, a field quoted where it needs it (a run's
/// status or folder may hold commas or quotes). Rows are not held to the header's length.
pub fn write_csv<H: AsRef<[u8]>, F: AsRef<[u8]>>(
    path: &std::path::Path,
    header: &[H],
    rows: &[Vec<F>],
) -> std::io::Result<()> {
    let mut w = csv::WriterBuilder::new()
        .flexible(true)
        .from_writer(Vec::new());
    w.write_record(header)?;
    for row in rows {
        w.write_record(row)?;
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    std::fs::write(path, bytes)
}

/// The error `e` met on `path`, naming it.
pub fn named(path: &std::path::Path, e: std::io::Error) -> std::io::Error {
    std::io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

/// Bytes free to an unprivileged writer on the file system holding `dir`, where it can be read.
#[cfg(unix)]
pub fn free_bytes(dir: &std::path::Path) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt as _;
    let path = std::ffi::CString::new(dir.as_os_str().as_bytes()).ok()?;
    let mut stat = std::mem::MaybeUninit::<libc::statvfs>::uninit();
    // SAFETY: `path` is a NUL-terminated string and `stat` is written by the call before it
    // is read, which happens only when the call succeeded.
    let stat = unsafe {
        if libc::statvfs(path.as_ptr(), stat.as_mut_ptr()) != 0 {
            return None;
        }
        stat.assume_init()
    };
    Some((stat.f_bavail as u64).saturating_mul(stat.f_frsize as u64))
}

#[cfg(not(unix))]
pub fn free_bytes(_dir: &std::path::Path) -> Option<u64> {
    None
}

/// `v` to `decimals` places for people to read: a value that rounds to zero is "0", not "-0"
/// (a projectile at rest moves back by µm/s).
pub fn fixed(v: f64, decimals: usize) -> String {
    let text = format!("{v:.decimals$}");
    match text.strip_prefix('-') {
        Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_string(),
        _ => text,
    }
}

#[cfg(test)]
mod tests {
    /// Fields with commas, quotes and newlines come back as they went in.
    #[test]
    fn csv_fields_round_trip() {
        let path = std::env::temp_dir().join(format!("penetrate-csv-{}.csv", std::process::id()));
        let row = vec!["a", "b,c", "say \"x\"", "two\nlines", ""];
        super::write_csv(
            &path,
            &["k", "l", "m", "n", "o"],
            std::slice::from_ref(&row),
        )
        .unwrap();
        let mut reader = csv::Reader::from_path(&path).unwrap();
        assert_eq!(reader.headers().unwrap(), vec!["k", "l", "m", "n", "o"]);
        let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
        assert_eq!(rows, vec![csv::StringRecord::from(row)]);
        let _ = std::fs::remove_file(&path);
    }

    #[test]
    fn fixed_drops_the_sign_of_a_rounded_zero() {
        assert_eq!(super::fixed(-0.004, 1), "0.0");
        assert_eq!(super::fixed(-0.0, 2), "0.00");
        assert_eq!(super::fixed(-0.06, 1), "-0.1");
        assert_eq!(super::fixed(-10.0, 0), "-10");
        assert_eq!(super::fixed(203.996, 2), "204.00");
    }
}
