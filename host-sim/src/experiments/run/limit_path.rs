//! The rendered (f_t, τn) path of a closed-loop run against the limit surface the contact model
//! uses (`softfinger_core::contact::limit_surface`): each touching tick's rendered force is split along the
//! contact normal into f_N and f_t, and the load is normalised by the model's own static limits at
//! that f_N, x = |f_t|/(μ_s·f_N), y = |τn|/τ_max,s with τ_max,s = (3π/16)·μ_s·f_N·a(f_N) and a(f_N)
//! the model's patch law (computed with the core's own f32 functions, so the limit is exactly the
//! model's). In these coordinates the model's surfaces are fixed curves:
//!
//! - rolling: the static ellipse x² + y² = 1; the state machine leaves rolling when the load is
//!   outside it by the hysteresis margin h, x² + y² > (1 + h)², with a steady normal force;
//! - sliding: the kinetic ellipse, x² + y² = (μ_k/μ_s)², onto which the slip projects the load.
//!
//! `host-sim run` charts the path for a scene that twists while sliding (`limit_surface_path.svg`)
//! with the Hertzian reference curve of `host-sim limit-surface` for comparison.

use super::result::{Row, RunResult};
use crate::chart::style::{
    draw_axes, draw_legend, draw_line, draw_markers, drawing_err, render_svg, state_color, Shape,
    FONT,
};
use crate::error::ChartError;
use crate::sim::closed_loop::ClosedLoopError;
use crate::sim::reference::limit_surface::curve;
use plotters::coord::CoordTranslate;
use plotters::prelude::*;
use softfinger_core::contact::limit_surface::patch_radius;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::spin::torsion_limit;
use softfinger_core::contact::state::ContactState;
use std::path::{Path, PathBuf};

/// Why the load path of a run could not be charted.
#[derive(Debug, thiserror::Error)]
pub enum LimitPathError {
    /// The scene's contact parameters were rejected.
    #[error(transparent)]
    Scene(#[from] ClosedLoopError),
    /// The chart could not be drawn or written.
    #[error(transparent)]
    Chart(#[from] ChartError),
}

/// One touching tick's load, normalised by the model's static limits at its normal force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadPoint {
    pub t_s: f64,
    pub state: ContactState,
    /// Normal force, N.
    pub f_n: f64,
    /// |f_t| / (μ_s·f_N).
    pub x: f64,
    /// |τn| / τ_max,s(f_N).
    pub y: f64,
}

impl LoadPoint {
    /// Distance from the origin in the normalised plane: 1 on the static ellipse.
    pub fn load(&self) -> f64 {
        self.x.hypot(self.y)
    }
}

/// The normalised load of every tick in contact with f_N above the model's force threshold.
pub fn load_path(rows: &[Row], p: &ContactParams) -> Vec<LoadPoint> {
    rows.iter()
        .filter(|r| r.state != ContactState::Broken)
        .filter_map(|r| {
            let f = r.force_n.map(f64::from);
            let n = r.normal.map(f64::from);
            let f_n = f[0] * n[0] + f[1] * n[1] + f[2] * n[2];
            // Also drops a NaN f_N (every comparison with NaN is false).
            if f_n.is_nan() || f_n <= p.tolerances.force_eps_n as f64 {
                return None;
            }
            let f_t = [0, 1, 2].map(|k| f[k] - f_n * n[k]);
            let f_t = (f_t[0] * f_t[0] + f_t[1] * f_t[1] + f_t[2] * f_t[2]).sqrt();
            let a = patch_radius(
                f_n as f32,
                p.patch_radius_m,
                p.patch_ref_force_n,
                p.patch_exponent,
            );
            let tau_max = torsion_limit(p.mu_s, f_n as f32, a) as f64;
            Some(LoadPoint {
                t_s: r.t_s,
                state: r.state,
                f_n,
                x: f_t / (p.mu_s as f64 * f_n),
                y: if tau_max > 0.0 {
                    (r.tau_n_nm as f64).abs() / tau_max
                } else {
                    0.0
                },
            })
        })
        .collect()
}

/// The extremes of a load path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadSummary {
    /// Largest load while rolling (1 = the static ellipse).
    pub max_rolling: f64,
    /// Largest load while sliding.
    pub max_sliding: f64,
    /// Largest |τn|/τ_max,s at any tick (how much of the budget the twist took).
    pub max_twist: f64,
    /// Ticks sliding.
    pub sliding_ticks: usize,
}

pub fn summarize(path: &[LoadPoint]) -> LoadSummary {
    let mut s = LoadSummary {
        max_rolling: 0.0,
        max_sliding: 0.0,
        max_twist: 0.0,
        sliding_ticks: 0,
    };
    for q in path {
        s.max_twist = s.max_twist.max(q.y);
        match q.state {
            ContactState::Sliding => {
                s.max_sliding = s.max_sliding.max(q.load());
                s.sliding_ticks += 1;
            }
            _ => s.max_rolling = s.max_rolling.max(q.load()),
        }
    }
    s
}

fn ellipse(scale: f64) -> Vec<(f64, f64)> {
    (0..=90)
        .map(|k| {
            let t = k as f64 / 90.0 * std::f64::consts::FRAC_PI_2;
            (scale * t.cos(), scale * t.sin())
        })
        .collect()
}

/// Chart the path (every `step`-th point, by state) against the model's surfaces and the Hertzian
/// reference curve.
pub fn chart(
    path: &Path,
    title: &str,
    load: &[LoadPoint],
    p: &ContactParams,
) -> Result<(), ChartError> {
    let (f_lo, f_hi) = load.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), q| {
        (lo.min(q.f_n), hi.max(q.f_n))
    });
    render_svg(path, (960, 680), |root| {
        let mut ch = ChartBuilder::on(root)
            .caption(title, (FONT, 18))
            .margin(14)
            .x_label_area_size(60)
            .y_label_area_size(64)
            .build_cartesian_2d(0.0f64..1.6, 0.0f64..1.15)
            .map_err(drawing_err)?;
        draw_axes(
            &mut ch,
            "|f_t| / (μ_s·f_N)  [-]   (1 = static friction cone)",
            "|τn| / τ_max,s(f_N)  [-]   (τ_max,s = 3π/16·μ_s·f_N·a(f_N))",
        )?;
        draw_surfaces(&mut ch, p)?;
        for state in [ContactState::Rolling, ContactState::Sliding] {
            let color = state_color(state).mix(0.8).filled();
            let label = format!("rendered, {}", state.name());
            let pts = path_points(load, state);
            draw_markers(&mut ch, &pts, Shape::Circle, color, Some(&label))?;
        }
        draw_legend(&mut ch, SeriesLabelPosition::UpperRight, 13)?;
        let notes = [
            format!("normal force f_N {f_lo:.2} to {f_hi:.2} N while touching"),
            format!(
                "μ_s {}, μ_k {}, patch a = {} mm·(f_N / {} N)^{:.2}",
                p.mu_s,
                p.mu_k,
                p.patch_radius_m * 1e3,
                p.patch_ref_force_n,
                p.patch_exponent
            ),
        ];
        for (k, note) in notes.iter().enumerate() {
            root.draw(&Text::new(
                note.as_str(),
                (590, 180 + 20 * k as i32),
                (FONT, 13),
            ))
            .map_err(drawing_err)?;
        }
        Ok(())
    })
}

/// The model's static, slip-threshold and kinetic limit surfaces and the Hertzian reference curve.
fn draw_surfaces<'a, 'b: 'a, CT>(
    ch: &mut ChartContext<'a, SVGBackend<'b>, CT>,
    p: &ContactParams,
) -> Result<(), ChartError>
where
    CT: CoordTranslate<From = (f64, f64)>,
{
    let hertz: Vec<(f64, f64)> = curve(40, 100, 200).iter().map(|c| (c.x, c.y)).collect();
    let h = 1.0 + p.state_params().tol.hysteresis as f64;
    let kinetic = (p.mu_k / p.mu_s) as f64;
    draw_line(
        ch,
        &ellipse(1.0),
        BLACK.stroke_width(2),
        Some("static limit surface (μ_s): rolling"),
    )?;
    draw_line(
        ch,
        &ellipse(h),
        BLACK.mix(0.4).stroke_width(1),
        Some(&format!(
            "slip threshold: static × (1 + h), h = {:.2}",
            h - 1.0
        )),
    )?;
    draw_line(
        ch,
        &ellipse(kinetic),
        RED.stroke_width(2),
        Some(&format!(
            "kinetic limit surface (μ_k/μ_s = {kinetic:.2}): sliding"
        )),
    )?;
    draw_line(
        ch,
        &hertz,
        BLUE.mix(0.6).stroke_width(1),
        Some("Hertzian patch, f64 reference (host-sim limit-surface)"),
    )?;
    Ok(())
}

/// The rendered path's points (every `step`-th, at most about 3000) in `state`.
fn path_points(load: &[LoadPoint], state: ContactState) -> Vec<(f64, f64)> {
    let step = (load.len() / 3000).max(1);
    load.iter()
        .step_by(step)
        .filter(|q| q.state == state)
        .map(|q| (q.x, q.y))
        .collect()
}

/// For a scene that twists while sliding: chart its load path into `dir/limit_surface_path.svg`
/// and return the file and the path's extremes; `None` for other scenes.
pub fn write_for_run(
    dir: &Path,
    res: &RunResult,
) -> Result<Option<(PathBuf, LoadSummary)>, LimitPathError> {
    if res.scene.script.twist_while_sliding != Some(true) {
        return Ok(None);
    }
    let params = crate::sim::closed_loop::contact_params(&res.scene)?;
    let load = load_path(&res.rows, &params);
    let file = dir.join("limit_surface_path.svg");
    let title = format!(
        "{}: rendered (f_t, τn) against the limit surface",
        res.scene.name
    );
    chart(&file, &title, &load, &params)?;
    Ok(Some((file, summarize(&load))))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(force_n: [f32; 3], tau_n_nm: f32, normal: [f32; 3], state: ContactState) -> Row {
        Row {
            t_s: 0.0,
            phase: "slide",
            state,
            flags: softfinger_core::Flags::NONE,
            probe_m: [0.0; 3],
            force_n,
            tau_n_nm,
            spin_rad: 0.0,
            object_point_m: [0.0; 3],
            finger_point_m: [0.0; 3],
            normal,
            duties: [0.0; 3],
            hand_force_n: [0.0; 3],
        }
    }

    /// A load on the static ellipse at the reference force (a = a_ref there): |f_t| = 0.6·μ_s·f_N
    /// and τn = 0.8·(3π/16)·μ_s·f_N·a_ref give (0.6, 0.8), load 1; on a tilted normal too. Bound:
    /// f32 rounding of the inputs (1e-6).
    #[test]
    fn a_load_on_the_ellipse_normalises_to_one() {
        let p = ContactParams::DEFAULT;
        let f_n = p.patch_ref_force_n;
        let f_t = 0.6 * p.mu_s * f_n;
        let tau_max = 3.0 * std::f32::consts::PI / 16.0 * p.mu_s * f_n * p.patch_radius_m;
        let (s, c) = 0.3f32.sin_cos();
        let n = [0.0, s, c];
        let t = [1.0, 0.0, 0.0];
        let force = [0, 1, 2].map(|k| f_n * n[k] + f_t * t[k]);
        let rows = [
            row(force, -0.8 * tau_max, n, ContactState::Rolling),
            row(force, 0.4 * tau_max, n, ContactState::Sliding),
            row([0.0; 3], 0.0, n, ContactState::Broken),
            row(
                [0.1, 0.0, 0.005],
                0.0,
                [0.0, 0.0, 1.0],
                ContactState::Rolling,
            ),
        ];
        let path = load_path(&rows, &p);
        assert_eq!(
            path.len(),
            2,
            "broken and below-threshold ticks are left out"
        );
        // f32 rounding of the rows; measured: x 1.4e-8, y 9.9e-9, load 3.3e-10, f_N 9.5e-8 N,
        // largest rolling load 3.3e-10, sliding 8.7e-9, twist 9.9e-9. Bounds 3× each.
        assert!(
            (path[0].x - 0.6).abs() < 4.1e-8 && (path[0].y - 0.8).abs() < 3e-8,
            "{path:?}"
        );
        assert!((path[0].load() - 1.0).abs() < 1e-9);
        assert!((path[0].f_n - f_n as f64).abs() < 2.9e-7);
        let s = summarize(&path);
        assert!(
            (s.max_rolling - 1.0).abs() < 1e-9
                && (s.max_sliding - 0.6f64.hypot(0.4)).abs() < 2.6e-8
        );
        assert_eq!(s.sliding_ticks, 1);
        assert!((s.max_twist - 0.8).abs() < 3e-8);
    }
}
