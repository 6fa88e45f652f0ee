//! The report's figures (`generated/plots/*.{svg,png}`), drawn with plotters from
//! the coefficient files and the analysis functions of airlight-fit.

use crate::output::Output;
use airlight_fit::analysis::{forward_error_grid, linspace, logspace, ratio_error_grid};
use airlight_fit::approx::{PhaseModel, Split};
use airlight_fit::coeffs::ModelFile;
use airlight_fit::family::split::ratio::Ratio;
use airlight_fit::family::split::segments::Segments;
use airlight_fit::vocab::Domain;
use airlight_fit::Phase;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

/// A figure failed to draw (a plotters backend error).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlotError(pub String);

impl std::fmt::Display for PlotError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "plot: {}", self.0)
    }
}

impl std::error::Error for PlotError {}

fn err(e: impl std::fmt::Debug) -> PlotError {
    PlotError(format!("{e:?}"))
}

const SIZE: (u32, u32) = (1200, 520);

/// The one font every figure is drawn with, bundled so that the figures are the
/// same on every machine (DejaVu Sans; licence in `codegen/fonts/LICENSE-DejaVu.txt`).
const FONT: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");

/// Makes [`FONT`] plotters' "sans-serif" (idempotent).
fn register_font() -> Result<(), PlotError> {
    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| PlotError("the bundled font does not parse".into()))
}

/// An 8-bit RGB image as PNG bytes (deterministic: fixed compression settings).
pub fn encode_png((width, height): (u32, u32), rgb: &[u8]) -> Result<Vec<u8>, PlotError> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Default);
        let mut w = enc.write_header().map_err(err)?;
        w.write_image_data(rgb).map_err(err)?;
    }
    Ok(out)
}

/// Renders one figure to `plots/<name>.svg` and `plots/<name>.png`: the drawing
/// code (`|root| …`) is expanded once per backend.
macro_rules! both {
    ($name:expr, |$root:ident| $body:expr) => {{
        let name: &str = $name;
        let mut svg = String::new();
        {
            let $root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
            $root.fill(&WHITE).map_err(err)?;
            $body?;
            $root.present().map_err(err)?;
        }
        // Drawn into memory and encoded here: no file, no system font.
        let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
        {
            let $root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
            $root.fill(&WHITE).map_err(err)?;
            $body?;
            $root.present().map_err(err)?;
        }
        let png = encode_png(SIZE, &rgb)?;
        vec![
            Output::text(format!("plots/{name}.svg"), svg),
            Output { path: format!("plots/{name}.png"), contents: png },
        ]
    }};
}

/// Colour for `log10(error)` in `[lo, hi]`: dark blue (small) through yellow to red (large).
fn heat(v: f64, lo: f64, hi: f64) -> RGBColor {
    let x = ((v - lo) / (hi - lo)).clamp(0.0, 1.0);
    let stops = [(0.0, (20, 30, 90)), (0.35, (30, 120, 180)), (0.65, (240, 220, 60)), (1.0, (200, 30, 30))];
    for w in stops.windows(2) {
        let ((a, ca), (b, cb)) = (w[0], w[1]);
        if x <= b {
            let t = (x - a) / (b - a);
            let m = |p: u8, q: u8| (p as f64 + t * (q as f64 - p as f64)).round() as u8;
            return RGBColor(m(ca.0, cb.0), m(ca.1, cb.1), m(ca.2, cb.2));
        }
    }
    RGBColor(200, 30, 30)
}

/// Forward-kernel error over `(T, θ)`: the paper's Fig. 4, paper vs refit.
fn forward_heatmaps<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    panels: &[(String, Vec<Vec<f64>>)],
    ts: &[f64],
    thetas: &[f64],
) -> Result<(), PlotError> {
    let (lo, hi) = (-6.0, 0.0);
    let areas = root.split_evenly((1, panels.len()));
    for (area, (title, grid)) in areas.iter().zip(panels) {
        let mut chart = ChartBuilder::on(area)
            .caption(title, ("sans-serif", 20))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0..FRAC_PI_2, 0.0..20.0)
            .map_err(err)?;
        chart.configure_mesh().x_desc("θ = π/2 − γ (rad)").y_desc("T = τ sin γ").disable_mesh().draw().map_err(err)?;
        let (dt, dth) = (ts[1] - ts[0], thetas[1] - thetas[0]);
        chart
            .draw_series(grid.iter().enumerate().flat_map(|(i, row)| {
                row.iter().enumerate().map(move |(j, e)| {
                    let (t, th) = (ts[i], thetas[j]);
                    let v = if *e > 0.0 { e.log10() } else { lo };
                    Rectangle::new(
                        [(th - 0.5 * dth, t - 0.5 * dt), (th + 0.5 * dth, t + 0.5 * dt)],
                        heat(v, lo, hi).filled(),
                    )
                })
            }))
            .map_err(err)?;
    }
    Ok(())
}

/// A named line and its colour.
type Series = (String, Vec<(f64, f64)>, RGBColor);

/// Log-scale line chart of named series.
#[allow(clippy::too_many_arguments)]
fn lines<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    x_desc: &str,
    y_desc: &str,
    x_range: (f64, f64),
    y_range: (f64, f64),
    x_log: bool,
    series: &[Series],
) -> Result<(), PlotError> {
    let mut builder = ChartBuilder::on(area);
    builder.caption(title, ("sans-serif", 20)).margin(10).x_label_area_size(40).y_label_area_size(60);
    macro_rules! body {
        ($chart:expr) => {{
            let mut chart = $chart;
            chart
                .configure_mesh()
                .x_desc(x_desc)
                .y_desc(y_desc)
                .y_label_formatter(&|y| format!("{y:.0e}"))
                .draw()
                .map_err(err)?;
            for (name, pts, colour) in series {
                let c = *colour;
                chart
                    .draw_series(LineSeries::new(
                        pts.iter().copied().filter(|p| p.1 > 0.0 && p.1.is_finite()),
                        c.stroke_width(2),
                    ))
                    .map_err(err)?
                    .label(name.as_str())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .position(SeriesLabelPosition::LowerRight)
                .draw()
                .map_err(err)?;
        }};
    }
    if x_log {
        body!(builder
            .build_cartesian_2d((x_range.0..x_range.1).log_scale(), (y_range.0..y_range.1).log_scale())
            .map_err(err)?);
    } else {
        body!(builder.build_cartesian_2d(x_range.0..x_range.1, (y_range.0..y_range.1).log_scale()).map_err(err)?);
    }
    Ok(())
}

const COLOURS: [RGBColor; 6] = [
    RGBColor(0, 0, 0),
    RGBColor(200, 40, 40),
    RGBColor(30, 110, 200),
    RGBColor(40, 160, 60),
    RGBColor(150, 60, 170),
    RGBColor(230, 140, 20),
];

/// The split family of the model `name`, if it is among `models`: a figure about
/// a model that is not there is not drawn.
fn split_of<'a>(models: &'a [ModelFile], name: &str) -> Option<&'a Split> {
    models.iter().find(|m| m.model.name == name)?.model.split()
}

/// Every figure, from the coefficient files.
pub fn render(models: &[ModelFile]) -> Result<Vec<Output>, PlotError> {
    register_font()?;
    let mut out = Vec::new();

    // 1. Forward kernel error over (T, θ): paper vs refit (Fig. 4).
    let ts = linspace(0.25, 19.75, 40);
    let thetas = linspace(FRAC_PI_2 / 80.0, FRAC_PI_2 * 79.0 / 80.0, 40);
    if let (Some(refit), Some(s16)) = (split_of(models, "paper-refit"), split_of(models, "segments-16")) {
        let panels = vec![
            ("paper, 3 segments: log10 |error|".to_string(), forward_error_grid(&Segments::paper(), &ts, &thetas)),
            ("refit, 3 segments".to_string(), forward_error_grid(&refit.forward, &ts, &thetas)),
            ("refit, 16 segments".to_string(), forward_error_grid(&s16.forward, &ts, &thetas)),
        ];
        out.extend(both!("forward-error", |root| forward_heatmaps(&root, &panels, &ts, &thetas)));
    }

    // 2. HG vs its approximations (Figs. 6–8).
    let gs = [0.1, 0.7, 0.97];
    let alphas = linspace(0.0, PI, 181);
    let paper_hg = match split_of(models, "paper-hg").map(|s| &s.phase) {
        Some(PhaseModel::Exp(e)) => Some(e.clone()),
        _ => None,
    };
    let mut fits = Vec::new();
    for k in 1..=3 {
        if let Some(PhaseModel::Exp(e)) = split_of(models, &format!("hg-exp{k}")).map(|s| &s.phase) {
            fits.push((format!("refit, {k} exp"), e.clone()));
        }
    }
    let phase_series: Vec<Vec<Series>> = gs
        .iter()
        .map(|&g| {
            let mut s = vec![(
                "Henyey-Greenstein".to_string(),
                alphas.iter().map(|&a| (a, Phase::from_g(g).eval(a))).collect(),
                COLOURS[0],
            )];
            if let Some(paper_hg) = &paper_hg {
                s.push((
                    "paper table".into(),
                    alphas.iter().map(|&a| (a, paper_hg.terms(g).eval(a))).collect(),
                    COLOURS[1],
                ));
            }
            for (i, (name, e)) in fits.iter().enumerate() {
                s.push((name.clone(), alphas.iter().map(|&a| (a, e.terms(g).eval(a))).collect(), COLOURS[2 + i]));
            }
            s
        })
        .collect();
    out.extend(both!("phase", |root| {
        let mut r: Result<(), PlotError> = Ok(());
        for ((area, &g), s) in root.split_evenly((1, 3)).iter().zip(&gs).zip(&phase_series) {
            let ymax = s[0].1.iter().map(|p| p.1).fold(0.0, f64::max) * 3.0;
            let ymin = s[0].1.iter().map(|p| p.1).fold(f64::INFINITY, f64::min) / 10.0;
            r = r.and_then(|_| {
                lines(area, &format!("g = {g}"), "α (rad)", "P(α) (1/sr)", (0.0, PI), (ymin, ymax), false, s)
            });
        }
        r
    }));

    // 3. Backscatter ratio error (Fig. 11): paper vs refit.
    let kappas = logspace(0.01, 20.0, 60);
    let theta1s = [0.2, 0.8, FRAC_PI_2];
    let refit_ratio = split_of(models, "paper-refit").and_then(|s| s.ratio.clone());
    let mut series = Vec::new();
    let ratios =
        std::iter::once(("paper", Ratio::paper(), [1, 3, 4])).chain(refit_ratio.map(|r| ("refit", r, [2, 5, 0])));
    for (label, r, palette) in ratios {
        let grid = ratio_error_grid(&r, &theta1s, &kappas);
        for (i, row) in grid.iter().enumerate() {
            let colour = COLOURS[palette[i]];
            series.push((
                format!("{label}, θ1 = {:.2}", theta1s[i]),
                kappas.iter().copied().zip(row.iter().copied()).collect::<Vec<_>>(),
                colour,
            ));
        }
    }
    out.extend(both!("backscatter-error", |root| {
        lines(
            &root,
            "backward integral: |relative error| of the ratio form",
            "κ = T",
            "|error|",
            (0.01, 20.0),
            (1e-4, 1e3),
            true,
            &series,
        )
    }));

    // 4. Error of A vs N for segments-N.
    let mut pts: Vec<(usize, &ModelFile)> = models
        .iter()
        .filter_map(|m| m.model.name.strip_prefix("segments-").and_then(|n| n.parse().ok()).map(|n| (n, m)))
        .collect();
    pts.sort_by_key(|p| p.0);
    let get = |d: Domain, f: &dyn Fn(&airlight_fit::domains::DomainErrors) -> f64| -> Vec<(f64, f64)> {
        pts.iter().filter_map(|(n, m)| m.error(d).map(|e| (*n as f64, f(e)))).collect()
    };
    let fwd: Vec<(f64, f64)> = pts
        .iter()
        .filter_map(|(n, m)| {
            m.provenance_value("forward.fit", "forward_integral_max_rel")
                .and_then(|v| v.as_float())
                .map(|v| (*n as f64, v))
        })
        .collect();
    let series = vec![
        ("A, thin: max".to_string(), get(Domain::Thin, &|e| e.max_rel), COLOURS[2]),
        ("A, thin: p99".to_string(), get(Domain::Thin, &|e| e.p99_rel), COLOURS[3]),
        ("A, dense: max".to_string(), get(Domain::Dense, &|e| e.max_rel), COLOURS[1]),
        ("A, dense: p99".to_string(), get(Domain::Dense, &|e| e.p99_rel), COLOURS[5]),
        ("forward integral alone: max (fit targets)".to_string(), fwd, COLOURS[0]),
    ];
    if pts.len() < 2 {
        return Ok(out);
    }
    out.extend(both!("error-vs-n", |root| {
        lines(
            &root,
            "segments-N: relative error vs number of segments",
            "N",
            "relative error",
            (2.0, 16.0),
            (1e-4, 1.0),
            false,
            &series,
        )
    }));
    Ok(out)
}

/// One panel of a pareto figure: error (by `measure`) against ns/eval, log-log.
fn pareto_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    ms: &[crate::front::Method],
    measure: &dyn Fn(&crate::front::Method) -> f64,
    dominated: &dyn Fn(&crate::front::Method) -> bool,
) -> Result<(), PlotError> {
    let finite = |m: &&crate::front::Method| measure(m).is_finite() && measure(m) > 0.0 && m.ns > 0.0;
    let shown: Vec<&crate::front::Method> = ms.iter().filter(finite).collect();
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
    for m in &shown {
        x0 = x0.min(m.ns);
        x1 = x1.max(m.ns);
        y0 = y0.min(measure(m));
        y1 = y1.max(measure(m));
    }
    if shown.is_empty() {
        (x0, x1, y0, y1) = (1.0, 10.0, 1e-6, 1.0);
    }
    let (x0, x1) = (x0 / 1.6, x1 * 1.6);
    let (y0, y1) = ((y0 / 4.0).max(1e-12), (y1 * 4.0).min(1e12));
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("CPU ns per evaluation (f32 Rust kernel, median)")
        .y_desc("relative error")
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .x_label_formatter(&|x| format!("{x:.0}"))
        .draw()
        .map_err(err)?;
    let grey = RGBColor(185, 185, 185);
    let blue = COLOURS[2];
    let orange = COLOURS[5];
    // Airlight's front as a line.
    let front = crate::front::airlight_front(ms, measure);
    chart
        .draw_series(LineSeries::new(
            front.iter().filter(|m| finite(m)).map(|m| (m.ns, measure(m))),
            blue.stroke_width(2),
        ))
        .map_err(err)?
        .label("airlight's front")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], blue.stroke_width(2)));
    for m in &shown {
        let p = (m.ns, measure(m));
        let colour = if dominated(m) {
            grey
        } else if m.baseline {
            orange
        } else {
            blue
        };
        if m.baseline {
            chart.draw_series(std::iter::once(TriangleMarker::new(p, 7, colour.filled()))).map_err(err)?;
        } else {
            chart.draw_series(std::iter::once(Circle::new(p, 5, colour.filled()))).map_err(err)?;
        }
        // Baselines always labelled; airlight's models where on its own front.
        if m.baseline || front.iter().any(|f| f.name == m.name) {
            let style = ("sans-serif", 12).into_font().color(if dominated(m) { &grey } else { &BLACK });
            chart.draw_series(std::iter::once(Text::new(m.name.clone(), p, style))).map_err(err)?;
        }
    }
    chart
        .draw_series(std::iter::once(Circle::new((x0, y0), 0, blue.filled())))
        .map_err(err)?
        .label("airlight model (circle), baseline (triangle); grey: dominated")
        .legend(move |(x, y)| Circle::new((x + 10, y), 5, blue.filled()));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(err)?;
    Ok(())
}

/// `plots/pareto-<g>.{svg,png}` for every `g` of the bench: max error (left) and
/// median error (right) against CPU ns/eval.
pub fn pareto(b: &airlight_fit::bench::Bench) -> Result<Vec<Output>, PlotError> {
    register_font()?;
    let mut out = Vec::new();
    for g in crate::front::gs(b) {
        let ms = crate::front::methods(b, g);
        let label = crate::front::g_label(g);
        let phase = if g == 0.0 { "isotropic".to_string() } else { format!("Henyey-Greenstein g = {label}") };
        out.extend(both!(&format!("pareto-{label}"), |root| {
            let areas = root.split_evenly((1, 2));
            pareto_panel(&areas[0], &format!("{phase}: max error, thin ∪ dense"), &ms, &|m| m.max, &|m| {
                m.dominated_max
            })
            .and_then(|_| {
                pareto_panel(&areas[1], &format!("{phase}: median error (larger domain)"), &ms, &|m| m.median, &|m| {
                    m.dominated_median
                })
            })
        }));
    }
    Ok(out)
}
