//! `history.csv`: one row per history interval.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

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
}

pub const HEADER: &str = "time_s,step,dt_s,depth_m,projectile_velocity_m_s,kinetic_J,internal_J,contact_dissipated_J,energy_error,max_damage,max_plastic_strain,hits,damage_area_m2,plastic_work_J,checkerboard_Pa";

pub struct History {
    out: BufWriter<File>,
}

impl History {
    pub fn create(path: &Path) -> io::Result<History> {
        let mut out = BufWriter::new(File::create(path)?);
        writeln!(out, "{HEADER}")?;
        Ok(History { out })
    }

    pub fn write(&mut self, r: &Row) -> io::Result<()> {
        writeln!(
            self.out,
            "{:e},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{:e},{:e},{:e}",
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
            r.checkerboard
        )
    }

    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}
