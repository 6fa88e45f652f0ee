//! Which models the report and the benches set side by side, as data
//! (`roles.toml` beside this file): the generator and the GPU harness read it, so
//! that adding a family or a member touches no code in `codegen/` or `shaders/`.

use serde::Deserialize;
use std::sync::OnceLock;

/// The table, as `roles.toml` holds it.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Roles {
    /// The engines' march: its members are `<march_prefix><steps>`.
    pub march_prefix: String,
    /// What the report compares.
    pub report: ReportRoles,
    /// What the shafts bench and render run.
    pub shafts: ShaftsRoles,
}

/// What the report compares.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReportRoles {
    /// Kernels quoted as flat, by name.
    pub flat: Vec<String>,
    /// Families quoted as flat, by name prefix.
    pub flat_prefixes: Vec<String>,
    /// CPU cost ratios `(model, against)`.
    pub cpu_two_ways: Vec<(String, String)>,
    /// GPU-path rate ratios `(model, against)`.
    pub gpu_two_ways: Vec<(String, String)>,
    /// The published model.
    pub published: String,
    /// The published forms refit.
    pub published_refit: String,
    /// The families (name prefixes) the gate's robustness table follows.
    pub gate_followed: Vec<String>,
}

/// What the shafts bench and render run.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShaftsRoles {
    /// The accumulators measured against the march.
    pub kernels: Vec<String>,
    /// The one whose losses the report lists, whose look-ups alone are timed and
    /// whose `F'` table the bench builds.
    pub headline: String,
    /// The march the render draws with.
    pub render_march: String,
}

impl Roles {
    /// The march member with `steps` steps.
    pub fn march(&self, steps: usize) -> String {
        format!("{}{steps}", self.march_prefix)
    }
    /// Whether `name` is a member of the march.
    pub fn is_march(&self, name: &str) -> bool {
        name.strip_prefix(&self.march_prefix).is_some_and(|n| n.parse::<usize>().is_ok())
    }
    /// Every model name the table mentions (names, not prefixes).
    pub fn names(&self) -> Vec<&str> {
        let r = &self.report;
        let mut v: Vec<&str> = r.flat.iter().map(String::as_str).collect();
        for (a, b) in r.cpu_two_ways.iter().chain(&r.gpu_two_ways) {
            v.extend([a.as_str(), b.as_str()]);
        }
        v.extend([r.published.as_str(), r.published_refit.as_str(), self.shafts.headline.as_str()]);
        v.extend(self.shafts.kernels.iter().map(String::as_str));
        v.push(self.shafts.render_march.as_str());
        v
    }
}

/// The table compiled in (`fit/src/roles.toml`).
pub fn roles() -> &'static Roles {
    static R: OnceLock<Roles> = OnceLock::new();
    R.get_or_init(|| toml::from_str(include_str!("roles.toml")).expect("fit/src/roles.toml parses (tested)"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roles_name_catalog_models() {
        let r = roles();
        let known: Vec<&str> = crate::catalog::CATALOG.iter().map(|e| e.name).collect();
        for n in r.names() {
            assert!(known.contains(&n), "fit/src/roles.toml names '{n}', not a catalog model");
        }
        for p in r.report.flat_prefixes.iter().chain(&r.report.gate_followed).chain([&r.march_prefix]) {
            assert!(known.iter().any(|k| k.starts_with(p.as_str())), "no catalog model starts with '{p}'");
        }
        assert!(r.is_march(&r.shafts.render_march) && r.is_march(&r.march(64)));
        assert!(r.shafts.kernels.contains(&r.shafts.headline));
    }
}
