//! The report's figures (`generated/plots/*.{svg,png}`), drawn with plotters:
//! each family's figures (`airlight_shapes::figure`, computed by the family from
//! its coefficient files) and the bench's Pareto fronts.

use crate::output::Output;
use airlight_fit::coeffs::ModelFile;
use airlight_shapes::figure::{Figure, Heatmap, Lines, Panel};
use plotters::coord::Shift;
use plotters::prelude::*;

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

/// A heat map of `log10` of its values.
fn heatmap<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, h: &Heatmap) -> Result<(), PlotError> {
    let (lo, hi) = h.log10_range;
    let mut chart = ChartBuilder::on(area)
        .caption(&h.title, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(h.x_range.0..h.x_range.1, h.y_range.0..h.y_range.1)
        .map_err(err)?;
    chart.configure_mesh().x_desc(&h.x_desc).y_desc(&h.y_desc).disable_mesh().draw().map_err(err)?;
    let (dy, dx) = (h.y[1] - h.y[0], h.x[1] - h.x[0]);
    chart
        .draw_series(h.values.iter().enumerate().flat_map(|(i, row)| {
            row.iter().enumerate().map(move |(j, e)| {
                let (y, x) = (h.y[i], h.x[j]);
                let v = if *e > 0.0 { e.log10() } else { lo };
                Rectangle::new([(x - 0.5 * dx, y - 0.5 * dy), (x + 0.5 * dx, y + 0.5 * dy)], heat(v, lo, hi).filled())
            })
        }))
        .map_err(err)?;
    Ok(())
}

/// A chart of named lines, `y` logarithmic (and `x` where asked).
fn lines<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, l: &Lines) -> Result<(), PlotError> {
    let mut builder = ChartBuilder::on(area);
    builder.caption(&l.title, ("sans-serif", 20)).margin(10).x_label_area_size(40).y_label_area_size(60);
    macro_rules! body {
        ($chart:expr) => {{
            let mut chart = $chart;
            chart
                .configure_mesh()
                .x_desc(&l.x_desc)
                .y_desc(&l.y_desc)
                .y_label_formatter(&|y| format!("{y:.0e}"))
                .draw()
                .map_err(err)?;
            for line in &l.series {
                let c = COLOURS[line.colour % COLOURS.len()];
                chart
                    .draw_series(LineSeries::new(
                        line.points.iter().copied().filter(|p| p.1 > 0.0 && p.1.is_finite()),
                        c.stroke_width(2),
                    ))
                    .map_err(err)?
                    .label(line.name.as_str())
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
    let (x, y) = (l.x_range, l.y_range);
    if l.x_log {
        body!(builder.build_cartesian_2d((x.0..x.1).log_scale(), (y.0..y.1).log_scale()).map_err(err)?);
    } else {
        body!(builder.build_cartesian_2d(x.0..x.1, (y.0..y.1).log_scale()).map_err(err)?);
    }
    Ok(())
}

/// The palette [`Line::colour`](airlight_shapes::figure::Line) indexes.
const COLOURS: [RGBColor; 6] = [
    RGBColor(0, 0, 0),
    RGBColor(200, 40, 40),
    RGBColor(30, 110, 200),
    RGBColor(40, 160, 60),
    RGBColor(150, 60, 170),
    RGBColor(230, 140, 20),
];

fn panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &Panel) -> Result<(), PlotError> {
    match p {
        Panel::Heatmap(h) => heatmap(area, h),
        Panel::Lines(l) => lines(area, l),
    }
}

/// A figure's panels side by side (one panel: the whole figure).
fn figure<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, f: &Figure) -> Result<(), PlotError> {
    if let [only] = f.panels.as_slice() {
        return panel(root, only);
    }
    let areas = root.split_evenly((1, f.panels.len()));
    areas.iter().zip(&f.panels).try_for_each(|(area, p)| panel(area, p))
}

/// Every family's figures (`airlight_fit::family::figures`), from the coefficient files.
pub fn render(models: &[ModelFile]) -> Result<Vec<Output>, PlotError> {
    register_font()?;
    let members: Vec<_> = models.iter().map(|m| m.member(None)).collect();
    let mut out = Vec::new();
    for f in airlight_fit::family::figures(&members) {
        out.extend(both!(&f.file, |root| figure(&root, &f)));
    }
    Ok(out)
}

/// One panel of a pareto figure: error (by `measure`) against ns/eval, log-log.
fn pareto_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    ms: &[crate::front::Method],
    measure: &dyn Fn(&crate::front::Method) -> f64,
    dominated: &dyn Fn(&crate::front::Method) -> bool,
    cost: crate::front::CostMeasure,
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
        .x_desc(cost.axis())
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

/// `plots/pareto-<g><measure>.{svg,png}` for every `g` of the bench and every
/// cost measure it holds ([`crate::front::CostMeasure::suffix`]): max error
/// (left) and median error (right) against ns/eval on that measure.
pub fn pareto(b: &airlight_shapes::bench::Bench) -> Result<Vec<Output>, PlotError> {
    register_font()?;
    let mut out = Vec::new();
    for cost in crate::front::CostMeasure::ALL.into_iter().filter(|c| c.measured(b)) {
        for g in crate::front::gs(b) {
            let ms = crate::front::methods_by(b, g, cost);
            let label = crate::front::g_label(g);
            let phase = if g == 0.0 { "isotropic".to_string() } else { format!("Henyey-Greenstein g = {label}") };
            out.extend(both!(&format!("pareto-{label}{}", cost.suffix()), |root| {
                let areas = root.split_evenly((1, 2));
                let title = |what: &str| format!("{phase}: {what} ({})", cost.title());
                pareto_panel(&areas[0], &title("max error, thin ∪ dense"), &ms, &|m| m.max, &|m| m.dominated_max, cost)
                    .and_then(|_| {
                        pareto_panel(
                            &areas[1],
                            &title("median error"),
                            &ms,
                            &|m| m.median,
                            &|m| m.dominated_median,
                            cost,
                        )
                    })
            }));
        }
    }
    Ok(out)
}
