//! `fem_stress`: per element, strain rates, Jaumann rate, EOS, Johnson–Cook plasticity and
//! damage, bulk viscosity, and the element's nodal forces (EPIC-2, physics.md §2).

use rayon::prelude::*;

use super::deviator::{deviatoric_rate, equivalent_rate, jaumann_trial, von_mises};
use crate::materials::flow;
use crate::materials::johnson_cook as jc;
use crate::materials::steel_eos;
use crate::mesh::geometry::Geometry;
use crate::state::{Elements, FemParams, Nodes};

const TWO_PI: f32 = 2.0 * std::f32::consts::PI;

/// Rate of deformation of a triangle (physics.md §2): ε̇_r, ε̇_z, γ̇_rz, ε̇_θ and the spin ω.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrainRate {
    pub rr: f32,
    pub zz: f32,
    /// Engineering shear γ̇_rz (twice the tensor component).
    pub gamma_rz: f32,
    pub tt: f32,
    /// ω = ½(∂v_r/∂z − ∂v_z/∂r).
    pub spin: f32,
}

impl StrainRate {
    pub fn new(g: &Geometry, vr: [f32; 3], vz: [f32; 3]) -> StrainRate {
        let inv = 1.0 / g.two_area;
        let mut rr = 0.0;
        let mut zz = 0.0;
        let mut drdz = 0.0;
        let mut dzdr = 0.0;
        // Velocities relative to node 0 (Σ b_k = Σ c_k = 0): a rigid translation then gives
        // exactly zero in f32, not round-off noise.
        for k in 1..3 {
            let (ur, uz) = (vr[k] - vr[0], vz[k] - vz[0]);
            rr += g.b[k] * ur;
            zz += g.c[k] * uz;
            drdz += g.c[k] * ur;
            dzdr += g.b[k] * uz;
        }
        let r_sum = g.r[0] + g.r[1] + g.r[2];
        StrainRate {
            rr: rr * inv,
            zz: zz * inv,
            gamma_rz: (drdz + dzdr) * inv,
            tt: (vr[0] + vr[1] + vr[2]) / r_sum,
            spin: 0.5 * (drdz - dzdr) * inv,
        }
    }

    pub fn volumetric(&self) -> f32 {
        self.rr + self.zz + self.tt
    }
}

/// Total stress of an element (tension positive): σ_r, σ_z, τ_rz, σ_θ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stress {
    pub rr: f32,
    pub zz: f32,
    pub rz: f32,
    pub tt: f32,
}

impl Stress {
    /// Stress power density σ:ε̇ (W/m³).
    pub fn power(&self, d: &StrainRate) -> f32 {
        self.rr * d.rr + self.zz * d.zz + self.rz * d.gamma_rz + self.tt * d.tt
    }
}

/// Nodal forces an element exerts on its nodes, paper eq. (1)-(2) in the power-consistent form
/// of physics.md §2: F_r,k = −π r̄ (σ_r b_k + τ c_k) − 2πA σ_θ/3, F_z,k = −π r̄ (σ_z c_k + τ b_k).
pub fn nodal_forces(g: &Geometry, s: &Stress) -> [f32; 6] {
    let pr = std::f32::consts::PI * g.r_mean;
    let hoop = TWO_PI * 0.5 * g.two_area * s.tt / 3.0;
    let mut f = [0.0; 6];
    for k in 0..3 {
        f[2 * k] = -pr * (s.rr * g.b[k] + s.rz * g.c[k]) - hoop;
        f[2 * k + 1] = -pr * (s.zz * g.c[k] + s.rz * g.b[k]);
    }
    f
}

/// An element turned inside out: the run must stop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inverted {
    pub element: usize,
    pub r: f32,
    pub z: f32,
}

/// The EOS state the elements of one pressure cell share (docs/physics.md §2.4): the cell's
/// relative volume V/V₀ and its internal energy per reference volume predicted to the end of
/// the step from the old stress power, eq. (14) summed over the cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellEos {
    pub rel_volume: f32,
    pub e_pred: f32,
}

/// The shared EOS state of the elements `range`, summed in element order (as the GPU sums);
/// `None` for a cell of one element, or one with a failed or inverted element: each of its
/// elements then takes the pressure of its own volume.
pub fn cell_eos(
    elements: &Elements,
    range: std::ops::Range<usize>,
    nodes: &Nodes,
    dt: f32,
) -> Option<CellEos> {
    if range.len() < 2 {
        return None;
    }
    let (mut v, mut v0, mut e) = (0.0f32, 0.0f32, 0.0f32);
    for k in range {
        let el = &elements.nodes[k];
        let g = Geometry::new(el, &nodes.r, &nodes.z);
        if elements.failed[k] != 0 || g.two_area.is_nan() || g.two_area <= 0.0 {
            return None;
        }
        let d = element_rate(&g, el, nodes);
        let volume = g.volume();
        let s = [
            elements.s_rr[k],
            elements.s_zz[k],
            elements.s_rz[k],
            elements.s_tt[k],
        ];
        let old_power = total_stress(&s, elements.p[k]).power(&d);
        v += volume;
        v0 += elements.volume0[k];
        e += elements.energy[k] * elements.volume0[k] + dt * volume * old_power;
    }
    Some(CellEos {
        rel_volume: v / v0,
        e_pred: e / v0,
    })
}

/// The share of the bulk stiffness that holds a shared-pressure cell's centre-node mode
/// (docs/physics.md §2.4): small enough that the cell's triangles keep nearly one pressure,
/// large enough that the mode no longer rests on the deviatoric stiffness alone.
pub const CELL_MODE_STIFFNESS: f32 = 0.03;

/// The pressure a triangle of a shared-pressure cell adds for its volume's departure from the
/// cell's, `β K (J_cell − J)` (docs/physics.md §2.4); it averages to zero over the cell
/// (weights V₀), so the cell's mean pressure is the EOS's.
fn cell_mode_pressure(bulk_tangent: f32, cell_rel_volume: f32, rel_volume: f32) -> f32 {
    CELL_MODE_STIFFNESS * bulk_tangent * (cell_rel_volume - rel_volume)
}

fn element_rate(g: &Geometry, el: &[u32; 3], nodes: &Nodes) -> StrainRate {
    let idx = [el[0] as usize, el[1] as usize, el[2] as usize];
    StrainRate::new(g, idx.map(|n| nodes.vr[n]), idx.map(|n| nodes.vz[n]))
}

/// Update every element's stress state over `dt` from the nodal velocities and write its
/// nodal forces and stable time step.
pub fn run(
    elements: &mut Elements,
    nodes: &Nodes,
    params: &FemParams,
    dt: f32,
) -> Result<(), Inverted> {
    assert_eq!(
        elements.cells.last().map_or(0, |&n| n as usize),
        elements.len(),
        "Elements::cells must cover every element"
    );
    // Each element's shared EOS state, read before any element is written; none to read when
    // every cell is one element (projectile.cell_pressure off).
    let shared: Option<Vec<Option<CellEos>>> =
        (elements.cells.len() <= elements.len()).then(|| {
            let e: &Elements = elements;
            e.cells
                .par_windows(2)
                .flat_map_iter(|w| {
                    let range = w[0] as usize..w[1] as usize;
                    std::iter::repeat_n(cell_eos(e, range.clone(), nodes, dt), range.len())
                })
                .collect()
        });
    let Elements {
        nodes: conn,
        cells: _,
        volume0,
        s_rr,
        s_zz,
        s_rz,
        s_tt,
        p,
        energy,
        eps_p,
        temperature,
        damage,
        failed,
        force,
        dt: dt_out,
        plastic_work,
    } = elements;
    let inverted = conn
        .par_iter()
        .zip(volume0.par_iter())
        .zip(s_rr.par_iter_mut())
        .zip(s_zz.par_iter_mut())
        .zip(s_rz.par_iter_mut())
        .zip(s_tt.par_iter_mut())
        .zip(p.par_iter_mut())
        .zip(energy.par_iter_mut())
        .zip(eps_p.par_iter_mut())
        .zip(temperature.par_iter_mut())
        .zip(damage.par_iter_mut())
        .zip(failed.par_iter_mut())
        .zip(force.par_iter_mut())
        .zip(dt_out.par_iter_mut())
        .zip(plastic_work.par_iter_mut())
        .enumerate()
        .map(
            |(
                e,
                (
                    (
                        (
                            (
                                (
                                    (((((((((el, &v0), srr), szz), srz), stt), pe), en), ep), temp),
                                    dmg,
                                ),
                                fail,
                            ),
                            f,
                        ),
                        dte,
                    ),
                    wp,
                ),
            )| {
                let cell = shared.as_ref().and_then(|s| s[e]);
                let mut st = ElementState {
                    s: [*srr, *szz, *srz, *stt],
                    p: *pe,
                    energy: *en,
                    eps_p: *ep,
                    temperature: *temp,
                    damage: *dmg,
                    failed: *fail != 0,
                };
                let out = update_element(el, v0, nodes, params, dt, cell, &mut st);
                *srr = st.s[0];
                *szz = st.s[1];
                *srz = st.s[2];
                *stt = st.s[3];
                *pe = st.p;
                *en = st.energy;
                *ep = st.eps_p;
                *temp = st.temperature;
                *dmg = st.damage;
                *fail = u32::from(st.failed);
                match out {
                    Some(o) => {
                        *f = o.force;
                        *dte = o.dt;
                        *wp = o.plastic_work;
                        None
                    }
                    None => {
                        let g = Geometry::new(el, &nodes.r, &nodes.z);
                        Some(Inverted {
                            element: e,
                            r: g.r_mean,
                            z: (g.z[0] + g.z[1] + g.z[2]) / 3.0,
                        })
                    }
                }
            },
        )
        .find_first(|x| x.is_some())
        .flatten();
    match inverted {
        Some(inv) => Err(inv),
        None => Ok(()),
    }
}

/// A failed element at least this many times its reference volume, whose EOS pressure is not
/// positive, is open: a crack, not a body. It carries no stress at all (no pressure, no deviator,
/// no bulk viscosity) and so exerts no force. It limits the time step only by the time it would
/// take to close (its EOS pressure to reach zero) at its present rate of compression; it keeps
/// its mass, and takes compressive pressure again once closed. Closer to its reference volume a
/// failed element is as before (tension cut off, viscosity on compression, the usual step),
/// so that one step cannot take an element from open to loaded. Without this rule failed
/// elements sheared and stretched into slivers (a failed element resists no shear) set a step
/// several times smaller than the body's (docs/physics.md §2.3).
pub const OPEN_RELATIVE_VOLUME: f32 = 1.02;

/// The state one element carries from step to step.
#[derive(Clone, Copy, Debug)]
pub struct ElementState {
    /// Deviator S_r, S_z, S_rz, S_θ.
    pub s: [f32; 4],
    pub p: f32,
    pub energy: f32,
    pub eps_p: f32,
    pub temperature: f32,
    pub damage: f32,
    pub failed: bool,
}

/// What one element's update produces.
#[derive(Clone, Copy, Debug)]
pub struct ElementOutput {
    pub force: [f32; 6],
    pub dt: f32,
    pub plastic_work: f32,
}

/// One element's constitutive update; `None` when the element is inverted (2A ≤ 0). `cell`:
/// the EOS state its pressure cell shares (`cell_eos`), or `None` for its own.
pub fn update_element(
    el: &[u32; 3],
    volume0: f32,
    nodes: &Nodes,
    m: &FemParams,
    dt: f32,
    cell: Option<CellEos>,
    st: &mut ElementState,
) -> Option<ElementOutput> {
    let g = Geometry::new(el, &nodes.r, &nodes.z);
    if g.two_area.is_nan() || g.two_area <= 0.0 {
        return None;
    }
    let d = element_rate(&g, el, nodes);
    let volume = g.volume();
    let rel_volume = volume / volume0;
    // Stress at the start of the step, for the trapezoidal power.
    let old = total_stress(&st.s, st.p);
    // The pressure's volume and energy: the cell's, or the element's own with the energy
    // predicted to the end of the step from the old stress power (explicit), eq. (14).
    let eos = cell.unwrap_or(CellEos {
        rel_volume,
        e_pred: st.energy + dt * rel_volume * old.power(&d),
    });
    let rho = m.density / eos.rel_volume;
    let mu = 1.0 / eos.rel_volume - 1.0;
    let g_mod = m.shear_modulus;

    // Deviatoric strain rate (θθ included), then the Jaumann-rotated elastic trial.
    let (dev, vol) = deviatoric_rate(d.rr, d.zz, 0.5 * d.gamma_rz, d.tt);
    let eq_rate = equivalent_rate(&dev);
    let mut s = jaumann_trial(st.s, dev, d.spin, g_mod, dt);
    let mut plastic_work = 0.0;
    if st.failed {
        s = [0.0; 4];
    } else {
        let seq = von_mises(&s);
        let ret = flow::radial_return(
            &m.strength,
            g_mod,
            seq,
            st.eps_p,
            eq_rate,
            st.temperature,
            m.return_iterations,
        );
        if ret.d_eps_p > 0.0 {
            for c in &mut s {
                *c *= ret.scale;
            }
            st.eps_p += ret.d_eps_p;
            // Adiabatic heating ΔT = β σ_y Δε_p /(ρ c_p), physics.md §2.1.
            let work_density = ret.flow_stress * ret.d_eps_p;
            st.temperature += m.taylor_quinney * work_density / (rho * m.specific_heat);
            plastic_work = work_density * volume;
        }
        if let Some(dm) = &m.damage {
            let seq_new = von_mises(&s);
            let mean = -st.p;
            let triax = if seq_new > 0.0 { mean / seq_new } else { 0.0 };
            let t_star = flow::homologous_temperature(&m.strength, st.temperature);
            st.damage += jc::damage_increment(
                dm,
                ret.d_eps_p,
                triax,
                eq_rate,
                m.strength.eps_rate_ref,
                t_star,
            );
            if st.damage >= 1.0 || jc::spalls(dm, mean) {
                st.damage = st.damage.min(1.0);
                st.failed = true;
                s = [0.0; 4];
            }
        }
    }

    let p_eos = steel_eos::pressure(&m.eos, mu, eos.e_pred);
    let k_t = steel_eos::bulk_tangent(&m.eos, mu);
    let p = if st.failed {
        p_eos.max(0.0)
    } else if cell.is_some() {
        p_eos + cell_mode_pressure(k_t, eos.rel_volume, rel_volume)
    } else {
        p_eos
    };
    let open = st.failed && eos.rel_volume >= OPEN_RELATIVE_VOLUME && p_eos <= 0.0;

    // Bulk viscosity on compression only.
    let length = g.min_altitude();
    let c = ((k_t + 4.0 / 3.0 * g_mod) / rho).sqrt();
    let q = if vol < 0.0 && !open {
        rho * length * (m.q_quad * length * vol * vol - m.q_lin * c * vol)
    } else {
        0.0
    };

    st.s = s;
    st.p = p;
    // Internal energy per reference volume: trapezoidal in the stress, plus the viscous heating
    // −q tr ε̇ (the viscosity acts only within this step).
    let power = 0.5 * (old.power(&d) + total_stress(&s, p).power(&d)) - q * vol;
    st.energy += dt * rel_volume * power;
    let new = total_stress(&s, p + q);

    let q_hat = m.q_quad * length * (-vol).max(0.0) + m.q_lin * c;
    let mut dt_el = length / (q_hat + (q_hat * q_hat + c * c).sqrt());
    if open {
        // Time to close: p_eos rises at k_t μ̇, μ̇ = −(1 + μ) tr ε̇.
        let closing = k_t * (1.0 + mu) * -vol;
        dt_el = if closing > 0.0 {
            dt_el.max(-p_eos / closing)
        } else {
            f32::MAX
        };
    }
    Some(ElementOutput {
        force: nodal_forces(&g, &new),
        dt: dt_el,
        plastic_work,
    })
}

/// Total stress σ = S − p I from the deviator (r, z, rz, θ) and the pressure.
pub fn total_stress(s: &[f32; 4], p: f32) -> Stress {
    Stress {
        rr: s[0] - p,
        zz: s[1] - p,
        rz: s[2],
        tt: s[3] - p,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
        fn range(&mut self, a: f32, b: f32) -> f32 {
            a + (b - a) * self.next()
        }
    }

    /// Σ F·v = −V σ:ε̇ for random triangles, velocities and stresses (physics.md §2).
    #[test]
    fn power_identity_on_random_data() {
        let mut rng = Rng(0x9e3779b97f4a7c15);
        for case in 0..500 {
            let on_axis = case % 3 == 0;
            let mut r = [
                rng.range(0.0, 0.01),
                rng.range(0.0, 0.01),
                rng.range(0.0, 0.01),
            ];
            let z = [
                rng.range(-0.01, 0.01),
                rng.range(-0.01, 0.01),
                rng.range(-0.01, 0.01),
            ];
            if on_axis {
                r[0] = 0.0;
            }
            let mut g = Geometry::new(&[0, 1, 2], &r, &z);
            if g.two_area.abs() < 1e-6 {
                continue;
            }
            if g.two_area < 0.0 {
                // Make it counter-clockwise.
                let (r2, z2) = ([r[0], r[2], r[1]], [z[0], z[2], z[1]]);
                g = Geometry::new(&[0, 1, 2], &r2, &z2);
            }
            let vr = [
                rng.range(-100.0, 100.0),
                rng.range(-100.0, 100.0),
                rng.range(-100.0, 100.0),
            ];
            let vz = [
                rng.range(-100.0, 100.0),
                rng.range(-100.0, 100.0),
                rng.range(-100.0, 100.0),
            ];
            let s = Stress {
                rr: rng.range(-1e9, 1e9),
                zz: rng.range(-1e9, 1e9),
                rz: rng.range(-1e9, 1e9),
                tt: rng.range(-1e9, 1e9),
            };
            let d = StrainRate::new(&g, vr, vz);
            let f = nodal_forces(&g, &s);
            let power: f64 = (0..3)
                .map(|k| f[2 * k] as f64 * vr[k] as f64 + f[2 * k + 1] as f64 * vz[k] as f64)
                .sum();
            let expected = -(g.volume() as f64) * s.power(&d) as f64;
            // Scale of the individual products, for an f32 round-off bound.
            let scale: f64 = (0..6).map(|k| (f[k] as f64).abs()).sum::<f64>() * 100.0;
            assert!(
                (power - expected).abs() <= 1e-5 * scale,
                "case {case}: {power} vs {expected}"
            );
        }
    }

    /// A crossed-triangle patch of 2×2 quads around one interior node at radius `r0`.
    fn patch(r0: f32, dz: f32) -> (Vec<f32>, Vec<f32>, Vec<[u32; 3]>, Vec<usize>) {
        let mut r = Vec::new();
        let mut z = Vec::new();
        let h = 0.002;
        for k in 0..3 {
            for i in 0..3 {
                r.push(r0 + i as f32 * h + if i == 1 && k == 1 { 0.0003 } else { 0.0 });
                z.push(k as f32 * h + dz);
            }
        }
        let mut elements = Vec::new();
        for k in 0..2u32 {
            for i in 0..2u32 {
                let a = k * 3 + i;
                let (b, c, d) = (a + 1, a + 4, a + 3);
                let e = r.len() as u32;
                let corners = [a, b, c, d];
                r.push(corners.iter().map(|&n| r[n as usize]).sum::<f32>() / 4.0);
                z.push(corners.iter().map(|&n| z[n as usize]).sum::<f32>() / 4.0);
                for q in 0..4 {
                    elements.push([corners[q], corners[(q + 1) % 4], e]);
                }
            }
        }
        // Interior nodes: the patch centre (4) and the four quad centres.
        (r, z, elements, vec![4, 9, 10, 11, 12])
    }

    /// Uniform hydrostatic stress gives zero residual at interior nodes, on and off the axis.
    #[test]
    fn hydrostatic_patch_test() {
        for r0 in [0.0f32, 0.05] {
            let (r, z, elements, interior) = patch(r0, 0.01);
            let mut f = vec![[0.0f64; 2]; r.len()];
            let s = Stress {
                rr: -1e9,
                zz: -1e9,
                rz: 0.0,
                tt: -1e9,
            };
            let mut scale = 0.0f64;
            for el in &elements {
                let g = Geometry::new(el, &r, &z);
                assert!(g.two_area > 0.0);
                let fe = nodal_forces(&g, &s);
                for k in 0..3 {
                    f[el[k] as usize][0] += fe[2 * k] as f64;
                    f[el[k] as usize][1] += fe[2 * k + 1] as f64;
                    scale = scale.max((fe[2 * k] as f64).abs());
                }
            }
            for &n in &interior {
                let res = f[n][0].hypot(f[n][1]);
                assert!(
                    res < 1e-5 * scale,
                    "r0 {r0}: node {n} residual {res} (element forces ~{scale})"
                );
            }
            // The boundary does feel the pressure: the test is not vacuous.
            assert!(f[0][0].abs() + f[0][1].abs() > 1e-2 * scale);
        }
    }

    /// The patch's elements at rest, 4340 steel (the Taylor case's), with `cells` from the
    /// mesh or, when `own`, one cell per element.
    fn patch_model(r0: f32, own: bool) -> (Nodes, Elements, FemParams) {
        let scene = crate::scene::load(std::path::Path::new("cases/taylor-4340-208.toml"), &[])
            .expect("taylor case");
        let params = FemParams::new(&scene.model_projectile().material);
        let (r, z, elements, _) = patch(r0, 0.0);
        let mesh = crate::mesh::ProjectileMesh {
            node_mass: vec![1.0; r.len()],
            node_r: r,
            node_z: z,
            elements,
            masters: Vec::new(),
            total_mass: 0.0,
            filler_mass: 0.0,
        };
        let p = crate::state::Projectile::from_mesh(&mesh, 0.0, 295.0, !own);
        (p.nodes, p.elements, params)
    }

    /// The patch's four quads are four cells of four triangles; a triangle fan whose centre
    /// another element also uses is not a cell.
    #[test]
    fn pressure_cells_are_the_crossed_quads() {
        let (_, _, conn, _) = patch(0.0, 0.0);
        assert_eq!(Elements::pressure_cells(&conn), vec![0, 4, 8, 12, 16]);
        let fan = [[0, 1, 9], [1, 2, 9], [2, 3, 9], [3, 9, 4], [4, 5, 6]];
        assert_eq!(Elements::pressure_cells(&fan), vec![0, 1, 2, 3, 4, 5]);
        assert_eq!(Elements::pressure_cells(&[]), vec![0]);
    }

    /// A patch compressed uniformly (every length 1 % shorter), with one quad's centre node then moved
    /// sideways by 1 % of the quad: the mode that shrinks one of its triangles and swells the
    /// opposite one while the quad's volume stays the same. Each element on its own takes the
    /// pressure of its own volume, which swings by several GPa; a cell shares the EOS of the
    /// cell's volume, which the centre's position does not change, so the moved quad's mean
    /// pressure is the homogeneous one, and its triangles depart from it only by the mode's
    /// stiffness, `CELL_MODE_STIFFNESS` of the swing they had on their own.
    #[test]
    fn a_cell_shares_the_pressure_of_its_volume() {
        let run_patch = |own: bool, failed: Option<usize>| {
            let (mut nodes, mut elements, params) = patch_model(0.05, own);
            for k in 0..nodes.len() {
                nodes.r[k] *= 0.99;
                nodes.z[k] *= 0.99;
            }
            // Node 9 is the first quad's centre.
            nodes.r[9] += 2.0e-5;
            if let Some(k) = failed {
                elements.failed[k] = 1;
            }
            run(&mut elements, &nodes, &params, 1.0e-9).expect("not inverted");
            elements
        };
        let swing = |p: &[f32]| {
            p.iter().fold(f32::MIN, |a, &b| a.max(b)) - p.iter().fold(f32::MAX, |a, &b| a.min(b))
        };
        let own = run_patch(true, None);
        let cells = run_patch(false, None);
        let p_homogeneous = own.p[4];
        assert!(p_homogeneous > 1.0e8, "compressed: {p_homogeneous}");
        // f32 positions resolve a triangle's volume to ~1e-6, a few 1e-4 of μ ≈ 0.03.
        let round_off = 2.0e-3 * p_homogeneous;
        assert!(swing(&own.p[4..8]) < round_off, "{:?}", &own.p[4..8]);
        assert!(
            swing(&own.p[0..4]) > 0.5 * p_homogeneous,
            "own: {:?}",
            &own.p[0..4]
        );
        for c in 0..4 {
            let k = 4 * c..4 * c + 4;
            let (p, v0) = (&cells.p[k.clone()], &cells.volume0[k]);
            let mean = p.iter().zip(v0).map(|(p, v)| p * v).sum::<f32>() / v0.iter().sum::<f32>();
            assert!(
                (mean - p_homogeneous).abs() < round_off,
                "cell {c}: mean {mean} vs {p_homogeneous}"
            );
            let expected_swing = if c == 0 {
                CELL_MODE_STIFFNESS * swing(&own.p[0..4])
            } else {
                0.0
            };
            assert!(
                (swing(p) - expected_swing).abs() < 0.1 * expected_swing + round_off,
                "cell {c}: {p:?}, swing expected {expected_swing}"
            );
        }
        // A failed element takes its cell back to the elements' own pressures (its own floored
        // at zero, a failed element's rule); the other cells are as before.
        let one_failed = run_patch(false, Some(1));
        for k in 0..4 {
            let expected = if k == 1 { own.p[k].max(0.0) } else { own.p[k] };
            assert_eq!(one_failed.p[k], expected, "element {k}");
        }
        assert_eq!(&one_failed.p[4..], &cells.p[4..]);
    }

    /// With no deviatoric stiffness at all (G = 0, as in a cell whose triangles flow), the
    /// moved centre node of `a_cell_shares_the_pressure_of_its_volume` is still pushed back:
    /// by `CELL_MODE_STIFFNESS` of the force the triangles' own pressures would exert, not by
    /// nothing (physics.md §2.4).
    #[test]
    fn a_cell_holds_its_centre_without_shear_stiffness() {
        let centre_force = |own: bool| {
            let (mut nodes, mut elements, mut params) = patch_model(0.05, own);
            params.shear_modulus = 0.0;
            for k in 0..nodes.len() {
                nodes.r[k] *= 0.99;
                nodes.z[k] *= 0.99;
            }
            nodes.r[9] += 2.0e-5;
            run(&mut elements, &nodes, &params, 1.0e-9).expect("not inverted");
            let mut f = 0.0f64;
            for (el, fe) in elements.nodes.iter().zip(&elements.force) {
                for k in 0..3 {
                    if el[k] == 9 {
                        f += fe[2 * k] as f64;
                    }
                }
            }
            f
        };
        let (own, cells) = (centre_force(true), centre_force(false));
        assert!(own < 0.0, "own pressures push the centre back: {own}");
        let ratio = cells / own;
        assert!(
            (ratio - CELL_MODE_STIFFNESS as f64).abs() < 0.2 * CELL_MODE_STIFFNESS as f64,
            "cells {cells} against own {own}: {ratio}"
        );
    }

    /// The volume checkerboard reads a cell's + − + − alternation of V/V₀ and leaves out a
    /// cell with a failed triangle.
    #[test]
    fn volume_checkerboard_reads_the_alternation() {
        let (nodes, mut elements, _) = patch_model(0.05, false);
        assert!(elements.max_volume_checkerboard(&nodes) < 1.0e-6);
        for (k, f) in [1.0, 1.02, 1.0, 1.02].into_iter().enumerate() {
            elements.volume0[k] *= f;
        }
        // J = 1, 1/1.02, 1, 1/1.02: (2 − 2/1.02)/4.
        let expected = (2.0 - 2.0 / 1.02) / 4.0;
        assert!((elements.max_volume_checkerboard(&nodes) - expected).abs() < 1.0e-5);
        elements.failed[0] = 1;
        assert!(elements.max_volume_checkerboard(&nodes) < 1.0e-6);
    }

    /// A rigid translation along z gives zero strain rate and no stress.
    #[test]
    fn rigid_translation_is_strain_free() {
        let (r, z, elements, _) = patch(0.0, 0.0);
        for el in &elements {
            let g = Geometry::new(el, &r, &z);
            let d = StrainRate::new(&g, [0.0; 3], [-300.0; 3]);
            assert_eq!(
                d,
                StrainRate {
                    rr: 0.0,
                    zz: 0.0,
                    gamma_rz: 0.0,
                    tt: 0.0,
                    spin: 0.0
                }
            );
        }
    }
}
