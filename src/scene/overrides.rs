//! `--set key.path=value` overrides, applied to the TOML tree before it is read against the
//! schema, so an override is checked exactly as the same key in the file.

use toml::{Table, Value};

use super::schema::{self, Need};

/// Whether `path` is a table whose presence means something (a wall scene, a hollow
/// projectile): an override may set keys inside it only when the file has it.
fn selects(path: &str) -> bool {
    schema::table(path).is_some_and(|t| t.need == Need::Selects)
}

/// Sets `key.path=value` in `doc`; returns the dotted key.
pub(super) fn apply_override(doc: &mut Table, set: &str) -> Result<String, String> {
    let (key, value) = set
        .split_once('=')
        .ok_or("expected key.path=value, e.g. projectile.velocity=499")?;
    let segments: Vec<&str> = key.split('.').map(str::trim).collect();
    if segments.iter().any(|s| s.is_empty()) {
        return Err(format!(
            "`{}` is not a dotted key like projectile.velocity",
            key.trim()
        ));
    }
    let key = segments.join(".");
    // The deepest scene key has three parts; the cap also bounds the tables an override creates.
    if segments.len() > 8 {
        return Err(format!("{key} is not a scene key (too many parts)"));
    }
    let value = parse_literal(value.trim())?;
    let (last, parents) = segments.split_last().ok_or("empty key")?;
    let mut table = doc;
    for (i, segment) in parents.iter().enumerate() {
        let path = segments[..=i].join(".");
        if !table.contains_key(*segment) {
            if selects(&path) {
                return Err(format!(
                    "the file has no [{path}] table; add the table to the file to set {key}"
                ));
            }
            table.insert(segment.to_string(), Value::Table(Table::new()));
        }
        table = match table.get_mut(*segment) {
            Some(Value::Table(t)) => t,
            _ => return Err(format!("{path} is a value, not a table; cannot set {key}")),
        };
    }
    table.insert(last.to_string(), value);
    Ok(key)
}

/// A TOML literal, or a bare word read as a string. A decimal integer too large for TOML's
/// 64 bits (`--set projectile.velocity=100000000000000000000`) is read as the float it is, so
/// that the key's own range check answers, not "wrong type".
fn parse_literal(text: &str) -> Result<Value, String> {
    if text.is_empty() {
        return Err("no value after `=`".into());
    }
    if let Ok(mut t) = format!("v = {text}").parse::<Table>() {
        if t.len() == 1 {
            if let Some(v) = t.remove("v") {
                return Ok(v);
            }
        }
    }
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) {
        if let Ok(x) = text.parse::<f64>() {
            return Ok(Value::Float(x));
        }
    }
    let bare = text
        .chars()
        .all(|c| c.is_ascii_alphanumeric() || "-_.+".contains(c));
    if bare {
        Ok(Value::String(text.to_string()))
    } else {
        Err(format!(
            "cannot read `{text}` as a value; write a number, true/false or a \"string\""
        ))
    }
}
