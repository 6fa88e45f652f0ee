//! The `airlight` binary from a shell's point of view: outputs, messages, exit
//! codes, and that a failed run leaves the output file alone.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn airlight(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_airlight")).args(args).output().expect("runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("airlight-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn eval_reference_to_stdout_and_file() {
    let dir = scratch("ok");
    let input = dir.join("points.csv");
    std::fs::write(&input, "tau,gamma,rho,g\n1,0.5,inf,0\n0.5,0,0.5,0.3\n2,0,2,0\n").unwrap();
    let o = airlight(&["eval", "--model", "reference", "--input", input.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], "tau,gamma,rho,g,airlight");
    assert_eq!(lines.len(), 4);
    // γ = 0 before the light: P(0) e^{−τ} ρ/(1 − ρ), HG g = 0.3.
    let p0 = (1.0 - 0.09) / (4.0 * std::f64::consts::PI * 0.7f64.powi(3));
    let want = p0 * (-0.5f64).exp();
    let got: f64 = lines[2].rsplit(',').next().unwrap().parse().unwrap();
    assert!(((got - want) / want).abs() < 1e-15, "{got} vs {want}");
    assert_eq!(lines[3], "2,0,2,0,inf");
    let output = dir.join("out.csv");
    let o = airlight(&["eval", "-i", input.to_str().unwrap(), "-o", output.to_str().unwrap()]);
    assert!(o.status.success());
    assert_eq!(std::fs::read_to_string(&output).unwrap(), out);
    // `-o -` is standard output, not a file named `-`.
    let o = Command::new(env!("CARGO_BIN_EXE_airlight"))
        .args(["eval", "-i", input.to_str().unwrap(), "-o", "-"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(o.status.success() && String::from_utf8_lossy(&o.stdout) == out, "{}", stderr(&o));
    assert!(!dir.join("-").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A FIFO named as the output is refused (exit 2, the FIFO stays), and a reader
/// that closes the pipe early ends the run quietly.
#[cfg(unix)]
#[test]
fn special_outputs_are_refused_and_a_closed_pipe_is_quiet() {
    let dir = scratch("pipe");
    let input = dir.join("points.csv");
    let rows: String = (0..20_000).map(|i| format!("{},1,inf,0\n", 1e-3 * f64::from(i))).collect();
    std::fs::write(&input, format!("tau,gamma,rho,g\n{rows}")).unwrap();
    let fifo = dir.join("fifo");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let o = airlight(&["eval", "-i", input.to_str().unwrap(), "-o", fifo.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("not a regular file"), "{}", stderr(&o));
    let mut child = Command::new(env!("CARGO_BIN_EXE_airlight"))
        .args(["eval", "-i", input.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader goes away before the first byte
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "exit {:?}: {}", o.status, stderr(&o));
    assert!(o.stderr.is_empty(), "quiet: {}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_input_is_one_line_exit_2_and_output_untouched() {
    let dir = scratch("bad");
    let output = dir.join("out.csv");
    let cases: [(&str, &str); 6] = [
        ("tau,gamma,rho\n1,1,1\n", "missing.csv:1: column 'g': missing from the header"),
        ("tau,gamma,rho,g\n1,1,1,0\n1,abc,1,0\n", "nonnum.csv:3: column 'gamma': 'abc' is not a number"),
        ("tau,gamma,rho,g\n-2,1,1,0\n", "domain.csv:2: column 'tau': tau = -2 is out of range"),
        ("tau,gamma,rho,g\n1,1,1,1.5\n", "g.csv:2: column 'g': g = 1.5 is out of range"),
        ("tau,gamma,rho,g\n1,1,0,0\n", "rho.csv:2: column 'rho': rho = 0 is out of range"),
        ("tau,gamma,rho,g\n1,1\n", "short.csv:2: column 'rho': missing value"),
    ];
    for (i, (contents, want)) in cases.iter().enumerate() {
        let name = want.split(':').next().unwrap();
        let input = dir.join(name);
        std::fs::write(&input, contents).unwrap();
        std::fs::write(&output, format!("previous {i}")).unwrap();
        let o = airlight(&["eval", "-i", input.to_str().unwrap(), "-o", output.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{name}");
        let err = stderr(&o);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.starts_with("error: ") && err.contains(want), "{err} should contain {want}");
        assert_eq!(std::fs::read_to_string(&output).unwrap(), format!("previous {i}"));
    }
    // An unknown model lists the known ones, and creates no output file.
    let fresh = dir.join("never.csv");
    let input = dir.join("missing.csv");
    let o = airlight(&["eval", "--model", "nope", "-i", input.to_str().unwrap(), "-o", fresh.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.trim().starts_with("error: unknown model 'nope'; known models: reference, paper-as-printed, paper,"),
        "{err}"
    );
    assert!(err.contains("segments-16") && err.contains("hg-exp3"), "{err}");
    assert!(!fresh.exists());
    // An input that does not exist.
    let o = airlight(&["eval", "-i", dir.join("absent.csv").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("absent.csv: cannot read"));
    // No temporary files left behind.
    assert!(std::fs::read_dir(&dir).unwrap().all(|e| !e.unwrap().file_name().to_string_lossy().ends_with(".tmp")));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn help_explains_the_canonical_parameters() {
    let o = airlight(&["--help"]);
    assert!(o.status.success());
    let help = String::from_utf8(o.stdout).unwrap();
    for word in ["sigma_t * D", "gamma", "rho", "Henyey-Greenstein", "eval", "regenerate"] {
        assert!(help.contains(word), "help lacks {word}");
    }
    let o = airlight(&["eval", "--help"]);
    let help = String::from_utf8(o.stdout).unwrap();
    assert!(help.contains("tau,gamma,rho,g") && help.contains("inf"));
}

/// Copies the committed inputs of `generate` into `root/generated`: the
/// coefficient files and the reference self-check.
fn copy_coefficients(root: &Path) {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let dst = root.join("generated/coefficients");
    std::fs::create_dir_all(&dst).unwrap();
    for e in std::fs::read_dir(repo.join("generated/coefficients")).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, dst.join(p.file_name().unwrap())).unwrap();
    }
    std::fs::copy(repo.join("generated/selfcheck.toml"), root.join("generated/selfcheck.toml")).unwrap();
}

#[test]
fn generate_check_names_missing_and_orphaned_files_and_writes_nothing() {
    let root = scratch("gen");
    std::fs::create_dir_all(root.join("generated")).unwrap();
    // Without coefficient files there is nothing to render from: a clear error.
    let o = airlight(&["generate", "--root", root.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("airlight fit"), "{}", stderr(&o));
    copy_coefficients(&root);
    std::fs::write(root.join("generated/stray.txt"), "x").unwrap();
    let o = airlight(&["generate", "--check", "--root", root.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(err.contains("REPORT.md: missing"), "{err}");
    assert!(err.contains("plots/phase.svg: missing"), "{err}");
    assert!(err.contains("wgsl/segments-8.wgsl: missing"), "{err}");
    assert!(err.contains("airlight-kernels/src/lib.rs: missing"), "{err}");
    assert!(err.contains("stray.txt: not produced by the generator (orphaned)"), "{err}");
    assert!(!err.contains("coefficients/"), "committed coefficient files re-render identically: {err}");
    assert!(!root.join("generated/REPORT.md").exists());
    // Generating writes the report and plots; the check then passes but for the stray file.
    let o = airlight(&["generate", "--root", root.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(root.join("generated/REPORT.md").exists());
    std::fs::remove_file(root.join("generated/stray.txt")).unwrap();
    let o = airlight(&["generate", "--check", "--root", root.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn fitted_models_evaluate_and_list_from_their_coefficient_files() {
    let root = scratch("models");
    copy_coefficients(&root);
    let input = root.join("p.csv");
    std::fs::write(&input, "tau,gamma,rho,g\n0.5,1.0,inf,0\n3,2.5,2,0\n").unwrap();
    let r = root.to_str().unwrap();
    let o = airlight(&["eval", "--model", "segments-16", "-i", input.to_str().unwrap(), "--root", r]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    let reference = airlight(&["eval", "-i", input.to_str().unwrap(), "--root", r]);
    let reference = String::from_utf8(reference.stdout).unwrap();
    for (a, b) in out.lines().skip(1).zip(reference.lines().skip(1)) {
        let (a, b): (f64, f64) =
            (a.rsplit(',').next().unwrap().parse().unwrap(), b.rsplit(',').next().unwrap().parse().unwrap());
        assert!((a / b - 1.0).abs() < 0.02, "{a} vs {b}");
    }
    // An isotropic model refuses g != 0, naming the column.
    std::fs::write(&input, "tau,gamma,rho,g\n0.5,1.0,inf,0.3\n").unwrap();
    let o = airlight(&["eval", "--model", "paper", "-i", input.to_str().unwrap(), "--root", r]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("p.csv:2: column 'g'"), "{}", stderr(&o));
    // The table lists every model with its measured errors.
    let o = airlight(&["models", "--root", r]);
    let table = String::from_utf8(o.stdout).unwrap();
    assert!(table.contains("paper-refit") && table.contains("thin max"), "{table}");
    // A damaged coefficient file: one line naming file, line and field; exit 2.
    let f = root.join("generated/coefficients/segments-2.toml");
    let text = std::fs::read_to_string(&f).unwrap();
    let broken = text.replacen("\"0x0p+0\", # 0.0", "\"zero\", # 0.0", 1);
    assert_ne!(broken, text);
    std::fs::write(&f, &broken).unwrap();
    let o = airlight(&["models", "--root", r]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    let line = broken.lines().position(|l| l.contains("\"zero\"")).unwrap() + 1;
    let want = format!("segments-2.toml:{}: field 'forward.breakpoints'", line - 1);
    assert!(err.contains("segments-2.toml:") && err.contains("field 'forward.breakpoints'"), "{err} vs {want}");
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn fit_one_family_prints_and_writes_nothing() {
    let root = scratch("fit");
    std::fs::create_dir_all(root.join("generated")).unwrap();
    let o = airlight(&["fit", "--family", "backscatter", "--root", root.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    assert!(out.contains("backscatter ratio: refit rms") && out.contains("nothing written"), "{out}");
    assert!(std::fs::read_dir(root.join("generated")).unwrap().next().is_none());
    // The φ family's part prints its fitted e^x E2.
    let o = airlight(&["fit", "--family", "phi", "--root", root.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    assert!(out.contains("phi e^x E2") && out.contains("max rel") && out.contains("nothing written"), "{out}");
    assert!(std::fs::read_dir(root.join("generated")).unwrap().next().is_none());
    // The lite family's part prints its one-path e^x E2.
    let o = airlight(&["fit", "--family", "lite", "--root", root.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    assert!(out.contains("lite e^x E2") && out.contains("max rel") && out.contains("nothing written"), "{out}");
    assert!(std::fs::read_dir(root.join("generated")).unwrap().next().is_none());
    let o = airlight(&["fit", "--family", "nope"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("unknown family 'nope'; known families: phi, lite, segments, phase, backscatter"));
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn eval_f32_runs_the_generated_kernel() {
    let dir = scratch("f32");
    let input = dir.join("points.csv");
    std::fs::write(&input, "tau,gamma,rho,g\n1,0.5,inf,0\n5,2.5,3,0\n2,0,2,0\n").unwrap();
    let run = |precision: &str| {
        let o = airlight(&["eval", "--model", "segments-8", "--precision", precision, "-i", input.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
        String::from_utf8(o.stdout).unwrap()
    };
    let (f64_out, f32_out) = (run("f64"), run("f32"));
    assert_ne!(f64_out, f32_out, "f32 must not be the f64 model");
    for (a, b) in f64_out.lines().zip(f32_out.lines()).skip(1) {
        let (x, y): (f64, f64) =
            (a.rsplit(',').next().unwrap().parse().unwrap(), b.rsplit(',').next().unwrap().parse().unwrap());
        assert!(x == y || ((x - y) / x).abs() < 1e-5, "{a} vs {b}");
    }
    assert!(f32_out.ends_with("2,0,2,0,inf\n"), "{f32_out}");
    let o = airlight(&["eval", "--model", "reference", "--precision", "f32", "-i", input.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no generated f32 kernel 'reference'"), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_bad_scene_is_one_line_naming_file_line_and_field_and_nothing_is_written() {
    let root = scratch("scene");
    copy_coefficients(&root);
    let scenes = root.join("codegen/scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let good = std::fs::read_to_string(repo.join("codegen/scenes/smoke-room.toml")).unwrap();
    std::fs::write(scenes.join("room.toml"), good.replace("max_rel_error = 0.02", "max_rel_error = 1e-9")).unwrap();
    let o = airlight(&["generate", "--root", root.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    let line = good.lines().position(|l| l.starts_with("max_rel_error")).unwrap() + 1;
    assert!(err.contains(&format!("codegen/scenes/room.toml:{line}: field 'accuracy.max_rel_error'")), "{err}");
    assert!(err.contains("best achievable"), "{err}");
    std::fs::write(scenes.join("room.toml"), good.replace("phase = \"isotropic\"", "phase = \"rayleigh\"")).unwrap();
    let o = airlight(&["generate", "--root", root.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let line = good.lines().position(|l| l.starts_with("phase")).unwrap() + 1;
    assert!(stderr(&o).contains(&format!("codegen/scenes/room.toml:{line}: field 'medium.phase'")), "{}", stderr(&o));
    assert!(!root.join("generated/REPORT.md").exists(), "nothing is written");
    std::fs::remove_dir_all(&root).unwrap();
}

fn gpu_required() -> bool {
    std::env::var("AIRLIGHT_REQUIRE_GPU").is_ok_and(|v| v == "1")
}

#[test]
fn check_gates_the_named_kernels_and_names_the_adapter_or_skips_loudly() {
    let o = airlight(&["check", "--kernel", "segments-2", "--kernel", "scene-harbour-fog", "--all"]);
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(o.status.success(), "{out}{}", stderr(&o));
    assert!(out.contains("adapter: ") || out.contains("GPU targets SKIPPED"), "{out}");
    assert!(out.contains("every kernel within its declared bound"), "{out}");
    assert!(out.contains("segments-2") && out.contains("rust-f32") && out.contains("physical"), "{out}");
    if gpu_required() {
        assert!(out.contains("adapter: ") && out.contains("wgsl") && out.contains("glsl"), "{out}");
    }
    let o = airlight(&["check", "--kernel", "no-such-kernel"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("no kernel 'no-such-kernel'"), "{}", stderr(&o));
}

#[test]
fn eval_on_the_gpu_targets_matches_the_rust_kernel() {
    let dir = scratch("gpu");
    let input = dir.join("points.csv");
    std::fs::write(&input, "tau,gamma,rho,g\n1,0.5,inf,0.3\n5,2.5,3,-0.5\n0.2,1.2,0.4,0.9\n").unwrap();
    let run = |target: &str| {
        airlight(&[
            "eval",
            "--model",
            "hg-exp2",
            "--target",
            target,
            "--precision",
            "f32",
            "-i",
            input.to_str().unwrap(),
        ])
    };
    let cpu = run("cpu");
    assert!(cpu.status.success(), "{}", stderr(&cpu));
    let cpu = String::from_utf8(cpu.stdout).unwrap();
    for target in ["wgsl", "glsl"] {
        let o = run(target);
        if !o.status.success() && !gpu_required() && stderr(&o).contains("no GPU adapter") {
            eprintln!("SKIPPED eval --target {target}: {}", stderr(&o));
            continue;
        }
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(stderr(&o).contains("adapter: "), "{}", stderr(&o));
        let out = String::from_utf8(o.stdout).unwrap();
        for (a, b) in cpu.lines().zip(out.lines()).skip(1) {
            let (x, y): (f64, f64) =
                (a.rsplit(',').next().unwrap().parse().unwrap(), b.rsplit(',').next().unwrap().parse().unwrap());
            assert!(((x - y) / x).abs() < 2e-4, "{target}: {a} vs {b}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `airlight` does not link the generated Rust kernels: a generated file that no
/// longer compiles is just a stale output, which `generate` rewrites.
#[test]
fn generate_repairs_a_broken_generated_kernel() {
    let root = scratch("repair");
    copy_coefficients(&root);
    let r = root.to_str().unwrap();
    let o = airlight(&["generate", "--root", r]);
    assert!(o.status.success(), "{}", stderr(&o));
    let file = root.join("generated/airlight-kernels/src/segments_8.rs");
    let good = std::fs::read(&file).unwrap();
    let mut broken = good.clone();
    broken.extend_from_slice(b"\nfn broken( {\n");
    std::fs::write(&file, &broken).unwrap();
    let o = airlight(&["generate", "--check", "--root", r]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("segments_8.rs:"), "{}", stderr(&o));
    let o = airlight(&["generate", "--root", r]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(&file).unwrap(), good, "restored byte for byte");
    std::fs::remove_dir_all(&root).unwrap();
}

/// A damaged coefficient file stops `models`, `eval` and `generate` alike: exit 2,
/// one line naming the file, line and key, and nothing written.
#[test]
fn a_damaged_coefficient_file_stops_every_command_and_writes_nothing() {
    let root = scratch("damaged");
    copy_coefficients(&root);
    let r = root.to_str().unwrap();
    let f = root.join("generated/coefficients/segments-8.toml");
    let text = std::fs::read_to_string(&f).unwrap();
    std::fs::write(&f, text.replacen("n = 8\n", "n = 8\nsegmnets = 8\n", 1)).unwrap();
    let input = root.join("p.csv");
    std::fs::write(&input, "tau,gamma,rho,g\n1,1,1,0\n").unwrap();
    let out = root.join("out.csv");
    let before = std::fs::read_dir(root.join("generated")).unwrap().count();
    for args in [
        vec!["models", "--root", r],
        vec!["eval", "--model", "segments-8", "-i", input.to_str().unwrap(), "-o", out.to_str().unwrap(), "--root", r],
        vec!["generate", "--root", r],
    ] {
        let o = airlight(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        let err = stderr(&o);
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains("segments-8.toml:") && err.contains("field 'forward.segmnets'"), "{args:?}: {err}");
    }
    assert!(!out.exists(), "eval wrote nothing");
    assert_eq!(std::fs::read_dir(root.join("generated")).unwrap().count(), before, "generate wrote nothing");
    std::fs::remove_dir_all(&root).unwrap();
}

/// A scene kernel was specialised away from some arguments: a point that needs
/// them is refused (naming the column), not silently evaluated elsewhere.
#[test]
fn scene_kernels_refuse_points_they_were_specialised_away_from() {
    let dir = scratch("specialised");
    let input = dir.join("p.csv");
    for (kernel, point, column) in [
        ("scene-haze-sky", "1,1,inf,0", "column 'tau': tau = 1 is out of range: it must be 0"),
        ("scene-harbour-fog", "1,1,2,0", "column 'rho': rho = 2 is out of range: it must be inf"),
        ("segments-8", "1,1,2,0.5", "column 'g': g = 0.5 is out of range: it must be 0"),
    ] {
        std::fs::write(&input, format!("tau,gamma,rho,g\n{point}\n")).unwrap();
        let o = airlight(&["eval", "--model", kernel, "--precision", "f32", "-i", input.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{kernel}: {}", stderr(&o));
        assert!(stderr(&o).contains(column), "{kernel}: {}", stderr(&o));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `eval --entry radiance`: the physical entry through the f64 model, the Rust
/// kernel and both shaders agree, including where the value saturates or
/// vanishes; kernels refuse rays they were specialised away from.
#[test]
fn eval_radiance_feeds_the_physical_entry_on_every_target() {
    let dir = scratch("radiance");
    let input = dir.join("rays.csv");
    let head = "ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g";
    std::fs::write(
        &input,
        format!(
            "{head}\n0,0,0,1,0,0,-1,10,1,0,100,0.1,0.08,0\n0,0,0,1,0,0,3.4028235e38,10,1,0,100,0.1,0.08,0\n\
             0,0,0,1,0,0,inf,10,1,0,100,0.1,0.08,0\n0,0,0,1e-30,0,0,-1,1e30,1,0,100,1e-30,1e-30,0\n\
             0,0,0,1,0,0,0,10,1,0,100,0.1,0.08,0\n0,0,0,1,0,0,-1,10,0,0,100,0.1,0.08,0\n"
        ),
    )
    .unwrap();
    let run = |args: &[&str]| {
        let mut all = vec!["eval", "--entry", "radiance", "--model", "segments-8", "-i", input.to_str().unwrap()];
        all.extend(args);
        airlight(&all)
    };
    let values = |o: &Output| -> Vec<f64> {
        String::from_utf8(o.stdout.clone())
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
            .collect()
    };
    let f64s = run(&[]);
    assert!(f64s.status.success(), "{}", stderr(&f64s));
    let want = values(&f64s);
    assert_eq!(want.len(), 6);
    assert_eq!(want[1], want[0], "a far plane of f32::MAX is no surface");
    assert_eq!(want[2], want[0], "a surface at +inf is none");
    assert!(want[3] > 0.0 && want[3] < 1e-20, "a light at 1e30 units: {}", want[3]);
    assert_eq!(want[4], 0.0, "a surface at the viewer");
    assert_eq!(want[5], f64::INFINITY, "the ray through the light");
    let mut targets = vec![("cpu f32", run(&["--precision", "f32"]))];
    for t in ["wgsl", "glsl"] {
        targets.push((t, run(&["--target", t])));
    }
    for (what, o) in &targets {
        if !o.status.success() && !gpu_required() && stderr(o).contains("no GPU adapter") {
            eprintln!("SKIPPED eval --entry radiance {what}: {}", stderr(o));
            continue;
        }
        assert!(o.status.success(), "{what}: {}", stderr(o));
        for (i, (&w, g)) in want.iter().zip(values(o)).enumerate() {
            if w.is_infinite() {
                assert_eq!(g, f64::from(f32::MAX), "{what}: row {i} saturates at the largest f32");
            } else {
                assert!(g.is_finite() && (g - w).abs() <= 2e-2 * w, "{what}: row {i}: {g} vs {w}");
            }
        }
    }
    // A kernel without surfaces refuses a ray that has one, naming the column.
    let o = airlight(&[
        "eval",
        "--entry",
        "radiance",
        "--model",
        "scene-harbour-fog",
        "--precision",
        "f32",
        "-i",
        input.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("rays.csv:3: column 'surface'"), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `eval --entry spot`: RGB from a spot light, through the f64 model, the Rust
/// kernel and both shaders; a point light (`cos_outer = -1`) is the physical
/// entry per channel; a bad cone is one line naming the column.
#[test]
fn eval_spot_feeds_the_spot_entry_on_every_target() {
    let dir = scratch("spot");
    let input = dir.join("spots.csv");
    let head = "ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,ax,ay,az,cos_outer,cos_inner,intensity,\
                sigma_t_r,sigma_t_g,sigma_t_b,sigma_s_r,sigma_s_g,sigma_s_b,g";
    std::fs::write(
        &input,
        format!(
            "{head}\n0,0,0,1,0,0,-1,10,1,0,0,-1,0,0.866,0.95,100,0.1,0.05,0.02,0.08,0.04,0.016,0.6\n\
             0,0,0,1,0,0,-1,10,1,0,0,-1,0,-1,-1,100,0.1,0.05,0.02,0.08,0.04,0.016,0.6\n\
             0,0,0,1,0,0,30,10,1,0,0,1,0,0.9,0.9,100,0.1,0.05,0.02,0.08,0.04,0.016,0.6\n"
        ),
    )
    .unwrap();
    let run = |args: &[&str]| {
        let mut all = vec!["eval", "--entry", "spot", "--model", "phi-8", "-i", input.to_str().unwrap()];
        all.extend(args);
        airlight(&all)
    };
    let values = |o: &Output| -> Vec<[f64; 3]> {
        String::from_utf8(o.stdout.clone())
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| {
                let v: Vec<f64> = l.rsplit(',').take(3).map(|x| x.parse().unwrap()).collect();
                [v[2], v[1], v[0]]
            })
            .collect()
    };
    let f64s = run(&[]);
    assert!(f64s.status.success(), "{}", stderr(&f64s));
    let want = values(&f64s);
    assert_eq!(want.len(), 3);
    assert!(want[0][0] > want[0][1] && want[0][1] > want[0][2] && want[0][2] > 0.0, "{:?}", want[0]);
    assert!(want[1][0] > want[0][0], "the point light lights the whole ray: {:?}", want[1]);
    assert_eq!(want[2], [0.0; 3], "a cone pointing away from the ray");
    // The point light is the physical entry per channel.
    let rays = dir.join("rays.csv");
    let rows: String = [(0.1, 0.08), (0.05, 0.04), (0.02, 0.016)]
        .iter()
        .map(|(t, s)| format!("0,0,0,1,0,0,-1,10,1,0,100,{t},{s},0.6\n"))
        .collect();
    std::fs::write(&rays, format!("ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g\n{rows}")).unwrap();
    let o = airlight(&["eval", "--entry", "radiance", "--model", "phi-8", "-i", rays.to_str().unwrap()]);
    let scalar: Vec<f64> = String::from_utf8(o.stdout)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(scalar, want[1].to_vec());
    // The same file given to --entry radiance goes to the spot entry (its header names a cone).
    let o = airlight(&["eval", "--entry", "radiance", "--model", "phi-8", "-i", input.to_str().unwrap()]);
    assert_eq!(values(&o), want);
    let mut targets = vec![("cpu f32", run(&["--precision", "f32"]))];
    for t in ["wgsl", "glsl"] {
        targets.push((t, run(&["--target", t])));
    }
    for (what, o) in &targets {
        if !o.status.success() && !gpu_required() && stderr(o).contains("no GPU adapter") {
            eprintln!("SKIPPED eval --entry spot {what}: {}", stderr(o));
            continue;
        }
        assert!(o.status.success(), "{what}: {}", stderr(o));
        for (i, (w, g)) in want.iter().zip(values(o)).enumerate() {
            for c in 0..3 {
                assert!((g[c] - w[c]).abs() <= 1e-3 * w[c], "{what}: row {i} channel {c}: {} vs {}", g[c], w[c]);
            }
        }
    }
    let bad = dir.join("bad.csv");
    std::fs::write(
        &bad,
        format!("{head}\n0,0,0,1,0,0,-1,10,1,0,0,-1,0,1.5,0.95,100,0.1,0.05,0.02,0.08,0.04,0.016,0.6\n"),
    )
    .unwrap();
    let o = airlight(&["eval", "--entry", "spot", "--model", "phi-8", "-i", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("bad.csv:2: column 'cos_outer'") && stderr(&o).lines().count() == 1, "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `airlight bench` on a small batch: every model gets a row with finite,
/// positive figures (speed itself lives in the benchmark, not here).
#[test]
fn bench_runs_on_a_small_batch_with_finite_positive_figures() {
    let dir = scratch("bench");
    let out = dir.join("bench.json");
    let o = airlight(&["bench", "--points", "60", "--batch", "300", "--repeats", "3", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let b = airlight_shapes::bench::Bench::from_json(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let models = airlight_fit::catalog::load(&airlight_tests_root().join("generated/coefficients")).unwrap();
    assert_eq!(b.models.len(), models.len());
    for (m, f) in b.models.iter().zip(&models) {
        assert_eq!(m.name, f.model.name);
        assert_eq!(m.kind, f.model.body.role());
        assert!(!m.errors.is_empty(), "{}", m.name);
        for e in &m.errors {
            for x in [e.max_rel, e.p99_rel, e.p50_rel] {
                assert!(
                    x.thin.is_finite() && x.thin > 0.0 && x.dense.is_finite() && x.dense > 0.0,
                    "{}: {e:?}",
                    m.name
                );
            }
            assert!(e.p50_rel.max() <= e.p99_rel.max() && e.p99_rel.max() <= e.max_rel.max(), "{}: {e:?}", m.name);
        }
        assert!(m.cpu_ns_per_eval.is_finite() && m.cpu_ns_per_eval > 0.0, "{}", m.name);
        assert!(m.cpu_ns_range[0] <= m.cpu_ns_per_eval && m.cpu_ns_per_eval <= m.cpu_ns_range[1]);
        assert!(m.cpu_ns_one_at_a_time.is_finite() && m.cpu_ns_one_at_a_time > 0.0, "{}", m.name);
        assert!(m.ops > 0 && m.transcendentals <= m.ops, "{}", m.name);
        if gpu_required() {
            assert!(m.gpu_evals_per_s.is_finite() && m.gpu_evals_per_s > 0.0, "{}: no GPU figure", m.name);
        }
    }
    // RGB: a row per model with a spot entry, finite and positive.
    assert_eq!(b.rgb.len(), b.models.len());
    for r in &b.rgb {
        for x in [r.three_scalar_ns, r.rgb_point_ns, r.rgb_hard_cone_ns, r.rgb_soft_cone_ns] {
            assert!(x.is_finite() && x > 0.0, "{}: {r:?}", r.name);
        }
    }
    // The march's IR cost grows with its steps (loops counted by trip count).
    let ops = |n: &str| b.model(n).unwrap().ops;
    assert!(ops("raymarch-1024") > 10 * ops("raymarch-8"));
    // `--only shadow-map` measures that section again into the same file: its
    // errors and steps (seeded rays) come out the same, the models' rows (the
    // planner's costs) stay as they were, and the section says it ran alone.
    assert!(b.shadow_map_alone.is_none() && !b.shadow_map.is_empty());
    let o = airlight(&["bench", "--only", "shadow-map", "--repeats", "1", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let again = airlight_shapes::bench::Bench::from_json(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert!(again.shadow_map_alone.is_some());
    assert_eq!(again.models.len(), b.models.len());
    for (m, n) in again.models.iter().zip(&b.models) {
        assert_eq!((m.cpu_ns_per_eval, m.gpu_evals_per_s), (n.cpu_ns_per_eval, n.gpu_evals_per_s), "{}", m.name);
    }
    assert_eq!(again.shadow_map.len(), b.shadow_map.len());
    for (r, s) in again.shadow_map.iter().zip(&b.shadow_map) {
        assert_eq!(
            (&r.method, r.max_of_unshadowed, r.mean_of_unshadowed, r.steps_mean, r.leaks),
            (&s.method, s.max_of_unshadowed, s.mean_of_unshadowed, s.steps_mean, s.leaks)
        );
    }
    // With no bench to put it in: one line naming the file, exit 2, nothing written.
    let missing = dir.join("missing.json");
    let o = airlight(&["bench", "--only", "shadow-map", "--out", missing.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("missing.json") && stderr(&o).lines().count() == 1, "{}", stderr(&o));
    assert!(!missing.exists());
    // --points and --batch size the models' part: refused beside --only, not ignored.
    for arg in ["--points", "--batch"] {
        let o = airlight(&["bench", "--only", "shadow-map", arg, "3", "--out", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(stderr(&o).contains("cannot be used with"), "{}", stderr(&o));
    }
}

fn airlight_tests_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `eval --entry shadowed`: the exact-interval path on every target agrees with the
/// reference; `--samples` and the march; bad spheres are one line with exit 2.
#[test]
fn eval_shadowed_on_every_target() {
    let dir = scratch("shadowed");
    let input = dir.join("shafts.csv");
    std::fs::write(
        &input,
        "ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g,spheres\n\
         0,0,0,1,0.05,0,25,6,2,0.5,3,0.12,0.08,0.6,3 1.2 0.3 0.35;7 1.6 0.4 0.25\n\
         0,0,0,1,0.05,0,-1,6,2,0.5,3,0.12,0.08,-0.3,3 1.2 0.3 0.35;7 1.6 0.4 0.25\n\
         0,0,0,1,0,0,40,10,1,0,1,0.05,0.05,0.3,\n",
    )
    .unwrap();
    let run = |args: &[&str]| {
        let mut all = vec!["eval", "--entry", "shadowed", "-i", input.to_str().unwrap()];
        all.extend_from_slice(args);
        airlight(&all)
    };
    let values = |o: &Output| -> Vec<f64> {
        assert!(o.status.success(), "{}", stderr(o));
        let out = String::from_utf8(o.stdout.clone()).unwrap();
        assert!(out.starts_with("ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g,spheres,radiance\n"));
        out.lines().skip(1).map(|l| l.rsplit(',').next().unwrap().parse().unwrap()).collect()
    };
    let reference = values(&run(&["--model", "reference"]));
    // The unshadowed third ray is the radiance entry's own value.
    let plain = dir.join("plain.csv");
    std::fs::write(
        &plain,
        "ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g\n0,0,0,1,0,0,40,10,1,0,1,0.05,0.05,0.3\n",
    )
    .unwrap();
    let o = airlight(&["eval", "--entry", "radiance", "-i", plain.to_str().unwrap()]);
    let unshadowed: f64 =
        String::from_utf8(o.stdout).unwrap().lines().nth(1).unwrap().rsplit(',').next().unwrap().parse().unwrap();
    assert!(((reference[2] - unshadowed) / unshadowed).abs() < 1e-13);
    for args in [
        &["--model", "phi-8"][..],
        &["--model", "phi-8", "--precision", "f32"],
        &["--model", "phi-8", "--target", "wgsl"],
        &["--model", "phi-8", "--target", "glsl"],
    ] {
        let o = run(args);
        if !o.status.success() && !gpu_required() && stderr(&o).contains("no GPU adapter") {
            eprintln!("SKIPPED eval --entry shadowed {args:?}: {}", stderr(&o));
            continue;
        }
        for (x, r) in values(&o).iter().zip(&reference) {
            assert!(((x - r) / r).abs() < 2e-5, "{args:?}: {x} vs {r}");
        }
    }
    // Shadow-map samples: both place each change between the samples that see
    // it; the march adds its quadrature error, the accumulator none (the third
    // ray, without occluders, is exact), so its mean error is below the march's.
    let acc = values(&run(&["--model", "reference", "--samples", "16"]));
    let march = values(&run(&["--model", "raymarch-16"]));
    let err = |v: &[f64]| v.iter().zip(&reference).map(|(x, r)| ((x - r) / r).abs()).sum::<f64>();
    assert!(err(&acc) < err(&march), "accumulator {:.2e}, march {:.2e}", err(&acc), err(&march));
    assert!(((acc[2] - reference[2]) / reference[2]).abs() < 1e-13);
    let o = run(&["--model", "raymarch-16", "--samples", "32"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("its own 16 steps"), "{}", stderr(&o));
    let o = airlight(&["eval", "--samples", "8", "-i", plain.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--entry shadowed"), "{}", stderr(&o));
    // A bad sphere: file, line and column.
    let bad = dir.join("bad.csv");
    std::fs::write(
        &bad,
        "ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g,spheres\n0,0,0,1,0,0,4,2,1,0,1,0.1,0.1,0,1 2 3\n",
    )
    .unwrap();
    let o = airlight(&["eval", "--entry", "shadowed", "-i", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("bad.csv:2") && e.contains("spheres") && e.lines().count() == 1, "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `eval --entry shadowed --shadow-map RES`: point rays (a cube map) and spot rays
/// (one face over the cone) on f64, f32, WGSL and GLSL agree with each other and,
/// to the map's resolution, with the analytic reference, the finer map closer;
/// the walk's steps go to standard error; bad maps and clashing feeds are one
/// line with exit 2.
#[test]
fn eval_shadow_map_on_every_target() {
    let dir = scratch("shadow-map");
    let input = dir.join("rays.csv");
    std::fs::write(
        &input,
        "ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,intensity,sigma_t,sigma_s,g,spheres\n\
         0,0,0,1,0.05,0,25,6,2,0.5,3,0.12,0.08,0.6,3 1.2 0.3 0.35;7 1.6 0.4 0.25\n\
         0,0,0,1,0.05,0,-1,6,2,0.5,3,0.12,0.08,-0.3,3 1.2 0.3 0.35;7 1.6 0.4 0.25\n\
         -3,0.5,0,1,0.1,0.02,12,0,1,0,2,0.3,0.2,0.5,-1 0.8 0 0.2;1.2 0.9 0.1 0.3\n",
    )
    .unwrap();
    let spot = dir.join("spot.csv");
    std::fs::write(
        &spot,
        "ox,oy,oz,dx,dy,dz,surface,lx,ly,lz,ax,ay,az,cos_outer,cos_inner,intensity,\
         sigma_t_r,sigma_t_g,sigma_t_b,sigma_s_r,sigma_s_g,sigma_s_b,g,spheres\n\
         0,0,0,1,0.05,0,25,6,4,0.5,0,-1,0,0.6,0.8,3,0.12,0.1,0.08,0.08,0.07,0.06,0.6,6 2 0.5 0.4;4 1 0.4 0.2\n",
    )
    .unwrap();
    let run = |file: &Path, args: &[&str]| {
        let mut all = vec!["eval", "--entry", "shadowed", "-i", file.to_str().unwrap()];
        all.extend_from_slice(args);
        airlight(&all)
    };
    let values = |o: &Output| -> Vec<f64> {
        assert!(o.status.success(), "{}", stderr(o));
        String::from_utf8(o.stdout.clone())
            .unwrap()
            .lines()
            .skip(1)
            .flat_map(|l| {
                l.rsplit(',')
                    .take(if l.contains("0.6,0.8") { 3 } else { 1 })
                    .map(|x| x.parse::<f64>().unwrap())
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    for file in [&input, &spot] {
        let reference = values(&run(file, &["--model", "reference"]));
        let err =
            |v: &[f64]| v.iter().zip(&reference).map(|(x, r)| (x - r).abs() / r.abs().max(1e-30)).fold(0.0, f64::max);
        let coarse = run(file, &["--model", "phi-6", "--shadow-map", "64"]);
        let fine = values(&run(file, &["--model", "phi-6", "--shadow-map", "1024"]));
        assert!(
            err(&fine) < err(&values(&coarse)),
            "{}: 1024² {:e} against 64² {:e}",
            file.display(),
            err(&fine),
            err(&values(&coarse))
        );
        assert!(err(&fine) < 0.05, "{}: {:e}", file.display(), err(&fine));
        for args in [&["--precision", "f32"][..], &["--target", "wgsl"], &["--target", "glsl"]] {
            let mut a = vec!["--model", "phi-6", "--shadow-map", "1024"];
            a.extend_from_slice(args);
            let o = run(file, &a);
            if !o.status.success() && !gpu_required() && stderr(&o).contains("no GPU adapter") {
                eprintln!("SKIPPED --shadow-map {args:?}: {}", stderr(&o));
                continue;
            }
            assert!(stderr(&o).contains("walk steps median"), "{}", stderr(&o));
            for (x, y) in values(&o).iter().zip(&fine) {
                assert!((x - y).abs() <= 1e-4 * y.abs() + 1e-30, "{args:?}: {x} against f64 {y}");
            }
        }
    }
    for (args, says) in [
        (&["--shadow-map", "100"][..], "power of two"),
        (&["--shadow-map", "64", "--samples", "8"], "not both"),
        (&["--shadow-map", "64", "--model", "raymarch-16"], "own 16 steps"),
    ] {
        let o = run(&input, args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let e = stderr(&o);
        assert!(e.contains(says) && e.lines().count() == 1, "{args:?}: {e}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
