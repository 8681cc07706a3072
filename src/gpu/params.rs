//! Uniform parameter blocks shared by the passes, each declared once: `uniform_block!` makes the
//! Rust struct (laid out by encase) and the WGSL declaration the shader prelude carries
//! (`shader::prelude`), so the two cannot differ in a field, its type or its place.

use encase::ShaderType;

use crate::materials::flow::FlowLaw;
use crate::materials::johnson_cook::JcFlow;
use crate::materials::zerilli_armstrong::ZaFcc;
use crate::state::{FemParams, SphParams};

/// Declares a uniform block: the Rust struct and, as `WGSL`, its WGSL struct. Field types are
/// written as WGSL spells them (f32, u32 or another block), so the text is the Rust tokens.
macro_rules! uniform_block {
    ($(#[$meta:meta])* pub struct $name:ident {
        $($(#[$field_meta:meta])* pub $field:ident: $ty:ident,)*
    }) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, ShaderType)]
        pub struct $name {
            $($(#[$field_meta])* pub $field: $ty,)*
        }

        impl $name {
            /// The block's WGSL declaration.
            pub const WGSL: &'static str = concat!(
                "struct ", stringify!($name), " {\n",
                $("    ", stringify!($field), ": ", stringify!($ty), ",\n",)*
                "}\n"
            );
        }
    };
}

/// Every block's WGSL, for the shader prelude.
pub const BLOCKS: [&str; 7] = [
    KernelUniform::WGSL,
    SphUniform::WGSL,
    FemUniform::WGSL,
    StepUniform::WGSL,
    DtSlot::WGSL,
    ScanLevel::WGSL,
    WallUniform::WGSL,
];

uniform_block! {
    /// The SPH kernel of `src/kernel.rs` (common.wgsl's kernel functions take it).
    pub struct KernelUniform {
        pub h: f32,
        pub inv_h: f32,
        /// SIGMA_2D / h²
        pub norm: f32,
        /// SIGMA_2D / h³
        pub dnorm: f32,
    }
}

uniform_block! {
/// `SphUniform`: the target's constants (SphParams and its HJC set) and the particle count.
pub struct SphUniform {
    pub kernel: KernelUniform,
    pub n: u32,
    pub alpha: f32,
    pub beta: f32,
    pub art_stress_eps: f32,
    pub art_stress_n: f32,
    pub w_spacing: f32,
    /// Crushing ends here (materials::hjc::lock_strain), precomputed once.
    pub mu_plock: f32,
    pub density: f32,
    pub shear_modulus: f32,
    pub a: f32,
    pub b: f32,
    pub n_exp: f32,
    pub c: f32,
    pub s_max: f32,
    pub fc: f32,
    pub t: f32,
    pub eps_rate_ref: f32,
    pub ef_min: f32,
    pub d1: f32,
    pub d2: f32,
    pub p_crush: f32,
    pub mu_crush: f32,
    pub k1: f32,
    pub k2: f32,
    pub k3: f32,
    pub p_lock: f32,
    pub mu_lock: f32,
    /// Fracture energy G_f (J/m²).
    pub g_f: f32,
    /// Width of the crack band (m): the spacing with target.tension = "crack-band", 0 for
    /// "static" (materials::hjc::Tension).
    pub crack_band: f32,
}
}

impl SphUniform {
    pub fn new(p: &SphParams, n: usize) -> SphUniform {
        let k = p.kernel;
        let c = p.concrete;
        SphUniform {
            kernel: KernelUniform {
                h: k.h,
                inv_h: k.inv_h,
                norm: k.norm,
                dnorm: k.dnorm,
            },
            n: n as u32,
            alpha: p.alpha,
            beta: p.beta,
            art_stress_eps: p.art_stress_eps,
            art_stress_n: p.art_stress_n,
            w_spacing: p.w_spacing,
            mu_plock: crate::materials::hjc::lock_strain(&c),
            density: c.density,
            shear_modulus: c.shear_modulus,
            a: c.a,
            b: c.b,
            n_exp: c.n,
            c: c.c,
            s_max: c.s_max,
            fc: c.fc,
            t: c.t,
            eps_rate_ref: c.eps_rate_ref,
            ef_min: c.ef_min,
            d1: c.d1,
            d2: c.d2,
            p_crush: c.p_crush,
            mu_crush: c.mu_crush,
            k1: c.k1,
            k2: c.k2,
            k3: c.k3,
            p_lock: c.p_lock,
            mu_lock: c.mu_lock,
            g_f: c.g_f,
            crack_band: match p.tension {
                crate::materials::hjc::Tension::Static => 0.0,
                crate::materials::hjc::Tension::CrackBand { band } => band,
            },
        }
    }
}

uniform_block! {
/// `FemUniform`: the projectile material (FemParams) and the element, node and cell counts.
pub struct FemUniform {
    pub n_elements: u32,
    pub n_nodes: u32,
    /// Pressure cells (`Elements::cells`): fem_stress's threads.
    pub n_cells: u32,
    pub density: f32,
    pub shear_modulus: f32,
    pub specific_heat: f32,
    pub taylor_quinney: f32,
    pub jc_a: f32,
    pub jc_b: f32,
    pub jc_n: f32,
    pub jc_c: f32,
    pub jc_m: f32,
    pub eps_rate_ref: f32,
    pub t_room: f32,
    pub t_melt: f32,
    pub eos_k1: f32,
    pub eos_k2: f32,
    pub eos_k3: f32,
    pub eos_gamma: f32,
    /// Johnson–Cook damage constants; zero for a material without damage (fem_stress then
    /// compiles without the update: its DAMAGE pipeline constant).
    pub d1: f32,
    pub d2: f32,
    pub d3: f32,
    pub d4: f32,
    pub d5: f32,
    pub spall_stress: f32,
    pub eps_f_min: f32,
    pub q_quad: f32,
    pub q_lin: f32,
    pub return_iterations: u32,
    /// 0: Johnson–Cook (jc_*); 1: Zerilli–Armstrong fcc (za_*), materials::flow::FlowLaw.
    pub flow_law: u32,
    pub za_c0: f32,
    pub za_c2: f32,
    pub za_c3: f32,
    pub za_c4: f32,
}
}

impl FemUniform {
    pub fn new(p: &FemParams, n_elements: usize, n_nodes: usize, n_cells: usize) -> FemUniform {
        let s = p.strength;
        let d = p.damage;
        // The other law's constants are zero: the shader reads only those of `flow_law`.
        let (flow_law, jc, za) = match s.law {
            FlowLaw::JohnsonCook(j) => (0, j, ZaFcc::default()),
            FlowLaw::ZerilliArmstrongFcc(z) => (1, JcFlow::default(), z),
        };
        FemUniform {
            n_elements: n_elements as u32,
            n_nodes: n_nodes as u32,
            n_cells: n_cells as u32,
            density: p.density,
            shear_modulus: p.shear_modulus,
            specific_heat: p.specific_heat,
            taylor_quinney: p.taylor_quinney,
            jc_a: jc.a,
            jc_b: jc.b,
            jc_n: jc.n,
            jc_c: jc.c,
            jc_m: jc.m,
            eps_rate_ref: s.eps_rate_ref,
            t_room: s.t_room,
            t_melt: s.t_melt,
            eos_k1: p.eos.k1,
            eos_k2: p.eos.k2,
            eos_k3: p.eos.k3,
            eos_gamma: p.eos.gamma,
            d1: d.map_or(0.0, |d| d.d1),
            d2: d.map_or(0.0, |d| d.d2),
            d3: d.map_or(0.0, |d| d.d3),
            d4: d.map_or(0.0, |d| d.d4),
            d5: d.map_or(0.0, |d| d.d5),
            spall_stress: d.map_or(0.0, |d| d.spall_stress),
            eps_f_min: d.map_or(0.0, |d| d.eps_f_min),
            q_quad: p.q_quad,
            q_lin: p.q_lin,
            return_iterations: p.return_iterations,
            flow_law,
            za_c0: za.c0,
            za_c2: za.c2,
            za_c3: za.c3,
            za_c4: za.c4,
        }
    }
}

uniform_block! {
    /// The step's own passes' block (integrate, timestep, contact_detect, fem_stress).
    #[derive(Default)]
    pub struct StepUniform {
        pub n_particles: u32,
        pub n_nodes: u32,
        pub n_elements: u32,
        pub n_slaves: u32,
        pub n_masters: u32,
        pub has_wall: u32,
        pub wall_z: f32,
        pub escape: f32,
        /// Particles are kept at least this far off the axis (0.1 h).
        pub r_min: f32,
        pub h: f32,
        pub alpha: f32,
        pub beta: f32,
        pub cfl: f32,
        /// 1 when the elements' stable step takes part (a deformable projectile).
        pub has_fem: u32,
    }
}

uniform_block! {
    /// Which running minima of the clock the time-step fold fills (0 or 1), and which the
    /// integration takes its step from (0, 1, or `DT_FROM_CLOCK`: the clock's Δt as the host
    /// set it, where no fold has run since the last integration); see step.wgsl.
    pub struct DtSlot {
        pub slot: u32,
    }
}

uniform_block! {
    /// One level of the prefix scan (scan.wgsl).
    pub struct ScanLevel {
        /// Entries of `data` to scan.
        pub len: u32,
    }
}

uniform_block! {
    /// The wall images' passes (walls.wgsl): counts, the support, the mirror line's depth
    /// inside the surface, how far the box test reaches past the support, and how far the
    /// segments' sums look past a segment for its particles.
    #[derive(Default)]
    pub struct WallUniform {
        pub n_particles: u32,
        pub n_masters: u32,
        pub n_elements: u32,
        pub support: f32,
        pub offset: f32,
        pub box_margin: f32,
        pub grow: f32,
    }
}
