//! The studies: tooling that runs many scenes and reports on them — the validation report
//! (`validate`), parameter sweeps (`sweep`, and `slurm` for a sweep run as a Slurm job
//! array), the stability suite (`stability`), the speed benchmark (`bench`) and the
//! nose-lining readings (`lining`); the report's PNG plots are `output::plot`'s.
//!
//! They drive the solver only through its public API (`scene::load`, `solver::run`,
//! `Simulation`), as any user of the library would, so nothing in the physics depends on them.

pub mod bench;
pub mod cavity;
pub mod lining;
pub mod slurm;
pub mod stability;
pub mod sweep;
pub mod validate;
