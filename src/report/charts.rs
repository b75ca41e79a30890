//! # Charts
//!
//! Every chart is written twice, as SVG and PNG, with DejaVu Sans embedded
//! (the `dejavu` crate) so that no system font is needed. Axes carry units,
//! decades are shown on log scales, and every series has a legend entry.
//!
//! Items: [`Style`], [`Series`], [`Chart`], [`write()`].

use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::Path;
use std::sync::OnceLock;

fn fonts() -> Result<()> {
    static DONE: OnceLock<bool> = OnceLock::new();
    let ok = DONE.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .is_ok()
    });
    if *ok {
        Ok(())
    } else {
        Err(Error::Io(
            "cannot register the embedded DejaVu Sans font".into(),
        ))
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// Line with circles (computed values).
    Line,
    /// Crosses only (published values).
    Markers,
    /// Filled circles only (categorical data).
    Points,
}

/// One series of a chart.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: Style,
    /// Palette index (series sharing a colour share a quantity).
    pub color: usize,
}

/// A chart with log or linear axes.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// Title.
    pub title: String,
    /// x-axis label with unit.
    pub x_label: String,
    /// y-axis label with unit.
    pub y_label: String,
    /// Log scale on x.
    pub log_x: bool,
    /// Log scale on y.
    pub log_y: bool,
    /// The series.
    pub series: Vec<Series>,
    /// Horizontal reference lines (y, label).
    pub hlines: Vec<(f64, String)>,
    /// Free text lines drawn under the plot.
    pub footnotes: Vec<String>,
    /// If non-empty, x = 1, 2, … are categories with these names.
    pub x_categories: Vec<String>,
    /// Fixed axis ranges (for example to leave room for the legend);
    /// `None` fits the data.
    pub x_range: Option<(f64, f64)>,
    /// See `x_range`.
    pub y_range: Option<(f64, f64)>,
}

fn label(v: f64, log: bool) -> String {
    if log {
        let e = v.log10().round();
        if (v.log10() - e).abs() < 1e-6 {
            return format!("1e{}", e as i32);
        }
        format!("{v:.1e}")
    } else {
        let r = (v * 1000.0).round() / 1000.0;
        format!("{r}")
    }
}

fn color(i: usize) -> RGBColor {
    const P: [RGBColor; 10] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
    ];
    P[i % P.len()]
}

fn range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let v: Vec<f64> = values
        .filter(|x| x.is_finite() && (!log || *x > 0.0))
        .collect();
    if v.is_empty() {
        return (1.0, 10.0);
    }
    let lo = v.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    if log {
        if hi / lo < 30.0 {
            return (lo / 1.3, hi * 1.3);
        }
        let (a, b) = (lo.log10().floor(), hi.log10().ceil());
        (10f64.powf(a), 10f64.powf(if b > a { b } else { a + 1.0 }))
    } else {
        let pad = 0.08 * (hi - lo).max(1e-12);
        ((lo - pad).min(0.0), hi + pad)
    }
}

fn map_err<E: std::fmt::Debug>(e: E) -> Error {
    Error::Io(format!("chart: {e:?}"))
}

/// The data range of the chart's axes: the fixed ranges if given, the
/// categories' slots, or the range of the points (and horizontal lines).
fn axis_ranges(chart: &Chart) -> ((f64, f64), (f64, f64)) {
    let xs = chart
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.0));
    let ys = chart
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .chain(chart.hlines.iter().map(|h| h.0));
    let mut x = chart.x_range.unwrap_or_else(|| range(xs, chart.log_x));
    if !chart.x_categories.is_empty() {
        x = (0.5, chart.x_categories.len() as f64 + 0.5);
    }
    let y = chart.y_range.unwrap_or_else(|| range(ys, chart.log_y));
    (x, y)
}

/// The x tick labels: numbers, or the category names at the integer slots.
fn x_tick_label(chart: &Chart) -> impl Fn(&f64) -> String {
    let cats = chart.x_categories.clone();
    let log_x = chart.log_x;
    move |v: &f64| {
        if cats.is_empty() {
            label(*v, log_x)
        } else if (v - v.round()).abs() < 1e-9 && v.round() >= 1.0 {
            cats.get(v.round() as usize - 1)
                .cloned()
                .unwrap_or_default()
        } else {
            String::new()
        }
    }
}

/// An axis of f64 values, linear or logarithmic: plotters gives each its
/// own coordinate type.
trait Axis: Ranged<ValueType = f64> {}
impl<T: Ranged<ValueType = f64>> Axis for T {}

/// A chart's drawing context on axes `X` × `Y`.
type Plot<'a, DB, X, Y> = ChartContext<'a, DB, Cartesian2d<X, Y>>;

/// The dashed horizontal reference lines, each with its legend entry.
fn draw_reference_lines<'a, DB, X: Axis, Y: Axis>(
    ctx: &mut Plot<'a, DB, X, Y>,
    chart: &Chart,
    (x0, x1): (f64, f64),
) -> Result<()>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
{
    for (y, label) in &chart.hlines {
        let c = RGBColor(90, 90, 90);
        ctx.draw_series(DashedLineSeries::new(
            vec![(x0, *y), (x1, *y)],
            6,
            4,
            c.stroke_width(1),
        ))
        .map_err(map_err)?
        .label(label.as_str())
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
    }
    Ok(())
}

/// The reference lines, then the series, each with its legend entry, on
/// any linear or logarithmic axes; then the legend.
fn draw_lines_and_series<'a, DB, X: Axis, Y: Axis>(
    ctx: &mut Plot<'a, DB, X, Y>,
    chart: &Chart,
    x_range: (f64, f64),
) -> Result<()>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
{
    draw_reference_lines(ctx, chart, x_range)?;
    for s in &chart.series {
        let c = color(s.color);
        match s.style {
            Style::Line => {
                ctx.draw_series(LineSeries::new(s.points.iter().copied(), c.stroke_width(2)))
                    .map_err(map_err)?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                    });
                ctx.draw_series(s.points.iter().map(|&p| Circle::new(p, 3, c.filled())))
                    .map_err(map_err)?;
            }
            Style::Points => {
                ctx.draw_series(s.points.iter().map(|&p| Circle::new(p, 7, c.filled())))
                    .map_err(map_err)?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| Circle::new((x + 10, y), 5, c.filled()));
            }
            Style::Markers => {
                ctx.draw_series(
                    s.points
                        .iter()
                        .map(|&p| Cross::new(p, 6, c.stroke_width(2))),
                )
                .map_err(map_err)?
                .label(s.label.as_str())
                .legend(move |(x, y)| Cross::new((x + 10, y), 5, c.stroke_width(2)));
            }
        }
    }
    ctx.configure_series_labels()
        .label_font(("sans-serif", 13))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()
        .map_err(map_err)?;
    Ok(())
}

/// The footnotes, one line each, under the plot.
fn draw_footnotes<DB: DrawingBackend>(notes: &DrawingArea<DB, Shift>, chart: &Chart) -> Result<()>
where
    DB::ErrorType: 'static,
{
    for (k, line) in chart.footnotes.iter().enumerate() {
        notes
            .draw_text(
                line,
                &("sans-serif", 13).into_text_style(notes),
                (16, 2 + 18 * k as i32),
            )
            .map_err(map_err)?;
    }
    Ok(())
}

/// Draws one chart: axes, reference lines, series, legend and footnotes.
/// plotters gives each of the four axis combinations (linear or log in x
/// and y) its own coordinate type, so the mesh is configured in a macro
/// expanded once per combination; the rest is generic.
fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, chart: &Chart) -> Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(map_err)?;
    let foot = 18 * chart.footnotes.len() as i32;
    let (plot_area, notes) = root.split_vertically(root.dim_in_pixel().1 as i32 - foot - 4);
    let ((x0, x1), (y0, y1)) = axis_ranges(chart);
    let fx = x_tick_label(chart);
    let log_y = chart.log_y;
    let fy = move |v: &f64| label(*v, log_y);
    macro_rules! body {
        ($ctx:expr) => {{
            let mut ctx = $ctx;
            let mut mesh = ctx.configure_mesh();
            if !chart.x_categories.is_empty() {
                mesh.x_labels(2 * chart.x_categories.len() + 1);
            }
            mesh.x_label_formatter(&fx)
                .y_label_formatter(&fy)
                .x_desc(chart.x_label.as_str())
                .y_desc(chart.y_label.as_str())
                .label_style(("sans-serif", 14))
                .axis_desc_style(("sans-serif", 16))
                .draw()
                .map_err(map_err)?;
            draw_lines_and_series(&mut ctx, chart, (x0, x1))?;
        }};
    }
    let mut builder = ChartBuilder::on(&plot_area);
    builder
        .caption(chart.title.as_str(), ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(72);
    match (chart.log_x, chart.log_y) {
        (true, true) => body!(builder
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(map_err)?),
        (true, false) => body!(builder
            .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
            .map_err(map_err)?),
        (false, true) => body!(builder
            .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
            .map_err(map_err)?),
        (false, false) => body!(builder
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(map_err)?),
    }
    draw_footnotes(&notes, chart)?;
    root.present().map_err(map_err)?;
    Ok(())
}

/// Writes `<dir>/<stem>.svg` and `<dir>/<stem>.png` (900 × 600 plus footnotes).
pub fn write(dir: &Path, stem: &str, chart: &Chart) -> Result<()> {
    fonts()?;
    std::fs::create_dir_all(dir).map_err(|e| Error::Io(format!("{}: {e}", dir.display())))?;
    let size = (900u32, 600u32 + 18 * chart.footnotes.len() as u32);
    let svg = dir.join(format!("{stem}.svg"));
    draw(SVGBackend::new(&svg, size).into_drawing_area(), chart)?;
    let png = dir.join(format!("{stem}.png"));
    draw(BitMapBackend::new(&png, size).into_drawing_area(), chart)?;
    Ok(())
}
