//! HLSL and Metal Shading Language from the validated WGSL: naga parses and
//! validates each plain WGSL kernel, and its `hlsl-out` and `msl-out` back ends
//! write the same functions in the other language. One source of truth: nothing
//! is templated twice, and what reaches HLSL or MSL has passed naga's validator.

use serde::Deserialize;

/// A back end of naga.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Backend {
    /// HLSL, shader model 5.1 (Direct3D 11/12, Unity, Unreal, DXC and FXC).
    Hlsl,
    /// Metal Shading Language 2.0 (Apple platforms).
    Msl,
}

impl Backend {
    /// Its name in the output table and in errors.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Hlsl => "hlsl",
            Backend::Msl => "msl",
        }
    }
}

/// Why a kernel did not translate.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TranslateError(pub String);

impl std::fmt::Display for TranslateError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for TranslateError {}

/// `wgsl` (a library of functions, no entry point) in `backend`'s language, every
/// top-level name carrying `prefix` (see [`prefix_helpers`]), so that two kernels'
/// translations compose in one shader. `functions` must keep their names through
/// naga's namer (a renamed entry point would break every caller), which is checked.
pub fn translate(wgsl: &str, backend: Backend, prefix: &str, functions: &[String]) -> Result<String, TranslateError> {
    let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| TranslateError(e.emit_to_string(wgsl)))?;
    let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
        .validate(&module)
        .map_err(|e| TranslateError(format!("naga's validator: {}", e.into_inner())))?;
    let text = match backend {
        Backend::Hlsl => {
            let options = naga::back::hlsl::Options::default();
            let pipeline = naga::back::hlsl::PipelineOptions::default();
            let mut out = String::new();
            naga::back::hlsl::Writer::new(&mut out, &options, &pipeline)
                .write(&module, &info, None)
                .map_err(|e| TranslateError(format!("naga hlsl-out: {e}")))?;
            out
        }
        Backend::Msl => {
            let options = naga::back::msl::Options { lang_version: (2, 0), ..Default::default() };
            let pipeline = naga::back::msl::PipelineOptions::default();
            naga::back::msl::write_string(&module, &info, &options, &pipeline)
                .map_err(|e| TranslateError(format!("naga msl-out: {e}")))?
                .0
        }
    };
    let text = prefix_helpers(&text, prefix)?;
    for f in functions {
        if !text.contains(&format!(" {f}(")) {
            return Err(TranslateError(format!("naga {}-out renamed the entry point {f}", backend.name())));
        }
    }
    Ok(text)
}

/// The names `text` (naga's HLSL or MSL) defines at top level: structs, typedefs,
/// functions and globals, in order of definition.
fn top_level_names(text: &str) -> Vec<String> {
    let mut names = Vec::new();
    for line in text.lines() {
        let starts = line.chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
        if !starts || line.starts_with("using ") {
            continue;
        }
        let line = line.split("//").next().unwrap_or_default();
        // `struct NAME {`, `typedef T NAME[2];`, `T NAME(…`, `static const T NAME = …;`
        let head = line.split(['(', '[', '=', '{', ':', ';']).next().unwrap_or_default();
        let name = if let Some(rest) = head.strip_prefix("struct ") { rest } else { head };
        if let Some(last) = name.split_whitespace().last() {
            let last = last.trim_start_matches(['*', '&']);
            let ident = !last.is_empty() && last.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            // `T NAME(` needs a type before it; a lone word at line start is a continuation.
            if ident && (name.split_whitespace().count() > 1 || line.starts_with("struct ")) {
                names.push(last.to_string());
            }
        }
    }
    names
}

/// `text` with every top-level name naga's back end wrote without `prefix`
/// (its helpers: `naga_div`, `_frexp_result_f32_`, `Constructarray2_float3_`, the
/// MSL array wrappers `type_3`, …) renamed to `prefix` + the name (leading
/// underscores dropped: C++ reserves `__`). Every identifier token is renamed but
/// a member (after `.` or `::`). A renamed helper that would collide with a name
/// already defined is an error.
pub fn prefix_helpers(text: &str, prefix: &str) -> Result<String, TranslateError> {
    let defined = top_level_names(text);
    let mut rename = std::collections::BTreeMap::new();
    // A name that carries the prefix in any case (`AirlightSmapWalk` for
    // `airlight_smap_`, `AIRLIGHT_SMAP_FAR`) is the library's own.
    let own = |n: &str| {
        let squash = |s: &str| s.to_ascii_lowercase().replace('_', "");
        n.starts_with(prefix) || squash(n).starts_with(&squash(prefix))
    };
    for name in defined.iter().filter(|n| !own(n)) {
        let new = format!("{prefix}{}", name.trim_start_matches('_'));
        if defined.contains(&new) {
            return Err(TranslateError(format!("naga's helper {name} renamed to {new} collides with a kernel name")));
        }
        rename.insert(name.as_str(), new);
    }
    let mut out = String::with_capacity(text.len() + 64 * rename.len());
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            let word = &text[start..i];
            let member = text[..start].ends_with('.') || text[..start].ends_with("::");
            match rename.get(word) {
                Some(new) if !member => out.push_str(new),
                _ => out.push_str(word),
            }
        } else if c.is_ascii_digit() {
            // A number (`2u`, `1e5f`): its letters are not names.
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'.' || bytes[i] == b'_') {
                i += 1;
            }
            out.push_str(&text[start..i]);
        } else {
            let ch = text[i..].chars().next().unwrap_or_default();
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIB: &str = "fn k_airlight(tau: f32) -> f32 { return exp(-tau); }\nfn k_radiance(x: vec3<f32>) -> f32 { return k_airlight(x.x); }\n";

    #[test]
    fn both_back_ends_keep_the_entry_points() {
        let names = ["k_airlight".to_string(), "k_radiance".to_string()];
        for b in [Backend::Hlsl, Backend::Msl] {
            let text = translate(LIB, b, "k_", &names).unwrap();
            assert!(text.contains(" k_radiance("), "{text}");
        }
    }

    #[test]
    fn invalid_wgsl_and_renamed_entry_points_are_errors() {
        // naga's namer appends `_` to a name ending in a digit.
        let digits = "fn k_airlight2(tau: f32) -> f32 { return tau; }\n";
        let e = translate(digits, Backend::Hlsl, "k_", &["k_airlight2".to_string()]).unwrap_err();
        assert!(e.0.contains("renamed"), "{e}");
        let bad = "fn k(tau: f32) -> f32 { return tau + 1u; }\n";
        assert!(translate(bad, Backend::Msl, "k_", &[]).is_err());
    }

    #[test]
    fn naga_helpers_take_the_kernel_prefix() {
        // frexp, integer division and an array constructor: naga writes helpers
        // (`naga_frexp`, `_frexp_result_f32_`, `naga_div`, array wrappers) for them.
        let lib = "fn k_f(x: f32, n: i32, m: i32) -> f32 {\n    let r = frexp(x);\n    let a = array<vec3<f32>, 2>(vec3(x), vec3(r.fract));\n    return a[n / m].x + f32(r.exp);\n}\n";
        for b in [Backend::Hlsl, Backend::Msl] {
            let text = translate(lib, b, "k_", &["k_f".to_string()]).unwrap();
            let names = top_level_names(&text);
            assert!(names.len() >= 3, "{b:?}: {names:?}\n{text}");
            for n in &names {
                assert!(n.starts_with("k_") && !n.contains("__"), "{b:?}: {n} unprefixed\n{text}");
            }
            assert!(!text.contains(" naga_div(") && !text.contains(" _frexp") && !text.contains("\n_frexp"), "{text}");
            // members keep their names
            assert!(text.contains(".fract"), "{text}");
        }
    }

    #[test]
    fn a_helper_that_would_collide_is_an_error() {
        let text = "int naga_div(int a, int b) { return a / b; }\nint k_naga_div(int a) { return a; }\n";
        assert!(prefix_helpers(text, "k_").unwrap_err().0.contains("collides"));
    }
}
