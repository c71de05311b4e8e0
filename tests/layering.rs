//! The stage modules form a pipeline, not a knot: each imports only modules below it
//! (docs/architecture.md). This test reads `src/` and fails on any upward reference, so a new
//! cycle is caught at the commit that introduces it.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Bottom to top. Modules on the same level may not use each other either.
const LAYERS: &[&[&str]] = &[
    &["geometry", "status"],
    &["error"],
    &["control"],
    &["robot"],
    &["instance"],
    &["placement"],
    &["actions"],
    &["motion"],
    &["sequence", "simulate"],
    &["plan"],
    &["verify", "render"],
    &["bench"],
    &["report"],
    &["cli"],
];

fn level(m: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&m))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// Code without `//` comments (doc links may point anywhere; imports may not).
fn code(text: &str) -> String {
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The top-level modules a piece of code names through `crate::`, including grouped imports
/// such as `use crate::{geometry::Rect, instance::Instance}`.
fn referenced(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let b = code.as_bytes();
    let mut i = 0;
    while let Some(k) = code[i..].find("crate::") {
        let start = i + k + "crate::".len();
        i = start;
        if start > "crate::".len() && (b[start - 8].is_ascii_alphanumeric() || b[start - 8] == b'_') {
            continue; // `mycrate::`
        }
        if b.get(start) == Some(&b'{') {
            // Only the first identifier of each path at depth 1 names a module.
            let mut depth = 0;
            let mut at_start = false;
            let mut ident = String::new();
            for &c in &b[start..] {
                let word = c.is_ascii_alphanumeric() || c == b'_';
                if depth == 1 && at_start && word {
                    ident.push(c as char);
                    continue;
                }
                if !ident.is_empty() {
                    out.insert(std::mem::take(&mut ident));
                    at_start = false;
                }
                match c {
                    b'{' => {
                        depth += 1;
                        at_start = depth == 1;
                    }
                    b'}' => depth -= 1,
                    b',' if depth == 1 => at_start = true,
                    _ => {}
                }
                if depth == 0 {
                    break;
                }
            }
        } else {
            let name: String = code[start..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            out.insert(name);
        }
    }
    out
}

#[test]
fn no_stage_module_imports_a_module_above_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut violations = Vec::new();
    let mut seen_modules = BTreeSet::new();
    for f in &files {
        let rel = f.strip_prefix(&src).unwrap();
        let top = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy()
            .trim_end_matches(".rs")
            .to_string();
        if matches!(top.as_str(), "lib" | "main") {
            continue;
        }
        seen_modules.insert(top.clone());
        let Some(own) = level(&top) else {
            violations.push(format!(
                "{}: module `{top}` has no place in LAYERS (tests/layering.rs)",
                rel.display()
            ));
            continue;
        };
        for m in referenced(&code(&std::fs::read_to_string(f).unwrap())) {
            if m == top || m.is_empty() {
                continue;
            }
            match level(&m) {
                Some(l) if l < own => {}
                Some(_) => violations.push(format!(
                    "{}: `{top}` uses `crate::{m}`, which is not below it",
                    rel.display()
                )),
                None => {}
            }
        }
    }
    for l in LAYERS.iter().flat_map(|l| l.iter()) {
        assert!(
            seen_modules.contains(*l),
            "LAYERS names `{l}`, which src/ no longer has"
        );
    }
    assert!(violations.is_empty(), "upward imports:\n{}", violations.join("\n"));
}

#[test]
fn the_scanner_sees_plain_and_grouped_imports() {
    let c = code("use crate::plan::Plan;\nuse crate::{geometry::Rect, instance::{Instance, Gripper}, error};\n// crate::bench in a comment\nlet x = crate::robot::DEFAULT;");
    let got: Vec<String> = referenced(&c).into_iter().collect();
    assert_eq!(got, ["error", "geometry", "instance", "plan", "robot"]);
}
