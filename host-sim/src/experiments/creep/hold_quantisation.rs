//! The closed-loop hold of issue 12 part 1 seen through the encoders: a hand presses 1 mm and
//! holds still; the motor counts under the hand dither between neighbouring values (the true arm
//! angles sit within a fraction of a count of a count boundary and the force steps each flip
//! makes move the arm across it again), so the probe position the controller sees jumps between
//! lattice points of the encoder grid while the contact anchor does not move. This module
//! measures what the rendered tangential force does during such a hold:
//!
//! - the instantaneous force (largest, percentiles): the spring on a probe one count or more off
//!   the anchor, plus the damping terms on the filtered velocity spike of every count flip (and,
//!   with the passivity stage on, its variable damper, see `softfinger_core::control::controller::passivity`);
//! - the mean tangential force over the first and the last `window_s` of the hold (after 1 s of
//!   settling): the dither averages out, so the mean is the spring on the distance between the
//!   true probe position and the anchor, at most one count's worth of force; a walk of the probe
//!   relative to the anchor (creep) makes the last window's mean grow away from the first's;
//! - how often the counts changed, and the anchor's walk.
//!
//! Units: N, m, s; forces in the device base frame (tangential = x, y on the plane scene).

use super::scene::{anchor_point, hold_scene, APPROACH_S};
use crate::sim::closed_loop::{self, SetupError};
use softfinger_core::contact::params::ContactParams;
use softfinger_core::control::controller::passivity::PassivityConfig;
use softfinger_core::{Libm, Math, Vec3};

/// What to run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HoldSetup {
    /// Simulated hold, s (after the 0.5 s press).
    pub hold_s: f64,
    /// Passivity stage on (the pipeline's default) or off.
    pub passivity: bool,
    /// Drift of the hand's reference along base x during the hold, m/s (0: still).
    pub drift_m_per_s: f64,
    /// Length of the first and last averaging windows, s.
    pub window_s: f64,
}

/// What one hold measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HoldProfile {
    /// Largest instantaneous tangential force after settling, N.
    pub max_n: f64,
    /// Largest tangential spring force after settling (the rendered force without its damping
    /// term), N.
    pub max_elastic_n: f64,
    /// 99th percentile and median of the instantaneous tangential force, N.
    pub p99_n: f64,
    pub median_n: f64,
    /// |mean tangential force| over the first and the last window, N.
    pub first_mean_n: f64,
    pub last_mean_n: f64,
    /// |difference of the two window means| (vector), N: the growth creep would make.
    pub mean_change_n: f64,
    /// Ticks on which a motor count changed after settling.
    pub count_changes: u64,
    /// Largest walk of the contact anchor after settling, m.
    pub anchor_walk_m: f64,
    /// The passivity observer's energy at the end, J.
    pub final_energy_j: f64,
}

/// Why a hold could not be measured.
#[derive(Debug, thiserror::Error)]
pub enum HoldError {
    /// The hold and window durations are inconsistent or not finite.
    #[error("hold: need hold_s > 1 + 2·window_s, all finite")]
    Setup,
    /// No sample fell in the first or the last window.
    #[error("hold: nothing measured")]
    NothingMeasured,
    /// The closed loop could not be set up.
    #[error(transparent)]
    Loop(#[from] SetupError),
}

/// Runs one hold (the exact method, the default contact parameters).
pub fn measure<M: Math>(setup: HoldSetup) -> Result<HoldProfile, HoldError> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if !(ok(setup.hold_s) && ok(setup.window_s) && setup.drift_m_per_s.is_finite())
        || 2.0 * setup.window_s > setup.hold_s - 1.0
    {
        return Err(HoldError::Setup);
    }
    let contact = ContactParams::DEFAULT;
    let (mut ctrl, mut plant) = hold_scene::<M>(contact, setup.hold_s, setup.drift_m_per_s)?;
    if !setup.passivity {
        ctrl.set_passivity(PassivityConfig {
            enabled: false,
            ..PassivityConfig::DEFAULT
        })
        .map_err(SetupError::Passivity)?;
    }
    let rate = f64::from(ctrl.config().timing.control_hz);
    // The approach and the press (0.5 s) before the hold; judged from 1 s into it.
    let ticks = ((APPROACH_S + 0.5 + setup.hold_s) * rate) as u64;
    let settle = ((APPROACH_S + 1.5) * rate) as u64;
    let first_end = settle + (setup.window_s * rate) as u64;
    let last_start = ticks - (setup.window_s * rate) as u64;
    let mut forces = Vec::with_capacity((ticks - settle) as usize);
    let (mut first, mut last) = ([0.0f64; 2], [0.0f64; 2]);
    let (mut n_first, mut n_last) = (0u64, 0u64);
    let mut prev_counts = [0i32; 3];
    let mut count_changes = 0u64;
    let mut anchor0: Option<Vec3> = None;
    let mut walk = 0.0f64;
    let mut max_elastic = 0.0f64;
    let b_t = f64::from(contact.tangential_damping);
    closed_loop::simulate(
        &mut ctrl,
        &mut plant,
        ticks,
        |_, _| {},
        |k, _, out, ctrl, _| {
            let counts = [out.counts[0], out.counts[1], out.counts[2]];
            if k < settle {
                prev_counts = counts;
                return;
            }
            let f = [out.control.force_n.x as f64, out.control.force_n.y as f64];
            forces.push(f[0].hypot(f[1]));
            // The plane's tangent plane is base x, y: the damping term is -b_t·v_t there.
            let v = ctrl.controller().probe_velocity();
            let elastic = [f[0] + b_t * v.x as f64, f[1] + b_t * v.y as f64];
            max_elastic = max_elastic.max(elastic[0].hypot(elastic[1]));
            if k < first_end {
                first = [first[0] + f[0], first[1] + f[1]];
                n_first += 1;
            }
            if k >= last_start {
                last = [last[0] + f[0], last[1] + f[1]];
                n_last += 1;
            }
            if counts != prev_counts {
                count_changes += 1;
            }
            prev_counts = counts;
            let a = anchor_point(ctrl);
            let a0 = *anchor0.get_or_insert(a);
            walk = walk.max((a - a0).norm::<Libm>() as f64);
        },
    );
    if forces.is_empty() || n_first == 0 || n_last == 0 {
        return Err(HoldError::NothingMeasured);
    }
    forces.sort_by(f64::total_cmp);
    let n = forces.len();
    let mean = |s: [f64; 2], k: u64| [s[0] / k as f64, s[1] / k as f64];
    let (m1, m2) = (mean(first, n_first), mean(last, n_last));
    Ok(HoldProfile {
        max_n: forces[n - 1],
        max_elastic_n: max_elastic,
        p99_n: forces[n * 99 / 100],
        median_n: forces[n / 2],
        first_mean_n: m1[0].hypot(m1[1]),
        last_mean_n: m2[0].hypot(m2[1]),
        mean_change_n: (m2[0] - m1[0]).hypot(m2[1] - m1[1]),
        count_changes,
        anchor_walk_m: walk,
        final_energy_j: f64::from(ctrl.controller().passivity().energy_j()),
    })
}

/// One line of `host-sim creep`'s report.
pub fn line(setup: &HoldSetup, p: &HoldProfile) -> String {
    format!(
        "hold {} s, passivity {}, drift {:.2e} m/s: tangential max {:.3e} N (elastic {:.3e} N), p99 {:.3e} N, median {:.3e} N; mean first {} s {:.3e} N, last {} s {:.3e} N, change {:.3e} N; {} count changes; anchor walk {:.3e} m; passivity energy {:.3e} J",
        setup.hold_s,
        if setup.passivity { "on" } else { "off" },
        setup.drift_m_per_s,
        p.max_n,
        p.max_elastic_n,
        p.p99_n,
        p.median_n,
        setup.window_s,
        p.first_mean_n,
        setup.window_s,
        p.last_mean_n,
        p.mean_change_n,
        p.count_changes,
        p.anchor_walk_m,
        p.final_energy_j
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_setups_are_rejected_before_running() {
        let good = HoldSetup {
            hold_s: 20.0,
            passivity: true,
            drift_m_per_s: 0.0,
            window_s: 5.0,
        };
        for bad in [
            HoldSetup {
                hold_s: 10.0,
                window_s: 5.0,
                ..good
            },
            HoldSetup {
                hold_s: f64::NAN,
                ..good
            },
            HoldSetup {
                window_s: 0.0,
                ..good
            },
            HoldSetup {
                drift_m_per_s: f64::INFINITY,
                ..good
            },
        ] {
            assert!(measure::<Libm>(bad).is_err(), "{bad:?}");
        }
    }
}
