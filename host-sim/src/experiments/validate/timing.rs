//! Wall-clock time per step, measured in the same run as the accuracy figures.
//!
//! A [`Case`] is one complete pass over a scene (e.g. the 100 steps of the paper's scene). Each case is
//! calibrated so that one batch of passes lasts at least [`Timing::min_batch`]; then [`Timing::batches`]
//! rounds are timed with [`std::time::Instant`], each round running one batch of every case in turn (each
//! round starting one case further on), and each case's median batch gives its figure. Interleaving the cases spreads any disturbance from other
//! processes on a shared machine over all of them, and the median discards the disturbed batches. Pass
//! results go through [`std::hint::black_box`] so the optimiser cannot drop the work.
//!
//! A speed ratio between two cases is taken round by round (both timed in the same round, moments
//! apart) and reported with its spread over the rounds ([`Spread`]), not as one ratio of medians.

use std::hint::black_box;
use std::time::{Duration, Instant};

/// How hard to measure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timing {
    /// Number of timed rounds; the median is reported.
    pub batches: u32,
    /// Shortest duration of one batch (the number of passes per batch is calibrated to reach it).
    pub min_batch: Duration,
}

impl Timing {
    /// For the commands: 41 rounds, batches of ≥ 1 ms.
    pub const STANDARD: Timing = Timing {
        batches: 41,
        min_batch: Duration::from_millis(1),
    };
    /// For tests (timings are not asserted there): one short batch.
    pub const QUICK: Timing = Timing {
        batches: 1,
        min_batch: Duration::from_micros(200),
    };
}

impl Default for Timing {
    fn default() -> Self {
        Timing::STANDARD
    }
}

/// One thing to time: a pass of `steps` steps.
pub struct Case<'a> {
    steps: usize,
    pass: Box<dyn FnMut() + 'a>,
}

impl std::fmt::Debug for Case<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Case").field("steps", &self.steps).finish()
    }
}

impl<'a> Case<'a> {
    /// A pass that runs `steps` steps and returns a value (fed to `black_box`).
    pub fn new<R>(steps: usize, mut pass: impl FnMut() -> R + 'a) -> Case<'a> {
        Case {
            steps,
            pass: Box::new(move || {
                black_box(pass());
            }),
        }
    }
}

/// Median time per step (ns) of every case, in order.
pub fn measure(cases: &mut [Case<'_>], timing: Timing) -> Vec<f64> {
    measure_rounds(cases, timing)
        .into_iter()
        .map(|mut s| {
            s.sort_by(f64::total_cmp);
            median(&s)
        })
        .collect()
}

/// Time per step (ns) of every case in every round: `result[case][round]`.
pub fn measure_rounds(cases: &mut [Case<'_>], timing: Timing) -> Vec<Vec<f64>> {
    let reps: Vec<u64> = cases
        .iter_mut()
        .map(|c| calibrate(c, timing.min_batch))
        .collect();
    let mut per_pass: Vec<Vec<f64>> = vec![Vec::new(); cases.len()];
    let n_cases = cases.len();
    for round in 0..timing.batches.max(1) as usize {
        // Each round starts with a different case, so no case is always first (or always after the same
        // neighbour).
        for k in 0..n_cases {
            let i = (round + k) % n_cases;
            let t = time_batch(reps[i], &mut cases[i]);
            per_pass[i].push(t.as_nanos() as f64 / reps[i] as f64);
        }
    }
    per_pass
        .into_iter()
        .zip(cases.iter())
        .map(|(s, c)| s.into_iter().map(|t| t / c.steps.max(1) as f64).collect())
        .collect()
}

/// The spread of a ratio over the timing rounds: median, quartiles and extremes.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Spread {
    /// Median of the per-round ratios.
    pub median: f64,
    /// Lower quartile.
    pub q1: f64,
    /// Upper quartile.
    pub q3: f64,
    /// Smallest per-round ratio.
    pub min: f64,
    /// Largest per-round ratio.
    pub max: f64,
    /// Number of rounds.
    pub rounds: usize,
}

/// The per-round ratio `numerator[r] / denominator[r]` (two cases timed in the same round r) and its
/// spread; `None` when there is no round or a time is not positive and finite.
pub fn ratio_spread(numerator: &[f64], denominator: &[f64]) -> Option<Spread> {
    let ok = |t: &f64| t.is_finite() && *t > 0.0;
    if numerator.is_empty() || numerator.len() != denominator.len() {
        return None;
    }
    if !numerator.iter().all(ok) || !denominator.iter().all(ok) {
        return None;
    }
    let mut r: Vec<f64> = numerator
        .iter()
        .zip(denominator)
        .map(|(a, b)| a / b)
        .collect();
    r.sort_by(f64::total_cmp);
    let n = r.len();
    Some(Spread {
        median: median(&r),
        q1: median(&r[..n / 2 + n % 2]),
        q3: median(&r[n / 2..]),
        min: r[0],
        max: r[n - 1],
        rounds: n,
    })
}

/// Passes per batch for `case` to last at least `min_batch` (also warms caches and branch predictors).
fn calibrate(case: &mut Case<'_>, min_batch: Duration) -> u64 {
    let mut reps: u64 = 1;
    loop {
        let t = time_batch(reps, case);
        if t >= min_batch || reps >= 1 << 40 {
            return reps;
        }
        // Jump close to the target once a batch is measurably long; otherwise double.
        let scale = if t.as_nanos() > 10_000 {
            (min_batch.as_nanos() as f64 / t.as_nanos() as f64 * 1.1).ceil() as u64
        } else {
            2
        };
        reps = reps.saturating_mul(scale.clamp(2, 1 << 20));
    }
}

fn time_batch(reps: u64, case: &mut Case<'_>) -> Duration {
    let start = Instant::now();
    for _ in 0..reps {
        (case.pass)();
    }
    start.elapsed()
}

/// Median of a sorted slice (mean of the two middle values for an even length); 0 if empty.
pub fn median(sorted: &[f64]) -> f64 {
    match sorted.len() {
        0 => 0.0,
        n if n % 2 == 1 => sorted[n / 2],
        n => 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    #[test]
    fn median_of_odd_and_even_lengths() {
        assert_eq!(median(&[1.0, 2.0, 10.0]), 2.0);
        assert_eq!(median(&[1.0, 2.0, 4.0, 10.0]), 3.0);
        assert_eq!(median(&[]), 0.0);
    }

    #[test]
    fn ratio_spread_is_taken_round_by_round() {
        // Rounds where both cases were slowed together give the same ratio: per-round ratios see
        // through a disturbance that a ratio of medians would not.
        let rk = [20.0, 40.0, 22.0, 200.0, 21.0];
        let ours = [1.0, 2.0, 1.0, 10.0, 1.0];
        let s = ratio_spread(&rk, &ours).unwrap();
        assert_eq!(
            (s.min, s.q1, s.median, s.q3, s.max),
            (20.0, 20.0, 20.0, 21.0, 22.0)
        );
        assert_eq!(s.rounds, 5);
        let even = ratio_spread(&[4.0, 8.0, 12.0, 16.0], &[1.0; 4]).unwrap();
        assert_eq!((even.q1, even.median, even.q3), (6.0, 10.0, 14.0));
        assert_eq!(ratio_spread(&[], &[]), None);
        assert_eq!(ratio_spread(&[1.0], &[0.0]), None);
        assert_eq!(ratio_spread(&[1.0, 2.0], &[1.0]), None);
    }

    #[test]
    fn every_case_runs_and_gets_a_figure() {
        // Each case really ran (its counter moved) and got a finite, non-negative figure, in order. No
        // timing bound is asserted (speed lives in the benchmarks).
        let (a, b) = (Cell::new(0u64), Cell::new(0u64));
        let mut cases = [
            Case::new(100, || a.set(a.get() + 1)),
            Case::new(1, || b.set(b.get() + 1)),
        ];
        let ns = measure(&mut cases, Timing::QUICK);
        assert_eq!(ns.len(), 2);
        assert!(
            a.get() >= 2 && b.get() >= 2,
            "calibration and one batch at least"
        );
        assert!(ns.iter().all(|n| n.is_finite() && *n >= 0.0));
    }
}
