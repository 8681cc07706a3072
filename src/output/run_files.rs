//! Files a run wrote, read back (by `validate`'s report and `penetrate plot`): whole, capped in
//! size, from regular files only.

use std::path::Path;

use crate::scene;

/// The most read of one file a run wrote (`history.csv`, a frame). A shipped case writes about
/// 500 history rows (0.2 MB) and binary frames of about 60 bytes a particle (a few MB); the
/// limit is far above both, and keeps a file that never ends (a run folder's file replaced by
/// a link to /dev/zero, say) from being read until memory runs out.
const RUN_FILE_LIMIT: u64 = 1 << 30;

/// A file a run wrote, read whole: a regular file of at most [`RUN_FILE_LIMIT`] bytes, or an
/// error naming the path and what is wrong with it.
pub fn read_run_file(path: &Path) -> Result<Vec<u8>, String> {
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
    scene::read_capped(path, RUN_FILE_LIMIT)
        .map_err(|e| fail(e.to_string()))?
        .ok_or_else(too_large)
}

/// Columns of a run's `history.csv` (in `dir`), by header name.
pub fn history(dir: &Path, columns: &[&str]) -> Result<Vec<Vec<f64>>, String> {
    let path = dir.join("history.csv");
    let bytes = read_run_file(&path)?;
    let text =
        String::from_utf8(bytes).map_err(|_| format!("{}: not UTF-8 text", path.display()))?;
    super::history::read_columns(&path, text.as_bytes(), columns)
}

#[cfg(test)]
mod tests {
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

        let _ = std::fs::remove_dir_all(&dir);
    }
}
