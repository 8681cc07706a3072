//! Reading a TOML tree against the schema: every value's type, unknown keys and missing
//! required keys, each error naming the dotted key. What comes out is only what the file
//! gives; defaults and bounds are resolve's.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use toml::{Table, Value};

use super::schema::{self, DefaultValue, Need, Ty};
use super::{join, render, SceneError};

/// A value as the file gives it, of its key's type.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Val {
    /// [`Ty::Number`]
    Number(f64),
    /// [`Ty::Count`]
    Count(u64),
    /// [`Ty::Flag`]
    Flag(bool),
    /// [`Ty::Text`] and [`Ty::Choice`] (the choice is checked in resolve).
    Text(String),
}

/// The keys and tables a scene file gives.
#[derive(Default)]
pub(super) struct Given {
    /// By the key's dotted path.
    pub values: HashMap<&'static str, Val>,
    /// The dotted paths of the tables the file has.
    pub tables: HashSet<&'static str>,
}

/// Reads `doc` against the schema.
pub(super) fn read(doc: &Table, origin: &Path) -> Result<Given, SceneError> {
    let mut given = Given::default();
    read_table(doc, "", &mut given, origin)?;
    Ok(given)
}

fn read_table(
    table: &Table,
    path: &str,
    given: &mut Given,
    origin: &Path,
) -> Result<(), SceneError> {
    let file = || origin.to_path_buf();
    // In the file's order, as serde reported the first bad entry.
    for (name, value) in table {
        let dotted = join(path, name);
        // A quoted name with a dot (`"run.cfl" = 1`) is a key of this table, not a path.
        let plain = !name.contains('.');
        if let Some(key) = schema::key(&dotted).filter(|_| plain) {
            let v = read_value(key.ty, value).map_err(|e| e.at(&file(), &dotted, value))?;
            given.values.insert(key.path, v);
        } else if let Some(t) = schema::table(&dotted).filter(|_| plain) {
            finite_in_f32(value).map_err(|e| e.at(&file(), &dotted, value))?;
            let Value::Table(sub) = value else {
                return Err(Bad::Type("a table").at(&file(), &dotted, value));
            };
            given.tables.insert(t.path);
            read_table(sub, &dotted, given, origin)?;
        } else {
            return Err(SceneError::UnknownKey {
                file: file(),
                key: dotted,
                expected: schema::members(path)
                    .iter()
                    .map(|s| s.to_string())
                    .collect(),
            });
        }
    }
    // Then the first required member left out, in schema order.
    for name in schema::members(path) {
        let dotted = join(path, name);
        let missing = match (schema::key(&dotted), schema::table(&dotted)) {
            (Some(k), _) => {
                k.default == DefaultValue::Required && !given.values.contains_key(k.path)
            }
            (None, Some(t)) => t.need == Need::Required && !given.tables.contains(t.path),
            (None, None) => false,
        };
        if missing {
            let why = if schema::table(&dotted).is_some() {
                format!("add a [{dotted}] table")
            } else {
                "add this required key".into()
            };
            return Err(SceneError::MissingKey {
                file: file(),
                key: dotted,
                why,
            });
        }
    }
    Ok(())
}

/// Why a value was refused, before the key is attached.
enum Bad {
    /// The wrong type: what to write instead.
    Type(&'static str),
    /// A number out of what the solver can hold.
    Range(&'static str),
}

impl Bad {
    fn at(self, file: &Path, key: &str, value: &Value) -> SceneError {
        match self {
            Bad::Type(expected) => SceneError::WrongType {
                file: file.to_path_buf(),
                key: key.into(),
                found: render(value),
                expected: expected.into(),
            },
            Bad::Range(why) => SceneError::NonPhysical {
                file: file.to_path_buf(),
                key: key.into(),
                value: render(value),
                why: why.into(),
            },
        }
    }
}

/// A float the solver's f32 cannot hold is refused whatever the key's type.
fn finite_in_f32(value: &Value) -> Result<(), Bad> {
    match value {
        Value::Float(x) if !x.is_finite() => Err(Bad::Range("must be a finite number")),
        Value::Float(x) if x.abs() > f64::from(f32::MAX) => Err(Bad::Range(
            "magnitude beyond the f32 range (3.4e38) the solver computes in; use a smaller value",
        )),
        Value::Float(x) if *x != 0.0 && x.abs() < f64::from(f32::MIN_POSITIVE) => Err(Bad::Range(
            "nonzero magnitude below f32's smallest normal number (1.2e-38), it would flush \
                 to zero; use 0 or a larger value",
        )),
        _ => Ok(()),
    }
}

fn read_value(ty: Ty, value: &Value) -> Result<Val, Bad> {
    finite_in_f32(value)?;
    match (ty, value) {
        (Ty::Number, Value::Integer(i)) => Ok(Val::Number(*i as f64)),
        (Ty::Number, Value::Float(x)) => Ok(Val::Number(*x)),
        // A count may be written as a float when it is a whole number (`max_steps = 5e6`), up
        // to 2⁵³, where every whole number is still a float.
        (Ty::Count, Value::Float(x)) if *x >= 0.0 && x.fract() == 0.0 && *x <= 2f64.powi(53) => {
            Ok(Val::Count(*x as u64))
        }
        (Ty::Count, Value::Integer(i)) if *i >= 0 => Ok(Val::Count(*i as u64)),
        (Ty::Flag, Value::Boolean(b)) => Ok(Val::Flag(*b)),
        (Ty::Text | Ty::Choice { .. }, Value::String(s)) => Ok(Val::Text(s.clone())),
        (Ty::Number, _) => Err(Bad::Type("a number")),
        (Ty::Count, _) => Err(Bad::Type(
            "a whole number ≥ 0 (written as a float, at most 2⁵³)",
        )),
        (Ty::Flag, _) => Err(Bad::Type("true or false")),
        (Ty::Text | Ty::Choice { .. }, _) => Err(Bad::Type("a \"string\" in quotes")),
    }
}
