//! Target lattice (in progress).
