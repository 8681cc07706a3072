//! What the schema writes out: the resolved table (`penetrate check`, every run's
//! `scene.toml`) and the scene reference, docs/scene-reference.md.

use std::fmt::Write as _;

use toml::Value;

use super::schema::{Bounds, DefaultValue, Need, Shown, Ty, KEYS, TABLES};
use super::{num, Scene};

impl Scene {
    /// Every resolved value, one `dotted.key = value  # unit` line each, under the same dotted
    /// names `--set` takes; passing the lines back as overrides reproduces the scene.
    pub fn resolved_table(&self) -> String {
        let mut out = String::new();
        for key in KEYS {
            let Some(value) = (key.show)(self) else {
                continue;
            };
            let value = match value {
                Shown::Number(x) => num(x),
                Shown::Single(x) => num(x),
                Shown::Count(n) => n.to_string(),
                Shown::Flag(b) => b.to_string(),
                Shown::Text(s) => Value::String(s).to_string(),
            };
            // Writing to a String cannot fail.
            let _ = writeln!(out, "{} = {value}  # {}", key.path, key.table_unit());
        }
        out
    }
}

/// The scene reference in Markdown: every table and key the schema declares, with its type,
/// unit, default, bounds and help. docs/scene-reference.md is this text.
pub fn reference_markdown() -> String {
    let mut out = String::from(
        "# Scene reference\n\n\
         Generated from the schema in `src/scene/schema.rs` by `scene::reference_markdown`; \
         do not edit by hand. Regenerate with `PENETRATE_BLESS=1 cargo test --lib \
         scene_reference`.\n\n\
         A scene is a TOML file (`cases/*.toml`). Every value is in SI units. `--set \
         key=value` takes the keys as written here, and `penetrate check CASE` lists every \
         resolved value under the same names. Bounds in words involve other keys.\n",
    );
    for table in TABLES {
        let title = if table.path.is_empty() {
            "Top level".to_string()
        } else {
            format!("`[{}]`", table.path)
        };
        let need = match table.need {
            Need::Required => "Required.",
            Need::Optional => "Optional: left out, its keys take their defaults.",
            Need::Selects => "Optional: its presence selects the kind of scene.",
        };
        let _ = write!(
            out,
            "\n## {title}\n\n{} {need}\n\n\
             | key | type | unit | default | bounds | help |\n\
             |---|---|---|---|---|---|\n",
            table.help
        );
        for key in KEYS.iter().filter(|k| k.table() == table.path) {
            let ty = match key.ty {
                Ty::Number => "number".to_string(),
                Ty::Count => "whole number".to_string(),
                Ty::Flag => "true | false".to_string(),
                Ty::Text => "string".to_string(),
                Ty::Choice { names, .. } => {
                    let names: Vec<String> = names.iter().map(|n| format!("`\"{n}\"`")).collect();
                    names.join(" | ")
                }
            };
            let default = match key.default {
                DefaultValue::Required => "**required**".to_string(),
                DefaultValue::Number(x) => format!("`{}`", num(x)),
                DefaultValue::Count(n) => format!("`{n}`"),
                DefaultValue::Flag(b) => format!("`{b}`"),
                DefaultValue::Text(s) => format!("`\"{s}\"`"),
                DefaultValue::Derived(words) => words.to_string(),
            };
            let bounds = match key.bounds {
                Bounds::None => String::new(),
                Bounds::Range(text) => format!("`{text}`"),
                Bounds::Rule(text) => text.to_string(),
            };
            let cells = [
                format!("`{}`", key.path),
                ty,
                key.unit.to_string(),
                default,
                bounds,
                key.help.to_string(),
            ];
            // A pipe inside a cell would end it.
            let cells: Vec<String> = cells.iter().map(|c| c.replace('|', "\\|")).collect();
            let row = cells.join(" | ");
            let _ = writeln!(out, "| {row} |");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::load;
    use crate::scene::tests::shipped_cases;
    use std::path::Path;

    #[test]
    fn resolved_table_read_back_as_overrides_reproduces_every_case() {
        for path in shipped_cases() {
            let scene = load(&path, &[]).unwrap();
            let table = scene.resolved_table();
            let sets: Vec<String> = table
                .lines()
                .map(|line| {
                    let (assignment, _unit) = line.split_once("  # ").expect("unit comment");
                    assignment.replacen(" = ", "=", 1)
                })
                .collect();
            assert!(sets.len() > 30, "{table}");
            let again = load(&path, &sets).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(again, scene, "{path:?}\n{table}");
        }
    }

    /// The table is a scene file too: `penetrate run` of a run's `scene.toml` (or of a member
    /// of `sweep --emit`) runs the very scene, wherever the file lies.
    #[test]
    fn resolved_table_read_as_a_scene_file_reproduces_every_case() {
        for path in shipped_cases() {
            let scene = load(&path, &[]).unwrap();
            let elsewhere = Path::new("/elsewhere/scene.toml");
            let mut again = crate::scene::parse_str(&scene.resolved_table(), elsewhere, &[])
                .unwrap_or_else(|e| panic!("{path:?}: {e}"));
            // Where it was read from, the one field no run reads.
            assert_eq!(again.path, elsewhere);
            again.path = scene.path.clone();
            assert_eq!(again, scene, "{path:?}");
        }
    }

    /// docs/scene-reference.md is the schema's text; `PENETRATE_BLESS=1` rewrites it.
    #[test]
    fn scene_reference_is_generated() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scene-reference.md");
        let text = reference_markdown();
        if std::env::var_os("PENETRATE_BLESS").is_some() {
            std::fs::write(&path, &text).expect("docs/scene-reference.md written");
        }
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            committed == text,
            "docs/scene-reference.md differs from the schema; regenerate it with \
             `PENETRATE_BLESS=1 cargo test --lib scene_reference` and commit it"
        );
    }

    #[test]
    fn every_key_has_a_row_in_the_reference() {
        let text = reference_markdown();
        for key in KEYS {
            assert!(
                text.contains(&format!("| `{}` |", key.path)),
                "{}",
                key.path
            );
        }
    }
}
