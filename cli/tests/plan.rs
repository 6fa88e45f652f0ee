//! `airlight plan` and `render --scene` on a scene file from anywhere (issue 40,
//! item 5): the plan printed, the kernel written where the user says — the bytes
//! `generate` writes for a scene of `codegen/scenes/` — and `render` drawing the
//! file it is given, not a generated kernel of the same name.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

/// The binary run from the repository root.
fn airlight(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_airlight")).args(args).current_dir(root()).output().expect("runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("airlight-plan-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(files_under(&p));
        } else {
            out.push(p);
        }
    }
    out.sort();
    out
}

fn text(o: &Output) -> (String, String) {
    (String::from_utf8_lossy(&o.stdout).into_owned(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// The pick in a printed plan: `**Model: `name`.**`.
fn pick(plan: &str) -> String {
    let at = plan.find("**Model: `").expect("a model line") + "**Model: `".len();
    plan[at..].split('`').next().unwrap().to_string()
}

#[test]
fn plan_writes_what_generate_writes_for_every_scene() {
    let scenes: Vec<PathBuf> = files_under(&root().join("codegen/scenes"))
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    assert!(scenes.len() >= 5, "{scenes:?}");
    for scene in scenes {
        let stem = scene.file_stem().unwrap().to_string_lossy().into_owned();
        let out = scratch(&format!("same-{stem}"));
        let rel = format!("codegen/scenes/{stem}.toml");
        let o = airlight(&["plan", &rel, "--out", out.to_str().unwrap()]);
        let (stdout, stderr) = text(&o);
        assert!(o.status.success(), "{rel}: {stderr}");
        // The plan printed is the plan file generate writes.
        let plan = std::fs::read_to_string(root().join(format!("generated/plans/scene-{stem}.md"))).unwrap();
        assert!(stdout.starts_with(&plan), "{rel}: the printed plan is not generated/plans/scene-{stem}.md");
        let written = files_under(&out);
        assert!(written.len() >= 4, "{rel}: {written:?}");
        for f in &written {
            let rel_path = f.strip_prefix(&out).unwrap();
            let committed = std::fs::read(root().join("generated").join(rel_path))
                .unwrap_or_else(|e| panic!("{rel}: wrote {}, which generate does not: {e}", rel_path.display()));
            assert!(std::fs::read(f).unwrap() == committed, "{rel}: {} differs from generate's", rel_path.display());
        }
        for k in ["wgsl", "glsl"] {
            assert!(out.join(format!("{k}/scene-{stem}.{k}")).is_file(), "{rel}: no {k} kernel");
        }
        std::fs::remove_dir_all(&out).unwrap();
    }
}

#[test]
fn a_scene_outside_the_repository_is_planned_by_its_own_budget() {
    let dir = scratch("mine");
    let base = std::fs::read_to_string(root().join("codegen/scenes/fog-street.toml")).unwrap();
    let mut picks = Vec::new();
    for (name, budget) in [("my-street-loose", "0.1"), ("my-street-tight", "1e-5")] {
        let file = dir.join(format!("{name}.toml"));
        std::fs::write(&file, base.replace("max_rel_error = 0.02", &format!("max_rel_error = {budget}"))).unwrap();
        let out = dir.join(format!("out-{name}"));
        let o = airlight(&["plan", file.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        let (stdout, stderr) = text(&o);
        assert!(o.status.success(), "{stderr}");
        assert!(stdout.contains(&format!("# Plan for scene `{name}`")), "{stdout}");
        // Every candidate is listed with its cost and bound; the pick meets the budget.
        assert!(stdout.contains("| model | cost | bound | meets budget |"), "{stdout}");
        let model = pick(&stdout);
        let row = stdout.lines().find(|l| l.starts_with(&format!("| `{model}` |"))).expect("the pick is a candidate");
        assert!(row.ends_with("| yes |"), "{row}");
        let wgsl = std::fs::read_to_string(out.join(format!("wgsl/scene-{name}.wgsl"))).unwrap();
        assert!(wgsl.contains(&format!("scene: {}", file.display())), "the kernel names its scene file");
        assert!(wgsl.contains(&format!("fn airlight_scene_{}_radiance(", name.replace('-', "_"))), "{name}");
        picks.push(model);
    }
    // A 10% budget and a 1e-5 one do not pick the same model.
    assert_ne!(picks[0], picks[1], "{picks:?}");
}

#[test]
fn a_bad_scene_names_its_line_and_writes_nothing() {
    let dir = scratch("bad");
    let base = std::fs::read_to_string(root().join("codegen/scenes/fog-street.toml")).unwrap();
    let file = dir.join("broken.toml");
    std::fs::write(&file, base.replace("max_rel_error = 0.02", "max_rel_error = -3")).unwrap();
    let out = dir.join("out");
    let o = airlight(&["plan", file.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let (_, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    let line = base.lines().position(|l| l.starts_with("max_rel_error")).unwrap() + 1;
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(stderr.contains(&format!("broken.toml:{line}")) && stderr.contains("max_rel_error"), "{stderr}");
    assert!(files_under(&out).is_empty(), "nothing is written");
    // A budget no model meets: the plan's own error, nothing written.
    std::fs::write(&file, base.replace("max_rel_error = 0.02", "max_rel_error = 1e-12")).unwrap();
    let o = airlight(&["plan", file.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let (_, stderr) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("no model meets max_rel_error"), "{stderr}");
    assert!(files_under(&out).is_empty(), "nothing is written");
}

/// `render --scene` on a copy that `generate` never saw: it plans the copy and
/// draws its kernel (before, it looked `scene-<name>` up among the generated
/// kernels and failed, or drew a stale one of the same name).
#[test]
fn render_draws_the_scene_file_it_is_given() {
    let dir = scratch("render");
    let base = std::fs::read_to_string(root().join("codegen/scenes/fog-street.toml")).unwrap();
    let file = dir.join("my-render.toml");
    std::fs::write(&file, base.replace("max_rel_error = 0.02", "max_rel_error = 0.1")).unwrap();
    let png = dir.join("my.png");
    let args =
        ["render", "--scene", file.to_str().unwrap(), "-o", png.to_str().unwrap(), "--width", "24", "--height", "16"];
    let o = airlight(&args);
    let (stdout, stderr) = text(&o);
    let no_gpu = !o.status.success() && stderr.to_lowercase().contains("adapter");
    if no_gpu && std::env::var("AIRLIGHT_REQUIRE_GPU").map_or(true, |v| v != "1") {
        eprintln!("SKIPPED: no GPU adapter ({stderr})");
        return;
    }
    assert!(o.status.success(), "{stdout}\n{stderr}");
    assert!(png.is_file() && dir.join("my-reference.png").is_file(), "{stdout}");
    assert!(stdout.contains("no Rust panel"), "the linked crate has no `scene-my-render`: {stdout}");
}
