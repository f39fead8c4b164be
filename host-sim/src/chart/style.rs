//! Shared drawing helpers: marker shapes, colours per method and backend, log-axis ranges, and writing an
//! SVG atomically.

use plotters::coord::CoordTranslate;
use plotters::prelude::*;
use plotters::style::full_palette::{
    BLUE_300, BLUE_600, BLUE_700, BLUE_900, DEEPORANGE_400, GREEN_400, GREEN_700, GREEN_900,
    GREY_500, ORANGE_700, PURPLE, RED_700, RED_900,
};
use softfinger_core::contact::decompose::Method;
use std::io::Write;
use std::path::Path;

use crate::atomic_file::AtomicFile;
use crate::validate::ours::Backend;

/// Errors below this (mm) are drawn at it on log axes (exact zeros cannot be drawn); charts say so.
pub const ERROR_FLOOR_MM: f64 = 1e-13;

/// A marker outline.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// Round (12-gon).
    Circle,
    /// Upward triangle.
    Triangle,
    /// Axis-aligned square.
    Square,
    /// Square on its corner.
    Diamond,
}

impl Shape {
    /// Vertex offsets in pixels around the marker's centre, `size` its half-width.
    pub fn offsets(self, size: i32) -> Vec<(i32, i32)> {
        let s = size as f64;
        let ring = |n: usize, phase: f64, r: f64| -> Vec<(i32, i32)> {
            (0..n)
                .map(|k| {
                    let a = phase + std::f64::consts::TAU * k as f64 / n as f64;
                    ((r * a.cos()).round() as i32, (r * a.sin()).round() as i32)
                })
                .collect()
        };
        match self {
            Shape::Circle => ring(12, 0.0, s),
            Shape::Triangle => ring(3, -std::f64::consts::FRAC_PI_2, s * 1.3),
            Shape::Square => ring(4, std::f64::consts::FRAC_PI_4, s * 1.2),
            Shape::Diamond => ring(4, 0.0, s * 1.4),
        }
    }
}

/// The marker used for a math backend: libm circle, fast triangle, micromath square.
pub fn backend_shape(b: Backend) -> Shape {
    match b {
        Backend::Libm => Shape::Circle,
        Backend::Fast => Shape::Triangle,
        Backend::Micromath => Shape::Square,
    }
}

/// Colour of a method × backend: blues for exact, greens for rpy, reds for paper-verbatim; the shade
/// tells the backend.
pub fn variant_color(m: Method, b: Backend) -> RGBColor {
    let shades = match m {
        Method::Exact => [BLUE_900, BLUE_600, BLUE_300],
        Method::Rpy => [GREEN_900, GREEN_700, GREEN_400],
        Method::PaperVerbatim => [RED_900, ORANGE_700, DEEPORANGE_400],
    };
    match b {
        Backend::Libm => shades[0],
        Backend::Fast => shades[1],
        Backend::Micromath => shades[2],
    }
}

/// Colour of the classical runs.
pub const RK45_COLORS: [RGBColor; 2] = [BLACK, PURPLE];
/// Colour of the Pareto staircase.
pub const FRONT_COLOR: RGBColor = GREY_500;

/// One colour per surface (plane, sphere, bowl, cylinder), in that order.
pub const SURFACE_COLORS: [RGBColor; 4] = [BLUE_700, RED_700, GREEN_700, ORANGE_700];

/// Draws `pts` with one marker shape and style, optionally with a legend entry.
pub fn draw_markers<'a, 'b: 'a, CT>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, CT>,
    pts: &[(f64, f64)],
    shape: Shape,
    style: ShapeStyle,
    label: Option<&str>,
) -> Result<(), String>
where
    CT: CoordTranslate<From = (f64, f64)>,
{
    let offsets = shape.offsets(4);
    let anno = chart
        .draw_series(
            pts.iter()
                .map(|&p| EmptyElement::at(p) + Polygon::new(offsets.clone(), style)),
        )
        .map_err(|e| format!("drawing: {e:?}"))?;
    if let Some(label) = label {
        anno.label(label)
            .legend(move |(x, y)| EmptyElement::at((x, y)) + Polygon::new(offsets.clone(), style));
    }
    Ok(())
}

/// Draws the legend box in this module's style: white, 85 % opaque, black border.
pub fn draw_legend<'a, 'b: 'a, CT>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, CT>,
    position: SeriesLabelPosition,
    font_size: u32,
) -> Result<(), String>
where
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", font_size))
        .draw()
        .map_err(|e| format!("{e:?}"))
}

/// Draws a polyline, optionally with a legend entry.
pub fn draw_line<'a, 'b: 'a, CT>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, CT>,
    pts: &[(f64, f64)],
    style: ShapeStyle,
    label: Option<&str>,
) -> Result<(), String>
where
    CT: CoordTranslate<From = (f64, f64)>,
{
    let anno = chart
        .draw_series(LineSeries::new(pts.iter().copied(), style))
        .map_err(|e| format!("drawing: {e:?}"))?;
    if let Some(label) = label {
        anno.label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x - 10, y), (x + 10, y)], style));
    }
    Ok(())
}

/// A log-axis range covering `values` (positive, finite ones), widened to whole decades with half a
/// decade of margin; `(1e-1, 1e1)` when there are none.
pub fn log_range(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if hi <= 0.0 {
        return (1e-1, 1e1);
    }
    (
        10f64.powf((lo.log10() - 0.3).floor()),
        10f64.powf((hi.log10() + 0.3).ceil()),
    )
}

/// Tick label of a log axis: `1e-6`, `0.01`, `100`, `1e5`.
pub fn log_label(v: &f64) -> String {
    if (0.999..1e4).contains(v) {
        format!("{v:.0}")
    } else if (0.00999..0.999).contains(v) {
        format!("{}", (v * 100.0).round() / 100.0)
    } else {
        format!("{v:.0e}")
    }
}

/// Writes `svg` to `path` atomically.
pub fn write_svg(path: &Path, svg: &str) -> Result<(), String> {
    let fail = |e: std::io::Error| format!("{}: {e}", path.display());
    let mut f = AtomicFile::create(path).map_err(fail)?;
    f.writer().write_all(svg.as_bytes()).map_err(fail)?;
    f.commit().map_err(fail)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_range_is_whole_decades_with_margin() {
        // 3e-6 … 2e2: log10 −5.52 … 2.30, minus/plus 0.3 → −5.82 … 2.60, floor/ceil → 1e-6 … 1e3.
        let (lo, hi) = log_range([3e-6, 2e2, f64::NAN, 0.0, -1.0]);
        assert!((lo / 1e-6 - 1.0).abs() < 1e-12 && (hi / 1e3 - 1.0).abs() < 1e-12);
        assert_eq!(log_range([]), (1e-1, 1e1));
    }

    #[test]
    fn log_labels_are_short() {
        assert_eq!(log_label(&99.999_999_999_97), "100");
        assert_eq!(log_label(&1.000_000_000_1), "1");
        assert_eq!(log_label(&0.010_000_000_02), "0.01");
        assert_eq!(log_label(&1e-6), "1e-6");
        assert_eq!(log_label(&1e5), "1e5");
    }

    #[test]
    fn marker_shapes_have_their_vertex_counts() {
        assert_eq!(Shape::Circle.offsets(4).len(), 12);
        assert_eq!(Shape::Triangle.offsets(4).len(), 3);
        assert_eq!(Shape::Square.offsets(4).len(), 4);
        // The triangle points up: its first vertex is straight above the centre (screen y down).
        assert_eq!(Shape::Triangle.offsets(4)[0], (0, -5));
    }
}
