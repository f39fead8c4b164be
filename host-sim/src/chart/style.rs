//! The one chart style of every SVG host-sim writes: the palette (series, methods × backends,
//! surfaces, contact states), the font, marker shapes, the legend box, number formats on the axes,
//! log-axis ranges, and rendering a figure into an SVG written atomically. The chart kinds built on
//! it: [`super::lines`] (line charts in panels, with state bands and equal axes), [`super::bars`],
//! [`super::heatmap`], and the `chart` command's own plots.

use crate::error::ChartError;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::{CoordTranslate, Shift};
use plotters::prelude::*;
use plotters::style::full_palette::{
    BLUE_300, BLUE_600, BLUE_900, DEEPORANGE_400, GREEN_400, GREEN_700, GREEN_900, GREY_500,
    ORANGE_700, PURPLE, RED_900,
};
use softfinger_core::contact::decompose::Method;
use softfinger_core::contact::state::ContactState;
use std::io::Write;
use std::path::Path;

use crate::atomic_file::AtomicFile;
use crate::sim::backend::Backend;

/// The font family of every label (the SVG leaves the glyphs to the viewer).
pub const FONT: &str = "sans-serif";

/// A drawing area of an SVG figure.
pub type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// The series palette: distinct, readable on white (blue, orange, green, red, purple, brown).
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// What the contact was doing over a stretch of time, as the charts colour it: the core's three
/// states, with `Broken` split into before the first touch and after a release.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactPhase {
    /// Broken before the first touch of the scene: the fingertip has not touched yet.
    NoContact,
    /// Rolling without slip.
    Rolling,
    /// Sliding on kinetic friction.
    Sliding,
    /// Broken after a touch: the contact was released or lost.
    Broken,
}

impl ContactPhase {
    /// The phase of a tick in `state`, `touched` telling whether any earlier tick was in contact.
    pub fn of(state: ContactState, touched: bool) -> ContactPhase {
        match state {
            ContactState::Rolling => ContactPhase::Rolling,
            ContactState::Sliding => ContactPhase::Sliding,
            ContactState::Broken if touched => ContactPhase::Broken,
            ContactState::Broken => ContactPhase::NoContact,
        }
    }

    /// Legend text.
    pub fn label(self) -> &'static str {
        match self {
            ContactPhase::NoContact => "no contact yet",
            ContactPhase::Rolling => "rolling",
            ContactPhase::Sliding => "sliding",
            ContactPhase::Broken => "broken (released)",
        }
    }

    /// Its colour, for bands (drawn pale) and path segments alike.
    pub fn color(self) -> RGBColor {
        match self {
            ContactPhase::NoContact => RGBColor(150, 150, 150),
            ContactPhase::Rolling => PALETTE[2],
            ContactPhase::Sliding => PALETTE[1],
            ContactPhase::Broken => PALETTE[3],
        }
    }
}

/// The colour of a contact state (a broken tick counts as released).
pub fn state_color(s: ContactState) -> RGBColor {
    ContactPhase::of(s, true).color()
}

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

/// The colour of a method (its libm shade): exact blue, rpy green, paper-verbatim red.
pub fn method_color(m: Method) -> RGBColor {
    variant_color(m, Backend::Libm)
}

/// Colour of the classical runs.
pub const RK45_COLORS: [RGBColor; 2] = [BLACK, PURPLE];
/// Colour of the Pareto staircase.
pub const FRONT_COLOR: RGBColor = GREY_500;

/// One colour per surface (plane, sphere, bowl, cylinder), in that order.
pub const SURFACE_COLORS: [RGBColor; 4] = [PALETTE[0], PALETTE[3], PALETTE[2], PALETTE[1]];

/// Draws `pts` with one marker shape and style, optionally with a legend entry.
pub fn draw_markers<'a, 'b: 'a, CT>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, CT>,
    pts: &[(f64, f64)],
    shape: Shape,
    style: ShapeStyle,
    label: Option<&str>,
) -> Result<(), ChartError>
where
    CT: CoordTranslate<From = (f64, f64)>,
{
    let offsets = shape.offsets(4);
    let anno = chart
        .draw_series(
            pts.iter()
                .map(|&p| EmptyElement::at(p) + Polygon::new(offsets.clone(), style)),
        )
        .map_err(drawing_err)?;
    if let Some(label) = label {
        anno.label(label)
            .legend(move |(x, y)| EmptyElement::at((x, y)) + Polygon::new(offsets.clone(), style));
    }
    Ok(())
}

/// Draws the axes (the one axis style of every x-y chart): tick labels in [`fmt_num`], the axis
/// names, a light grid. On an axis through zero, a tick within rounding of zero reads `0`.
pub fn draw_axes<'a, 'b: 'a, X, Y>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>,
    x_desc: &str,
    y_desc: &str,
) -> Result<(), ChartError>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let (x, y) = (chart.x_range(), chart.y_range());
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&|v| tick_label(*v, (x.start, x.end)))
        .y_label_formatter(&|v| tick_label(*v, (y.start, y.end)))
        .label_style((FONT, 13))
        .axis_desc_style((FONT, 15))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(drawing_err)
}

/// Draws the legend box (the one legend style of every chart): white, 85 % opaque, black border.
pub fn draw_legend<'a, 'b: 'a, CT>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, CT>,
    position: SeriesLabelPosition,
    font_size: u32,
) -> Result<(), ChartError>
where
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, font_size))
        .draw()
        .map_err(drawing_err)
}

/// Width (px) of a legend of `labels` at `font_size` beside a plot: the longest label at about
/// 0.55 of the font size per character, plus the key and the box's padding.
pub fn legend_width<'s>(labels: impl IntoIterator<Item = &'s str>, font_size: u32) -> u32 {
    let chars = labels
        .into_iter()
        .map(|l| l.chars().count())
        .max()
        .unwrap_or(0);
    if chars == 0 {
        return 0;
    }
    (chars as f64 * 0.55 * f64::from(font_size)).ceil() as u32 + 56
}

/// `c` drawn at opacity `alpha` on white, as one opaque colour (for a legend key of a pale line).
pub fn on_white(c: RGBColor, alpha: f64) -> RGBColor {
    let m = |v: u8| (f64::from(v) * alpha + 255.0 * (1.0 - alpha)).round() as u8;
    RGBColor(m(c.0), m(c.1), m(c.2))
}

/// What a legend entry's key looks like.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Key {
    /// A pale filled box (a band behind the data).
    Band(RGBColor),
    /// A filled box (a bar).
    Fill(RGBColor),
    /// A line, solid or dashed (`Some((dash, gap))`, px).
    Line(RGBColor, Option<(u32, u32)>),
    /// A marker of that shape.
    Marker(RGBColor, Shape),
    /// A line with a marker on it.
    LineMarker(RGBColor, Shape),
}

/// One legend entry.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    pub label: String,
    pub key: Key,
}

/// Pixel height of one legend row at `font_size`.
fn legend_row(font_size: u32) -> i32 {
    font_size as i32 + 6
}

/// Draws `entries` as a legend in their own `area` (beside the plot, off the data): a key and
/// its label per row from the top, in a white box with a black border; returns the legend's
/// height (px).
pub fn draw_side_legend(area: &Area, entries: &[Entry], font_size: u32) -> Result<i32, ChartError> {
    if entries.is_empty() {
        return Ok(0);
    }
    let row = legend_row(font_size);
    let (w, _) = area.dim_in_pixel();
    let h = row * entries.len() as i32 + 10;
    area.draw(&Rectangle::new(
        [(0, 0), (w as i32 - 4, h)],
        ShapeStyle::from(&BLACK).stroke_width(1),
    ))
    .map_err(drawing_err)?;
    for (k, e) in entries.iter().enumerate() {
        let y = 5 + row * k as i32 + row / 2;
        let (x0, x1) = (8, 28);
        match e.key {
            Key::Band(c) => area
                .draw(&Rectangle::new(
                    [(x0, y - 6), (x1, y + 6)],
                    c.mix(0.45).filled(),
                ))
                .map_err(drawing_err)?,
            Key::Fill(c) => area
                .draw(&Rectangle::new([(x0, y - 6), (x1, y + 6)], c.filled()))
                .map_err(drawing_err)?,
            Key::Line(c, dash) => {
                let st = ShapeStyle::from(&c).stroke_width(2);
                match dash {
                    None => area
                        .draw(&PathElement::new(vec![(x0, y), (x1, y)], st))
                        .map_err(drawing_err)?,
                    Some((d, g)) => {
                        let mut x = x0;
                        while x < x1 {
                            let e = (x + d as i32).min(x1);
                            area.draw(&PathElement::new(vec![(x, y), (e, y)], st))
                                .map_err(drawing_err)?;
                            x = e + g as i32;
                        }
                    }
                }
            }
            Key::Marker(c, shape) | Key::LineMarker(c, shape) => {
                if matches!(e.key, Key::LineMarker(..)) {
                    area.draw(&PathElement::new(
                        vec![(x0, y), (x1, y)],
                        ShapeStyle::from(&c).stroke_width(2),
                    ))
                    .map_err(drawing_err)?;
                }
                area.draw(
                    &(EmptyElement::at(((x0 + x1) / 2, y))
                        + Polygon::new(shape.offsets(4), c.filled())),
                )
                .map_err(drawing_err)?;
            }
        }
        area.draw(&Text::new(
            e.label.clone(),
            (x1 + 8, y - font_size as i32 / 2 - 1),
            (FONT, font_size).into_font(),
        ))
        .map_err(drawing_err)?;
    }
    Ok(h)
}

/// Splits `area` into the plot (left) and a legend column of [`legend_width`] of `entries`
/// (right; empty when there are no entries).
pub fn split_for_legend<'a>(
    area: &Area<'a>,
    entries: &[Entry],
    font_size: u32,
) -> (Area<'a>, Option<Area<'a>>) {
    let lw = legend_width(entries.iter().map(|e| e.label.as_str()), font_size);
    let (w, h) = area.dim_in_pixel();
    if lw == 0 {
        return (area.clone(), None);
    }
    if f64::from(lw) > 0.35 * f64::from(w) {
        // Too wide beside the plot: below it, across the panel.
        let lh = (legend_row(font_size) * entries.len() as i32 + 14) as u32;
        if lh + 150 >= h {
            return (area.clone(), None);
        }
        let (plot, legend) = area.split_vertically(h - lh);
        return (plot, Some(legend.margin(4, 0, 80, 0)));
    }
    let (plot, legend) = area.split_horizontally(w - lw);
    (plot, Some(legend.margin(8, 0, 4, 0)))
}

/// Draws a polyline, optionally with a legend entry.
pub fn draw_line<'a, 'b: 'a, CT>(
    chart: &mut ChartContext<'a, SVGBackend<'b>, CT>,
    pts: &[(f64, f64)],
    style: ShapeStyle,
    label: Option<&str>,
) -> Result<(), ChartError>
where
    CT: CoordTranslate<From = (f64, f64)>,
{
    let anno = chart
        .draw_series(LineSeries::new(pts.iter().copied(), style))
        .map_err(drawing_err)?;
    if let Some(label) = label {
        anno.label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x - 10, y), (x + 10, y)], style));
    }
    Ok(())
}

/// `(lo, hi)` covering the finite `values` with 5 % margin (at least `min_pad`), and `top` (a
/// fraction of the span) more above, e.g. room for a legend; `(-1, 1)` when there are none.
pub fn linear_range(values: impl IntoIterator<Item = f64>, min_pad: f64, top: f64) -> (f64, f64) {
    let (lo, hi) = values
        .into_iter()
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    if lo > hi {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(min_pad);
    (lo - pad, hi + pad + (hi - lo) * top)
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

/// An axis tick label, short: powers of ten as `1e-7`, others with at most 3 decimals (`0.01`,
/// `100`, `2000`, `1e5`).
pub fn fmt_num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if (1e-2..1e4).contains(&v.abs()) {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.1e}").replace(".0e", "e")
    }
}

/// [`fmt_num`] of a tick on an axis spanning `range`: `0` for a tick within 1e-9 of the span of
/// zero when the axis holds zero (ticks there are computed in floating point, e.g. -1.1e-16).
pub fn tick_label(v: f64, (lo, hi): (f64, f64)) -> String {
    if lo <= 0.0 && 0.0 <= hi && v.abs() < 1e-9 * (hi - lo) {
        "0".into()
    } else {
        fmt_num(v)
    }
}

/// A plotters drawing error as this crate's error text.
pub fn drawing_err<E: std::fmt::Display>(e: E) -> ChartError {
    ChartError(format!("drawing failed: {e}"))
}

/// Renders a `size` (px) figure on white with `draw` and writes it to `path` atomically; errors
/// name the file.
pub fn render_svg(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&Area) -> Result<(), ChartError>,
) -> Result<(), ChartError> {
    let svg = svg_string(size, draw).map_err(|e| format!("{}: {e}", path.display()))?;
    write_svg(path, &svg)
}

/// Renders a `size` (px) figure on white with `draw` into an SVG string.
pub fn svg_string(
    size: (u32, u32),
    draw: impl FnOnce(&Area) -> Result<(), ChartError>,
) -> Result<String, ChartError> {
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing_err)?;
        draw(&root)?;
        root.present().map_err(drawing_err)?;
    }
    Ok(buf)
}

/// Writes `svg` to `path` atomically.
pub fn write_svg(path: &Path, svg: &str) -> Result<(), ChartError> {
    let fail = |e: std::io::Error| ChartError(format!("{}: {e}", path.display()));
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
    fn a_tick_near_zero_reads_zero_only_on_an_axis_through_zero() {
        assert_eq!(tick_label(-1.1e-16, (-0.5, 0.5)), "0");
        // The threshold, 1e-9 of the span (1 here), just below and just above.
        assert_eq!(tick_label(0.9e-9, (-0.5, 0.5)), "0");
        assert_eq!(tick_label(1.1e-9, (-0.5, 0.5)), "1.1e-9");
        assert_eq!(tick_label(1e-16, (1e-16, 100.0)), "1e-16");
        assert_eq!(tick_label(0.25, (-0.5, 0.5)), "0.25");
    }

    #[test]
    fn linear_range_pads_and_leaves_room_on_top() {
        assert_eq!(linear_range([0.0, 10.0, f64::NAN], 0.1, 0.0), (-0.5, 10.5));
        assert_eq!(linear_range([0.0, 10.0], 0.1, 0.3), (-0.5, 13.5));
        // A single value: the minimum pad either side.
        assert_eq!(linear_range([2.0], 0.25, 0.0), (1.75, 2.25));
        assert_eq!(linear_range([], 0.1, 0.0), (-1.0, 1.0));
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(fmt_num(99.999_999_999_97), "100");
        assert_eq!(fmt_num(1.000_000_000_1), "1");
        assert_eq!(fmt_num(0.010_000_000_02), "0.01");
        assert_eq!(fmt_num(1e-6), "1e-6");
        assert_eq!(fmt_num(1e-7), "1e-7");
        assert_eq!(fmt_num(1e5), "1e5");
        assert_eq!(fmt_num(0.5), "0.5");
        assert_eq!(fmt_num(-2.25), "-2.25");
        assert_eq!(fmt_num(2000.0), "2000");
        assert_eq!(fmt_num(0.0), "0");
    }

    #[test]
    fn broken_before_the_first_touch_is_no_contact() {
        assert_eq!(
            ContactPhase::of(ContactState::Broken, false),
            ContactPhase::NoContact
        );
        assert_eq!(
            ContactPhase::of(ContactState::Broken, true),
            ContactPhase::Broken
        );
        assert_eq!(
            ContactPhase::of(ContactState::Sliding, false),
            ContactPhase::Sliding
        );
        assert_ne!(ContactPhase::Rolling.color(), ContactPhase::Sliding.color());
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
