//! The passes of one step, as data: a scene's pass list holds only what it needs, in the order
//! they run, and both backends run the list (architecture.md, "Shape of one step").

/// One pass of the step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    Integrate,
    ContactDetect,
    ContactCorrect,
    Neighbours,
    Walls,
    SphRates,
    Concrete,
    SphForces,
    FemStress,
    FemForces,
    WallForces,
}

impl Pass {
    /// The pass's name: its files in `cpu/`, `gpu/` and `shaders/`, and in `summary.json`.
    pub fn name(&self) -> &'static str {
        match self {
            Pass::Integrate => "integrate",
            Pass::ContactDetect => "contact_detect",
            Pass::ContactCorrect => "contact_correct",
            Pass::Neighbours => "neighbours",
            Pass::Walls => "walls",
            Pass::SphRates => "sph_rates",
            Pass::Concrete => "concrete",
            Pass::SphForces => "sph_forces",
            Pass::FemStress => "fem_stress",
            Pass::FemForces => "fem_forces",
            Pass::WallForces => "wall_forces",
        }
    }

    /// A pass of the step's second half: rates, stresses and forces at the configuration the
    /// first half (integration and contact) reached.
    pub fn is_force(&self) -> bool {
        !matches!(
            self,
            Pass::Integrate | Pass::ContactDetect | Pass::ContactCorrect
        )
    }
}

/// The passes a scene needs, in the order they run: the target's (contact, neighbours, SPH
/// rates, concrete, SPH forces) when it has one, the projectile's stress and forces when it
/// deforms (not a rigid λ = 0 projectile), and with `images` (`contact.kernel = "images"`, which
/// needs both) the walls before the rates and their reaction after the projectile's forces.
pub fn for_scene(has_target: bool, deformable: bool, images: bool) -> Vec<Pass> {
    let images = images && has_target && deformable;
    let mut passes = vec![Pass::Integrate];
    if has_target {
        passes.extend([Pass::ContactDetect, Pass::ContactCorrect, Pass::Neighbours]);
        if images {
            passes.push(Pass::Walls);
        }
        passes.extend([Pass::SphRates, Pass::Concrete, Pass::SphForces]);
    }
    if deformable {
        passes.extend([Pass::FemStress, Pass::FemForces]);
    }
    if images {
        passes.push(Pass::WallForces);
    }
    passes
}
