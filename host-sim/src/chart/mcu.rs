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
use super::style::{
    backend_shape, draw_axes, draw_legend, draw_line, draw_markers, drawing_err, log_range,
    svg_string, variant_color, ERROR_FLOOR_MM, FONT, FRONT_COLOR,
};
use crate::validate::ours::{Backend, Variant};

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

/// Renders the chart as SVG.
pub fn svg(points: &[McuPoint]) -> Result<String, ChartError> {
    svg_string((1100, 760), |root| {
        let (x0, x1) = log_range(points.iter().map(|p| xy(p).0));
        // Linear instructions axis from 0, with room above the points for the legend.
        let y1 = points.iter().map(|p| p.instructions).fold(100.0, f64::max) * 1.6;
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "MCU twin: instructions per step (Cortex-M4F, QEMU -icount) vs accuracy on the paper scene; \
                     errors < {ERROR_FLOOR_MM:.0e} mm drawn at {ERROR_FLOOR_MM:.0e} mm"
                ),
                (FONT, 16),
            )
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
            Some("Pareto front of the rolling step"),
        )?;
        for p in points {
            let color = variant_color(p.variant.method, p.variant.backend);
            let (style, label) = match p.kind {
                Kind::Rolling => (color.filled(), format!("{} rolling step", p.variant.name())),
                Kind::ContactStep => (
                    color.mix(0.4).filled(),
                    format!("{} full contact step ({})", p.variant.name(), p.name),
                ),
            };
            draw_markers(
                &mut chart,
                &[xy(p)],
                backend_shape(p.variant.backend),
                style,
                Some(&label),
            )?;
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight, 12)?;
        Ok(())
    })
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
