//! Files a run wrote, read back for the report: whole, capped in size, from regular files of
//! UTF-8 text only.

use std::path::Path;

use crate::scene;

/// The most `validate` reads of one file a run wrote (`history.csv`, a projectile frame). A
/// shipped case writes about 500 history rows (0.2 MB) and frames of a few MB; the limit is far
/// above both, and keeps a file that never ends (a run folder's file replaced by a link to
/// /dev/zero, say) from being read until memory runs out.
const RUN_FILE_LIMIT: u64 = 1 << 30;

/// A text file a run wrote, read whole: a regular file of at most [`RUN_FILE_LIMIT`] bytes of
/// UTF-8, or an error naming the path and what is wrong with it.
pub(super) fn read_run_file(path: &Path) -> Result<String, String> {
    let fail = |why: String| format!("{}: {why}", path.display());
    let meta = std::fs::metadata(path).map_err(|e| fail(e.to_string()))?;
    let too_large = || {
        fail(format!(
            "larger than {} GiB, not read",
            RUN_FILE_LIMIT >> 30
        ))
    };
    if !meta.is_file() {
        return Err(fail("not a regular file".into()));
    }
    if meta.len() > RUN_FILE_LIMIT {
        return Err(too_large());
    }
    // Capped again while reading: the file may grow after the look.
    let bytes = scene::read_capped(path, RUN_FILE_LIMIT)
        .map_err(|e| fail(e.to_string()))?
        .ok_or_else(too_large)?;
    String::from_utf8(bytes).map_err(|_| fail("not UTF-8 text".into()))
}

/// Columns of a run's `history.csv`, by header name.
pub(super) fn history(dir: &Path, columns: &[&str]) -> Result<Vec<Vec<f64>>, String> {
    let path = dir.join("history.csv");
    let text = read_run_file(&path)?;
    crate::output::history::read_columns(&path, text.as_bytes(), columns)
}

#[cfg(test)]
mod tests {
    use super::super::frame;
    use super::*;

    /// A run's file that never ends, is too large or is not text is refused with its path
    /// named, before it is read; a good one is read.
    #[test]
    fn a_run_file_that_never_ends_is_refused() {
        let dir = std::env::temp_dir().join(format!("penetrate-run-file-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let csv = dir.join("history.csv");
        let refused = |why: &str| {
            let e = history(&dir, &["time_s"]).unwrap_err();
            assert!(
                e.starts_with(&csv.display().to_string()) && e.contains(why),
                "{e}"
            );
        };

        std::fs::write(&csv, "time_s,depth_m\n0,0\n1e-6,0.5\n").unwrap();
        assert_eq!(
            history(&dir, &["depth_m", "time_s"]).unwrap(),
            vec![vec![0.0, 0.5], vec![0.0, 1e-6]]
        );
        std::fs::remove_file(&csv).unwrap();
        std::os::unix::fs::symlink("/dev/zero", &csv).unwrap();
        refused("not a regular file");
        std::fs::remove_file(&csv).unwrap();
        // Sparse: one byte over the limit takes no disk and no time to make.
        let file = std::fs::File::create(&csv).unwrap();
        file.set_len(RUN_FILE_LIMIT + 1).unwrap();
        refused("larger than 1 GiB");
        file.set_len(0).unwrap();
        std::fs::write(&csv, b"time_s\n\xff\n").unwrap();
        refused("not UTF-8");
        // A malformed row is named by its line, not a panic.
        std::fs::write(&csv, "depth_m,time_s\n0,0\n0.5\n").unwrap();
        refused(":3: the row has no `time_s` field");
        std::fs::write(&csv, "time_s,depth_m\n0,0\n1e-6,deep\n").unwrap();
        let e = history(&dir, &["depth_m"]).unwrap_err();
        assert!(
            e.ends_with("history.csv:3: depth_m = `deep` is not a number"),
            "{e}"
        );
        std::fs::write(&csv, "depth_m\n0\n").unwrap();
        refused("no column time_s");

        let vtu = dir.join("projectile_00007.vtu");
        std::os::unix::fs::symlink("/dev/zero", &vtu).unwrap();
        let e = frame::last_projectile_frame(&dir).unwrap_err();
        assert!(
            e.contains("projectile_00007.vtu: not a regular file"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
