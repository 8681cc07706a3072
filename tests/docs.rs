//! The documentation holds together: every relative link of the README and the manual
//! (`docs/`, `docs/notes/`, the committed validation report, `data/README.md`,
//! `CHANGELOG.md`) names a file or folder in the repository, and a link to a heading names one the page has; every docs page and `physics.md`
//! section that the source cites exists; and the README stays a short page for users.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The README's length limit: a page a user reads, not a notebook (issue 56).
const README_MAX_LINES: usize = 250;

/// The Markdown pages whose links are checked.
fn pages() -> Vec<PathBuf> {
    let mut pages: Vec<PathBuf> = ["README.md", "CHANGELOG.md", "data/README.md"]
        .iter()
        .map(|p| root().join(p))
        .collect();
    for dir in ["docs", "docs/notes", "docs/validation"] {
        let mut found: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
            .unwrap_or_else(|e| panic!("{dir}: {e}"))
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "md"))
            .collect();
        found.sort();
        pages.extend(found);
    }
    pages
}

/// The lines of `text` outside fenced code blocks, with their 1-based numbers.
fn prose_lines(text: &str) -> Vec<(usize, &str)> {
    let mut fenced = false;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if !fenced {
            out.push((i + 1, line));
        }
    }
    out
}

/// The targets of the Markdown links and images on `line`: what stands between `](` and the
/// next `)`, without a title. Inline code spans (`` `…` ``) hold no links.
fn link_targets(line: &str) -> Vec<String> {
    let mut in_code = false;
    let prose: String = line
        .chars()
        .map(|c| {
            if c == '`' {
                in_code = !in_code;
                ' '
            } else if in_code {
                ' '
            } else {
                c
            }
        })
        .collect();
    let mut out = Vec::new();
    let mut rest = prose.as_str();
    while let Some(at) = rest.find("](") {
        let after = &rest[at + 2..];
        let Some(end) = after.find(')') else { break };
        let target = after[..end].split_whitespace().next().unwrap_or("");
        out.push(target.to_string());
        rest = &after[end..];
    }
    out
}

/// GitHub's anchor for a heading: lower case, letters, digits, `-` and `_` kept, spaces made
/// `-`, everything else dropped.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

/// The anchors of a Markdown page's headings.
fn anchors(text: &str) -> BTreeSet<String> {
    prose_lines(text)
        .into_iter()
        .filter_map(|(_, line)| {
            let hashes = line.chars().take_while(|&c| c == '#').count();
            (hashes > 0 && line[hashes..].starts_with(' ')).then(|| slug(&line[hashes..]))
        })
        .collect()
}

/// What is wrong with the links of the page `page` whose text is `text`: one line each.
fn broken_links(page: &Path, text: &str) -> Vec<String> {
    let dir = page.parent().unwrap();
    let name = page.strip_prefix(root()).unwrap_or(page).display();
    let mut broken = Vec::new();
    for (n, line) in prose_lines(text) {
        for target in link_targets(line) {
            if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (path, anchor) = match target.split_once('#') {
                Some((p, a)) => (p, Some(a)),
                None => (target.as_str(), None),
            };
            let file = if path.is_empty() {
                page.to_path_buf()
            } else {
                dir.join(path)
            };
            if !file.exists() {
                broken.push(format!("{name}:{n}: {target}: no such file"));
                continue;
            }
            if let Some(anchor) = anchor {
                if file.extension().is_some_and(|x| x == "md") {
                    let page_text = std::fs::read_to_string(&file).unwrap();
                    if !anchors(&page_text).contains(anchor) {
                        broken.push(format!("{name}:{n}: {target}: no such heading"));
                    }
                }
            }
        }
    }
    broken
}

#[test]
fn every_relative_link_resolves() {
    let mut broken = Vec::new();
    for page in pages() {
        let text = std::fs::read_to_string(&page).unwrap();
        broken.extend(broken_links(&page, &text));
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn the_link_check_finds_a_broken_link() {
    let page = root().join("docs/user-guide.md");
    let text = "A [page](cli.md), a [heading](cli.md#exit-codes), a [site](https://example.org),\n\
                a [lost page](no-such-page.md), a [lost heading](cli.md#no-such-heading),\n\
                code `f[x](y)` and\n```\n[in code](not-checked.md)\n```\n";
    let broken = broken_links(&page, text);
    assert_eq!(broken.len(), 2, "{broken:?}");
    assert!(
        broken[0].contains("no-such-page.md: no such file"),
        "{broken:?}"
    );
    assert!(
        broken[1].contains("#no-such-heading: no such heading"),
        "{broken:?}"
    );
}

#[test]
fn headings_give_githubs_anchors() {
    assert_eq!(
        slug(" 3.1 Concrete: Holmquist–Johnson–Cook (HJC)"),
        "31-concrete-holmquistjohnsoncook-hjc"
    );
    assert_eq!(slug(" The nose cell's mode"), "the-nose-cells-mode");
    assert_eq!(slug(" `summary.json`"), "summaryjson");
}

#[test]
fn the_readme_is_short() {
    let text = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = text.lines().count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines, more than {README_MAX_LINES}: move detail to docs/"
    );
}

/// The files under `dir` whose names end in one of `exts`, recursively.
fn sources(dir: &Path, exts: &[&str], out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, exts, out);
        } else if path
            .extension()
            .is_some_and(|x| exts.iter().any(|e| x == *e))
        {
            out.push(path);
        }
    }
}

/// Every `docs/….md` page a source comment or message names exists, and every
/// `physics.md §N` or `§N.M` it cites is a section of docs/physics.md.
#[test]
fn the_docs_the_source_cites_exist() {
    let mut files = Vec::new();
    for dir in ["src", "shaders", "tests", "scripts", "cases"] {
        sources(
            &root().join(dir),
            &["rs", "wgsl", "py", "toml", "sh"],
            &mut files,
        );
    }
    let physics = std::fs::read_to_string(root().join("docs/physics.md")).unwrap();
    let sections: BTreeSet<String> = prose_lines(&physics)
        .into_iter()
        .filter(|(_, l)| l.starts_with("## ") || l.starts_with("### "))
        .filter_map(|(_, l)| l.split_whitespace().nth(1))
        .map(|n| n.trim_end_matches('.').to_string())
        .collect();
    let mut missing = BTreeSet::new();
    for file in files {
        if file.ends_with("tests/docs.rs") {
            continue;
        }
        let text = std::fs::read_to_string(&file).unwrap();
        let name = file.strip_prefix(root()).unwrap().display().to_string();
        for (at, _) in text.match_indices("docs/") {
            let page: String = text[at..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || "/-_.".contains(*c))
                .collect();
            let page = page.trim_end_matches('.');
            if page.ends_with(".md") && !root().join(page).exists() {
                missing.insert(format!("{name}: {page}"));
            }
        }
        for (at, _) in text.match_indices("physics.md §") {
            let number: String = text[at + "physics.md §".len()..]
                .chars()
                .take_while(|c| c.is_ascii_digit() || *c == '.')
                .collect();
            let number = number.trim_end_matches('.');
            if !sections.contains(number) {
                missing.insert(format!("{name}: physics.md §{number}"));
            }
        }
    }
    assert!(missing.is_empty(), "cited but missing:\n{missing:#?}");
}
