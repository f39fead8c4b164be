//! The MCU twin of the speed–accuracy chart: instructions per step on an emulated Cortex-M4F (from
//! `scripts/mcu-bench --json`) against the largest contact-path error on the paper's scene.
//!
//! Input: a JSON array of `{"name", "backend", "instructions"}`. Used entries: `rolling_plane_exact`,
//! `rolling_plane_rpy`, `rolling_plane_paper` (the rolling step on the plane, what `validate` measures) and
//! `contact_step` (exact), `contact_step_rpy` (the full contact step: rolling, spin torque, state machine,
//! proxy coupling). Backends `libm`, `fast`, `micromath`. Other entries are ignored.

use crate::error::ChartError;
use plotters::prelude::*;
use serde::Deserialize;
use softfinger_core::contact::decompose::Method;
use std::path::Path;

use super::pareto;
use crate::chart::style::{
    backend_shape, draw_axes, draw_line, draw_markers, draw_side_legend, drawing_err, log_range,
    split_for_legend, svg_string, variant_color, Entry as LegendEntry, Key, ERROR_FLOOR_MM, FONT,
    FRONT_COLOR,
};
use crate::experiments::validate::ours::{Backend, Variant};

/// One entry of the mcu-bench JSON.
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct Entry {
    /// Benchmark name.
    pub name: String,
    /// Math backend name.
    pub backend: String,
    /// Instructions per call.
    pub instructions: f64,
}

/// What an MCU figure measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// The rolling step on the plane (`rolling_plane_<method>`).
    Rolling,
    /// The full contact step (`contact_step`, `contact_step_rpy`).
    ContactStep,
}

/// A point: a variant, what was measured, instructions per call, error (mm, paper scene).
#[derive(Clone, Debug, PartialEq)]
pub struct McuPoint {
    /// Method × backend.
    pub variant: Variant,
    /// Which benchmark.
    pub kind: Kind,
    /// The benchmark's name in the JSON.
    pub name: String,
    /// Instructions per call.
    pub instructions: f64,
    /// Largest contact-path error of the variant on the paper's scene, mm.
    pub error_mm: f64,
}

/// Reads the mcu-bench JSON.
pub fn read(path: &Path) -> Result<Vec<Entry>, ChartError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| {
        ChartError(format!(
            "{}: not an mcu-bench JSON array of {{name, backend, instructions}}: {e}",
            path.display()
        ))
    })
}

/// The benchmark name → (method, kind) mapping.
pub fn classify(name: &str) -> Option<(Method, Kind)> {
    Some(match name {
        "rolling_plane_exact" => (Method::Exact, Kind::Rolling),
        "rolling_plane_rpy" => (Method::Rpy, Kind::Rolling),
        "rolling_plane_paper" => (Method::PaperVerbatim, Kind::Rolling),
        "contact_step" => (Method::Exact, Kind::ContactStep),
        "contact_step_rpy" => (Method::Rpy, Kind::ContactStep),
        _ => return None,
    })
}

fn backend(name: &str) -> Option<Backend> {
    Backend::ALL.into_iter().find(|b| b.name() == name)
}

/// The entries that map to a variant with a known error (`error_mm` of a variant on the paper scene).
pub fn points(entries: &[Entry], error_mm: impl Fn(Variant) -> Option<f64>) -> Vec<McuPoint> {
    entries
        .iter()
        .filter_map(|e| {
            let (method, kind) = classify(&e.name)?;
            let variant = Variant {
                method,
                backend: backend(&e.backend)?,
            };
            Some(McuPoint {
                variant,
                kind,
                name: e.name.clone(),
                instructions: e.instructions,
                error_mm: error_mm(variant)?,
            })
        })
        .collect()
}

/// `(error clamped to the floor, instructions)`.
pub fn xy(p: &McuPoint) -> (f64, f64) {
    (p.error_mm.max(ERROR_FLOOR_MM), p.instructions)
}

/// Indices of the Pareto front of the rolling-step points (fewest instructions, smallest error).
pub fn front(points: &[McuPoint]) -> Vec<usize> {
    let xy: Vec<(f64, f64)> = points
        .iter()
        .map(|p| match p.kind {
            Kind::Rolling => xy(p),
            Kind::ContactStep => (f64::NAN, f64::NAN),
        })
        .collect();
    pareto::front(&xy)
}

/// The legend label of a point.
fn label(p: &McuPoint) -> String {
    match p.kind {
        Kind::Rolling => format!("{} rolling step", p.variant.name()),
        Kind::ContactStep => format!("{} full contact step ({})", p.variant.name(), p.name),
    }
}

/// Renders the chart as SVG, the legend beside the plot (off the data).
pub fn svg(points: &[McuPoint]) -> Result<String, ChartError> {
    svg_string((1100, 1000), |root| {
        let (x0, x1) = log_range(points.iter().map(|p| xy(p).0));
        // Linear instructions axis from 0, sized to the data.
        let y1 = points.iter().map(|p| p.instructions).fold(100.0, f64::max) * 1.12;
        let mut entries = vec![LegendEntry {
            label: "Pareto front of the rolling step".into(),
            key: Key::Line(FRONT_COLOR, None),
        }];
        for p in points {
            let color = variant_color(p.variant.method, p.variant.backend);
            let color = match p.kind {
                Kind::Rolling => color,
                Kind::ContactStep => pale(color),
            };
            entries.push(LegendEntry {
                label: label(p),
                key: Key::Marker(color, backend_shape(p.variant.backend)),
            });
        }
        let root = root
            .titled(
                &format!(
                    "Which step costs least on the MCU for its accuracy? Instructions per step \
                     (Cortex-M4F, QEMU -icount) vs error on the paper's scene \
                     (errors < {ERROR_FLOOR_MM:.0e} mm drawn at {ERROR_FLOOR_MM:.0e} mm)"
                ),
                (FONT, 15),
            )
            .map_err(drawing_err)?;
        let (plot, legend) = split_for_legend(&root, &entries, 12);
        if let Some(l) = &legend {
            draw_side_legend(&l.margin(10, 0, 0, 0), &entries, 12)?;
        }
        let mut chart = ChartBuilder::on(&plot)
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d((x0..x1).log_scale(), 0.0..y1)
            .map_err(drawing_err)?;
        draw_axes(
            &mut chart,
            "max contact-path error on the paper's scene (mm, log)",
            "instructions per step",
        )?;
        let front_xy: Vec<(f64, f64)> = front(points).iter().map(|&i| xy(&points[i])).collect();
        draw_line(
            &mut chart,
            &pareto::staircase(&front_xy, x1),
            FRONT_COLOR.mix(0.45).stroke_width(9),
            None,
        )?;
        for p in points {
            let color = variant_color(p.variant.method, p.variant.backend);
            let style = match p.kind {
                Kind::Rolling => color.filled(),
                Kind::ContactStep => pale(color).filled(),
            };
            draw_markers(
                &mut chart,
                &[xy(p)],
                backend_shape(p.variant.backend),
                style,
                None,
            )?;
        }
        Ok(())
    })
}

/// The colour at 40 % over white (the full contact step's markers).
fn pale(c: RGBColor) -> RGBColor {
    let m = |v: u8| (255.0 - 0.4 * (255.0 - f64::from(v))).round() as u8;
    RGBColor(m(c.0), m(c.1), m(c.2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_backends_map_to_variants() {
        let json = r#"[
            {"name": "rolling_plane_exact", "backend": "fast", "instructions": 412},
            {"name": "contact_step_rpy", "backend": "micromath", "instructions": 832},
            {"name": "sin", "backend": "libm", "instructions": 1240},
            {"name": "state_machine", "backend": "-", "instructions": 95},
            {"name": "rolling_plane_paper", "backend": "other", "instructions": 1}
        ]"#;
        let entries: Vec<Entry> = serde_json::from_str(json).unwrap();
        let pts = points(&entries, |v| {
            Some(if v.method == Method::Exact { 1e-6 } else { 0.5 })
        });
        assert_eq!(pts.len(), 2);
        assert_eq!(
            pts[0].variant,
            Variant {
                method: Method::Exact,
                backend: Backend::Fast
            }
        );
        assert_eq!(
            (pts[0].kind, pts[0].instructions, pts[0].error_mm),
            (Kind::Rolling, 412.0, 1e-6)
        );
        assert_eq!(pts[1].kind, Kind::ContactStep);
        assert_eq!(pts[1].variant.method, Method::Rpy);
        // Contact steps are not on the rolling-step front.
        assert_eq!(front(&pts), vec![0]);
    }
}
