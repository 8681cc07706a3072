//! The CPU reference path: one module per pass of the step, named as the shaders will be.
//! Each pass is a loop over its entities in which every item writes only its own slots, so the
//! rayon-parallel loops give the same bits whatever the thread count.

pub mod concrete;
pub mod contact_detect;
pub mod deviator;
pub mod fem_forces;
pub mod fem_stress;
pub mod integrate;
pub mod neighbours;
pub mod sph_filter;
pub mod sph_forces;
pub mod sph_rates;
pub mod timestep;
pub mod wall;
