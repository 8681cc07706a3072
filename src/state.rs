//! Simulation state as structures of arrays (f32), laid out as the GPU buffers will be.
//! Global sums (time, energies, momenta) are kept in f64 by the solver, not here.

use crate::materials::flow::{flow_stress, Strength};
use crate::materials::hjc::Hjc;
use crate::materials::johnson_cook::JcDamage;
use crate::materials::steel_eos::PolyEos;
use crate::mesh::{MasterSegment, ProjectileMesh, TargetLattice};
use crate::scene::{SteelMaterial, TargetSpec, ViscosityJump};

/// SPH particles of the concrete target. Masses are whole-ring masses.
#[derive(Clone, Debug, Default)]
pub struct Particles {
    pub r: Vec<f32>,
    pub z: Vec<f32>,
    pub vr: Vec<f32>,
    pub vz: Vec<f32>,
    pub ar: Vec<f32>,
    pub az: Vec<f32>,
    pub mass: Vec<f32>,
    pub rho: Vec<f32>,
    /// Specific internal energy (J/kg): the work the particle forces have done, split pairwise
    /// (`sph_forces`, booked by `integrate`), so that it is the exact counterpart of the motion.
    pub energy: Vec<f32>,
    /// The same energy as the strain power `σ:ε̇/ρ` of the velocity gradient L plus the viscous
    /// heating (physics.md §3), integrated by `concrete`: a diagnostic only (HJC's
    /// pressure does not depend on the energy), reported beside the account.
    pub strain_energy: Vec<f32>,
    /// Pressure (Pa, compression positive).
    pub p: Vec<f32>,
    /// Stress deviator S_rr, S_zz, S_rz, S_θθ (Pa).
    pub s_rr: Vec<f32>,
    pub s_zz: Vec<f32>,
    pub s_rz: Vec<f32>,
    pub s_tt: Vec<f32>,
    pub damage: Vec<f32>,
    /// Largest volumetric strain μ reached (HJC crushing history).
    pub mu_max: Vec<f32>,
    /// Equivalent plastic strain.
    pub eps_p: Vec<f32>,
    pub sound: Vec<f32>,
    /// Velocity gradient L_ab = ∂v_a/∂x_b from `sph_rates`: rr, rz, zr, zz.
    pub l_rr: Vec<f32>,
    pub l_rz: Vec<f32>,
    pub l_zr: Vec<f32>,
    pub l_zz: Vec<f32>,
    /// Density rate from `sph_rates`.
    pub drho: Vec<f32>,
    /// Viscous heating rate (W/kg) and the largest viscosity μ_ij, from `sph_forces`.
    pub de_visc: Vec<f32>,
    /// Rate of the work-conjugate energy (W/kg), from `sph_forces`, at its velocities.
    pub de_work: Vec<f32>,
    pub mu_visc: Vec<f32>,
    /// The factor on this particle's viscosity, from `sph_rates`: 1 without a switch, the
    /// Balsara factor `|∇·v|/(|∇·v| + |∇×v| + 10⁻⁴ c/h)` with `target.viscosity_switch =
    /// "balsara"`. A pair's Π is scaled by the mean of its two factors.
    pub visc_switch: Vec<f32>,
    /// Per-radian-area mass m̃ = m/(2π r) and planar area m̃/ρ, from `sph_rates`.
    pub m_tilde: Vec<f32>,
    pub area: Vec<f32>,
    /// The hoop weight `n_i = Σ_j m̃_j (w_i + w_j − 2 r_i) ∂_r W_ij / ρ_i` (≈ 1; about ½ at a
    /// free face normal to r), from `sph_rates`: the hoop source's weight in `sph_forces`, and
    /// with the conjugate gradient the weight on the hoop rate `v_r/r` as well.
    pub hoop_weight: Vec<f32>,
    /// The corrected velocity gradient (rr, rz, zr, zz) whose slopes the viscosity's
    /// reconstruction takes, from `sph_rates`; empty unless `target.viscosity_jump =
    /// "reconstructed"` (`from_lattice`).
    pub l_visc: Vec<[f32; 4]>,
    /// Total stress over ρ² (rr, zz, rz) and the Gray–Monaghan artificial stress, from the
    /// start of `sph_forces`.
    pub stress_rho2: Vec<[f32; 3]>,
    pub art_stress: Vec<[f32; 3]>,
    /// 1 where the particle is held at zero velocity (fixed boundary).
    pub fixed: Vec<u32>,
}

impl Particles {
    pub fn len(&self) -> usize {
        self.r.len()
    }

    pub fn is_empty(&self) -> bool {
        self.r.is_empty()
    }

    /// Particles at rest, at the reference density, from the lattice.
    pub fn from_lattice(lattice: &TargetLattice, spec: &TargetSpec) -> Particles {
        let fixed = (0..lattice.r.len())
            .map(|i| {
                u32::from(
                    (spec.fix_rear && lattice.rear[i]) || (spec.fix_lateral && lattice.lateral[i]),
                )
            })
            .collect();
        let mut p = Particles::at_rest(lattice, &spec.concrete, fixed);
        // Only the reconstructed viscosity reads the corrected gradients: keep none otherwise
        // (16 bytes a particle, on the GPU, in every full read-back and in checkpoints).
        if spec.viscosity_jump != ViscosityJump::Reconstructed {
            p.l_visc = Vec::new();
        }
        p
    }

    /// Particles of `concrete` at rest, at its reference density, at the lattice's places;
    /// `fixed` as the field of that name.
    pub fn at_rest(
        lattice: &TargetLattice,
        concrete: &crate::materials::hjc::Hjc,
        fixed: Vec<u32>,
    ) -> Particles {
        let n = lattice.r.len();
        let zero = vec![0.0f32; n];
        let c0 = crate::materials::hjc::sound_speed(concrete, concrete.p_crush / concrete.mu_crush);
        Particles {
            r: lattice.r.clone(),
            z: lattice.z.clone(),
            vr: zero.clone(),
            vz: zero.clone(),
            ar: zero.clone(),
            az: zero.clone(),
            mass: lattice.mass.clone(),
            rho: vec![concrete.density; n],
            energy: zero.clone(),
            strain_energy: zero.clone(),
            p: zero.clone(),
            s_rr: zero.clone(),
            s_zz: zero.clone(),
            s_rz: zero.clone(),
            s_tt: zero.clone(),
            damage: zero.clone(),
            mu_max: zero.clone(),
            eps_p: zero.clone(),
            sound: vec![c0; n],
            l_rr: zero.clone(),
            l_rz: zero.clone(),
            l_zr: zero.clone(),
            l_zz: zero.clone(),
            drho: zero.clone(),
            de_visc: zero.clone(),
            de_work: zero.clone(),
            mu_visc: zero.clone(),
            visc_switch: vec![1.0; n],
            m_tilde: zero.clone(),
            area: zero,
            hoop_weight: vec![1.0; n],
            l_visc: vec![[0.0; 4]; n],
            stress_rho2: vec![[0.0; 3]; n],
            art_stress: vec![[0.0; 3]; n],
            fixed,
        }
    }
}

/// Constants of the target that every SPH pass reads (a uniform buffer on the GPU).
#[derive(Clone, Copy, Debug)]
pub struct SphParams {
    pub h: f32,
    pub kernel: crate::kernel::Kernel,
    pub concrete: Hjc,
    pub alpha: f32,
    pub beta: f32,
    /// Scale Π by the Balsara switch (`target.viscosity_switch = "balsara"`).
    pub balsara: bool,
    /// Π reads the reconstructed velocity jump (`target.viscosity_jump = "reconstructed"`,
    /// `cpu::sph_forces`), with the corrected gradients `Particles::l_visc`.
    pub reconstruct_viscosity: bool,
    /// Take L from the filtered velocity (`target.velocity_filter = "linear"`,
    /// `cpu::sph_rates`).
    pub velocity_filter: bool,
    /// Take L as the conjugate gradient (`target.velocity_gradient = "conjugate"`,
    /// `cpu::sph_rates`) instead of the corrected one.
    pub conjugate_gradient: bool,
    /// Gray–Monaghan artificial stress factor ε (0 = off) and exponent n.
    pub art_stress_eps: f32,
    pub art_stress_n: f32,
    /// W(Δ, h): the reference kernel value of the artificial stress.
    pub w_spacing: f32,
    /// How the concrete fails in tension (`target.tension`; the crack band is one spacing).
    pub tension: crate::materials::hjc::Tension,
}

impl SphParams {
    pub fn new(spec: &TargetSpec) -> SphParams {
        let h = (spec.spacing * spec.smoothing_ratio) as f32;
        let kernel = crate::kernel::Kernel::new(h);
        SphParams {
            h,
            kernel,
            concrete: spec.concrete,
            alpha: spec.viscosity_alpha as f32,
            beta: spec.viscosity_beta as f32,
            balsara: spec.viscosity_switch == crate::scene::ViscositySwitch::Balsara,
            reconstruct_viscosity: spec.viscosity_jump
                == crate::scene::ViscosityJump::Reconstructed,
            velocity_filter: spec.velocity_filter == crate::scene::VelocityFilter::Linear,
            conjugate_gradient: spec.velocity_gradient == crate::scene::VelocityGradient::Conjugate,
            art_stress_eps: if spec.artificial_stress { 0.3 } else { 0.0 },
            art_stress_n: 4.0,
            w_spacing: kernel.w(spec.spacing as f32),
            tension: match spec.tension {
                crate::scene::TensionModel::Static => crate::materials::hjc::Tension::Static,
                crate::scene::TensionModel::CrackBand => {
                    crate::materials::hjc::Tension::CrackBand {
                        band: spec.spacing as f32,
                    }
                }
            },
        }
    }
}

/// Projectile nodes. Masses are whole-ring lumped masses; forces are totals over the ring.
#[derive(Clone, Debug, Default)]
pub struct Nodes {
    pub r: Vec<f32>,
    pub z: Vec<f32>,
    pub vr: Vec<f32>,
    pub vz: Vec<f32>,
    pub fr: Vec<f32>,
    pub fz: Vec<f32>,
    pub mass: Vec<f32>,
    /// 1 for nodes on the axis (ṙ = 0 there).
    pub on_axis: Vec<u32>,
    /// Node → element CSR: `elems[offsets[n]..offsets[n+1]]` holds `3·element + local index`.
    pub elem_offsets: Vec<u32>,
    pub elem_refs: Vec<u32>,
}

impl Nodes {
    pub fn len(&self) -> usize {
        self.r.len()
    }

    pub fn is_empty(&self) -> bool {
        self.r.is_empty()
    }
}

/// Projectile elements (linear triangles) and their state.
#[derive(Clone, Debug, Default)]
pub struct Elements {
    pub nodes: Vec<[u32; 3]>,
    /// Pressure cells as offsets: cell c is elements `cells[c]..cells[c + 1]`, which share one
    /// pressure (docs/physics.md §2.4): the mesh's cells (`Elements::pressure_cells`) with
    /// `projectile.cell_pressure`, else one per element. Static.
    pub cells: Vec<u32>,
    /// Reference ring volume V₀ (m³).
    pub volume0: Vec<f32>,
    pub s_rr: Vec<f32>,
    pub s_zz: Vec<f32>,
    pub s_rz: Vec<f32>,
    pub s_tt: Vec<f32>,
    /// EOS pressure (Pa) without the bulk viscosity.
    pub p: Vec<f32>,
    /// Internal energy per unit reference volume (J/m³).
    pub energy: Vec<f32>,
    pub eps_p: Vec<f32>,
    pub temperature: Vec<f32>,
    pub damage: Vec<f32>,
    /// 1 once the element has failed (damage or spall).
    pub failed: Vec<u32>,
    /// Nodal forces this element exerts on (i, j, m): r_i, z_i, r_j, z_j, r_m, z_m.
    pub force: Vec<[f32; 6]>,
    /// Stable time step of the element from the last stress pass.
    pub dt: Vec<f32>,
    /// Plastic work done in the last step (J), for the energy account.
    pub plastic_work: Vec<f32>,
}

impl Elements {
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The pressure cells of a mesh, as offsets (see `cells`): each run of consecutive elements
    /// whose third node is the same and used by no other element (a crossed-triangle cell's
    /// centre, in the mesher's order) is one cell; every other element is a cell of its own.
    pub fn pressure_cells(conn: &[[u32; 3]]) -> Vec<u32> {
        let n_nodes = conn.iter().flatten().map(|&n| n as usize + 1).max();
        let mut uses = vec![0usize; n_nodes.unwrap_or(0)];
        for &n in conn.iter().flatten() {
            uses[n as usize] += 1;
        }
        let mut cells = vec![0u32];
        let mut e = 0;
        while e < conn.len() {
            let centre = conn[e][2];
            let run = conn[e..].iter().take_while(|el| el[2] == centre).count();
            let len = if uses[centre as usize] == run { run } else { 1 };
            e += len;
            cells.push(e as u32);
        }
        cells
    }

    /// The mesh's intact four-triangle cells (none failed), as element ranges, whether or not
    /// they share a pressure: where a cell can take the + − + − pattern of `max_checkerboard`
    /// and `max_volume_checkerboard`.
    fn intact_quads(&self) -> Vec<std::ops::Range<usize>> {
        Self::pressure_cells(&self.nodes)
            .windows(2)
            .map(|w| w[0] as usize..w[1] as usize)
            .filter(|c| c.len() == 4 && self.failed[c.clone()].iter().all(|&f| f == 0))
            .collect()
    }

    /// The largest alternation of the triangles' relative volumes J = V/V₀ inside one intact
    /// four-triangle cell, |J₀ − J₁ + J₂ − J₃|/4: the cell mode itself, of which a shared
    /// pressure (docs/physics.md §2.4) shows only the mode stiffness's share as a pressure
    /// swing. K₁ times it is the swing each triangle's own pressure would have.
    pub fn max_volume_checkerboard(&self, nodes: &Nodes) -> f32 {
        let j = |k: usize| {
            crate::mesh::geometry::Geometry::new(&self.nodes[k], &nodes.r, &nodes.z).volume()
                / self.volume0[k]
        };
        self.intact_quads()
            .into_iter()
            .map(|c| ((j(c.start) - j(c.start + 1) + j(c.start + 2) - j(c.start + 3)) / 4.0).abs())
            .fold(0.0, f32::max)
    }

    /// The largest pressure checkerboard inside one intact four-triangle cell (Pa),
    /// |p₀ − p₁ + p₂ − p₃|/4. Where the triangles share one pressure (docs/physics.md §2.4)
    /// only the mode stiffness's term, `CELL_MODE_STIFFNESS` K times the volume alternation;
    /// else a smooth field gives little and a cell whose triangles take alternating volumes
    /// its pressure swing. 0 without such cells.
    pub fn max_checkerboard(&self) -> f32 {
        self.pressure_alternations()
            .map(|(_, swing)| swing)
            .fold(0.0, f32::max)
    }

    /// The largest pressure checkerboard of a cell as a fraction of the cell's strength: the
    /// mean of its triangles' quasi-static flow stress (at their plastic strain and
    /// temperature, the reference strain rate), the scale against which a spurious mode has to
    /// be small. Cells with no strength left (at melt) are left out. 0 without such cells.
    pub fn max_checkerboard_over_flow(&self, strength: &Strength) -> f32 {
        self.pressure_alternations()
            .filter_map(|(c, swing)| {
                let flow = c
                    .map(|e| {
                        flow_stress(
                            strength,
                            self.eps_p[e],
                            strength.eps_rate_ref,
                            self.temperature[e],
                        )
                    })
                    .sum::<f32>()
                    / 4.0;
                (flow > 0.0).then(|| swing / flow)
            })
            .fold(0.0, f32::max)
    }

    /// Each intact cell's elements and pressure checkerboard |p₀ − p₁ + p₂ − p₃|/4 (Pa).
    fn pressure_alternations(&self) -> impl Iterator<Item = (std::ops::Range<usize>, f32)> + '_ {
        self.intact_quads().into_iter().map(|c| {
            let p = &self.p[c.clone()];
            (c, ((p[0] - p[1] + p[2] - p[3]) / 4.0).abs())
        })
    }
}

/// Projectile material constants that the FEM passes read (a uniform buffer on the GPU).
#[derive(Clone, Copy, Debug)]
pub struct FemParams {
    pub density: f32,
    pub shear_modulus: f32,
    pub specific_heat: f32,
    pub taylor_quinney: f32,
    pub strength: Strength,
    pub eos: PolyEos,
    pub damage: Option<JcDamage>,
    /// Bulk viscosity: quadratic and linear coefficients.
    pub q_quad: f32,
    pub q_lin: f32,
    /// Newton iterations of the radial return, on both paths (1 = the single linearised step
    /// of physics.md §2.1).
    pub return_iterations: u32,
}

impl FemParams {
    pub fn new(m: &SteelMaterial) -> FemParams {
        FemParams {
            density: m.density as f32,
            shear_modulus: (m.youngs_modulus / (2.0 * (1.0 + m.poisson_ratio))) as f32,
            specific_heat: m.specific_heat as f32,
            taylor_quinney: m.taylor_quinney as f32,
            strength: m.strength,
            eos: m.eos,
            damage: m.damage,
            // LS-DYNA's defaults Q1 = 1.5, Q2 = 0.06 (physics.md §2).
            q_quad: 1.5,
            q_lin: 0.06,
            // Bracketed Newton: 2–4 iterations once hardened, up to ~30 at first yield
            // (materials::flow::radial_return).
            return_iterations: 30,
        }
    }
}

/// The projectile: nodes, elements and the master segments of the sliding surface.
#[derive(Clone, Debug, Default)]
pub struct Projectile {
    pub nodes: Nodes,
    pub elements: Elements,
    pub masters: Vec<MasterSegment>,
    /// Total mass M (kg).
    pub total_mass: f64,
}

impl Projectile {
    /// Projectile at rest in its reference state, moving at `velocity` along −z, at `t_room`;
    /// `cell_pressure`: the mesh's cells share one pressure (else each element is its own cell).
    pub fn from_mesh(
        mesh: &ProjectileMesh,
        velocity: f32,
        t_room: f32,
        cell_pressure: bool,
    ) -> Projectile {
        let nn = mesh.node_r.len();
        let ne = mesh.elements.len();
        let mut counts = vec![0u32; nn + 1];
        for el in &mesh.elements {
            for &n in el {
                counts[n as usize + 1] += 1;
            }
        }
        for i in 0..nn {
            counts[i + 1] += counts[i];
        }
        let offsets = counts.clone();
        let mut fill = counts;
        let mut refs = vec![0u32; offsets[nn] as usize];
        for (e, el) in mesh.elements.iter().enumerate() {
            for (local, &n) in el.iter().enumerate() {
                refs[fill[n as usize] as usize] = 3 * e as u32 + local as u32;
                fill[n as usize] += 1;
            }
        }
        let volume0 = mesh
            .elements
            .iter()
            .map(|el| {
                let g = crate::mesh::geometry::Geometry::new(el, &mesh.node_r, &mesh.node_z);
                g.volume()
            })
            .collect();
        let zero = vec![0.0f32; ne];
        Projectile {
            nodes: Nodes {
                r: mesh.node_r.clone(),
                z: mesh.node_z.clone(),
                vr: vec![0.0; nn],
                vz: vec![-velocity; nn],
                fr: vec![0.0; nn],
                fz: vec![0.0; nn],
                mass: mesh.node_mass.clone(),
                on_axis: mesh.node_r.iter().map(|&r| u32::from(r == 0.0)).collect(),
                elem_offsets: offsets,
                elem_refs: refs,
            },
            elements: Elements {
                nodes: mesh.elements.clone(),
                cells: if cell_pressure {
                    Elements::pressure_cells(&mesh.elements)
                } else {
                    (0..=ne as u32).collect()
                },
                volume0,
                s_rr: zero.clone(),
                s_zz: zero.clone(),
                s_rz: zero.clone(),
                s_tt: zero.clone(),
                p: zero.clone(),
                energy: zero.clone(),
                eps_p: zero.clone(),
                temperature: vec![t_room; ne],
                damage: zero.clone(),
                failed: vec![0; ne],
                force: vec![[0.0; 6]; ne],
                dt: vec![f32::MAX; ne],
                plastic_work: zero,
            },
            masters: mesh.masters.clone(),
            total_mass: mesh.total_mass,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The corrected gradients are kept exactly where the viscosity reads them.
    #[test]
    fn corrected_gradients_only_with_the_reconstructed_viscosity() {
        for (jump, kept) in [("raw", false), ("reconstructed", true)] {
            let set = format!("target.viscosity_jump=\"{jump}\"");
            let scene = crate::scene::tests::smoke(&[&set]).unwrap();
            let t = scene.target.as_ref().unwrap();
            let lattice =
                crate::mesh::target::lattice(t.radius, t.thickness, t.spacing, 2400.0).unwrap();
            let p = Particles::from_lattice(&lattice, t);
            assert!(!p.is_empty());
            assert_eq!(p.l_visc.len(), if kept { p.len() } else { 0 }, "{jump}");
        }
    }

    /// Three cells of four triangles round a centre: a checkerboard of ±1 GPa about 2 GPa, a
    /// uniform 5 GPa, and a ±4 GPa one with a failed element (left out); then four elements
    /// without a shared centre (not a cell, left out). The answer is the first cell's swing.
    #[test]
    fn checkerboard_is_the_largest_alternation_in_a_cell() {
        let cell = |c: u32| {
            [
                [c, c + 1, 99 + c],
                [c + 1, c + 2, 99 + c],
                [c + 2, c + 3, 99 + c],
                [c + 3, c, 99 + c],
            ]
        };
        let mut nodes = Vec::new();
        for c in [0, 10, 20] {
            nodes.extend(cell(c));
        }
        nodes.extend([[30, 31, 40], [31, 32, 41], [32, 33, 40], [33, 30, 41]]);
        let p = [
            3.0e9, 1.0e9, 3.0e9, 1.0e9, // 1 GPa swing
            5.0e9, 5.0e9, 5.0e9, 5.0e9, // none
            6.0e9, -2.0e9, 6.0e9, -2.0e9, // 4 GPa, but one element failed
            9.0e9, -9.0e9, 9.0e9, -9.0e9, // not a cell
        ];
        let mut failed = vec![0u32; 16];
        failed[9] = 1;
        let e = Elements {
            nodes,
            p: p.to_vec(),
            failed,
            ..Elements::default()
        };
        assert_eq!(e.max_checkerboard(), 1.0e9);
        assert_eq!(Elements::default().max_checkerboard(), 0.0);
    }

    /// The same three cells against a Johnson–Cook flow stress A + B ε_p^n (no rate term at
    /// the reference rate, none of the temperature at room temperature): the first cell at
    /// ε_p = 0 (σ_y = A = 2 GPa) swings 0.5 of it, the second none; with the first cell's
    /// strain at 1, σ_y = A + B = 4 GPa and the ratio halves; at melt the cell has no strength
    /// and is left out.
    #[test]
    fn checkerboard_over_flow_divides_by_the_cells_flow_stress() {
        use crate::materials::flow::FlowLaw;
        use crate::materials::johnson_cook::JcFlow;
        let strength = Strength {
            law: FlowLaw::JohnsonCook(JcFlow {
                a: 2.0e9,
                b: 2.0e9,
                n: 0.5,
                c: 0.1,
                m: 1.0,
            }),
            eps_rate_ref: 1.0,
            t_room: 300.0,
            t_melt: 1800.0,
        };
        let cell = |c: u32| {
            [
                [c, c + 1, 99 + c],
                [c + 1, c + 2, 99 + c],
                [c + 2, c + 3, 99 + c],
                [c + 3, c, 99 + c],
            ]
        };
        let mut e = Elements {
            nodes: [cell(0), cell(10)].concat(),
            p: vec![3.0e9, 1.0e9, 3.0e9, 1.0e9, 5.0e9, 5.0e9, 5.0e9, 5.0e9],
            failed: vec![0; 8],
            eps_p: vec![0.0; 8],
            temperature: vec![300.0; 8],
            ..Elements::default()
        };
        assert_eq!(e.max_checkerboard_over_flow(&strength), 0.5);
        e.eps_p[..4].fill(1.0);
        assert_eq!(e.max_checkerboard_over_flow(&strength), 0.25);
        e.temperature[..4].fill(1800.0);
        assert_eq!(e.max_checkerboard_over_flow(&strength), 0.0);
        assert_eq!(
            Elements::default().max_checkerboard_over_flow(&strength),
            0.0
        );
    }
}
