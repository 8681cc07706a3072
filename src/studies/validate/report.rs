//! The report: `report.md` put together from the sections' parts, and the Markdown helpers the
//! sections share.

use crate::output::summary::build_id;
use crate::scene::Backend;

use super::context::Context;
use super::Section;

/// A pass/fail line of the report's summary.
pub(super) struct Check {
    pub(super) section: Section,
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

pub(super) fn render(
    ctx: &Context,
    chosen: &[Section],
    parts: &[(Section, SectionOut)],
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
    let skipped: Vec<Section> = Section::ALL
        .into_iter()
        .filter(|s| !chosen.contains(s))
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
    md += &format!("- Sections run: {}\n", names(chosen));
    md += &format!("- Sections not run: {}\n", names(&skipped));
    md += &format!(
        "- Backends: {} (the error-against-run-time section runs on each, the others on the first)\n",
        backends.join(", ")
    );
    md += &format!("- Data: `{}`\n", opts.data.display());
    md += &set_line(opts);
    md += &format!(
        "- Runs: {} ({} of them resumed from earlier output in this folder; {} more asked again \
         and reused), {} did not complete\n",
        ctx.done.len(),
        ctx.resumed,
        ctx.reused,
        ctx.failed.len()
    );
    md += &builds_line(ctx);
    md += &format!("- Wall time: {wall_s:.0} s\n\n");
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
        .flat_map(|(_, p)| &p.checks)
        .map(|c| {
            vec![
                c.section.name().to_string(),
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
    for (s, p) in parts {
        md += &format!("\n## {}\n\n", s.title());
        md += &format!("- Command: `{}`\n", command(ctx, *s));
        md += &format!("- Data source: {}\n", s.source());
        md += &format!("- Verdict: {}\n\n", verdict(&p.checks));
        md += &p.markdown;
    }
    md
}

/// The one-page summary beside the report: how it was made, and its checks with their
/// verdicts, each section linked to its part of `report.md`.
pub(super) fn render_summary(ctx: &Context, parts: &[(Section, SectionOut)]) -> String {
    let mut md = String::from("# Validation summary\n\n");
    if ctx.opts.quick {
        md += "> **Quick run** (`--quick`): these numbers test the tooling; **they are not \
               validation**.\n\n";
    }
    md += "Every check of `penetrate validate`, as its last run wrote them; the setup, data, \
           results and plots of each section are in [report.md](report.md).\n\n";
    md += &builds_line(ctx);
    md += &set_line(ctx.opts);
    md += "\n";
    let rows: Vec<Vec<String>> = parts
        .iter()
        .map(|(s, p)| {
            // The heading's anchor as Markdown renderers make it (GitHub's rule).
            let anchor: String = s
                .title()
                .to_lowercase()
                .chars()
                .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-')
                .map(|c| if c == ' ' { '-' } else { c })
                .collect();
            vec![
                format!("[{}](report.md#{anchor})", s.title()),
                s.source().to_string(),
                p.checks
                    .iter()
                    .map(|c| format!("{}: {}", c.what, c.result))
                    .collect::<Vec<_>>()
                    .join("; "),
                verdict(&p.checks),
            ]
        })
        .collect();
    md += &table(&["section", "data", "result", "verdict"], &rows);
    md
}

/// The command that makes a section's part again.
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

/// A section's verdict from its checks: pass when every check passed.
fn verdict(checks: &[Check]) -> String {
    if checks.is_empty() {
        return "no accuracy target (a study: read its figures)".into();
    }
    let passed = checks.iter().filter(|c| c.pass == Some(true)).count();
    let failed = checks.iter().filter(|c| c.pass == Some(false)).count();
    match (failed, passed == checks.len()) {
        (0, true) => format!("pass ({passed} of {} checks)", checks.len()),
        (0, false) => format!(
            "n/a: {} of {} checks not evaluated (a run did not complete)",
            checks.len() - passed,
            checks.len()
        ),
        _ => format!("**fail** ({failed} of {} checks)", checks.len()),
    }
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
