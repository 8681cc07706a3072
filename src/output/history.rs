//! `history.csv`: one row per history interval.

use std::fs::File;
use std::io::{self, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use serde::{Serialize, Serializer};

/// One row of the time series.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Row {
    pub time: f64,
    pub step: u64,
    pub dt: f64,
    pub depth: f64,
    pub velocity: f64,
    pub kinetic: f64,
    pub internal: f64,
    pub contact_dissipated: f64,
    /// Axial impulse the contact has given the projectile so far (N s, +z against a flight
    /// along −z).
    pub contact_impulse: f64,
    /// The part of `contact_impulse` given through the nose's segments (N s).
    pub nose_impulse: f64,
    pub energy_error: f64,
    pub max_damage: f64,
    pub max_plastic_strain: f64,
    pub hits: usize,
    /// Damage-weighted r–z area of the projectile (m², `Simulation::damage_area`).
    pub damage_area: f64,
    /// Plastic work done in the projectile so far (J, the sum over its elements).
    pub plastic_work: f64,
    /// Largest pressure checkerboard in a crossed-triangle cell (Pa, `Elements::max_checkerboard`).
    pub checkerboard: f64,
    /// The projectile body's axial extent and largest radius (m, `Simulation::projectile_extent`:
    /// at the last row `summary.json`'s `final_length_m` and `max_radius_m`).
    pub length: f64,
    pub radius: f64,
}

/// A row as written: its fields' names are the file's column names, in order. Floats are
/// written as Rust's `{:e}` writes them (the csv crate's own float form differs), so a run's
/// file keeps the bytes it has always had.
#[derive(Default, Serialize)]
struct Record {
    #[serde(rename = "time_s", serialize_with = "exp")]
    time: f64,
    step: u64,
    #[serde(rename = "dt_s", serialize_with = "exp")]
    dt: f64,
    #[serde(rename = "depth_m", serialize_with = "exp")]
    depth: f64,
    #[serde(rename = "projectile_velocity_m_s", serialize_with = "exp")]
    velocity: f64,
    #[serde(rename = "kinetic_J", serialize_with = "exp")]
    kinetic: f64,
    #[serde(rename = "internal_J", serialize_with = "exp")]
    internal: f64,
    #[serde(rename = "contact_dissipated_J", serialize_with = "exp")]
    contact_dissipated: f64,
    #[serde(serialize_with = "exp")]
    energy_error: f64,
    #[serde(serialize_with = "exp")]
    max_damage: f64,
    #[serde(serialize_with = "exp")]
    max_plastic_strain: f64,
    hits: usize,
    #[serde(rename = "damage_area_m2", serialize_with = "exp")]
    damage_area: f64,
    #[serde(rename = "plastic_work_J", serialize_with = "exp")]
    plastic_work: f64,
    #[serde(rename = "checkerboard_Pa", serialize_with = "exp")]
    checkerboard: f64,
    #[serde(rename = "contact_impulse_Ns", serialize_with = "exp")]
    contact_impulse: f64,
    #[serde(rename = "contact_force_N", serialize_with = "exp")]
    contact_force: f64,
    #[serde(rename = "nose_impulse_Ns", serialize_with = "exp")]
    nose_impulse: f64,
    #[serde(rename = "nose_force_N", serialize_with = "exp")]
    nose_force: f64,
    #[serde(rename = "projectile_length_m", serialize_with = "exp")]
    length: f64,
    #[serde(rename = "projectile_radius_m", serialize_with = "exp")]
    radius: f64,
}

fn exp<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{x:e}"))
}

/// The header line of `history.csv` (without its newline): [`Record`]'s field names.
pub fn header() -> io::Result<String> {
    // The crate writes a header only before a first record: write one and keep the header.
    let mut w = csv::Writer::from_writer(Vec::new());
    w.serialize(Record::default())?;
    let text = w.into_inner().map_err(|e| e.into_error())?;
    let text =
        String::from_utf8(text).map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))?;
    Ok(text.lines().next().unwrap_or_default().to_string())
}

/// Columns of a CSV file with a header line (`history.csv`), by header name, as numbers, from
/// `data`; errors name `path` and the line (counted as the csv crate does: without blank
/// lines, which a history has none of).
pub fn read_columns(
    path: &Path,
    data: impl io::Read,
    columns: &[&str],
) -> Result<Vec<Vec<f64>>, String> {
    let file = path.display();
    // Flexible: a short row is named below with its missing column, not as a length mismatch.
    let mut reader = csv::ReaderBuilder::new().flexible(true).from_reader(data);
    let header = reader
        .headers()
        .map_err(|e| format!("{file}: {e}"))?
        .clone();
    let index: Vec<usize> = columns
        .iter()
        .map(|c| {
            header
                .iter()
                .position(|h| h == *c)
                .ok_or_else(|| format!("{file}: no column {c}"))
        })
        .collect::<Result<_, _>>()?;
    let mut out = vec![Vec::new(); columns.len()];
    for record in reader.records() {
        let record = record.map_err(|e| format!("{file}: {e}"))?;
        let line = record.position().map_or(0, |p| p.line());
        for ((col, &k), name) in out.iter_mut().zip(&index).zip(columns) {
            let field = record
                .get(k)
                .ok_or_else(|| format!("{file}:{line}: the row has no `{name}` field"))?;
            let x = field
                .parse::<f64>()
                .map_err(|_| format!("{file}:{line}: {name} = `{field}` is not a number"))?;
            col.push(x);
        }
    }
    Ok(out)
}

/// Rows gathered before they go to the file together.
const CHUNK: usize = 8192;

/// The file of the time series. It ends on a whole row whatever happens: rows go out in whole
/// chunks, and a chunk the disk could not take is cut off again (`set_len`), so a run stopped
/// by a full disk leaves every row it wrote readable.
pub struct History {
    file: File,
    path: PathBuf,
    /// Whole rows not yet in the file.
    pending: Vec<u8>,
    /// Bytes of whole rows in the file.
    written: u64,
    /// The last row written and its mean contact and nose forces (N).
    last: Option<(Row, f64, f64)>,
    /// CRC-32 of the bytes in the file, for a restart to know the file it continues.
    crc: crc32fast::Hasher,
}

/// Where a history stood when a checkpoint was written: what a restart needs to go on with it
/// as if the run had never stopped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mark {
    /// Bytes of whole rows in the file (the header included).
    pub bytes: u64,
    /// Their CRC-32.
    pub crc: u32,
    /// The last row written and its mean contact and nose forces (N): the next row's forces
    /// are differences from it.
    pub last: Option<(Row, f64, f64)>,
}

impl History {
    pub fn create(path: &Path) -> io::Result<History> {
        let file = File::create(path).map_err(|e| super::named(path, e))?;
        let mut history = History {
            file,
            path: path.to_path_buf(),
            pending: format!("{}\n", header()?).into_bytes(),
            written: 0,
            last: None,
            crc: crc32fast::Hasher::new(),
        };
        history.flush()?;
        Ok(history)
    }

    /// The rows gathered so far sent to the file, and where the file stands.
    pub fn mark(&mut self) -> io::Result<Mark> {
        self.flush()?;
        Ok(Mark {
            bytes: self.written,
            crc: self.crc.clone().finalize(),
            last: self.last,
        })
    }

    /// The file at `path` as it stood at `mark`, to be written on: what a run killed after the
    /// mark wrote beyond it is cut off. The caller has checked it with [`check_prefix`].
    pub fn resume(path: &Path, mark: &Mark) -> io::Result<History> {
        let mut file = File::options()
            .write(true)
            .open(path)
            .map_err(|e| super::named(path, e))?;
        file.set_len(mark.bytes)
            .and_then(|()| file.seek(SeekFrom::End(0)))
            .map_err(|e| super::named(path, e))?;
        Ok(History {
            file,
            path: path.to_path_buf(),
            pending: Vec::new(),
            written: mark.bytes,
            last: mark.last,
            crc: crc32fast::Hasher::new_with_initial(mark.crc),
        })
    }

    /// Appends `r`, with the mean axial contact force since the previous row, on the whole
    /// projectile and on its nose: the impulse between the two rows over the time between
    /// them (0 on the first row; a row at the previous row's time repeats its forces).
    pub fn write(&mut self, r: &Row) -> io::Result<()> {
        let (force, nose_force) = match self.last {
            Some((p, ..)) if r.time > p.time => {
                let dt = r.time - p.time;
                (
                    (r.contact_impulse - p.contact_impulse) / dt,
                    (r.nose_impulse - p.nose_impulse) / dt,
                )
            }
            Some((_, force, nose_force)) => (force, nose_force),
            None => (0.0, 0.0),
        };
        self.last = Some((*r, force, nose_force));
        // The row goes into `pending` through a writer that owns it for the one row.
        let mut rows = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(std::mem::take(&mut self.pending));
        rows.serialize(Record {
            time: r.time,
            step: r.step,
            dt: r.dt,
            depth: r.depth,
            velocity: r.velocity,
            kinetic: r.kinetic,
            internal: r.internal,
            contact_dissipated: r.contact_dissipated,
            energy_error: r.energy_error,
            max_damage: r.max_damage,
            max_plastic_strain: r.max_plastic_strain,
            hits: r.hits,
            damage_area: r.damage_area,
            plastic_work: r.plastic_work,
            checkerboard: r.checkerboard,
            contact_impulse: r.contact_impulse,
            contact_force: force,
            nose_impulse: r.nose_impulse,
            nose_force,
            length: r.length,
            radius: r.radius,
        })?;
        self.pending = rows.into_inner().map_err(|e| e.into_error())?;
        if self.pending.len() >= CHUNK {
            self.flush()?;
        }
        Ok(())
    }

    /// Sends the rows gathered so far to the file; on failure they are dropped and the file
    /// cut back to the rows it held whole.
    pub fn flush(&mut self) -> io::Result<()> {
        if self.pending.is_empty() {
            return Ok(());
        }
        let sent = self.file.write_all(&self.pending);
        if sent.is_ok() {
            self.crc.update(&self.pending);
        }
        let len = self.pending.len() as u64;
        self.pending.clear();
        match sent {
            Ok(()) => {
                self.written += len;
                Ok(())
            }
            Err(e) => {
                let _ = self.file.set_len(self.written);
                let _ = self.file.seek(SeekFrom::Start(self.written));
                Err(super::named(&self.path, e))
            }
        }
    }
}

/// Why the file at `path` is not the history `mark` was taken of (it is shorter, or its first
/// `mark.bytes` differ), if it is not.
pub fn check_prefix(path: &Path, mark: &Mark) -> Result<(), String> {
    let file = File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut crc = crc32fast::Hasher::new();
    let read = io::copy(&mut file.take(mark.bytes), &mut HashWriter(&mut crc))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    if read < mark.bytes {
        return Err(format!(
            "{} holds {read} bytes, fewer than the {} it had at the checkpoint",
            path.display(),
            mark.bytes
        ));
    }
    if crc.finalize() != mark.crc {
        return Err(format!(
            "the first {} bytes of {} are not the rows the checkpoint's run wrote",
            mark.bytes,
            path.display()
        ));
    }
    Ok(())
}

/// Bytes written into a CRC-32.
struct HashWriter<'a>(&'a mut crc32fast::Hasher);

impl Write for HashWriter<'_> {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        self.0.update(bytes);
        Ok(bytes.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

impl Drop for History {
    /// Rows still gathered when a run ends by an error go out too, as far as the disk takes them.
    fn drop(&mut self) {
        let _ = self.flush();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The columns keep their names and order, and a history reads back by them, floats in
    /// Rust's exponent form.
    #[test]
    fn a_history_reads_back_by_column_name() {
        assert_eq!(
            header().unwrap(),
            "time_s,step,dt_s,depth_m,projectile_velocity_m_s,kinetic_J,internal_J,\
             contact_dissipated_J,energy_error,max_damage,max_plastic_strain,hits,damage_area_m2,\
             plastic_work_J,checkerboard_Pa,contact_impulse_Ns,contact_force_N,nose_impulse_Ns,\
             nose_force_N,projectile_length_m,projectile_radius_m"
        );
        let path =
            std::env::temp_dir().join(format!("penetrate-history-{}.csv", std::process::id()));
        let mut history = History::create(&path).unwrap();
        for (k, time) in [0.0, 1e-6, 2e-6].into_iter().enumerate() {
            let row = Row {
                time,
                step: k as u64,
                contact_impulse: 0.5 * k as f64,
                ..Row::default()
            };
            history.write(&row).unwrap();
        }
        drop(history);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.lines().nth(2).unwrap().starts_with("1e-6,1,0e0,"),
            "{text}"
        );
        let columns = read_columns(
            &path,
            text.as_bytes(),
            &["contact_force_N", "time_s", "step"],
        )
        .unwrap();
        assert_eq!(
            columns,
            vec![
                vec![0.0, 5e5, 5e5],
                vec![0.0, 1e-6, 2e-6],
                vec![0.0, 1.0, 2.0]
            ]
        );
        let _ = std::fs::remove_file(&path);
    }
}
