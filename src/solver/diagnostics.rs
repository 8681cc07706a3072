//! What is measured of the state: the body's depth and extent, damage and strain, why a run
//! should stop, non-finite values, the fastest entity and the site of the smallest step.

use super::{Fresh, Model, Pass, RunError, Simulation};
use crate::cpu;

impl Model {
    /// Penetration depth: how far the nose tip is beyond the original front face z = 0 (m).
    /// The tip is the deepest node of the body ([`Model::attached_nodes`]): debris, free
    /// to run ahead of the body, is not the nose.
    pub fn depth(&self) -> f64 {
        self.body_bounds().depth
    }

    /// Centre-of-mass speed along the flight direction (−z), m/s.
    pub fn projectile_velocity(&self) -> f64 {
        -self.projectile_momentum() / self.projectile.total_mass
    }

    /// (length along z, largest radius) of the projectile, over its attached nodes (as
    /// [`Model::depth`]).
    pub fn projectile_extent(&self) -> (f64, f64) {
        let b = self.body_bounds();
        (b.length, b.radius)
    }

    /// The depth and extent of the body, from one pass over its nodes (the body is found once).
    pub(super) fn body_bounds(&self) -> BodyBounds {
        let n = &self.projectile.nodes;
        let (mut z_min, mut z_max, mut r_max) = (f32::MAX, f32::MIN, 0.0f32);
        for i in self.attached_nodes() {
            z_min = z_min.min(n.z[i]);
            z_max = z_max.max(n.z[i]);
            r_max = r_max.max(n.r[i]);
        }
        BodyBounds {
            depth: match self.scene.target {
                Some(_) => (-self.world_z(z_min)).max(0.0),
                None => 0.0,
            },
            length: (z_max - z_min) as f64,
            radius: r_max as f64,
        }
    }

    /// The nodes of the projectile's body: the largest set (by reference volume) of elements
    /// that have not failed, joined through shared nodes. A node whose elements have all failed
    /// is debris, and so is a piece still intact but held to the body only by failed elements
    /// (a broken-off tip). Every node if every element has failed (nothing is left to tell the
    /// body from its debris).
    pub(super) fn attached_nodes(&self) -> impl Iterator<Item = usize> + '_ {
        let body = body_nodes(
            &self.projectile.elements.nodes,
            &self.projectile.elements.failed,
            &self.projectile.elements.volume0,
            self.projectile.nodes.len(),
        );
        (0..self.projectile.nodes.len()).filter(move |&i| body[i])
    }

    pub fn max_damage(&self) -> f64 {
        self.projectile
            .elements
            .damage
            .iter()
            .copied()
            .fold(0.0f32, f32::max) as f64
    }

    /// Largest damage over the elements that started behind the nose (the shank; for a shell,
    /// its wall): the nose's surface elements, which fail at any speed here, left out.
    pub fn max_damage_shank(&self) -> f64 {
        self.shank_max(&self.projectile.elements.damage)
    }

    /// Largest plastic strain over the same elements: the body's deformation, the failed nose
    /// elements' strain left out.
    pub fn max_plastic_strain_shank(&self) -> f64 {
        self.shank_max(&self.projectile.elements.eps_p)
    }

    pub(super) fn shank_max(&self, values: &[f32]) -> f64 {
        self.shank
            .iter()
            .map(|&e| values[e as usize])
            .fold(0.0f32, f32::max) as f64
    }

    /// Σ damage × r–z area over the projectile's elements in the current configuration (m²):
    /// the failed part of its section, partial damage counted by its share (the shell study's
    /// damaged area, paper Fig. 9).
    pub fn damage_area(&self) -> f64 {
        let n = &self.projectile.nodes;
        let e = &self.projectile.elements;
        let at = |k: u32| (n.r[k as usize] as f64, n.z[k as usize] as f64);
        e.nodes
            .iter()
            .zip(&e.damage)
            .filter(|(_, &d)| d > 0.0)
            .map(|(&[i, j, m], &d)| {
                let ((ri, zi), (rj, zj), (rm, zm)) = (at(i), at(j), at(m));
                let area = 0.5 * ((rj - ri) * (zm - zi) - (rm - ri) * (zj - zi));
                d as f64 * area.abs()
            })
            // Not `sum`, whose empty total is −0, which the history would print as "-0e0".
            .fold(0.0, |total, a| total + a)
    }

    pub fn max_plastic_strain(&self) -> f64 {
        self.projectile
            .elements
            .eps_p
            .iter()
            .copied()
            .fold(0.0f32, f32::max) as f64
    }

    /// Why the run should stop now, if it should. Reads of the state only the nodes' z and
    /// v_z: all that a GPU step leaves current on the host (`Fresh::Nodes`).
    pub(super) fn stop_reason(&self) -> Option<&'static str> {
        if self.time >= self.scene.run.end_time {
            return Some(crate::output::summary::END_TIME_REACHED);
        }
        if self.scene.run.stop_at_rest {
            if let Some(t) = &self.scene.target {
                let v = self.projectile_velocity();
                if self.step > 10 && v <= 0.0 {
                    return Some("projectile at rest");
                }
                let z_max = self
                    .projectile
                    .nodes
                    .z
                    .iter()
                    .copied()
                    .fold(f32::MIN, f32::max);
                if self.world_z(z_max) < -t.thickness {
                    return Some(crate::output::summary::PERFORATED);
                }
            }
        }
        None
    }

    /// Non-finite values in the state: positions, velocities, density, energy, pressure and
    /// deviator of the particles; positions and velocities of the nodes; stresses and energy
    /// of the elements.
    pub fn nonfinite_values(&self) -> usize {
        let p = &self.particles;
        let n = &self.projectile.nodes;
        let e = &self.projectile.elements;
        let fields: [&[f32]; 20] = [
            &p.r, &p.z, &p.vr, &p.vz, &p.rho, &p.energy, &p.p, &p.s_rr, &p.s_zz, &p.s_rz, &p.s_tt,
            &n.r, &n.z, &n.vr, &n.vz, &e.s_rr, &e.s_zz, &e.s_rz, &e.p, &e.energy,
        ];
        fields
            .iter()
            .map(|f| f.iter().filter(|x| !x.is_finite()).count())
            .sum()
    }

    /// Particles whose density is at the floor the continuity update holds it to.
    pub fn particles_at_density_floor(&self) -> usize {
        self.sph.as_ref().map_or(0, |sph| {
            let floor = crate::cpu::concrete::density_floor(&sph.concrete);
            self.particles
                .rho
                .iter()
                .filter(|&&rho| rho <= floor)
                .count()
        })
    }

    /// Mass (kg) of the particles more than one spacing in front of the front face (z = 0) and
    /// behind the rear face (z = −thickness): concrete spalled off the entry face and scabbed
    /// off the rear one. Zero without a target.
    pub fn ejecta(&self) -> [f64; 2] {
        let Some(t) = &self.scene.target else {
            return [0.0; 2];
        };
        let p = &self.particles;
        let mut out = [0.0; 2];
        for (&z, &m) in p.z.iter().zip(&p.mass) {
            let z = self.world_z(z);
            if z > t.spacing {
                out[0] += f64::from(m);
            } else if z < -t.thickness - t.spacing {
                out[1] += f64::from(m);
            }
        }
        out
    }

    /// Largest speed of a particle or node (m/s).
    pub fn max_speed(&self) -> f64 {
        self.fastest().speed as f64
    }

    /// The fastest particle or node.
    pub(super) fn fastest(&self) -> Fastest {
        let p = &self.particles;
        let n = &self.projectile.nodes;
        // Nothing at rest is anybody's fastest.
        let nobody = |what| Fastest {
            what,
            index: 0,
            r: f32::NAN,
            z: f32::NAN,
            speed: 0.0,
        };
        let find = |what, r: &[f32], z: &[f32], vr: &[f32], vz: &[f32]| {
            (0..vr.len()).fold(nobody(what), |f, i| {
                let speed = vr[i].hypot(vz[i]);
                if speed > f.speed {
                    Fastest {
                        what,
                        index: i,
                        r: r[i],
                        z: z[i],
                        speed,
                    }
                } else {
                    f
                }
            })
        };
        let a = match &self.reduced {
            Some(t) => t
                .fastest
                .map_or(nobody("particle"), |(index, r, z, speed)| Fastest {
                    what: "particle",
                    index,
                    r,
                    z,
                    speed,
                }),
            None => find("particle", &p.r, &p.z, &p.vr, &p.vz),
        };
        let b = find("node", &n.r, &n.z, &n.vr, &n.vz);
        if b.speed > a.speed {
            b
        } else {
            a
        }
    }

    /// Where the step is smallest: the element or particle whose own stable step is the least,
    /// where it is and the state that made it so (a crushed element, a compressed particle).
    /// Reads the CPU copy of the state, which a GPU run must have downloaded.
    pub(super) fn smallest_step_site(&self) -> String {
        let mut site: Option<(f32, String)> = None;
        let mut offer = |dt: f32, what: &dyn Fn() -> String| {
            if site.as_ref().is_none_or(|s| dt < s.0) {
                site = Some((dt, what()));
            }
        };
        if self.has(Pass::FemStress) {
            let e = &self.projectile.elements;
            let n = &self.projectile.nodes;
            if let Some(k) = (0..e.len()).min_by(|&a, &b| e.dt[a].total_cmp(&e.dt[b])) {
                offer(e.dt[k], &|| {
                    let el = e.nodes[k];
                    let c = |v: &[f32]| el.iter().map(|&i| v[i as usize]).sum::<f32>() / 3.0;
                    let volume = crate::mesh::geometry::Geometry::new(&el, &n.r, &n.z).volume();
                    format!(
                        "element {k} has the smallest stable step, {:e} s, at (r {:.4e}, \
                         z {:.4e}) m: {:.3e} of its initial volume, plastic strain {:.3}, \
                         damage {:.2}{}",
                        e.dt[k],
                        c(&n.r),
                        self.world_z(c(&n.z)),
                        volume / e.volume0[k],
                        e.eps_p[k],
                        e.damage[k],
                        if e.failed[k] != 0 { ", failed" } else { "" }
                    )
                });
            }
        }
        if let Some(sph) = &self.sph {
            let p = &self.particles;
            let step = |i: usize| cpu::timestep::particle_step(p, sph, i);
            if let Some(i) = (0..p.len()).min_by(|&a, &b| step(a).total_cmp(&step(b))) {
                offer(step(i), &|| {
                    format!(
                        "particle {i} has the smallest stable step, {:e} s, at (r {:.4e}, \
                         z {:.4e}) m: density {:.4e} kg/m³, sound speed {:.0} m/s, speed {:.0} \
                         m/s",
                        step(i),
                        p.r[i],
                        self.world_z(p.z[i]),
                        p.rho[i],
                        p.sound[i],
                        p.vr[i].hypot(p.vz[i])
                    )
                });
            }
        }
        site.map_or_else(|| "nothing sets it".into(), |s| s.1)
    }

    /// Count the slaves left inside the projectile (beyond 10⁻⁴ of an element: round-off of
    /// the correction's projection) and book the worst in the account.
    pub(super) fn check_slaves_inside(&mut self) {
        if self.slaves.is_empty() {
            return;
        }
        let tol = 1.0e-4 * self.scene.projectile.element_size as f32;
        let (n, depth) = cpu::contact_detect::inside(
            &self.slaves,
            &self.particles,
            &self.projectile.nodes,
            &self.projectile.masters,
            tol,
        );
        let a = &mut self.account;
        a.slaves_inside = a.slaves_inside.max(n);
        a.max_residual_penetration = a.max_residual_penetration.max(depth);
    }
}

/// The body's depth beyond the target's face and its extent (m, [`Model::body_bounds`]).
pub(super) struct BodyBounds {
    pub(super) depth: f64,
    pub(super) length: f64,
    pub(super) radius: f64,
}

/// The fastest particle or node, for the message of a run that blew up.
#[derive(Clone, Copy)]
pub(super) struct Fastest {
    pub(super) what: &'static str,
    pub(super) index: usize,
    pub(super) r: f32,
    pub(super) z: f32,
    pub(super) speed: f32,
}

/// Which nodes belong to the body: the largest set, by reference volume, of elements that have
/// not failed and are joined through shared nodes (union–find over the nodes). Every node when
/// every element has failed.
pub(super) fn body_nodes(
    conn: &[[u32; 3]],
    failed: &[u32],
    volume0: &[f32],
    n_nodes: usize,
) -> Vec<bool> {
    if !failed.contains(&0) {
        return vec![true; n_nodes];
    }
    let mut parent: Vec<usize> = (0..n_nodes).collect();
    pub(super) fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let intact = || (0..conn.len()).filter(|&e| failed[e] == 0);
    for e in intact() {
        let a = root(&mut parent, conn[e][0] as usize);
        for &n in &conn[e][1..] {
            let b = root(&mut parent, n as usize);
            parent[b] = a;
        }
    }
    let mut volume = vec![0.0f64; n_nodes];
    for e in intact() {
        let a = root(&mut parent, conn[e][0] as usize);
        volume[a] += volume0[e] as f64;
    }
    let body = (0..n_nodes)
        .max_by(|&a, &b| volume[a].total_cmp(&volume[b]))
        .unwrap_or(0);
    let mut held = vec![false; n_nodes];
    for e in intact() {
        for &n in &conn[e] {
            held[n as usize] = true;
        }
    }
    (0..n_nodes)
        .map(|i| held[i] && root(&mut parent, i) == body)
        .collect()
}

impl Simulation {
    /// [`Model::check_slaves_inside`] on the positions a history row reads, brought up to
    /// date first.
    pub(super) fn check_slaves_inside(&mut self) -> Result<(), RunError> {
        self.current(Fresh::History)?.check_slaves_inside();
        Ok(())
    }
}
