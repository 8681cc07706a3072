//! Meshers: the projectile (axisymmetric triangles) and the concrete target (SPH lattice).
//!
//! Coordinates are (r, z): r ≥ 0 is the distance from the symmetry axis, z the axial position.
//! The projectile flies along −z; the target's front face is z = 0.

pub mod geometry;
pub mod projectile;
pub mod target;

/// Projectile mesh of linear axisymmetric triangles.
#[derive(Clone, Debug, Default)]
pub struct ProjectileMesh {
    pub node_r: Vec<f32>,
    pub node_z: Vec<f32>,
    /// Lumped ring mass of each node (kg): ρ₀V₀/3 from each element, plus filler mass.
    pub node_mass: Vec<f32>,
    /// Node indices (i, j, m), counter-clockwise in the (r, z) plane (r to the right, z up),
    /// so that 2A = Σ r_i b_i > 0 with b_i = z_j − z_m.
    pub elements: Vec<[u32; 3]>,
    /// Master segments of the sliding surface: the outer boundary edges (edges on r = 0 and
    /// cavity walls excluded).
    pub masters: Vec<MasterSegment>,
    /// Total mass (steel + filler), kg, summed in f64.
    pub total_mass: f64,
    /// Mass of the filler alone (kg).
    pub filler_mass: f64,
}

/// One outer boundary edge A→B of the projectile and the element it belongs to.
/// A and B are ordered so that walking from A to B the projectile's material lies on the left,
/// i.e. the outward normal is (Δz, −Δr)/|AB| with Δ = B − A.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MasterSegment {
    pub element: u32,
    pub a: u32,
    pub b: u32,
    /// The element's third node, C.
    pub c: u32,
}

/// SPH target lattice.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TargetLattice {
    pub r: Vec<f32>,
    pub z: Vec<f32>,
    /// Ring mass ρ₀ · 2π r Δ² (kg).
    pub mass: Vec<f32>,
    /// Particle in the last row at the rear face.
    pub rear: Vec<bool>,
    /// Particle in the last column at the lateral surface.
    pub lateral: Vec<bool>,
    /// The row-by-row index of the particle's lattice site (row k, column i: k · columns + i):
    /// the order the contact applies its hits in, whatever order the particles are stored in.
    pub site: Vec<u32>,
}

/// A mesher refused its input (the scene validator should have caught it first).
#[derive(Clone, Debug, PartialEq)]
pub struct MeshError(pub String);

impl std::fmt::Display for MeshError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for MeshError {}
