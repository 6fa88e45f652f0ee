//! WGSL and GLSL are written twice (GLSL cannot be derived from the WGSL through
//! naga: README, "One source per concept"), so the twins are held together here:
//! every generated kernel's WGSL and GLSL (`generated/wgsl/`, `generated/glsl/`,
//! exactly what the templates render now: `generated_is_current.rs`) must have the
//! same functions (GLSL defines before use, so not always in the same
//! order), and each function the same number of
//! parameters, the same calls of the kernel's functions in the same order, the same
//! numeric literals (as f32 values), returns and loops. A constant changed, a branch
//! or a call added in one language only fails here.
//!
//! The differences the two languages force are listed, each with its reason, and
//! nothing else is forgiven:
//! * GLSL ES 3.00 has no `frexp`: GLSL's `split` takes its place (WGSL calls the
//!   built-in);
//! * WGSL's `two_sum` returns the pair as an array; GLSL forms it in place;
//! * a WGSL `select` evaluates both arms, so a division there is guarded by
//!   `max(x, 1e-30)` where GLSL's `?:` needs no guard;
//! * the accumulator's run store is zeroed by WGSL's declaration and by a GLSL loop
//!   (`shafts_begin`: only its parameters are compared).

use std::collections::BTreeMap;
use std::path::Path;

/// Helpers one language has and the other does not (see the module's list).
const ONE_LANGUAGE_ONLY: [&str; 2] = ["split", "two_sum"];

/// A function's shape: parameter count, calls of the kernel's own functions (by
/// suffix after the kernel prefix), numeric literals (sorted f32 bits), returns, loops.
#[derive(Debug, PartialEq)]
struct Shape {
    params: usize,
    calls: Vec<String>,
    literals: Vec<u32>,
    returns: usize,
    loops: usize,
}

/// Functions in source order: `(name, parameter list, body)`.
fn functions(text: &str, wgsl: bool) -> Vec<(String, String, String)> {
    let mut out = Vec::new();
    for (start, line) in line_starts(text) {
        let head = if wgsl {
            line.strip_prefix("fn ")
        } else {
            // `type name(` at the start of a line: a definition (a prototype ends in `;`).
            let mut words = line.splitn(2, ' ');
            let ty = words.next().unwrap_or("");
            let ok = !ty.is_empty()
                && ty.chars().all(|c| c.is_alphanumeric() || c == '_' || c == '[' || c == ']')
                && !matches!(ty, "const" | "struct" | "return" | "if" | "for" | "while" | "else" | "#define");
            words.next().filter(|_| ok)
        };
        let Some(head) = head else { continue };
        let Some(paren) = head.find('(') else { continue };
        let name = head[..paren].trim();
        if name.is_empty() || !name.chars().all(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let after_name = start + (line.len() - head.len()) + paren;
        let close = matching(text, after_name, b'(', b')');
        let rest = &text[close + 1..];
        let brace = rest.find(['{', ';']).unwrap();
        if rest.as_bytes()[brace] == b';' {
            continue;
        }
        let open = close + 1 + brace;
        let end = matching(text, open, b'{', b'}');
        out.push((name.to_string(), text[after_name + 1..close].to_string(), text[open + 1..end].to_string()));
    }
    out
}

fn line_starts(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut pos = 0;
    text.split_inclusive('\n').map(move |l| {
        let s = pos;
        pos += l.len();
        (s, l.trim_end())
    })
}

/// The index of the bracket that closes the one at `open`.
fn matching(text: &str, open: usize, o: u8, c: u8) -> usize {
    let b = text.as_bytes();
    let mut depth = 0;
    for (i, &ch) in b.iter().enumerate().skip(open) {
        if ch == o {
            depth += 1;
        } else if ch == c {
            depth -= 1;
            if depth == 0 {
                return i;
            }
        }
    }
    panic!("unbalanced at {open}")
}

fn strip_comments(s: &str) -> String {
    s.lines().map(|l| l.split("//").next().unwrap()).collect::<Vec<_>>().join("\n")
}

/// Parameters at bracket depth 0 (`ptr<function, T>` is one).
fn count_params(list: &str) -> usize {
    if list.trim().is_empty() {
        return 0;
    }
    let mut depth = 0i32;
    let mut n = 1;
    for ch in list.chars() {
        match ch {
            '<' | '(' => depth += 1,
            '>' | ')' => depth -= 1,
            ',' if depth == 0 => n += 1,
            _ => {}
        }
    }
    n
}

/// Numeric literals with a point or an exponent (integers are loop bounds and
/// indices, typed differently in the two languages).
fn literals(body: &str) -> Vec<u32> {
    let b = body.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = (b[i].is_ascii_digit() || (b[i] == b'.' && i + 1 < b.len() && b[i + 1].is_ascii_digit()))
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'.'));
        if !starts {
            i += 1;
            continue;
        }
        let mut j = i;
        while j < b.len()
            && (b[j].is_ascii_digit()
                || b[j] == b'.'
                || b[j] == b'e'
                || b[j] == b'E'
                || ((b[j] == b'-' || b[j] == b'+') && j > i && (b[j - 1] == b'e' || b[j - 1] == b'E')))
        {
            j += 1;
        }
        let lit = &body[i..j];
        if lit.contains(['.', 'e', 'E']) {
            out.push(lit.parse::<f32>().unwrap_or_else(|_| panic!("literal {lit}")).to_bits());
        }
        i = j.max(i + 1);
    }
    out.sort_unstable();
    out
}

fn shape(params: &str, body: &str, prefix: &str, names: &[String], wgsl: bool) -> Shape {
    let mut body = strip_comments(body);
    if wgsl {
        // A `select` evaluates both arms: its divisions carry a guard GLSL's `?:` needs not.
        body = body
            .lines()
            .map(|l| if l.contains("select(") { remove_guards(l) } else { l.to_string() })
            .collect::<Vec<_>>()
            .join("\n");
    }
    let mut calls = Vec::new();
    let mut rest = body.as_str();
    while let Some(k) = rest.find(prefix) {
        let tail = &rest[k + prefix.len()..];
        let end = tail.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(tail.len());
        let name = &tail[..end];
        let before_ok = k == 0 || !rest.as_bytes()[k - 1].is_ascii_alphanumeric();
        if before_ok
            && tail[end..].trim_start().starts_with('(')
            && names.iter().any(|n| n == name)
            && !ONE_LANGUAGE_ONLY.contains(&name)
        {
            calls.push(name.to_string());
        }
        rest = &tail[end..];
    }
    let words = |w: &str| {
        body.match_indices(w)
            .filter(|(i, _)| {
                let b = body.as_bytes();
                (*i == 0 || !b[i - 1].is_ascii_alphanumeric() && b[i - 1] != b'_')
                    && !b.get(i + w.len()).is_some_and(|c| c.is_ascii_alphanumeric() || *c == b'_')
            })
            .count()
    };
    Shape {
        params: count_params(params),
        calls,
        literals: literals(&body),
        returns: words("return"),
        loops: words("for") + words("loop") + words("while"),
    }
}

/// `max(x, 1e-30)` → `x` on a line.
fn remove_guards(line: &str) -> String {
    let mut s = line.to_string();
    while let Some(k) = s.find("max(") {
        let close = matching(&s, k + 3, b'(', b')');
        let inner = &s[k + 4..close];
        let Some(arg) = inner.strip_suffix(", 1e-30") else { break };
        s = format!("{}{}{}", &s[..k], arg, &s[close + 1..]);
    }
    s
}

/// Every difference between a kernel's WGSL and GLSL, in words.
fn differences(wgsl: &str, glsl: &str) -> Vec<String> {
    let w = functions(wgsl, true);
    let g = functions(glsl, false);
    let prefix = common_prefix(&w);
    let short = |n: &str| n.strip_prefix(&prefix).unwrap_or(n).to_string();
    let keep = |v: &Vec<(String, String, String)>| -> Vec<(String, String, String)> {
        v.iter().filter(|(n, _, _)| !ONE_LANGUAGE_ONLY.contains(&short(n).as_str())).cloned().collect()
    };
    let (w, g) = (keep(&w), keep(&g));
    // GLSL defines before use, WGSL in any order: the sets are compared.
    let sorted = |v: &Vec<(String, String, String)>| {
        let mut n: Vec<String> = v.iter().map(|(n, _, _)| short(n)).collect();
        n.sort();
        n
    };
    let names_w: Vec<String> = w.iter().map(|(n, _, _)| short(n)).collect();
    let names_g: Vec<String> = g.iter().map(|(n, _, _)| short(n)).collect();
    let mut out = Vec::new();
    if sorted(&w) != sorted(&g) {
        out.push(format!("functions differ: WGSL {names_w:?}\n  GLSL {names_g:?}"));
        return out;
    }
    let all: Vec<String> = names_w.clone();
    let gl: BTreeMap<&str, &(String, String, String)> = names_g.iter().map(String::as_str).zip(g.iter()).collect();
    for (name, (_, pw, bw)) in names_w.iter().zip(&w) {
        let (_, pg, bg) = gl[name.as_str()];
        // The constructors (the accumulator's, the shadow-map walk's): GLSL
        // zero-initialises field by field what WGSL's `var` does at once.
        let (mut a, b) = if name == "shafts_begin" || name == "begin" {
            let p = |x: &str| Shape { params: count_params(x), calls: vec![], literals: vec![], returns: 0, loops: 0 };
            (p(pw), p(pg))
        } else {
            (shape(pw, bw, &prefix, &all, true), shape(pg, bg, &prefix, &all, false))
        };
        // The walk's pyramid: a WGSL texture parameter; GLSL reads it through the
        // caller's `airlight_smap_node`.
        if pw.contains("texture_2d_array<") {
            a.params -= 1;
        }
        if a != b {
            out.push(format!("{name}: WGSL {a:?}\n  GLSL {b:?}"));
        }
    }
    out
}

/// The kernel's prefix (`airlight_phi_8_`): the longest common prefix of its functions' names.
fn common_prefix(fns: &[(String, String, String)]) -> String {
    let mut p = fns[0].0.clone();
    for (n, _, _) in fns {
        while !n.starts_with(&p) {
            p.pop();
        }
    }
    // Up to the last `_`, so a name's own start is not taken for the prefix.
    p[..=p.rfind('_').unwrap()].to_string()
}

#[test]
fn every_wgsl_kernel_and_its_glsl_twin_have_the_same_structure() {
    let generated = airlight_tests::generated_dir();
    let mut pairs = 0;
    let mut report = Vec::new();
    let mut names: Vec<_> = std::fs::read_dir(generated.join("wgsl")).unwrap().map(|e| e.unwrap().path()).collect();
    names.sort();
    for wgsl_path in names {
        let stem = wgsl_path.file_stem().unwrap().to_string_lossy().into_owned();
        let glsl_path = generated.join("glsl").join(format!("{stem}.glsl"));
        if !glsl_path.exists() {
            continue;
        }
        let (w, g) = (read(&wgsl_path), read(&glsl_path));
        assert!(functions(&w, true).len() > 10, "{stem}: functions found");
        pairs += 1;
        for d in differences(&w, &g) {
            report.push(format!("{stem}: {d}"));
        }
    }
    assert!(pairs >= 60, "every kernel, and the shadow-map walk, has a pair ({pairs})");
    assert!(report.is_empty(), "{} difference(s):\n{}", report.len(), report.join("\n"));
}

/// The check itself: a literal changed, a call dropped or a function added in one
/// language only is found.
#[test]
fn a_drift_in_one_language_is_found() {
    let generated = airlight_tests::generated_dir();
    let w = read(&generated.join("wgsl/phi-8.wgsl"));
    let g = read(&generated.join("glsl/phi-8.glsl"));
    assert!(differences(&w, &g).is_empty());
    let lit = g.replacen("5.77215672e-1", "5.77215600e-1", 1);
    assert_ne!(lit, g);
    assert!(differences(&w, &lit).iter().any(|d| d.starts_with("exp_e2")), "{:?}", differences(&w, &lit));
    let call = g.replacen("airlight_phi_8_max_abs(dir)", "max(abs(dir.x), 0.0)", 1);
    assert_ne!(call, g);
    assert!(!differences(&w, &call).is_empty());
    let extra = format!("{g}\nfloat airlight_phi_8_extra(float x) {{\n    return x;\n}}\n");
    assert!(!differences(&w, &extra).is_empty());
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}
