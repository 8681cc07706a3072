//! Material laws as small pure functions, each with its equation number from `physics.md`.

pub mod hjc;
pub mod johnson_cook;
pub mod steel_eos;
