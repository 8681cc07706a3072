//! The energy and momentum account: what the state holds, what the run has booked, and the
//! guard that stops a run whose account has come apart.

use super::{Entity, Instability, Model, Moving, RunError, Unstable};

impl Model {
    pub fn kinetic_energy(&self) -> f64 {
        let p = &self.particles;
        let n = &self.projectile.nodes;
        let ke = |m: &[f32], vr: &[f32], vz: &[f32]| -> f64 {
            (0..m.len())
                .map(|i| 0.5 * m[i] as f64 * ((vr[i] as f64).powi(2) + (vz[i] as f64).powi(2)))
                .sum()
        };
        let particles = match &self.reduced {
            Some(t) => t.kinetic,
            None => ke(&p.mass, &p.vr, &p.vz),
        };
        particles + ke(&n.mass, &n.vr, &n.vz)
    }

    pub(super) fn projectile_momentum(&self) -> f64 {
        let n = &self.projectile.nodes;
        (0..n.len())
            .map(|i| n.mass[i] as f64 * n.vz[i] as f64)
            .sum()
    }

    /// Total z-momentum of projectile and target.
    pub fn momentum_z(&self) -> f64 {
        let p = &self.particles;
        self.projectile_momentum()
            + match &self.reduced {
                Some(t) => t.momentum_z,
                None => (0..p.len())
                    .map(|i| p.mass[i] as f64 * p.vz[i] as f64)
                    .sum::<f64>(),
            }
    }

    pub fn internal_target(&self) -> f64 {
        if let Some(t) = &self.reduced {
            return t.internal;
        }
        let p = &self.particles;
        (0..p.len())
            .map(|i| p.mass[i] as f64 * p.energy[i] as f64)
            .sum()
    }

    /// The target's energy as the integrated strain power (`Particles::strain_energy`), J.
    pub fn strain_energy_target(&self) -> f64 {
        let p = &self.particles;
        (0..p.len())
            .map(|i| p.mass[i] as f64 * p.strain_energy[i] as f64)
            .sum()
    }

    pub fn internal_projectile(&self) -> f64 {
        let e = &self.projectile.elements;
        (0..e.len())
            .map(|i| e.volume0[i] as f64 * e.energy[i] as f64)
            .sum()
    }

    /// (E_kin + E_int + dissipated − E₀)/E₀.
    pub fn energy_error(&self) -> f64 {
        let a = &self.account;
        let total = self.kinetic_energy()
            + self.internal_target()
            + self.internal_projectile()
            + a.contact_dissipated
            + a.wall_dissipated;
        (total - a.initial_kinetic) / a.initial_kinetic.max(f64::MIN_POSITIVE)
    }

    pub fn momentum_error(&self) -> f64 {
        let a = &self.account;
        (self.momentum_z() - a.initial_momentum - a.boundary_impulse).abs()
            / a.initial_momentum.abs().max(f64::MIN_POSITIVE)
    }

    /// An error when the energy account has come apart (off by more than [`ENERGY_GUARD`] of
    /// the impact energy, or not a number), or when the target has given back more than that
    /// share of the impact energy beyond what was done on it (its internal energy, the work its
    /// forces did, below −[`ENERGY_GUARD`]: a target that starts at rest and unstressed can
    /// only return what it stored, so its forces are making energy even though the account
    /// books it): the run has blown up somewhere, and the message says when and names the
    /// fastest particle or node. A scene with nothing moving at the start has no impact energy
    /// to measure against and is not checked.
    pub fn check_energy(&self) -> Result<(), RunError> {
        self.energy_guard(self.energy_error())
    }

    /// [`Self::check_energy`] on an energy error already computed (a history row's).
    pub(super) fn energy_guard(&self, error: f64) -> Result<(), RunError> {
        let impact = self.account.initial_kinetic;
        if impact <= 0.0 {
            return Ok(());
        }
        let made = -self.internal_target() / impact;
        let f = self.fastest();
        let fastest = Moving {
            entity: Entity::named(f.what, f.index),
            r: f.r as f64,
            z: self.world_z(f.z),
            speed: f.speed as f64,
        };
        let what = if error.is_nan() || error.abs() > ENERGY_GUARD {
            Unstable::EnergyLost { error, fastest }
        } else if made > ENERGY_GUARD {
            Unstable::EnergyMade {
                share: made,
                fastest,
            }
        } else {
            return Ok(());
        };
        Err(RunError::from(Instability {
            what,
            when: self.when(),
        }))
    }
}

/// Share of the impact energy by which the energy account may be off before a run is stopped
/// as unstable. Every run of the validation and of the stability suite closes it to 0.9 % or
/// better (docs/notes/2026-11-stability-suite.md), so this catches a blow-up, not an
/// inaccuracy.
pub const ENERGY_GUARD: f64 = 0.05;
