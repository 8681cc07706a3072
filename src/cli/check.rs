//! `penetrate check`: a scene validated and sized without running it.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use super::fail;
use crate::scene::{self, Scene};
use crate::{estimate, mesh, solver};

/// `penetrate check`'s arguments.
#[derive(Args)]
pub struct CheckArgs {
    /// Scene file (cases/*.toml)
    case: PathBuf,
    /// Override a scene value, as in `run` (repeatable)
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

/// Prints the resolved scene, counts, step and memory estimate: 0, or 2 where the scene is bad
/// or would not fit.
pub fn check(args: CheckArgs) -> ExitCode {
    let CheckArgs { case, set } = args;
    match scene::load(&case, &set) {
        Ok(s) => match check_report(&s) {
            Ok(report) => {
                print!("{report}");
                ExitCode::SUCCESS
            }
            Err(e) => fail(2, &format!("{}: {e}", case.display())),
        },
        Err(e) => fail(2, &e.to_string()),
    }
}

/// `check`'s line on the lattice column nearest the shank of radius `shank` (m), with a note
/// where it lies within 5 % of the spacing and the projectile is rigid (λ = 0): there such a
/// column made the 277 m/s shot scatter 4 % from one ulp of its speed, against 0.1–0.3 % with
/// the column 0.4–0.5 mm off (docs/limitations.md, "Round-off and single runs"; a deforming
/// projectile scattered as far either way).
fn shank_column_line(shank: f64, spacing: f64, lambda: f64) -> String {
    let (column, gap) = mesh::target::nearest_column(shank, spacing);
    let side = if gap >= 0.0 { "outside" } else { "inside" };
    let mut line = format!(
        "# lattice: the column nearest the shank at r = {:.3} mm, {:.3} mm {side} it ({:.1} % of the spacing)",
        column * 1e3,
        gap.abs() * 1e3,
        100.0 * gap.abs() / spacing
    );
    if lambda == 0.0 && gap.abs() < 0.05 * spacing {
        line += "; with a rigid projectile a column this close to the shank amplifies round-off \
                 (docs/limitations.md): a spacing a few % larger or smaller moves it off";
    }
    line + "\n"
}

/// Below this fraction of the lattice's spacing the projectile's elements take each particle's
/// impulse on a segment shorter than the particle: 1.5 mm elements against a 4 mm lattice
/// overstrained the Forrestal 642 m/s tip (plastic strain 3.4 and damage 1 in 0.5 ms, against
/// 0.017 and 0.003 with the shipped ¾; docs/limitations.md, "The nose cell's mode").
const FINEST_ELEMENT_PER_SPACING: f64 = 0.75;

/// The line `check` prints where the projectile's mesh is much finer than the lattice.
fn fine_mesh_line(element: f64, spacing: f64) -> Option<String> {
    (element < FINEST_ELEMENT_PER_SPACING * spacing).then(|| {
        format!(
            "# contact: elements of {:.2} mm against particles {:.2} mm apart, finer than {} of the \
             spacing: each particle's impulse lands on a segment shorter than it, which can overstrain \
             the tip (docs/limitations.md)\n",
            element * 1e3,
            spacing * 1e3,
            FINEST_ELEMENT_PER_SPACING
        )
    })
}

fn check_report(s: &Scene) -> Result<String, String> {
    let mut out = s.resolved_table();
    estimate::check_fits(s)?;
    match mesh::projectile::build(&s.model_projectile()) {
        Ok(m) => {
            let e = estimate::estimate(s, &m);
            out += &format!(
                "\n# projectile: {} nodes, {} elements, mass {:.4} kg (filler {:.4} kg)\n",
                m.node_r.len(),
                m.elements.len(),
                m.total_mass,
                m.filler_mass
            );
            out += &match &s.wall {
                Some(w) => format!("# target: none, a rigid wall at z = {} m\n", w.z),
                None => format!(
                    "# target: {} particles, {} slaves (approx.)\n",
                    e.particles, e.slaves
                ),
            };
            if let Some(t) = &s.target {
                out += &shank_column_line(s.projectile.diameter / 2.0, t.spacing, s.contact.lambda);
                out += &fine_mesh_line(s.projectile.element_size, t.spacing).unwrap_or_default();
            }
            let cap = if e.dt <= f64::from(solver::MIN_STEP) {
                format!(
                    "; not above {:e} s, under which a run takes its step as collapsed and stops",
                    solver::MIN_STEP
                )
            } else if e.steps > s.run.max_steps {
                format!(
                    "; more than run.max_steps = {}, which would stop the run",
                    s.run.max_steps
                )
            } else {
                String::new()
            };
            let sph = if s.target.is_some() {
                format!(
                    ", SPH {:.3e} at the stiffest EOS tangent up to locking",
                    e.dt_sph
                )
            } else {
                String::new()
            };
            out += &format!(
                "# stable step ≈ {:.3e} s (FEM {:.3e}, its smallest element {:.3e} m high{sph}) → {} steps to end_time{cap}\n",
                e.dt,
                e.dt_fem,
                e.fem_altitude,
                e.steps_text()
            );
            out += &format!("# memory ≈ {:.1} MiB\n", e.bytes as f64 / estimate::MIB);
            out += &format!(
                "# frames: {} to the run's end (none with --no-vtk), ≈ {:.1} MiB of binary VTU\n",
                e.frames,
                e.frames_bytes() / estimate::MIB
            );
            out += &format!(
                "# history: {} rows to the run's end, ≈ {:.1} MiB\n",
                e.history_rows,
                e.history_bytes() / estimate::MIB
            );
        }
        Err(e) => return Err(format!("projectile mesh: {e}")),
    }
    Ok(out)
}
