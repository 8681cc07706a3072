//! `history.csv`: one row per history interval.

use std::fmt::Write as _;
use std::fs::File;
use std::io::{self, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// One row of the time series.
#[derive(Clone, Copy, Debug, Default)]
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

pub const HEADER: &str = "time_s,step,dt_s,depth_m,projectile_velocity_m_s,kinetic_J,internal_J,contact_dissipated_J,energy_error,max_damage,max_plastic_strain,hits,damage_area_m2,plastic_work_J,checkerboard_Pa,contact_impulse_Ns,contact_force_N,nose_impulse_Ns,nose_force_N,projectile_length_m,projectile_radius_m";

/// Rows gathered before they go to the file together.
const CHUNK: usize = 8192;

/// The file of the time series. It ends on a whole row whatever happens: rows go out in whole
/// chunks, and a chunk the disk could not take is cut off again (`set_len`), so a run stopped
/// by a full disk leaves every row it wrote readable.
pub struct History {
    file: File,
    path: PathBuf,
    pending: String,
    /// Bytes of whole rows in the file.
    written: u64,
    /// The last row written and its mean contact and nose forces (N).
    last: Option<(Row, f64, f64)>,
}

impl History {
    pub fn create(path: &Path) -> io::Result<History> {
        let file = File::create(path).map_err(|e| super::named(path, e))?;
        let mut history = History {
            file,
            path: path.to_path_buf(),
            pending: format!("{HEADER}\n"),
            written: 0,
            last: None,
        };
        history.flush()?;
        Ok(history)
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
        let _ = writeln!(
            self.pending,
            "{:e},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
            r.time,
            r.step,
            r.dt,
            r.depth,
            r.velocity,
            r.kinetic,
            r.internal,
            r.contact_dissipated,
            r.energy_error,
            r.max_damage,
            r.max_plastic_strain,
            r.hits,
            r.damage_area,
            r.plastic_work,
            r.checkerboard,
            r.contact_impulse,
            force,
            r.nose_impulse,
            nose_force,
            r.length,
            r.radius
        );
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
        let sent = self.file.write_all(self.pending.as_bytes());
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

impl Drop for History {
    /// Rows still gathered when a run ends by an error go out too, as far as the disk takes them.
    fn drop(&mut self) {
        let _ = self.flush();
    }
}
