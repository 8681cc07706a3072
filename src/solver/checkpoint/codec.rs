//! The checkpoint's binary encoding: little-endian numbers, length-prefixed arrays and strings,
//! and the state's structs field by field (every field listed, or the pattern does not compile,
//! so a new state field cannot be left out of a checkpoint).

use crate::output::history::{Mark, Row};
use crate::solver::Account;
use crate::state::{Elements, Nodes, Particles};

use super::Counters;

/// The payload being read, and how far.
pub(super) struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    pub(super) fn new(bytes: &'a [u8]) -> Reader<'a> {
        Reader { bytes, at: 0 }
    }

    /// Bytes not read yet.
    pub(super) fn left(&self) -> usize {
        self.bytes.len() - self.at
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], String> {
        let bytes = self.take(N)?;
        let mut out = [0; N];
        out.copy_from_slice(bytes);
        Ok(out)
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let left = self.bytes.len() - self.at;
        if n > left {
            return Err(format!(
                "it ends at byte {} of its payload, inside a field of {n} bytes",
                self.bytes.len()
            ));
        }
        let bytes = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(bytes)
    }

    /// A length read, no more than the bytes left (every item takes at least one).
    fn length(&mut self) -> Result<usize, String> {
        let n = u64::get(self)?;
        let left = self.bytes.len() - self.at;
        usize::try_from(n)
            .ok()
            .filter(|&n| n <= left)
            .ok_or_else(|| format!("a length of {n} is more than the {left} bytes left"))
    }
}

/// A value as the payload holds it.
pub(super) trait Put {
    fn put(&self, w: &mut Vec<u8>);
}

/// A value read back from the payload.
pub(super) trait Get: Sized {
    fn get(r: &mut Reader<'_>) -> Result<Self, String>;
}

macro_rules! number {
    ($($t:ty),*) => {$(
        impl Put for $t {
            fn put(&self, w: &mut Vec<u8>) {
                w.extend_from_slice(&self.to_le_bytes());
            }
        }
        impl Get for $t {
            fn get(r: &mut Reader<'_>) -> Result<Self, String> {
                Ok(<$t>::from_le_bytes(r.array()?))
            }
        }
    )*};
}

number!(u8, u32, u64, f32, f64);

impl Put for usize {
    fn put(&self, w: &mut Vec<u8>) {
        (*self as u64).put(w);
    }
}

impl Get for usize {
    fn get(r: &mut Reader<'_>) -> Result<Self, String> {
        let n = u64::get(r)?;
        usize::try_from(n).map_err(|_| format!("a count of {n} is more than this machine holds"))
    }
}

impl Put for str {
    fn put(&self, w: &mut Vec<u8>) {
        self.len().put(w);
        w.extend_from_slice(self.as_bytes());
    }
}

impl Get for String {
    fn get(r: &mut Reader<'_>) -> Result<Self, String> {
        let n = r.length()?;
        String::from_utf8(r.take(n)?.to_vec()).map_err(|_| "a string is not UTF-8".to_string())
    }
}

impl Put for String {
    fn put(&self, w: &mut Vec<u8>) {
        self.as_str().put(w);
    }
}

impl<T: Put> Put for [T] {
    fn put(&self, w: &mut Vec<u8>) {
        self.len().put(w);
        for item in self {
            item.put(w);
        }
    }
}

impl<T: Put> Put for Vec<T> {
    fn put(&self, w: &mut Vec<u8>) {
        self.as_slice().put(w);
    }
}

impl<T: Get> Get for Vec<T> {
    fn get(r: &mut Reader<'_>) -> Result<Self, String> {
        let n = r.length()?;
        (0..n).map(|_| T::get(r)).collect()
    }
}

impl<T: Put, const N: usize> Put for [T; N] {
    fn put(&self, w: &mut Vec<u8>) {
        for item in self {
            item.put(w);
        }
    }
}

impl<T: Get + Copy + Default, const N: usize> Get for [T; N] {
    fn get(r: &mut Reader<'_>) -> Result<Self, String> {
        let mut out = [T::default(); N];
        for item in &mut out {
            *item = T::get(r)?;
        }
        Ok(out)
    }
}

impl<T: Put> Put for Option<T> {
    fn put(&self, w: &mut Vec<u8>) {
        match self {
            None => 0u8.put(w),
            Some(x) => {
                1u8.put(w);
                x.put(w);
            }
        }
    }
}

impl<T: Get> Get for Option<T> {
    fn get(r: &mut Reader<'_>) -> Result<Self, String> {
        match u8::get(r)? {
            0 => Ok(None),
            1 => Ok(Some(T::get(r)?)),
            tag => Err(format!("an option's tag is {tag}, not 0 or 1")),
        }
    }
}

impl<T: Put + ?Sized> Put for &T {
    fn put(&self, w: &mut Vec<u8>) {
        (**self).put(w);
    }
}

impl<A: Put, B: Put, C: Put> Put for (A, B, C) {
    fn put(&self, w: &mut Vec<u8>) {
        self.0.put(w);
        self.1.put(w);
        self.2.put(w);
    }
}

impl<A: Get, B: Get, C: Get> Get for (A, B, C) {
    fn get(r: &mut Reader<'_>) -> Result<Self, String> {
        Ok((A::get(r)?, B::get(r)?, C::get(r)?))
    }
}

/// `Put` and `Get` for a struct, its fields in the order listed: every field, or the
/// pattern does not compile.
macro_rules! record {
    ($ty:ident { $($field:ident),* $(,)? }) => {
        impl Put for $ty {
            fn put(&self, w: &mut Vec<u8>) {
                let $ty { $($field),* } = self;
                $($field.put(w);)*
            }
        }
        impl Get for $ty {
            fn get(r: &mut Reader<'_>) -> Result<Self, String> {
                Ok($ty { $($field: Get::get(r)?),* })
            }
        }
    };
}

/// [`record!`] for a struct of arrays, and the arrays' lengths by name.
macro_rules! arrays {
    ($ty:ident { $($field:ident),* $(,)? }) => {
        record!($ty { $($field),* });
        impl Lengths for $ty {
            fn lengths(&self) -> Vec<(&'static str, usize)> {
                vec![$((stringify!($field), self.$field.len())),*]
            }
        }
    };
}

/// The lengths of a struct of arrays, by field name.
pub(super) trait Lengths {
    fn lengths(&self) -> Vec<(&'static str, usize)>;
}

record!(Account {
    initial_kinetic,
    initial_momentum,
    contact_dissipated,
    wall_dissipated,
    boundary_impulse,
    contact_impulse,
    nose_impulse,
    segment_impulse,
    plastic_work,
    max_penetration,
    slaves_inside,
    max_residual_penetration,
    min_dt,
    max_dt,
    fem_limited_steps,
    sph_limited_steps,
});

record!(Counters {
    frame,
    frame_step,
    history_step,
    next_history,
    next_frame,
});

record!(Mark { bytes, crc, last });

record!(Row {
    time,
    step,
    dt,
    depth,
    velocity,
    kinetic,
    internal,
    contact_dissipated,
    contact_impulse,
    nose_impulse,
    energy_error,
    max_damage,
    max_plastic_strain,
    hits,
    damage_area,
    plastic_work,
    checkerboard,
    length,
    radius,
});

arrays!(Particles {
    r,
    z,
    vr,
    vz,
    ar,
    az,
    mass,
    rho,
    energy,
    strain_energy,
    p,
    s_rr,
    s_zz,
    s_rz,
    s_tt,
    damage,
    mu_max,
    eps_p,
    sound,
    l_rr,
    l_rz,
    l_zr,
    l_zz,
    drho,
    de_visc,
    de_work,
    mu_visc,
    visc_switch,
    m_tilde,
    area,
    hoop_weight,
    l_visc,
    stress_rho2,
    art_stress,
    fixed,
});

arrays!(Nodes {
    r,
    z,
    vr,
    vz,
    fr,
    fz,
    mass,
    on_axis,
    elem_offsets,
    elem_refs,
});

arrays!(Elements {
    nodes,
    cells,
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
    dt,
    plastic_work,
});
