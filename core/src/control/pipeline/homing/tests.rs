//! Homing's tests: the seek, the range check at both stops, the park, on the named device.

use super::*;
use crate::omega_like::OMEGA_LIKE;

const RATE: f32 = 10_000.0;

fn homing() -> Homing {
    Homing::new(OMEGA_LIKE.homing, &OMEGA_LIKE.params, RATE)
}

/// Three arms on rails between two stops, in motor counts (θ increasing = counts up): each
/// tick an arm moves one count in the direction of its duty until a stop or an obstruction.
/// Independent of the procedure's code.
struct Rails {
    pos: [i32; 3],
    lo: [i32; 3],
    hi: [i32; 3],
    /// An obstruction on the way up (towards `lo`): the arm cannot pass below it.
    block: [Option<i32>; 3],
}

impl Rails {
    /// Reference stops at `lo`, far stops `range` counts above, arms starting `start` above.
    fn new(lo: i32, range: i32, start: i32) -> Rails {
        let lo = [lo, lo + 7, lo - 3];
        Rails {
            pos: lo.map(|l| l + start),
            lo,
            hi: lo.map(|l| l + range),
            block: [None; 3],
        }
    }

    #[allow(clippy::needless_range_loop)] // four arrays indexed together
    fn step(&mut self, duties: [f32; 3]) {
        for i in 0..3 {
            let floor = self.block[i].unwrap_or(self.lo[i]).max(self.lo[i]);
            if duties[i] > 0.0 {
                self.pos[i] = (self.pos[i] + 1).min(self.hi[i]);
            } else if duties[i] < 0.0 {
                self.pos[i] = (self.pos[i] - 1).max(floor);
            }
        }
    }
}

/// Run until homing stops driving (or `max_ticks`): (tick, step).
fn run(h: &mut Homing, rails: &mut Rails, max_ticks: u32) -> (u32, HomingStep) {
    let dev = OMEGA_LIKE.params;
    for k in 1..=max_ticks {
        let step = h.tick(rails.pos, &dev);
        match step {
            HomingStep::Drive(d) => rails.step(d),
            other => return (k, other),
        }
    }
    (max_ticks, HomingStep::Drive([0.0; 3]))
}

/// The mechanism's 145° in counts: 2.5307 rad / 0.12783 mrad = 19 797.3.
const RANGE: i32 = 19_797;

#[test]
fn derived_thresholds() {
    let h = homing();
    // 0.1 s stall, 8 s timeout at 10 kHz; travel 0.05 rad = 391 counts (0.128 mrad each).
    assert_eq!((h.stall_ticks, h.timeout_ticks), (1_000, 80_000));
    assert_eq!(h.min_travel_counts, 391);
    // −40° at 4096·12 counts per arm turn: −5461.3 → −5461.
    assert_eq!(h.target_count(), -5461);
    assert!(
        (h.range_counts - 19_797.3).abs() < 0.1,
        "{}",
        h.range_counts
    );
    assert!((h.range_tolerance_counts - 156.46).abs() < 0.01);
}

/// Down to the far stops, up to the reference stops, the range checked, the offsets set so
/// that the reference stop reads its angle, then the park.
#[test]
fn both_stops_then_the_range_check_set_the_offsets_then_park() {
    let mut h = homing();
    let mut rails = Rails::new(1_000, RANGE, 5_000);
    let (_, step) = run(&mut h, &mut rails, 80_000);
    assert!(matches!(step, HomingStep::Done(_)), "{step:?}");
    assert_eq!(h.far_stop_counts(), Some(rails.hi));
    let off = rails.lo.map(|l| -5461 - l);
    assert_eq!(step, HomingStep::Done(off));
    // Parked at the park angle (homed 0 ↔ 0 rad) within its tolerance.
    for (p, o) in rails.pos.iter().zip(off) {
        assert!((p + o).abs() <= 234, "{:?}", rails.pos);
    }
}

/// The measured range may differ from the mechanism's by 156.46 counts (0.02 rad): 156 and
/// −156 pass, 158 and −158 fail, with no zero taken.
#[test]
fn range_tolerance_is_bracketed() {
    for (extra, ok) in [(156, true), (158, false), (-156, true), (-158, false)] {
        let mut h = homing();
        let mut rails = Rails::new(0, RANGE + extra, 3_000);
        let (_, step) = run(&mut h, &mut rails, 80_000);
        assert_eq!(matches!(step, HomingStep::Done(_)), ok, "{extra}: {step:?}");
        if !ok {
            assert_eq!(step, HomingStep::Failed);
            assert_eq!(h.found_offsets(), None, "no zero taken");
        }
    }
}

/// An arm held or blocked on its way up, 30° short of its stop: homing fails at the
/// reference stops, no zero taken.
#[test]
fn a_stall_midway_fails_with_no_zero_taken() {
    let mut h = homing();
    let mut rails = Rails::new(0, RANGE, 3_000);
    rails.block[1] = Some(rails.lo[1] + 4_096);
    let (_, step) = run(&mut h, &mut rails, 80_000);
    assert_eq!(step, HomingStep::Failed);
    assert_eq!(h.found_offsets(), None);
    // And on the way down (a far stop found short): the range is short too.
    let mut h = homing();
    let mut rails = Rails::new(0, RANGE, 3_000);
    rails.hi[2] = rails.lo[2] + RANGE - 4_096;
    assert_eq!(run(&mut h, &mut rails, 80_000).1, HomingStep::Failed);
}

/// An arm that never moves (dead encoder): both legs stall at once, the range is 0.
#[test]
fn a_dead_encoder_fails_after_two_stall_times() {
    let dev = OMEGA_LIKE.params;
    let mut h = homing();
    let mut failed = None;
    for k in 1..=10_000u32 {
        if h.tick([0; 3], &dev) == HomingStep::Failed {
            failed = Some(k);
            break;
        }
    }
    assert_eq!(failed, Some(2_000));
}

#[test]
fn park_tolerance_is_bracketed() {
    let dev = OMEGA_LIKE.params;
    // 0.03 rad is 234.7 counts: 234 counts off is parked, 236 is not.
    for (off_counts, parks) in [(234, true), (236, false)] {
        let mut h = homing();
        let mut rails = Rails::new(0, RANGE, 3_000);
        while h.found_offsets().is_none() {
            let HomingStep::Drive(d) = h.tick(rails.pos, &dev) else {
                panic!("stopped before the park")
            };
            rails.step(d);
        }
        let off = h.found_offsets().unwrap_or_default();
        let near = off.map(|o| -o + off_counts);
        let parked = (0..2_000).any(|_| matches!(h.tick(near, &dev), HomingStep::Done(_)));
        assert_eq!(parked, parks, "{off_counts}");
    }
}

#[test]
fn jitter_within_the_window_is_still_a_stall_and_beyond_it_is_motion() {
    let dev = OMEGA_LIKE.params;
    for (jitter, stalls) in [(2, true), (3, false)] {
        let mut h = homing();
        let mut c = 0;
        for _ in 0..500 {
            c += 1;
            let _ = h.tick([c; 3], &dev);
        }
        let base = c;
        let mut done = false;
        for k in 0..3_000 {
            let x = if k % 2 == 0 { base } else { base + jitter };
            let _ = h.tick([x; 3], &dev);
            if h.far_stop_counts().is_some() {
                done = true;
                break;
            }
        }
        assert_eq!(done, stalls, "jitter {jitter}");
    }
}

#[test]
fn times_out_exactly_at_the_timeout() {
    let mut h = homing();
    // No stops: never stalls.
    let mut rails = Rails::new(0, i32::MAX / 2, 3_000);
    let (k, step) = run(&mut h, &mut rails, 90_000);
    assert_eq!((k, step), (80_001, HomingStep::Failed));
}

#[test]
fn drive_pushes_towards_the_stop_within_the_torque_limit() {
    let dev = OMEGA_LIKE.params;
    let mut h = homing();
    // At rest the velocity loop asks for the full torque towards θ increasing (the far stop).
    let HomingStep::Drive(d) = h.tick([0; 3], &dev) else {
        panic!("not driving")
    };
    let expect = dev.arm_torque_to_duty(0.15, 0.0);
    assert_eq!(d, [expect; 3]);
    assert!(expect > 0.0 && expect < 0.1, "{expect}");
}

#[test]
fn invalid_specs_are_rejected() {
    let ok = OMEGA_LIKE.homing;
    assert_eq!(ok.validate(), Ok(()));
    for bad in [
        HomingSpec {
            speed_rad_s: 0.0,
            ..ok
        },
        HomingSpec {
            speed_rad_s: f32::NAN,
            ..ok
        },
        HomingSpec {
            max_torque_nm: 0.0,
            ..ok
        },
        HomingSpec {
            velocity_gain_nm_s_per_rad: -1.0,
            ..ok
        },
        HomingSpec { stall_s: 0.0, ..ok },
        HomingSpec {
            min_travel_rad: 0.0,
            ..ok
        },
        HomingSpec {
            timeout_s: f32::INFINITY,
            ..ok
        },
        HomingSpec {
            stop_angle_rad: f32::NAN,
            ..ok
        },
        HomingSpec {
            far_stop_angle_rad: f32::NAN,
            ..ok
        },
        HomingSpec {
            range_tolerance_rad: 0.0,
            ..ok
        },
        // The far stop on the homing side of the reference stop.
        HomingSpec {
            far_stop_angle_rad: -1.0,
            ..ok
        },
    ] {
        assert!(bad.validate().is_err(), "{bad:?}");
    }
}

#[test]
fn ticks_for_rounds_and_saturates() {
    assert_eq!(ticks_for(0.1, 10_000.0), 1_000);
    assert_eq!(ticks_for(0.0, 10_000.0), 1);
    assert_eq!(ticks_for(f32::NAN, 10_000.0), 1);
    assert_eq!(ticks_for(1e12, 10_000.0), u32::MAX);
    assert_eq!(round_i32(-2.5), -3);
    assert_eq!(round_i32(f32::NAN), 0);
}
