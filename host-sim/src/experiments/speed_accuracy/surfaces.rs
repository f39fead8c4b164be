//! The curved-surface validation chart: each surface's contact-point error against the
//! Montana-form RK45 reference along `host-sim validate`'s 10 s roll-and-spin motion (Fast backend,
//! exact method), object point solid, fingertip point thin, log error axis.

use crate::error::ChartError;
use plotters::prelude::*;

use crate::chart::style::{
    draw_axes, draw_line, draw_side_legend, drawing_err, log_range, on_white, split_for_legend,
    svg_string, Entry, Key, ERROR_FLOOR_MM, FONT, SURFACE_COLORS,
};
use crate::experiments::validate::surfaces::{
    SurfaceErrors, DURATION_S, FINGER_R, OBJECT_R, RATE_HZ,
};

/// At most this many points per line (the run has 10 001 samples; every k-th is drawn, and the
/// largest error of each stride, so no peak is lost).
const MAX_POINTS: usize = 1_000;

/// A polyline: (time s, error mm) points.
type Line = Vec<(f64, f64)>;

/// The line of `v` against `t`: per stride, the largest value at the stride's first time, clamped to
/// the chart's error floor.
pub fn decimated(t: &[f64], v: &[f64]) -> Line {
    let stride = v.len().div_ceil(MAX_POINTS).max(1);
    t.chunks(stride)
        .zip(v.chunks(stride))
        .map(|(tc, vc)| {
            let worst = vc.iter().copied().fold(0.0, f64::max);
            (tc[0], worst.max(ERROR_FLOOR_MM))
        })
        .collect()
}

/// Renders the chart as SVG.
pub fn svg(series: &[SurfaceErrors]) -> Result<String, ChartError> {
    svg_string((1200, 700), |root| {
        let lines: Vec<(&SurfaceErrors, Line, Line)> = series
            .iter()
            .map(|e| {
                (
                    e,
                    decimated(&e.t_s, &e.object_mm),
                    decimated(&e.t_s, &e.finger_mm),
                )
            })
            .collect();
        let (y0, y1) = log_range(
            lines
                .iter()
                .flat_map(|(_, o, f)| o.iter().chain(f.iter()).map(|p| p.1)),
        );
        let root = root
            .titled(
                &format!(
                    "How far does our rolling drift from the Montana-form RK45 reference (rtol 1e-12) on each surface? \
                     {DURATION_S} s at {RATE_HZ} Hz, fingertip {} mm, object {} mm, exact, Fast backend",
                    FINGER_R * 1e3,
                    OBJECT_R * 1e3
                ),
                (FONT, 15),
            )
            .map_err(drawing_err)?;
        let entries: Vec<Entry> = lines
            .iter()
            .enumerate()
            .flat_map(|(i, (e, _, _))| {
                let color = SURFACE_COLORS[i % SURFACE_COLORS.len()];
                [
                    Entry {
                        label: format!("{}: object point", e.surface),
                        key: Key::Line(color, None),
                    },
                    Entry {
                        label: format!("{}: fingertip point", e.surface),
                        key: Key::Line(on_white(color, 0.6), None),
                    },
                ]
            })
            .collect();
        let (root, legend) = split_for_legend(&root, &entries, 13);
        if let Some(l) = &legend {
            draw_side_legend(&l.margin(16, 0, 0, 0), &entries, 13)?;
        }
        let mut chart = ChartBuilder::on(&root)
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..DURATION_S, (y0..y1).log_scale())
            .map_err(drawing_err)?;
        draw_axes(
            &mut chart,
            "time (s)",
            &format!("contact-point error (mm, log; below {ERROR_FLOOR_MM:.0e} drawn at it)"),
        )?;
        for (i, (_, object, finger)) in lines.iter().enumerate() {
            let color = SURFACE_COLORS[i % SURFACE_COLORS.len()];
            draw_line(&mut chart, object, color.stroke_width(2), None)?;
            draw_line(&mut chart, finger, color.mix(0.6).stroke_width(1), None)?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Decimation keeps each stride's worst value (a single spike survives) and clamps zeros to
    /// the floor.
    #[test]
    fn decimation_keeps_peaks_and_clamps_zeros() {
        let n = 10_001;
        let t: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3).collect();
        let mut v = vec![0.0; n];
        v[5_003] = 2e-4;
        let d = decimated(&t, &v);
        assert!(d.len() <= MAX_POINTS);
        assert_eq!(d.iter().filter(|p| p.1 == 2e-4).count(), 1);
        assert!(d.iter().all(|p| p.1 >= ERROR_FLOOR_MM));
        assert_eq!(d[0], (0.0, ERROR_FLOOR_MM));
    }

    #[test]
    fn every_surface_has_its_legend_entries() {
        let e = |name| SurfaceErrors {
            surface: name,
            t_s: vec![0.0, 1.0, 2.0],
            object_mm: vec![0.0, 1e-5, 3e-5],
            finger_mm: vec![0.0, 2e-6, 4e-6],
        };
        let svg = svg(&[e("plane"), e("sphere"), e("bowl"), e("cylinder")]).unwrap();
        for name in ["plane", "sphere", "bowl", "cylinder"] {
            assert!(svg.contains(&format!("{name}: object point")), "{name}");
            assert!(svg.contains(&format!("{name}: fingertip point")), "{name}");
        }
        assert!(svg.contains("time (s)"));
    }
}
