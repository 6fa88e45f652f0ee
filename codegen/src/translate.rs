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

/// `wgsl` (a library of functions, no entry point) in `backend`'s language.
/// `functions` must keep their names through naga's namer (a renamed entry
/// point would break every caller), which is checked.
pub fn translate(wgsl: &str, backend: Backend, functions: &[String]) -> Result<String, TranslateError> {
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
    for f in functions {
        if !text.contains(&format!(" {f}(")) {
            return Err(TranslateError(format!("naga {}-out renamed the entry point {f}", backend.name())));
        }
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIB: &str = "fn k_airlight(tau: f32) -> f32 { return exp(-tau); }\nfn k_radiance(x: vec3<f32>) -> f32 { return k_airlight(x.x); }\n";

    #[test]
    fn both_back_ends_keep_the_entry_points() {
        let names = ["k_airlight".to_string(), "k_radiance".to_string()];
        for b in [Backend::Hlsl, Backend::Msl] {
            let text = translate(LIB, b, &names).unwrap();
            assert!(text.contains(" k_radiance("), "{text}");
        }
    }

    #[test]
    fn invalid_wgsl_and_renamed_entry_points_are_errors() {
        // naga's namer appends `_` to a name ending in a digit.
        let digits = "fn k_airlight2(tau: f32) -> f32 { return tau; }\n";
        let e = translate(digits, Backend::Hlsl, &["k_airlight2".to_string()]).unwrap_err();
        assert!(e.0.contains("renamed"), "{e}");
        let bad = "fn k(tau: f32) -> f32 { return tau + 1u; }\n";
        assert!(translate(bad, Backend::Msl, &[]).is_err());
    }
}
