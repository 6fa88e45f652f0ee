//! A frame's fog against the reference: lit pixels and shaft edges apart, the
//! difference images, and the march frame nearest the accumulator's GPU time.

use super::*;

/// Errors of a frame's fog against the reference's, relative per pixel (the
/// largest channel's): max and mean over the lit pixels off the shafts' edges,
/// and over the edge pixels.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FogErrors {
    /// Max relative error, lit pixels off the edges.
    pub lit_max: f64,
    /// Mean relative error, lit pixels off the edges.
    pub lit_mean: f64,
    /// Max relative error, shaft-edge pixels.
    pub edge_max: f64,
    /// Mean relative error, shaft-edge pixels.
    pub edge_mean: f64,
}

/// Which pixels are lit (reference fog luminance at least 1% of its 99th
/// percentile) and which of those lie on a shaft's edge (a neighbour's reference
/// fog differs from the pixel's by more than [`EDGE_STEP`] of the larger).
pub fn classify(view: &ShaftsView, fog: &[[f64; 3]]) -> Vec<Option<bool>> {
    let lum: Vec<f64> = fog.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).collect();
    let mut sorted: Vec<f64> = lum.iter().copied().filter(|x| x.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    let p99 = sorted.get((sorted.len() as f64 * 0.99) as usize).copied().unwrap_or(0.0);
    let (w, h) = (view.width as i64, view.height as i64);
    (0..w * h)
        .map(|i| {
            let l = lum[i as usize];
            if l.is_nan() || l < 0.01 * p99 {
                return None;
            }
            let (x, y) = (i % w, i / w);
            let mut edge = false;
            for (dx, dy) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
                let (u, v) = (x + dx, y + dy);
                if u >= 0 && u < w && v >= 0 && v < h {
                    let m = lum[(v * w + u) as usize];
                    edge |= (m - l).abs() > EDGE_STEP * m.max(l);
                }
            }
            Some(edge)
        })
        .collect()
}

/// Light leaks: the pixels whose fog (the mean of its channels) is above
/// [`LEAK_FACTOR`] times the reference's plus [`LEAK_FLOOR`] of the reference
/// fog's 99th percentile over the frame.
pub fn leak_pixels(frame: &Frame, fog: &[[f64; 3]]) -> usize {
    let lum = |p: [f64; 3]| (p[0] + p[1] + p[2]) / 3.0;
    let mut sorted: Vec<f64> = fog.iter().map(|p| lum(*p)).filter(|x| x.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    let p99 = sorted.get((sorted.len() as f64 * 0.99) as usize).copied().unwrap_or(0.0);
    frame
        .fog
        .iter()
        .zip(fog)
        .filter(|(g, r)| {
            let g = lum([0, 1, 2].map(|c| f64::from(g[c])));
            // A NaN counts as a leak.
            g.is_nan() || g > LEAK_FACTOR * lum(**r) + LEAK_FLOOR * p99
        })
        .count()
}

/// A leak is brighter than this many times the reference ...
pub const LEAK_FACTOR: f64 = 1.5;

/// ... plus this fraction of the reference fog's 99th percentile.
pub const LEAK_FLOOR: f64 = 0.01;

/// A neighbouring pixel's fog differs by more than this fraction on a shaft's edge.
pub const EDGE_STEP: f64 = 0.1;

/// The fog errors of `frame` against the reference `fog`, by `classes` ([`classify`]).
pub fn fog_errors(frame: &Frame, fog: &[[f64; 3]], classes: &[Option<bool>]) -> FogErrors {
    let (mut lit, mut edge) = (Vec::new(), Vec::new());
    for ((g, r), class) in frame.fog.iter().zip(fog).zip(classes) {
        let Some(on_edge) = class else { continue };
        let e = (0..3)
            .map(|c| if r[c] > 0.0 { (f64::from(g[c]) - r[c]).abs() / r[c] } else { f64::from(g[c]).abs() })
            .fold(0.0, f64::max);
        if *on_edge {
            edge.push(e);
        } else {
            lit.push(e);
        }
    }
    let max = |e: &[f64]| e.iter().copied().fold(0.0, f64::max);
    let mean = |e: &[f64]| e.iter().sum::<f64>() / e.len().max(1) as f64;
    FogErrors { lit_max: max(&lit), lit_mean: mean(&lit), edge_max: max(&edge), edge_mean: mean(&edge) }
}

/// A relative-difference image of a frame's fog: log10 of the largest
/// channel's relative error from 1e-3 (black) through 3e-2 (orange) to 1
/// (white); pixels off the lit set dark blue.
pub fn difference(frame: &Frame, fog: &[[f64; 3]], classes: &[Option<bool>]) -> Vec<[u8; 3]> {
    frame
        .fog
        .iter()
        .zip(fog)
        .zip(classes)
        .map(|((g, r), class)| {
            if class.is_none() {
                return [10, 14, 40];
            }
            let e = (0..3).map(|c| (f64::from(g[c]) - r[c]).abs() / r[c].max(1e-300)).fold(0.0, f64::max);
            let s = ((e.max(1e-3).log10() + 3.0) / 3.0).clamp(0.0, 1.0);
            let c = |a: f64| (255.0 * a.clamp(0.0, 1.0)).round() as u8;
            [c(2.0 * s), c(2.0 * s - 0.6), c(2.0 * s - 1.2)]
        })
        .collect()
}

/// The march frame whose GPU time is nearest `frame`'s (by ratio; the frame's
/// pyramid pass counted in).
pub fn nearest_in_time<'f>(frame: &Frame, marches: &'f [Frame]) -> Option<&'f Frame> {
    let t = frame.gpu_s + frame.pyramid_s;
    marches.iter().min_by(|a, b| {
        let d = |f: &Frame| (f.gpu_s.max(1e-12) / t.max(1e-12)).ln().abs();
        d(a).total_cmp(&d(b))
    })
}
