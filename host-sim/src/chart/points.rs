//! The points of the speed–accuracy chart: every method × math backend × sampling rate of ours, and the
//! classical RK45 at a ladder of tolerances, each with its time per step and its largest contact-path
//! error, all timed in one interleaved measurement.

use crate::reference::scene::{paper_scene_at_rate, Scene};
use crate::reference::ReferencePaths;
use crate::validate::classical::{self, Rk45Call, SceneRef, ATOL_PER_RTOL};
use crate::validate::ours::{self, Variant};
use crate::validate::timing::{self, Case, Timing};
use crate::validate::ValidateError;
use crate::validate::{closed_form, reference_for, run_ours};

/// Sampling rates of the sweep (Hz): the paper's 100 Hz and haptic-loop rates.
pub const RATES_HZ: [f64; 5] = [100.0, 1_000.0, 4_000.0, 10_000.0, 20_000.0];
/// Relative tolerances of the classical curves (atol = rtol · [`ATOL_PER_RTOL`]).
pub const RK45_RTOLS: [f64; 10] = [
    1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12,
];
/// Sampling rate of the classical curves (the paper's scene).
pub const RK45_RATE_HZ: f64 = 100.0;

/// What a point belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Series {
    /// One of ours (the series runs over the sampling rates).
    Ours(Variant),
    /// The classical method called one way (the series runs over the tolerances).
    Rk45(Rk45Call),
}

impl Series {
    /// Legend / table name: `exact/libm`, `rk45/restart`, ...
    pub fn name(self) -> String {
        match self {
            Series::Ours(v) => v.name(),
            Series::Rk45(c) => format!("rk45/{}", c.name()),
        }
    }
}

/// One point of the chart.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// Its series.
    pub series: Series,
    /// Sampling rate of the scene, Hz.
    pub rate_hz: f64,
    /// Relative tolerance (classical points).
    pub rtol: Option<f64>,
    /// Median time per step (per sample), ns.
    pub ns_per_step: f64,
    /// Largest per-axis contact-path error on the plane or the sphere, mm (ours against the RK45
    /// reference, the classical points against the closed form).
    pub error_mm: f64,
}

/// The scenes of the sweep with their references.
struct Prepared {
    scene: Scene,
    reference: ReferencePaths,
    samples32: Vec<softfinger_core::Quat>,
}

/// Computes and times every point (ours at `rates_hz`, classical at [`RK45_RTOLS`] on the 100 Hz scene).
pub fn sweep(rates_hz: &[f64], timing: Timing) -> Result<Vec<Point>, ValidateError> {
    let prepared = rates_hz
        .iter()
        .map(|&rate| {
            let scene = paper_scene_at_rate(rate);
            let closed = closed_form(&scene)?;
            let reference = reference_for(&scene, &closed)?.paths;
            let samples32 = ours::to_f32(&scene.samples);
            Ok(Prepared {
                scene,
                reference,
                samples32,
            })
        })
        .collect::<Result<Vec<_>, ValidateError>>()?;
    let rk_scene = paper_scene_at_rate(RK45_RATE_HZ);
    let rk_closed = closed_form(&rk_scene)?;
    let mut points = Vec::new();
    let mut cases: Vec<Case<'_>> = Vec::new();
    for p in &prepared {
        for v in Variant::all() {
            let run = run_ours(v, &p.scene, &p.reference);
            points.push(Point {
                series: Series::Ours(v),
                rate_hz: 1.0 / p.scene.dt,
                rtol: None,
                ns_per_step: f64::NAN,
                error_mm: run.errors.max_mm(),
            });
            cases.push(v.case(&p.samples32, p.scene.radius as f32));
        }
    }
    let sref = SceneRef {
        samples: &rk_scene.samples,
        dt: rk_scene.dt,
        radius: rk_scene.radius,
        closed: &rk_closed,
    };
    for call in [Rk45Call::Restart, Rk45Call::SingleCall] {
        for rtol in RK45_RTOLS {
            let run = classical::run(sref, call, rtol, rtol * ATOL_PER_RTOL)?;
            points.push(Point {
                series: Series::Rk45(call),
                rate_hz: RK45_RATE_HZ,
                rtol: Some(rtol),
                ns_per_step: f64::NAN,
                error_mm: run.errors.max_mm(),
            });
            cases.push(run.case(sref));
        }
    }
    let ns = timing::measure(&mut cases, timing);
    for (p, t) in points.iter_mut().zip(ns) {
        p.ns_per_step = t;
    }
    Ok(points)
}
