//! The README and the guides (`docs/*.md`) say only what runs. Every relative
//! link resolves (the file, and a `#anchor` to one of its headings); every
//! `airlight` command in a shell block exists with every flag it names (its
//! `--help` says so); every other command names packages, tests, benches,
//! features and files that exist; and every other code block is an excerpt of a
//! file that the tests compile or run (`TESTED`), its lines in order, `// …`
//! marking a gap. The CLI quick start's input is evaluated for real.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The files whose code the docs may quote, each compiled or run by a test.
const TESTED: &[(&str, &str)] = &[
    ("examples/three/quickstart.js", "the example page's browser test (WebGPU) runs it"),
    ("examples/three/main.js", "the example page's browser tests run it"),
    ("examples/shaders/fog.wgsl", "tests/tests/examples.rs validates it with naga"),
    ("examples/shaders/fog.frag", "tests/tests/examples.rs compiles it with glslang"),
    ("examples/shaders/shafts.frag", "tests/tests/examples.rs compiles it with glslang"),
    ("examples/shaders/fog.hlsl", "tests/tests/examples.rs compiles it with glslang"),
    ("tests/tests/examples.rs", "a test: it runs"),
    ("examples/bevy/src/lib.rs", "compiled by cargo test; the headless test draws its street"),
    ("examples/bevy/Cargo.toml", "the example crate's manifest, built by cargo test"),
    ("bevy/src/lib.rs", "the Bevy plugin, compiled and run by the headless test"),
    ("codegen/scenes/fog-street.toml", "planned by generate, held by tests/tests/generated_is_current.rs"),
];

/// The README and every guide.
fn documents() -> Vec<PathBuf> {
    let mut docs = vec![root().join("README.md")];
    let mut guides: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .expect("docs/")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    guides.sort();
    docs.extend(guides);
    docs
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn name(p: &Path) -> String {
    p.strip_prefix(root()).unwrap_or(p).display().to_string()
}

/// A fenced code block: its language, its first line's number, its lines.
struct Block {
    lang: String,
    line: usize,
    lines: Vec<String>,
}

/// The text outside code blocks (blocks blanked, so line numbers hold) and the blocks.
fn split(text: &str) -> (Vec<String>, Vec<Block>) {
    let mut prose = Vec::new();
    let mut blocks = Vec::new();
    let mut open: Option<(Block, usize)> = None;
    for (i, l) in text.lines().enumerate() {
        let t = l.trim_start();
        if let Some(rest) = t.strip_prefix("```") {
            match open.take() {
                None => {
                    let block = Block { lang: rest.trim().to_string(), line: i + 1, lines: Vec::new() };
                    open = Some((block, l.len() - t.len()));
                }
                Some((b, _)) => blocks.push(b),
            }
            prose.push(String::new());
            continue;
        }
        match open.as_mut() {
            Some((b, indent)) => {
                let cut = l.len() - l.trim_start().len();
                b.lines.push(l[cut.min(*indent)..].to_string());
                prose.push(String::new());
            }
            None => prose.push(l.to_string()),
        }
    }
    assert!(open.is_none(), "an unclosed code block");
    (prose, blocks)
}

/// GitHub's anchor for a heading.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

fn anchors(md: &Path) -> BTreeSet<String> {
    let (prose, _) = split(&read(md));
    prose.iter().filter_map(|l| l.strip_prefix('#')).map(|h| slug(h.trim_start_matches('#'))).collect()
}

/// Every link target of a line: markdown `](target)` and HTML `src="…"`, `href="…"`.
fn targets(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(k) = rest.find("](") {
        let tail = &rest[k + 2..];
        let end = tail.find(')').unwrap_or(tail.len());
        out.push(tail[..end].split_whitespace().next().unwrap_or("").to_string());
        rest = &tail[end..];
    }
    for attr in ["src=\"", "href=\""] {
        let mut rest = line;
        while let Some(k) = rest.find(attr) {
            let tail = &rest[k + attr.len()..];
            let end = tail.find('"').unwrap_or(tail.len());
            out.push(tail[..end].to_string());
            rest = &tail[end..];
        }
    }
    out
}

/// What is wrong with each relative link of `doc`.
fn broken_links(doc: &Path) -> Vec<String> {
    let (prose, _) = split(&read(doc));
    let dir = doc.parent().unwrap();
    let mut bad = Vec::new();
    for (i, line) in prose.iter().enumerate() {
        for t in targets(line) {
            if t.is_empty() || t.contains("://") || t.starts_with("mailto:") {
                continue;
            }
            let (file, anchor) = t.split_once('#').map_or((t.as_str(), None), |(f, a)| (f, Some(a)));
            let path = if file.is_empty() { doc.to_path_buf() } else { dir.join(file) };
            let at = format!("{}:{}: {t}", name(doc), i + 1);
            if !path.exists() {
                bad.push(format!("{at}: no such file"));
            } else if let Some(a) = anchor {
                if path.extension().is_some_and(|x| x == "md") && !anchors(&path).contains(a) {
                    bad.push(format!("{at}: no heading with that anchor in {}", name(&path)));
                }
            }
        }
    }
    bad
}

#[test]
fn every_relative_link_in_the_readme_and_the_guides_resolves() {
    let bad: Vec<String> = documents().iter().flat_map(|d| broken_links(d)).collect();
    assert!(bad.is_empty(), "broken links:\n{}", bad.join("\n"));
}

#[test]
fn the_link_check_finds_a_missing_file_and_a_missing_anchor() {
    let dir = std::env::temp_dir().join(format!("airlight-docs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let doc = dir.join("guide.md");
    std::fs::write(&doc, "# A guide\n\n## Light shafts: `street-lamp`\n\n[ok](#light-shafts-street-lamp) [gone](nowhere.md) [bad](#nothing)\n<img src=\"missing.png\">\n```sh\n[not a link](nowhere.md)\n```\n").unwrap();
    let bad = broken_links(&doc);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(bad.len(), 3, "{bad:?}");
}

fn airlight(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_airlight")).args(args).current_dir(root()).output().expect("airlight runs")
}

/// `dir/Cargo.toml`'s package name, for every workspace member.
fn packages() -> Vec<(String, PathBuf)> {
    let manifest = read(&root().join("Cargo.toml"));
    let members = manifest.split("members = [").nth(1).and_then(|m| m.split(']').next()).expect("members");
    members
        .split(',')
        .map(|m| m.trim().trim_matches('"'))
        .filter(|m| !m.is_empty())
        .map(|m| {
            let dir = root().join(m);
            let text = read(&dir.join("Cargo.toml"));
            let name = text
                .lines()
                .find_map(|l| l.strip_prefix("name = \""))
                .and_then(|l| l.split('"').next())
                .expect("a package name")
                .to_string();
            (name, dir)
        })
        .collect()
}

/// Whether `tokens` (one command) names only what exists; the problem if not.
fn check_command(tokens: &[&str]) -> Result<(), String> {
    let flag = |f: &str| tokens.iter().position(|t| *t == f).and_then(|i| tokens.get(i + 1)).copied();
    // Paths: under the repository (or `path/to/airlight/…`, the reader's checkout of it).
    for t in tokens.iter().filter(|t| t.contains('/') && !t.starts_with('-') && !t.starts_with('~')) {
        let rel = t.strip_prefix("path/to/airlight/").unwrap_or(t);
        if rel.contains("://") || rel.starts_with("http") {
            continue;
        }
        if tokens.first() == Some(&"cargo") && flag("--out") == Some(*t) {
            continue; // an output directory the command creates
        }
        if !root().join(rel).exists() {
            return Err(format!("`{t}` does not exist"));
        }
    }
    match tokens {
        ["cargo", "run", rest @ ..] => {
            if let Some(k) = rest.iter().position(|t| *t == "--") {
                let args = &rest[k + 1..];
                let sub = args.first().ok_or("no airlight command")?;
                let help = airlight(&[sub, "--help"]);
                if !help.status.success() {
                    return Err(format!("`airlight {sub}` is not a command"));
                }
                let text = String::from_utf8_lossy(&help.stdout);
                for f in args.iter().filter(|a| a.starts_with("--")) {
                    let f = f.split('=').next().unwrap_or(f);
                    let known = text.match_indices(f).any(|(i, _)| {
                        !text[i + f.len()..].starts_with(|c: char| c.is_ascii_alphanumeric() || c == '-')
                    });
                    if !known {
                        return Err(format!("`airlight {sub}` has no flag {f}"));
                    }
                }
            }
            check_cargo(rest)
        }
        ["cargo", "test" | "bench" | "build" | "package" | "clippy" | "fmt", rest @ ..] => check_cargo(rest),
        ["cargo", "install", "cargo-fuzz"] => Ok(()),
        ["npm", "ci" | "install" | "pack", ..] | [".ci/device" | ".ci/run" | "fuzz/run", ..] => Ok(()),
        ["node", file, ..] if root().join(file).exists() => Ok(()),
        _ => Err("the docs test does not know this command; teach it (cli/tests/docs.rs)".into()),
    }
}

/// `-p`, `--test`, `--bench` and `--features` of a cargo command name what exists.
fn check_cargo(args: &[&str]) -> Result<(), String> {
    let value = |f: &str| args.iter().position(|t| *t == f).and_then(|i| args.get(i + 1)).copied();
    let packages = packages();
    let dir = match value("-p") {
        Some(p) => packages.iter().find(|(n, _)| n == p).map(|(_, d)| d.clone()).ok_or(format!("no package {p}"))?,
        None => root().join("cli"),
    };
    if let Some(t) = value("--test") {
        let (file, folder) = (dir.join(format!("tests/{t}.rs")), dir.join(format!("tests/{t}/main.rs")));
        if !file.exists() && !folder.exists() {
            return Err(format!("no test {t} in {}", name(&dir)));
        }
    }
    if let Some(b) = value("--bench") {
        if !dir.join(format!("benches/{b}.rs")).exists() {
            return Err(format!("no bench {b} in {}", name(&dir)));
        }
    }
    if let Some(f) = value("--features") {
        let manifest = read(&dir.join("Cargo.toml"));
        let features = manifest.split("[features]").nth(1).unwrap_or("");
        if !features.lines().any(|l| l.trim_start().starts_with(&format!("{f} ="))) {
            return Err(format!("no feature {f} in {}", name(&dir)));
        }
    }
    Ok(())
}

/// One shell line's commands: comments cut, `&&` split, `[ ]` and `…` dropped.
fn commands(line: &str) -> Vec<Vec<String>> {
    let line = match line.find(" #") {
        Some(k) => &line[..k],
        None => line,
    };
    line.split("&&")
        .map(|c| {
            c.split_whitespace()
                .map(|t| t.trim_matches(|c| c == '[' || c == ']').to_string())
                .filter(|t| !t.is_empty() && t != "..." && t != "…")
                .collect::<Vec<_>>()
        })
        .filter(|c| !c.is_empty())
        .collect()
}

/// Whether `block`'s lines are lines of `source`, in order (blank lines aside; a
/// gap marker skips any number).
fn excerpt_of(block: &[String], source: &str) -> bool {
    let src: Vec<&str> = source.lines().map(str::trim).filter(|l| !l.is_empty()).collect();
    let want: Vec<&str> = block.iter().map(|l| l.trim()).filter(|l| !l.is_empty()).collect();
    let gap = |l: &str| matches!(l, "// …" | "# …" | "…");
    fn from(src: &[&str], want: &[&str], at: usize, gap: &dyn Fn(&str) -> bool) -> bool {
        match want.split_first() {
            None => true,
            Some((w, rest)) if gap(w) => (at..=src.len()).any(|k| from(src, rest, k, gap)),
            Some((w, rest)) => src.get(at) == Some(w) && from(src, rest, at + 1, gap),
        }
    }
    if want.is_empty() {
        return false;
    }
    (0..src.len()).any(|start| from(&src, &want, start, &gap))
}

/// What is wrong with `doc`'s code blocks (`sources`: the `TESTED` files' text).
fn bad_blocks(doc: &Path, sources: &[String]) -> Vec<String> {
    let (_, blocks) = split(&read(doc));
    let mut bad = Vec::new();
    for b in &blocks {
        let at = format!("{}:{}", name(doc), b.line);
        if matches!(b.lang.as_str(), "sh" | "bash" | "console") {
            for (k, l) in b.lines.iter().enumerate() {
                for c in commands(l) {
                    let tokens: Vec<&str> = c.iter().map(String::as_str).collect();
                    if let Err(e) = check_command(&tokens) {
                        bad.push(format!("{}:{}: `{}`: {e}", name(doc), b.line + 1 + k, c.join(" ")));
                    }
                }
            }
        } else if !sources.iter().any(|s| excerpt_of(&b.lines, s)) {
            bad.push(format!(
                "{at}: a {} block that is no excerpt of a tested file (cli/tests/docs.rs, TESTED)",
                b.lang
            ));
        }
    }
    bad
}

#[test]
fn every_command_and_code_block_in_the_readme_and_the_guides_runs() {
    let sources: Vec<String> = TESTED.iter().map(|(p, _)| read(&root().join(p))).collect();
    let bad: Vec<String> = documents().iter().flat_map(|d| bad_blocks(d, &sources)).collect();
    assert!(bad.is_empty(), "stale commands or code:\n{}", bad.join("\n"));
}

#[test]
fn the_command_check_finds_a_stale_flag_a_missing_command_and_changed_code() {
    let stale = |line: &str| {
        commands(line).iter().any(|c| check_command(&c.iter().map(String::as_str).collect::<Vec<_>>()).is_err())
    };
    assert!(!stale("cargo run --release -- eval --model phi-6 --input examples/cli/points.csv  # fine"));
    assert!(stale("cargo run --release -- eval --modle phi-6"), "a misspelt flag");
    assert!(stale("cargo run --release -- evaluate --model phi-6"), "no such command");
    assert!(stale("cargo bench -p airlight-tests --bench nothing"), "no such bench");
    assert!(stale("cargo run --release -p airlight-bevy-example --features nowindow"), "no such feature");
    assert!(stale("node examples/three/gone.mjs"), "no such file");
    let quick = read(&root().join("examples/three/quickstart.js"));
    let lines = |t: &str| t.lines().map(String::from).collect::<Vec<_>>();
    assert!(excerpt_of(
        &lines("  for (const light of lights) fog.add(light);\n  const scenePass = pass(scene, camera);"),
        &quick
    ));
    assert!(!excerpt_of(&lines("  for (const light of lights) fog.add(light, 1);"), &quick), "a changed line");
    assert!(
        !excerpt_of(
            &lines("  const scenePass = pass(scene, camera);\n  for (const light of lights) fog.add(light);"),
            &quick
        ),
        "lines out of order"
    );
}

#[test]
fn the_cli_quick_start_evaluates_its_points() {
    let out = airlight(&["eval", "--model", "phi-6", "--input", "examples/cli/points.csv"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows[0], "tau,gamma,rho,g,airlight");
    assert_eq!(rows.len(), 4, "{text}");
    for r in &rows[1..] {
        let a: f64 = r.rsplit(',').next().unwrap().parse().unwrap();
        assert!(a.is_finite() && a > 0.0, "{r}");
    }
}
