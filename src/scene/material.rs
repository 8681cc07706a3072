//! `[projectile.material]`: a preset, the scene's constants over it, and the checks that tie
//! the constants together (the EOS to the elastic moduli, the flow law's keys to the preset).

use super::resolve::Check;
use super::schema::{self as k, Key};
use super::{approx, num, SceneError, SteelMaterial};
use crate::materials::flow::{FlowLaw, Strength};
use crate::materials::johnson_cook::{JcDamage, JcFlow};
use crate::materials::presets::{self, DamageConstants, SteelConstants};
use crate::materials::steel_eos::{self, PolyEos};
use crate::materials::zerilli_armstrong::ZaFcc;

/// The preset with the scene's constants over it, checked.
pub(super) fn resolve_steel(c: &Check) -> Result<SteelMaterial, SceneError> {
    let preset = c.choice(&k::PRESET_NAME)?;
    let p = presets::preset(preset).expect("every preset name has constants");
    let density = c.num_or(&k::DENSITY, p.density)?;
    let youngs_modulus = c.num_or(&k::YOUNGS_MODULUS, p.youngs_modulus)?;
    let poisson_ratio = c.num_or(&k::POISSON_RATIO, p.poisson_ratio)?;
    let specific_heat = c.num_or(&k::SPECIFIC_HEAT, p.specific_heat)?;
    let taylor_quinney = c.num_or(&k::TAYLOR_QUINNEY, p.taylor_quinney)?;
    let t_room = c.num_or(&k::T_ROOM, p.t_room)?;
    let t_melt = c.given_num(&k::T_MELT).unwrap_or(p.t_melt);
    c.require(
        t_melt > t_room && t_melt <= 4000.0,
        k::T_MELT.path,
        t_melt,
        &format!(
            "must be > t_room = {} and ≤ 4000 (K): no metal melts above tungsten's 3695",
            num(t_room)
        ),
    )?;
    // First, so that a Johnson–Cook key given to a Zerilli–Armstrong preset is named as
    // belonging to the other law rather than checked against its range.
    let law = resolve_flow_law(c, preset, &p)?;
    let eps_rate_ref = c.num_or(&k::EPS_RATE_REF, p.eps_rate_ref)?;
    // Copper's K₁ is the elastic bulk modulus of the final E and ν.
    let bulk = youngs_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio));
    let eos_k1 = c.num_or(&k::EOS_K1, p.eos_k1.unwrap_or(bulk))?;
    c.require(
        (eos_k1 as f32).is_finite(),
        k::EOS_K1.path,
        eos_k1,
        &k::EOS_K1.bound_message(),
    )?;
    let eos_gamma = c.num_or(&k::EOS_GAMMA, p.eos_gamma)?;
    let eos = PolyEos {
        k1: eos_k1 as f32,
        k2: c.given_num(&k::EOS_K2).unwrap_or(p.eos_k2) as f32,
        k3: c.given_num(&k::EOS_K3).unwrap_or(p.eos_k3) as f32,
        gamma: eos_gamma as f32,
    };
    // The EOS's K₁ and the elastic E, ν describe one solid: the stress update takes its
    // shear modulus from E and ν and its pressure from K₁, so a K₁ far from E/(3(1 − 2ν)) runs
    // another Poisson's ratio than the one given (or one of them is in the wrong unit).
    let ratio = eos_k1 / bulk;
    if !(0.5..=2.0).contains(&ratio) {
        return Err(c.conflict(
            &[
                k::EOS_K1.path,
                k::YOUNGS_MODULUS.path,
                k::POISSON_RATIO.path,
            ],
            &format!(
                "K₁ = {} Pa is {} times the elastic bulk modulus E/(3(1 − 2ν)) = {} Pa; \
                 both are the solid's bulk modulus and must agree within a factor of 2 (is \
                 one of them in the wrong unit?)",
                approx(eos_k1),
                approx(ratio),
                approx(bulk)
            ),
        ));
    }
    if let Some(why) = steel_eos::compression_fault(&eos) {
        let keys = [k::EOS_K1.path, k::EOS_K2.path, k::EOS_K3.path];
        return Err(c.conflict(&keys, &why));
    }
    let damage = resolve_damage(c, preset, p.damage)?;
    Ok(SteelMaterial {
        preset: preset.to_string(),
        density,
        youngs_modulus,
        poisson_ratio,
        specific_heat,
        taylor_quinney,
        strength: Strength {
            law,
            eps_rate_ref: eps_rate_ref as f32,
            t_room: t_room as f32,
            t_melt: t_melt as f32,
        },
        eos,
        damage,
    })
}

/// A metal yields, and hardens, at stresses far below its modulus (4340: A/E = 0.004): a
/// Johnson–Cook A or B at or above E is in another unit. Checked once E itself has passed the
/// checks that name it (its range, K₁, the wave speed).
pub(super) fn check_strength_below_modulus(c: &Check, m: &SteelMaterial) -> Result<(), SceneError> {
    let e = m.youngs_modulus;
    let strengths = match &m.strength.law {
        FlowLaw::JohnsonCook(j) => [(&k::JC_A, j.a), (&k::JC_B, j.b)],
        FlowLaw::ZerilliArmstrongFcc(z) => [(&k::ZA_C0, z.c0), (&k::ZA_C2, z.c2)],
    };
    for (key, value) in strengths {
        c.require(
            f64::from(value) < e,
            key.path,
            f64::from(value),
            &format!(
                "must be below projectile.material.youngs_modulus = {} (Pa): a metal yields at \
                 stresses far below its modulus (4340: A/E = 0.004)",
                num(e)
            ),
        )?;
    }
    Ok(())
}

/// The first of `keys` the file gives.
fn first_given(c: &Check, keys: &[&'static Key]) -> Option<&'static Key> {
    keys.iter().copied().find(|key| c.given_num(key).is_some())
}

/// The flow-stress law: Johnson–Cook's with the scene's `jc_*` over the preset's, or, for a
/// preset with Zerilli–Armstrong constants, those with the scene's `za_*` overrides. A key of
/// the other law is refused, not ignored.
fn resolve_flow_law(c: &Check, preset: &str, p: &SteelConstants) -> Result<FlowLaw, SceneError> {
    let jc_keys = [&k::JC_A, &k::JC_B, &k::JC_N, &k::JC_C, &k::JC_M];
    let za_keys = [&k::ZA_C0, &k::ZA_C2, &k::ZA_C3, &k::ZA_C4];
    let Some(z) = p.za else {
        if let Some(key) = first_given(c, &za_keys) {
            return Err(c.conflict(
                &[key.path, k::PRESET_NAME.path],
                &format!(
                    "preset \"{preset}\" takes the Johnson–Cook law (jc_a … jc_m); the \
                     Zerilli–Armstrong constants are for preset \"copper-ofhc-za\""
                ),
            ));
        }
        return Ok(FlowLaw::JohnsonCook(JcFlow {
            a: c.num_or(&k::JC_A, p.jc_a)? as f32,
            b: c.num_or(&k::JC_B, p.jc_b)? as f32,
            n: c.num_or(&k::JC_N, p.jc_n)? as f32,
            c: c.num_or(&k::JC_C, p.jc_c)? as f32,
            m: c.num_or(&k::JC_M, p.jc_m)? as f32,
        }));
    };
    if let Some(key) = first_given(c, &jc_keys) {
        return Err(c.conflict(
            &[key.path, k::PRESET_NAME.path],
            &format!(
                "preset \"{preset}\" takes the Zerilli–Armstrong law (za_c0 … za_c4); the \
                 Johnson–Cook constants would be unused"
            ),
        ));
    }
    Ok(FlowLaw::ZerilliArmstrongFcc(ZaFcc {
        c0: c.num_or(&k::ZA_C0, z.c0)? as f32,
        c2: c.num_or(&k::ZA_C2, z.c2)? as f32,
        c3: c.num_or(&k::ZA_C3, z.c3)? as f32,
        c4: c.num_or(&k::ZA_C4, z.c4)? as f32,
    }))
}

fn resolve_damage(
    c: &Check,
    preset: &str,
    constants: Option<DamageConstants>,
) -> Result<Option<JcDamage>, SceneError> {
    let keys = [
        &k::D1,
        &k::D2,
        &k::D3,
        &k::D4,
        &k::D5,
        &k::SPALL_STRESS,
        &k::EPS_F_MIN,
    ];
    let given_damage = c.given_flag(&k::DAMAGE);
    if !given_damage.unwrap_or(constants.is_some()) {
        if let Some(key) = first_given(c, &keys) {
            let why = if given_damage.is_some() {
                "damage constants given with damage = false; remove them or set damage = true"
            } else {
                "this preset has no damage model; set damage = true to use the constants"
            };
            return Err(c.conflict(&[key.path, k::DAMAGE.path], why));
        }
        return Ok(None);
    }
    let from_preset =
        constants.map(|d| [d.d1, d.d2, d.d3, d.d4, d.d5, d.spall_stress, d.eps_f_min]);
    let mut v = [0.0; 7];
    for (i, key) in keys.iter().enumerate() {
        v[i] = c
            .given_num(key)
            .or(from_preset.map(|p| p[i]))
            .ok_or_else(|| {
                c.missing(
                    key.path,
                    format!(
                        "required with damage = true: preset \"{preset}\" has no damage constants"
                    ),
                )
            })?;
    }
    let [d1, d2, d3, d4, d5, spall_stress, eps_f_min] = v;
    let spall_stress = c.check(&k::SPALL_STRESS, spall_stress)?;
    let eps_f_min = c.check(&k::EPS_F_MIN, eps_f_min)?;
    Ok(Some(JcDamage {
        d1: d1 as f32,
        d2: d2 as f32,
        d3: d3 as f32,
        d4: d4 as f32,
        d5: d5 as f32,
        spall_stress: spall_stress as f32,
        eps_f_min: eps_f_min as f32,
    }))
}
