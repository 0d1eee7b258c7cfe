//! PNG plots (plotters, bitmap backend, bundled DejaVu Sans font).

use anyhow::{anyhow, Result};
use plotters::prelude::*;
use std::path::Path;

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// A log-axis tick label: plain decimals from 0.01 to 10⁴, powers of ten beyond.
fn tick(v: f64) -> String {
    if (0.01..1e4).contains(&v) {
        let s = format!("{v:.2}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.0e}")
    }
}

/// A linear-axis tick label: up to two decimals, trailing zeros dropped; powers of ten
/// outside 0.01–10⁵.
fn linear_tick(v: f64) -> String {
    let a = v.abs();
    // a tick at zero computed as a sum of steps lands a round-off away from it
    if a < 1e-12 {
        "0".into()
    } else if (0.01..1e5).contains(&a) {
        let s = format!("{v:.2}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.1e}")
    }
}

/// One named curve of (x, y) points.
pub struct Curve {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

/// A chart with logarithmic axes, drawn into a PNG.
type LogChart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

/// Log–log plot of several curves; `hlines` are dashed reference levels (value, label).
pub fn loglog(
    path: &Path,
    title: &str,
    xlabel: &str,
    ylabel: &str,
    curves: &[Curve],
    hlines: &[(f64, String)],
) -> Result<()> {
    register_font();
    let ((x0, x1), (y0, y1)) = loglog_extent(curves, hlines)
        .ok_or_else(|| anyhow!("nothing to plot in {}", path.display()))?;
    let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (x0 / 1.5..x1 * 1.5).log_scale(),
            (y0 / 1.5..y1 * 1.5).log_scale(),
        )
        .map_err(|e| anyhow!("{e}"))?;
    chart
        .configure_mesh()
        .x_desc(xlabel)
        .y_desc(ylabel)
        .label_style(("sans-serif", 14))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    for (k, c) in curves.iter().enumerate() {
        draw_log_curve(&mut chart, k, c)?;
    }
    for (y, label) in hlines {
        draw_hline(&mut chart, (x0 / 1.5, x1 * 1.5), *y, label)?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    root.present().map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

/// The x range and the y range (reference levels included) of the positive points of
/// `curves`; `None` without any.
fn loglog_extent(curves: &[Curve], hlines: &[(f64, String)]) -> Option<((f64, f64), (f64, f64))> {
    let pts: Vec<(f64, f64)> = curves
        .iter()
        .flat_map(|c| c.points.iter().copied())
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .collect();
    if pts.is_empty() {
        return None;
    }
    let (x0, x1) = pts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), (x, _)| {
        (a.min(*x), b.max(*x))
    });
    let (y0, y1) = pts
        .iter()
        .map(|p| p.1)
        .chain(hlines.iter().map(|h| h.0))
        .fold((f64::INFINITY, 0.0f64), |(a, b), y| (a.min(y), b.max(y)));
    Some(((x0, x1), (y0, y1)))
}

/// Draw curve `c`, the `k`-th, as a line with markers at its positive points, and
/// enter it in the legend.
fn draw_log_curve(chart: &mut LogChart, k: usize, c: &Curve) -> Result<()> {
    let color = Palette99::pick(k).to_rgba();
    let p: Vec<(f64, f64)> = c
        .points
        .iter()
        .copied()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .collect();
    chart
        .draw_series(LineSeries::new(p.clone(), color.stroke_width(2)))
        .map_err(|e| anyhow!("{e}"))?
        .label(c.label.clone())
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
    chart
        .draw_series(
            p.iter()
                .map(|&(x, y)| Circle::new((x, y), 4, color.filled())),
        )
        .map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

/// Draw the dashed reference level `y` across `xa..xb`, labelled at its left end.
fn draw_hline(chart: &mut LogChart, (xa, xb): (f64, f64), y: f64, label: &str) -> Result<()> {
    let dashes: Vec<(f64, f64)> = (0..40)
        .map(|k| xa * (xb / xa).powf(k as f64 / 40.0))
        .map(|x| (x, y))
        .collect();
    chart
        .draw_series(
            dashes
                .chunks(2)
                .map(|c| PathElement::new(c.to_vec(), BLACK.stroke_width(1))),
        )
        .map_err(|e| anyhow!("{e}"))?;
    chart
        .draw_series(std::iter::once(Text::new(
            label.to_string(),
            (xa * 1.05, y * 1.08),
            ("sans-serif", 13),
        )))
        .map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

/// One panel of a [`panels`] figure: curves on linear axes sharing the x-axis.
pub struct Panel {
    pub title: String,
    pub ylabel: String,
    pub curves: Vec<Curve>,
    /// A y range the axis always covers (None: the curves' own), so that a quantity
    /// that barely moves is drawn as flat rather than magnified.
    pub include: Option<(f64, f64)>,
}

/// (min, max) of `values`, widened to a non-empty range with a 5 % margin.
fn span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if lo > hi {
        return (0.0, 1.0);
    }
    let pad = 0.05 * (hi - lo).max(1e-12 * hi.abs().max(1.0));
    (lo - pad, hi + pad)
}

/// A linear-axis chart as the stacked figures draw it.
type LinearChart<'a, 'b> = ChartContext<
    'a,
    BitMapBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// A white figure of `rows` stacked panels under `title`: its drawing area.
fn stacked_root<'b>(
    path: &'b Path,
    title: &str,
    rows: usize,
) -> Result<DrawingArea<BitMapBackend<'b>, plotters::coord::Shift>> {
    register_font();
    let height = 40 + 330 * rows.max(1) as u32;
    let root = BitMapBackend::new(path, (1000, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
    root.titled(title, ("sans-serif", 24))
        .map_err(|e| anyhow!("{e}"))
}

/// One panel's chart on `area`: its caption, the x range `x` and y range `y`, and the
/// mesh with its axis labels.
fn linear_panel<'a, 'b>(
    area: &'a DrawingArea<BitMapBackend<'b>, plotters::coord::Shift>,
    caption: &str,
    (xlabel, ylabel): (&str, &str),
    x: (f64, f64),
    y: (f64, f64),
) -> Result<LinearChart<'a, 'b>> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(85)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)
        .map_err(|e| anyhow!("{e}"))?;
    chart
        .configure_mesh()
        .x_desc(xlabel)
        .y_desc(ylabel)
        .label_style(("sans-serif", 14))
        .y_label_formatter(&|v| linear_tick(*v))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    Ok(chart)
}

/// The legend of a panel's labelled series, upper right.
fn legend<'a, 'b: 'a>(chart: &mut LinearChart<'a, 'b>) -> Result<()> {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(|e| anyhow!("{e}"))
}

/// Panels stacked one above another, each with linear axes and a legend, against a
/// shared x-axis (time): the quick-look plot of a run.
pub fn panels(path: &Path, title: &str, xlabel: &str, panels: &[Panel]) -> Result<()> {
    let root = stacked_root(path, title, panels.len())?;
    let x = span(
        panels
            .iter()
            .flat_map(|p| p.curves.iter().flat_map(|c| c.points.iter().map(|q| q.0))),
    );
    for (area, panel) in root.split_evenly((panels.len(), 1)).iter().zip(panels) {
        let y = span(
            panel
                .curves
                .iter()
                .flat_map(|c| c.points.iter().map(|q| q.1))
                .chain(panel.include.into_iter().flat_map(|(a, b)| [a, b])),
        );
        let mut chart = linear_panel(area, &panel.title, (xlabel, &panel.ylabel), x, y)?;
        for (k, c) in panel.curves.iter().enumerate() {
            let color = Palette99::pick(k).to_rgba();
            let p: Vec<(f64, f64)> = c
                .points
                .iter()
                .copied()
                .filter(|(a, b)| a.is_finite() && b.is_finite())
                .collect();
            chart
                .draw_series(LineSeries::new(p, color.stroke_width(2)))
                .map_err(|e| anyhow!("{e}"))?
                .label(c.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
        }
        legend(&mut chart)?;
    }
    root.present().map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

/// One panel of an [`envelopes`] figure: a quantity's curve in each member of an
/// ensemble.
pub struct Band {
    pub title: String,
    pub ylabel: String,
    /// Each member's (t, value) points, at the same times.
    pub members: Vec<Vec<(f64, f64)>>,
}

/// The mean and the sample standard deviation over the members at each sample time
/// (the members' common times: the shortest member's).
fn mean_sd(members: &[Vec<(f64, f64)>]) -> Vec<(f64, f64, f64)> {
    let n = members.iter().map(Vec::len).min().unwrap_or(0);
    (0..n)
        .map(|k| {
            let x: Vec<f64> = members.iter().map(|m| m[k].1).collect();
            let mean = x.iter().sum::<f64>() / x.len() as f64;
            let var = if x.len() > 1 {
                x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (x.len() - 1) as f64
            } else {
                0.0
            };
            (members[0][k].0, mean, var.sqrt())
        })
        .collect()
}

/// Panels stacked one above another against a shared x-axis (time): in each, every
/// member's curve (thin, grey), the members' mean (thick) and the mean ± sd band.
pub fn envelopes(path: &Path, title: &str, xlabel: &str, bands: &[Band]) -> Result<()> {
    let root = stacked_root(path, title, bands.len())?;
    let x = span(
        bands
            .iter()
            .flat_map(|b| b.members.iter().flat_map(|m| m.iter().map(|q| q.0))),
    );
    for (area, band) in root.split_evenly((bands.len().max(1), 1)).iter().zip(bands) {
        let stats = mean_sd(&band.members);
        let y = span(
            band.members
                .iter()
                .flat_map(|m| m.iter().map(|q| q.1))
                .chain(stats.iter().flat_map(|s| [s.1 - s.2, s.1 + s.2])),
        );
        let mut chart = linear_panel(area, &band.title, (xlabel, &band.ylabel), x, y)?;
        let blue = Palette99::pick(0).to_rgba();
        let outline: Vec<(f64, f64)> = stats
            .iter()
            .map(|s| (s.0, s.1 + s.2))
            .chain(stats.iter().rev().map(|s| (s.0, s.1 - s.2)))
            .filter(|(a, b)| a.is_finite() && b.is_finite())
            .collect();
        chart
            .draw_series(std::iter::once(Polygon::new(
                outline,
                blue.mix(0.25).filled(),
            )))
            .map_err(|e| anyhow!("{e}"))?
            .label("mean ± sd")
            .legend(move |(x, y)| {
                Rectangle::new([(x, y - 5), (x + 20, y + 5)], blue.mix(0.25).filled())
            });
        let grey = RGBColor(120, 120, 120).mix(0.6);
        for (k, m) in band.members.iter().enumerate() {
            let p: Vec<(f64, f64)> = m
                .iter()
                .copied()
                .filter(|(a, b)| a.is_finite() && b.is_finite())
                .collect();
            let s = chart
                .draw_series(LineSeries::new(p, grey.stroke_width(1)))
                .map_err(|e| anyhow!("{e}"))?;
            if k == 0 {
                s.label(format!("each of {} members", band.members.len()))
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], grey.stroke_width(1))
                    });
            }
        }
        chart
            .draw_series(LineSeries::new(
                stats
                    .iter()
                    .map(|s| (s.0, s.1))
                    .filter(|(a, b)| a.is_finite() && b.is_finite()),
                blue.stroke_width(3),
            ))
            .map_err(|e| anyhow!("{e}"))?
            .label("mean")
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], blue.stroke_width(3))
            });
        legend(&mut chart)?;
    }
    root.present().map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn tick_labels_are_short() {
        assert_eq!(super::tick(1e-7), "1e-7");
        assert_eq!(super::tick(0.1), "0.1");
        assert_eq!(super::tick(100.0), "100");
        assert_eq!(super::tick(1e5), "1e5");
    }
}
