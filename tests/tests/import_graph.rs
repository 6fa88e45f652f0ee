//! The shape of the house, checked: the import graph of every hand-written source
//! file (`crate::`, `super::`, `self::` and `airlight_<crate>::` paths, doc links
//! included) has no circle at any depth, and no family reaches into a sibling
//! family. A file is a node; a path names the longest module prefix that is a file.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The workspace's hand-written crates: folder and the name other crates use.
const CRATES: [(&str, &str); 8] = [
    ("truth", "airlight_truth"),
    ("shapes", "airlight_shapes"),
    ("fit", "airlight_fit"),
    ("codegen", "airlight_codegen"),
    ("shaders", "airlight_shaders"),
    ("cli", "airlight_cli"),
    ("run", "airlight_run"),
    ("tests", "airlight_tests"),
];

type Node = (String, Vec<String>);

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let mut entries: Vec<_> = entries.map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// Every source file of every crate, as (crate folder, module path) → file.
fn modules(root: &Path) -> BTreeMap<Node, PathBuf> {
    let mut mods = BTreeMap::new();
    for (dir, _) in CRATES {
        let src = root.join(dir).join("src");
        let mut files = Vec::new();
        rust_files(&src, &mut files);
        for f in files {
            let rel = f.strip_prefix(&src).unwrap().with_extension("");
            let mut path: Vec<String> = rel.iter().map(|c| c.to_string_lossy().into_owned()).collect();
            if matches!(path.last().map(String::as_str), Some("mod" | "lib" | "main")) {
                path.pop();
            }
            if path.first().is_some_and(|p| p == "bin") {
                continue;
            }
            mods.insert((dir.to_string(), path), f);
        }
    }
    mods
}

/// The words of a path starting at byte `i` of `text`: `a::b::c`.
fn path_at(text: &str, i: usize) -> Vec<String> {
    let rest = &text[i..];
    let end = rest.find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':')).unwrap_or(rest.len());
    rest[..end].split("::").filter(|s| !s.is_empty()).map(str::to_string).collect()
}

/// The files `file` (module `node`) names, by the longest module prefix of each path.
fn imports(node: &Node, file: &Path, mods: &BTreeMap<Node, PathBuf>) -> BTreeSet<Node> {
    let text = std::fs::read_to_string(file).unwrap();
    let by_name: BTreeMap<&str, &str> = CRATES.iter().map(|(d, n)| (*n, *d)).collect();
    let resolve = |krate: &str, path: &[String]| -> Option<Node> {
        (0..=path.len()).rev().map(|k| (krate.to_string(), path[..k].to_vec())).find(|n| mods.contains_key(n))
    };
    // Inline modules (`mod tests {`): `super` inside one is the file's own module.
    let mut inline_depths: Vec<usize> = Vec::new();
    let mut depth = 0usize;
    let mut out = BTreeSet::new();
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'{' => depth += 1,
            b'}' => {
                depth = depth.saturating_sub(1);
                if inline_depths.last() == Some(&depth) {
                    inline_depths.pop();
                }
            }
            _ => {}
        }
        let boundary =
            i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_' || bytes[i - 1] == b':');
        if boundary && bytes[i..].starts_with(b"mod ") {
            let name_end = text[i + 4..].find(|c: char| !(c.is_alphanumeric() || c == '_')).map(|k| i + 4 + k);
            if let Some(e) = name_end {
                if text[e..].trim_start().starts_with('{') {
                    inline_depths.push(depth);
                }
            }
        }
        if boundary && bytes[i].is_ascii_alphabetic() {
            let words = path_at(&text, i);
            if words.len() >= 2 || (words.len() == 1 && words[0] == "super" && bytes[i..].starts_with(b"super::")) {
                let target = match words[0].as_str() {
                    "crate" => resolve(&node.0, &words[1..]),
                    "self" if inline_depths.is_empty() => {
                        let mut base = node.1.clone();
                        base.extend_from_slice(&words[1..]);
                        resolve(&node.0, &base)
                    }
                    "super" => {
                        let mut base = node.1.clone();
                        let mut rest = &words[..];
                        // `super` inside an inline module first leaves that module.
                        let mut inline = inline_depths.len();
                        while rest.first().is_some_and(|w| w == "super") {
                            if inline > 0 {
                                inline -= 1;
                            } else {
                                base.pop();
                            }
                            rest = &rest[1..];
                        }
                        if inline > 0 {
                            None
                        } else {
                            base.extend_from_slice(rest);
                            resolve(&node.0, &base)
                        }
                    }
                    name => by_name.get(name).and_then(|dir| resolve(dir, &words[1..])),
                };
                if let Some(t) = target {
                    if &t != node {
                        out.insert(t);
                    }
                }
                i += words.iter().map(|w| w.len() + 2).sum::<usize>().max(1);
                continue;
            }
        }
        i += 1;
    }
    out
}

/// Strongly connected components of more than one node (Tarjan).
fn circles(edges: &BTreeMap<Node, BTreeSet<Node>>) -> Vec<Vec<Node>> {
    struct State<'a> {
        edges: &'a BTreeMap<Node, BTreeSet<Node>>,
        index: BTreeMap<Node, usize>,
        low: BTreeMap<Node, usize>,
        stack: Vec<Node>,
        on: BTreeSet<Node>,
        found: Vec<Vec<Node>>,
    }
    fn visit(s: &mut State, v: &Node) {
        let n = s.index.len();
        s.index.insert(v.clone(), n);
        s.low.insert(v.clone(), n);
        s.stack.push(v.clone());
        s.on.insert(v.clone());
        for w in s.edges.get(v).into_iter().flatten() {
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if s.on.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = s.stack.pop().unwrap();
                s.on.remove(&w);
                let done = &w == v;
                comp.push(w);
                if done {
                    break;
                }
            }
            if comp.len() > 1 {
                s.found.push(comp);
            }
        }
    }
    let mut s = State {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        found: Vec::new(),
    };
    for v in edges.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.found
}

fn label(n: &Node) -> String {
    format!("{}/{}", n.0, n.1.join("/"))
}

fn graph() -> BTreeMap<Node, BTreeSet<Node>> {
    let root = airlight_tests::repo_root();
    let mods = modules(&root);
    assert!(mods.len() > 60, "the walk found the sources ({} files)", mods.len());
    mods.iter().map(|(n, f)| (n.clone(), imports(n, f, &mods))).collect()
}

#[test]
fn the_import_graph_has_no_circle() {
    let edges = graph();
    let found = circles(&edges);
    // Each circle as its files and, per file, the files of the circle it names.
    let text: Vec<String> = found
        .iter()
        .map(|c| {
            let members: BTreeSet<&Node> = c.iter().collect();
            let lines: Vec<String> = c
                .iter()
                .map(|n| {
                    let to: Vec<String> = edges[n].iter().filter(|t| members.contains(t)).map(label).collect();
                    format!("  {} → {}", label(n), to.join(", "))
                })
                .collect();
            format!("a circle of {} files:\n{}", c.len(), lines.join("\n"))
        })
        .collect();
    assert!(found.is_empty(), "import circles:\n{}", text.join("\n"));
}

#[test]
fn no_family_reaches_into_a_sibling_and_the_truth_names_no_model() {
    let edges = graph();
    let family =
        |n: &Node| -> Option<String> { (n.0 == "fit" && n.1.len() >= 2 && n.1[0] == "family").then(|| n.1[1].clone()) };
    let mut bad = Vec::new();
    for (from, tos) in &edges {
        for to in tos {
            if let (Some(a), Some(b)) = (family(from), family(to)) {
                if a != b && n_is_family_folder(&b) && n_is_family_folder(&a) {
                    bad.push(format!("{} → {}", label(from), label(to)));
                }
            }
            if from.0 == "truth" && to.0 != "truth" {
                bad.push(format!("{} → {}", label(from), label(to)));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// A family's own folder (`fit/src/family/<name>/mod.rs`), not a shared module.
fn n_is_family_folder(name: &str) -> bool {
    airlight_tests::repo_root().join("fit/src/family").join(name).is_dir()
}

/// The checker itself: a circle of two files through `crate::` and `super::` is
/// found, and `super::` inside an inline `mod tests` is the file's own module.
#[test]
fn the_checker_finds_a_planted_circle() {
    let dir = std::env::temp_dir().join(format!("airlight-import-graph-{}", std::process::id()));
    let src = dir.join("fit/src");
    std::fs::create_dir_all(src.join("family/a")).unwrap();
    std::fs::write(src.join("lib.rs"), "pub mod family;\npub mod x;\n").unwrap();
    std::fs::write(src.join("x.rs"), "use crate::family::a::Thing;\nmod tests { use super::*; }\n").unwrap();
    std::fs::write(src.join("family/mod.rs"), "pub mod a;\n").unwrap();
    std::fs::write(src.join("family/a/mod.rs"), "pub struct Thing;\nfn f() { let _ = crate::x::g; }\n").unwrap();
    let mods = modules(&dir);
    let edges: BTreeMap<Node, BTreeSet<Node>> = mods.iter().map(|(n, f)| (n.clone(), imports(n, f, &mods))).collect();
    let found = circles(&edges);
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].len(), 2);
    let x = ("fit".to_string(), vec!["x".to_string()]);
    assert!(!edges[&x].contains(&("fit".to_string(), vec![])), "super:: in mod tests is x itself");
}
