//! penetrate: a steel projectile (axisymmetric FEM) penetrating concrete (axisymmetric SPH),
//! coupled by the sliding-surface algorithm with artificial momentum transport
//! (Song, Cai & Wang 2006). See `docs/physics.md` for the equations and
//! `docs/architecture.md` for the shape of the program.
//!
//! The source tree follows the step: scene (parse, validate) → mesh → materials (pure laws) →
//! state (structure-of-arrays, f32) → passes (`cpu/<pass>.rs`) → contact correction → output.
//! Beside it, `studies` runs many scenes through the public API (validation report, sweeps,
//! stability suite, benchmark) and `cli` holds the subcommands that `main.rs` dispatches to.

pub mod cli;
pub mod contact;
pub mod cpu;
pub mod estimate;
pub mod gpu;
pub mod interrupt;
pub mod kernel;
pub mod materials;
pub mod mesh;
pub mod output;
pub mod pass;
pub mod scene;
pub mod scope;
pub mod solver;
pub mod state;
pub mod studies;
