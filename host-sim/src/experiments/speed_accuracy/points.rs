//! The points of the speed–accuracy chart: every method × math backend × sampling rate of ours, and the
//! classical RK45 at a ladder of tolerances at every rate too, each with its time per step (median and
//! quartiles over the timing rounds) and its largest contact-path error, all timed in one interleaved
//! measurement.

use crate::experiments::validate::classical::{self, Rk45Call, SceneRef, ATOL_PER_RTOL};
use crate::experiments::validate::ours::{self, Variant};
use crate::experiments::validate::timing::{self, Case, Timing};
use crate::experiments::validate::ValidateError;
use crate::experiments::validate::{closed_form, reference_for, run_ours};
use crate::sim::reference::scene::{paper_scene_at_rate, Scene};
use crate::sim::reference::ReferencePaths;

/// Sampling rates of the sweep (Hz): the paper's 100 Hz and haptic-loop rates.
pub const RATES_HZ: [f64; 5] = [100.0, 1_000.0, 4_000.0, 10_000.0, 20_000.0];
/// Relative tolerances of the classical curves (atol = rtol · [`ATOL_PER_RTOL`]).
pub const RK45_RTOLS: [f64; 10] = [
    1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12,
];

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
    /// Median time per step (per sample) over the timing rounds, ns.
    pub ns_per_step: f64,
    /// Lower and upper quartile of the time per step over the timing rounds, ns (both the median
    /// with one round).
    pub ns_quartiles: (f64, f64),
    /// Classical points: accepted RK45 steps per sampling interval (1.0: every sample is one step).
    pub steps_per_sample: Option<f64>,
    /// Largest per-axis contact-path error on the plane or the sphere, mm (ours against the RK45
    /// reference, the classical points against the closed form).
    pub error_mm: f64,
}

/// The scenes of the sweep with their references.
struct Prepared {
    scene: Scene,
    reference: ReferencePaths,
    closed: ReferencePaths,
    samples32: Vec<softfinger_core::Quat>,
}

/// Computes and times every point (ours and the classical at [`RK45_RTOLS`], both at every rate of
/// `rates_hz`).
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
                closed,
                samples32,
            })
        })
        .collect::<Result<Vec<_>, ValidateError>>()?;
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
                ns_quartiles: (f64::NAN, f64::NAN),
                steps_per_sample: None,
                error_mm: run.errors.max_mm(),
            });
            cases.push(v.case(&p.samples32, p.scene.radius as f32));
        }
        let sref = SceneRef {
            samples: &p.scene.samples,
            dt: p.scene.dt,
            radius: p.scene.radius,
            closed: &p.closed,
        };
        let intervals = p.scene.samples.len().saturating_sub(1).max(1) as f64;
        for call in [Rk45Call::Restart, Rk45Call::SingleCall] {
            for rtol in RK45_RTOLS {
                let run = classical::run(sref, call, rtol, rtol * ATOL_PER_RTOL)?;
                points.push(Point {
                    series: Series::Rk45(call),
                    rate_hz: 1.0 / p.scene.dt,
                    rtol: Some(rtol),
                    ns_per_step: f64::NAN,
                    ns_quartiles: (f64::NAN, f64::NAN),
                    steps_per_sample: Some(run.stats.steps as f64 / intervals),
                    error_mm: run.errors.max_mm(),
                });
                cases.push(run.case(sref));
            }
        }
    }
    let rounds = timing::measure_rounds(&mut cases, timing);
    for (p, mut t) in points.iter_mut().zip(rounds) {
        t.sort_by(f64::total_cmp);
        p.ns_per_step = timing::median(&t);
        p.ns_quartiles = quartiles(&t);
    }
    Ok(points)
}

/// Lower and upper quartile of sorted `t` (the medians of its lower and upper halves, the middle
/// value in both for an odd length, as [`timing::Spread`] takes them); NaN when empty.
pub fn quartiles(t: &[f64]) -> (f64, f64) {
    let n = t.len();
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    (
        timing::median(&t[..n / 2 + n % 2]),
        timing::median(&t[n / 2..]),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quartiles_of_odd_even_and_single() {
        assert_eq!(quartiles(&[1.0, 2.0, 3.0, 4.0, 5.0]), (2.0, 4.0));
        assert_eq!(quartiles(&[1.0, 2.0, 3.0, 4.0]), (1.5, 3.5));
        assert_eq!(quartiles(&[7.0]), (7.0, 7.0));
        assert!(quartiles(&[]).0.is_nan());
    }

    /// Why rk45/restart keeps one error from rtol 1e-3 to 1e-8 on the paper's 100 Hz scene: each
    /// restart's first step spans the whole 10 ms sample and passes its error test at every one of
    /// those tolerances, so the integration is the same steps and the error that of one
    /// Dormand-Prince step per sample; from 1e-9 on, steps are rejected and split and the error
    /// falls.
    #[test]
    fn restart_plateau_is_one_step_per_sample() {
        let scene = paper_scene_at_rate(100.0);
        let closed = closed_form(&scene).unwrap();
        let sref = SceneRef {
            samples: &scene.samples,
            dt: scene.dt,
            radius: scene.radius,
            closed: &closed,
        };
        let intervals = (scene.samples.len() - 1) as u64;
        let run = |rtol: f64| classical::run(sref, Rk45Call::Restart, rtol, rtol * ATOL_PER_RTOL);
        // Measured: 104 steps (one per sample, plus one where each of the 4 chart re-centrings
        // splits a sample), no rejection, 725 right-hand-side evaluations, 6.2012e-9 mm, the same at
        // every rtol from 1e-3 to 1e-8 (the error's 6th digit moves at 1e-7).
        let loose = run(1e-3).unwrap();
        assert_eq!(loose.stats.steps, intervals + loose.stats.recharts);
        assert_eq!(loose.stats.rejected, 0);
        let tight_plateau = run(1e-8).unwrap();
        assert_eq!(tight_plateau.stats, loose.stats);
        assert_eq!(tight_plateau.errors.max_mm(), loose.errors.max_mm());
        let split = run(1e-9).unwrap();
        assert!(split.stats.steps > intervals, "{:?}", split.stats);
        assert!(split.errors.max_mm() < loose.errors.max_mm());
    }
}
