//! The report: `report.md` put together from the sections' parts, and the Markdown helpers the
//! sections share.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::output::summary::build_id;
use crate::scene::Backend;

use super::context::Context;
use super::Section;

/// A pass/fail line of the report's summary.
pub(super) struct Check {
    pub(super) what: String,
    pub(super) target: String,
    pub(super) result: String,
    /// `None`: not evaluated (a run it needs did not complete).
    pub(super) pass: Option<bool>,
}

/// A section's part of the report.
pub(super) struct SectionOut {
    pub(super) markdown: String,
    pub(super) checks: Vec<Check>,
}

/// A check as the report keeps it, without its section.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(super) struct CheckRow {
    what: String,
    target: String,
    result: String,
    pass: Option<bool>,
}

/// What a section's part was made with. A part is kept in a later run's report only when that
/// run asks for the same, so that one report never mixes quick and full numbers, data folders,
/// parameter sets or backends.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(super) struct MadeWith {
    quick: bool,
    set: Vec<String>,
    data: String,
    backends: Vec<String>,
}

impl MadeWith {
    pub(super) fn of(opts: &super::Options) -> MadeWith {
        MadeWith {
            quick: opts.quick,
            set: opts.set.clone(),
            data: opts.data.display().to_string(),
            backends: opts.backends.iter().map(|b| b.name().to_string()).collect(),
        }
    }
}

/// A section's part of the report as written, also kept in the section's folder
/// ([`PART_FILE`]) so that a later `--only` run of other sections keeps it in the report.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(super) struct Part {
    /// The section's name (`--only`).
    section: String,
    made_with: MadeWith,
    checks: Vec<CheckRow>,
    /// Its Markdown, from its heading on.
    block: String,
}

/// A part's file in its section's folder.
const PART_FILE: &str = "part.json";

impl Part {
    /// The part `out` of section `s`, made by this run.
    pub(super) fn new(ctx: &Context, s: Section, out: &SectionOut) -> Part {
        let mut block = format!("## {}\n\n", s.title());
        block += &format!("- Command: `{}`\n", command(ctx, s));
        block += &format!("- Data source: {}\n", s.source());
        block += &format!(
            "- Verdict: {}\n",
            verdict_of(out.checks.iter().map(|c| c.pass))
        );
        block += &made_by_line(ctx, s);
        block += "\n";
        block += &out.markdown;
        Part {
            section: s.name().to_string(),
            made_with: MadeWith::of(ctx.opts),
            checks: out
                .checks
                .iter()
                .map(|c| CheckRow {
                    what: c.what.clone(),
                    target: c.target.clone(),
                    result: c.result.clone(),
                    pass: c.pass,
                })
                .collect(),
            block,
        }
    }

    /// The part an earlier run left in `dir` (a section's folder), if it was made with
    /// `made_with`; `None` where there is none or it cannot be read.
    pub(super) fn kept(dir: &Path, s: Section, made_with: &MadeWith) -> Option<Part> {
        let text = std::fs::read_to_string(dir.join(PART_FILE)).ok()?;
        let part: Part = serde_json::from_str(&text).ok()?;
        (part.section == s.name() && part.made_with == *made_with).then_some(part)
    }

    pub(super) fn write(&self, dir: &Path) -> Result<(), String> {
        let path = dir.join(PART_FILE);
        let json = serde_json::to_string_pretty(self).map_err(|e| e.to_string())?;
        std::fs::write(&path, json + "\n").map_err(|e| format!("{}: {e}", path.display()))
    }

    /// The title its heading gives it.
    fn title(&self) -> Option<&str> {
        self.block.lines().next()?.strip_prefix("## ")
    }

    fn verdict(&self) -> String {
        verdict_of(self.checks.iter().map(|c| c.pass))
    }
}

/// `report.md`: how this run was made, the checks of every part, and the parts, in the order
/// of [`Section::ALL`]. `parts` holds the sections this run made and those `kept` from earlier
/// runs in the folder.
pub(super) fn render(
    ctx: &Context,
    made: &[Section],
    kept: &[Section],
    parts: &[(Section, Part)],
    wall_s: f64,
) -> String {
    let opts = ctx.opts;
    let mut md = String::from("# Validation report\n\n");
    if opts.quick {
        md += "> **Quick run** (`--quick`): every section at a tiny resolution (12 mm lattice, \
               6.5 mm elements, a 0.1 m × 0.3 m target) and 0.3 ms of flight, the Taylor bars at \
               3–5× the shipped element size. Its numbers test the tooling; **they are not \
               validation**.\n\n";
    }
    let names = |list: &[Section]| -> String {
        let n: Vec<&str> = list.iter().map(|s| s.name()).collect();
        if n.is_empty() {
            "none".into()
        } else {
            n.join(", ")
        }
    };
    let missing: Vec<Section> = Section::ALL
        .into_iter()
        .filter(|s| !made.contains(s) && !kept.contains(s))
        .collect();
    let backends: Vec<String> = opts
        .backends
        .iter()
        .map(|&b| {
            let adapter = ctx
                .done
                .iter()
                .filter(|r| r.backend == b && b == Backend::Gpu)
                .find_map(|r| r.summary().map(|s| format!(" ({})", s.adapter)))
                .unwrap_or_default();
            format!("{}{adapter}", b.name())
        })
        .collect();
    md += &format!("- Sections made by this run: {}\n", names(made));
    if !kept.is_empty() {
        md += &format!(
            "- Sections kept from an earlier run in this folder, as it wrote them (each says \
             which build made it): {}\n",
            names(kept)
        );
    }
    md += &format!("- Sections not in the report: {}\n", names(&missing));
    md += &format!(
        "- Backends: {} (the error-against-run-time section runs on each, the others on the first)\n",
        backends.join(", ")
    );
    md += &format!("- Data: `{}`\n", opts.data.display());
    md += &set_line(opts);
    md += &format!(
        "- Runs of this run: {} ({} of them resumed from earlier output in this folder; {} more \
         asked again and reused), {} did not complete\n",
        ctx.done.len(),
        ctx.resumed,
        ctx.reused,
        ctx.failed.len()
    );
    md += &builds_line(ctx);
    md += &format!("- Wall time of this run: {wall_s:.0} s\n\n");
    if !ctx.failed.is_empty() {
        md += "Runs that did not complete:\n\n";
        for f in &ctx.failed {
            md += &format!("- {f}\n");
        }
        md += "\n";
    }
    md += "## Checks\n\n";
    let rows: Vec<Vec<String>> = parts
        .iter()
        .flat_map(|(s, p)| p.checks.iter().map(move |c| (s, c)))
        .map(|(s, c)| {
            vec![
                s.name().to_string(),
                c.what.clone(),
                c.target.clone(),
                c.result.clone(),
                match c.pass {
                    Some(true) => "pass".into(),
                    Some(false) => "**fail**".into(),
                    None => "n/a".into(),
                },
            ]
        })
        .collect();
    if rows.is_empty() {
        md += "No section with an accuracy target ran.\n\n";
    } else {
        md += &table(&["section", "check", "target", "result", "verdict"], &rows);
    }
    for (_, p) in parts {
        md += "\n";
        md += &p.block;
    }
    md
}

/// The one-page summary beside the report: how it was made, and its checks with their
/// verdicts, each section linked to its part of `report.md`.
pub(super) fn render_summary(ctx: &Context, kept: &[Section], parts: &[(Section, Part)]) -> String {
    let mut md = String::from("# Validation summary\n\n");
    if ctx.opts.quick {
        md += "> **Quick run** (`--quick`): these numbers test the tooling; **they are not \
               validation**.\n\n";
    }
    md += "Every check of `penetrate validate`, as its last run wrote them; the setup, data, \
           results and plots of each section, and the solver build that made it, are in \
           [report.md](report.md).\n\n";
    md += &builds_line(ctx);
    if !kept.is_empty() {
        let n: Vec<&str> = kept.iter().map(|s| s.name()).collect();
        md += &format!(
            "- Sections kept from an earlier run in this folder: {}\n",
            n.join(", ")
        );
    }
    md += &set_line(ctx.opts);
    md += "\n";
    let rows: Vec<Vec<String>> = parts
        .iter()
        .map(|(s, p)| {
            // The part's own heading: a kept part keeps the title it was written with.
            let title = p.title().unwrap_or(s.title());
            let anchor = anchor(title);
            vec![
                format!("[{title}](report.md#{anchor})"),
                s.source().to_string(),
                p.checks
                    .iter()
                    .map(|c| format!("{}: {}", c.what, c.result))
                    .collect::<Vec<_>>()
                    .join("; "),
                p.verdict(),
            ]
        })
        .collect();
    md += &table(&["section", "data", "result", "verdict"], &rows);
    md
}

/// A heading's anchor as Markdown renderers make it (GitHub's rule).
fn anchor(heading: &str) -> String {
    heading
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The `--set` values, where any were given: the parameter set is not the shipped one.
fn set_line(opts: &super::Options) -> String {
    if opts.set.is_empty() {
        return String::new();
    }
    let values: Vec<String> = opts.set.iter().map(|s| format!("`{s}`")).collect();
    format!(
        "- **Not the shipped parameter set**: every run whose scene has the key's table was \
         made with {} (`--set`; `target.` and `contact.` keys in the runs with a target)\n",
        values.join(", ")
    )
}

/// The command that makes a section's part again.
fn command(ctx: &Context, s: Section) -> String {
    let o = ctx.opts;
    let backends: Vec<&str> = o.backends.iter().map(|b| b.name()).collect();
    let set: String = o.set.iter().map(|s| format!(" --set '{s}'")).collect();
    format!(
        "penetrate validate --only {} --backend {} --data {}{}{set}",
        s.name(),
        backends.join(","),
        o.data.display(),
        if o.quick { " --quick" } else { "" }
    )
}

/// A section's verdict from its checks' outcomes: pass when every check passed.
fn verdict_of(checks: impl Iterator<Item = Option<bool>> + Clone) -> String {
    let total = checks.clone().count();
    if total == 0 {
        return "no accuracy target (a study: read its figures)".into();
    }
    let passed = checks.clone().filter(|&c| c == Some(true)).count();
    let failed = checks.filter(|&c| c == Some(false)).count();
    match (failed, passed == total) {
        (0, true) => format!("pass ({passed} of {total} checks)"),
        (0, false) => format!(
            "n/a: {} of {total} checks not evaluated (a run did not complete)",
            total - passed,
        ),
        _ => format!("**fail** ({failed} of {total} checks)"),
    }
}

/// A part's line naming the build that wrote it and those of its runs (which `--resume` may
/// have taken from other builds).
fn made_by_line(ctx: &Context, s: Section) -> String {
    let mut counts: Vec<(&str, usize)> = Vec::new();
    for (_, b) in ctx.builds.iter().filter(|(t, _)| *t == s) {
        match counts.iter_mut().find(|(c, _)| c == b) {
            Some((_, n)) => *n += 1,
            None => counts.push((b, 1)),
        }
    }
    let runs: usize = counts.iter().map(|(_, n)| n).sum();
    let mut line = format!("- Made by solver build `{}`", build_id());
    if runs > 0 {
        let each: Vec<String> = counts.iter().map(|(b, n)| format!("`{b}` ({n})")).collect();
        line += &format!("; its {runs} runs by {}", each.join(", "));
    }
    line + "\n"
}

/// The report's line naming the solver build of every run it used, this executable's first.
fn builds_line(ctx: &Context) -> String {
    let this = build_id();
    let mut counts: Vec<(String, usize)> = vec![(this.to_string(), 0)];
    for s in ctx.done.iter().filter_map(|r| r.summary()) {
        match counts.iter_mut().find(|(b, _)| *b == s.solver_build) {
            Some((_, n)) => *n += 1,
            None => counts.push((s.solver_build.clone(), 1)),
        }
    }
    let parts: Vec<String> = counts
        .iter()
        .enumerate()
        .filter(|(i, (_, n))| *i == 0 || *n > 0)
        .map(|(i, (b, n))| {
            let whose = if i == 0 {
                "this executable"
            } else {
                "taken with --resume-build"
            };
            format!("`{b}` ({whose}): {n}")
        })
        .collect();
    format!("- Solver builds of the runs: {}\n", parts.join("; "))
}

/// A Markdown table (a `|` in a cell is escaped).
pub(super) fn table<S: AsRef<str>>(header: &[&str], rows: &[Vec<S>]) -> String {
    let line = |cells: Vec<String>| format!("| {} |\n", cells.join(" | "));
    let escape = |c: &str| c.replace('|', "\\|");
    let mut t = line(header.iter().map(|h| escape(h)).collect());
    t += &format!("|{}\n", "---|".repeat(header.len()));
    for r in rows {
        t += &line(r.iter().map(|c| escape(c.as_ref())).collect());
    }
    t + "\n"
}

/// A signed relative error in per cent.
pub(super) fn pct(x: f64) -> String {
    format!("{:+.1} %", 100.0 * x)
}

/// `f(x)`, or a dash where there is no value.
pub(super) fn or_dash<T>(x: Option<T>, f: impl FnOnce(T) -> String) -> String {
    x.map_or_else(|| "–".into(), f)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The summary links a part by the heading it was written with, which a kept part may
    /// have from before its section's title changed.
    #[test]
    fn a_part_is_linked_by_its_own_heading() {
        let part = Part {
            section: "nose-lining".into(),
            made_with: MadeWith {
                quick: false,
                set: vec![],
                data: "data".into(),
                backends: vec!["cpu".into()],
            },
            checks: vec![],
            block: "## Concrete lining the nose: CRH 2 against CRH 6\n\n- Command: …\n".into(),
        };
        let title = part.title().unwrap();
        assert_eq!(title, "Concrete lining the nose: CRH 2 against CRH 6");
        assert_eq!(
            anchor(title),
            "concrete-lining-the-nose-crh-2-against-crh-6"
        );
        assert_eq!(anchor("Taylor bars"), "taylor-bars");
    }
}
