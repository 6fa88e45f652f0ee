//! Figures as data: what a family exposes for the report's plots
//! (`generated/plots/<file>.{svg,png}`), drawn by the generator. A figure is a
//! row of panels, each a heat map of `log10 |error|` or a chart of lines on a
//! logarithmic `y` axis.

/// One figure: its file stem under `plots/` and its panels, side by side.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// `plots/<file>.svg` and `.png`.
    pub file: String,
    /// Left to right.
    pub panels: Vec<Panel>,
}

/// One panel.
#[derive(Debug, Clone, PartialEq)]
pub enum Panel {
    /// `log10` of non-negative values on a grid, coloured from dark blue to red.
    Heatmap(Heatmap),
    /// Named lines, `y` logarithmic.
    Lines(Lines),
}

/// A heat map: `values[i][j]` at `(x[j], y[i])`, one cell per value.
#[derive(Debug, Clone, PartialEq)]
pub struct Heatmap {
    /// Caption.
    pub title: String,
    /// Axis labels.
    pub x_desc: String,
    /// Axis labels.
    pub y_desc: String,
    /// Axis ranges.
    pub x_range: (f64, f64),
    /// Axis ranges.
    pub y_range: (f64, f64),
    /// Cell centres, evenly spaced.
    pub x: Vec<f64>,
    /// Cell centres, evenly spaced.
    pub y: Vec<f64>,
    /// Rows (one per `y`) of values (one per `x`); 0 is drawn as the low end.
    pub values: Vec<Vec<f64>>,
    /// The colour scale's range in `log10` of the values.
    pub log10_range: (f64, f64),
}

/// Lines on a chart with a logarithmic `y` axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Lines {
    /// Caption.
    pub title: String,
    /// Axis labels.
    pub x_desc: String,
    /// Axis labels.
    pub y_desc: String,
    /// Axis ranges.
    pub x_range: (f64, f64),
    /// Axis ranges.
    pub y_range: (f64, f64),
    /// Whether `x` is logarithmic too.
    pub x_log: bool,
    /// The lines; points with `y ≤ 0` or not finite are left out.
    pub series: Vec<Line>,
}

/// A named line.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// Legend.
    pub name: String,
    /// Points.
    pub points: Vec<(f64, f64)>,
    /// Index into the generator's palette (0 black, 1 red, 2 blue, 3 green, 4 purple, 5 orange).
    pub colour: usize,
}
