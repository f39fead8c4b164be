//! Homing: find the encoder zero of the three arms by driving each, with a bounded torque, to its
//! mechanical stop.
//!
//! Each arm is driven by a velocity loop toward its stop with the torque limited to
//! `max_torque_nm`; it is at its stop when its count has stayed within `stall_window_counts` for
//! `stall_s`, which sets its offset from `stop_angle_rad` once all three are there. A stall before
//! `min_travel_rad` of travel fails homing. Then the arms **park**: with the same torque limit
//! they are driven to `park_angle_rad` and homing ends when all three have stayed within
//! `park_tolerance_rad` of it for the stall time. The wrist's zero is the pose in which the
//! operator holds the handle when giving `Home`. Why this procedure, and why the park:
//! docs/design.md#homing.

use crate::contact::params::{positive, ParamError};
use crate::device::DeviceParams;

/// The homing procedure of a device, in physical units.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HomingSpec {
    /// Arm speed toward the stop, rad/s; the sign selects the stop (negative: θ decreasing).
    pub speed_rad_s: f32,
    /// Largest arm torque during homing, N·m.
    pub max_torque_nm: f32,
    /// Velocity-loop gain, N·m per rad/s of speed error.
    pub velocity_gain_nm_s_per_rad: f32,
    /// Time without motion that counts as "at the stop", s.
    pub stall_s: f32,
    /// Count change that still counts as "no motion" over the stall time, counts.
    pub stall_window_counts: u32,
    /// Travel required before a stall is accepted, rad.
    pub min_travel_rad: f32,
    /// Give up (HOMING_FAILED) after this long, s.
    pub timeout_s: f32,
    /// Arm angle at the stop under the homing torque, rad (device frame, see `crate::device::delta`).
    pub stop_angle_rad: f32,
    /// Arm angle the arms are driven to after the stops are found, rad.
    pub park_angle_rad: f32,
    /// Parking is done when every arm is this close to the park angle, rad.
    pub park_tolerance_rad: f32,
}

impl HomingSpec {
    /// Check every field.
    pub fn validate(&self) -> Result<(), ParamError> {
        if !self.speed_rad_s.is_finite() || self.speed_rad_s == 0.0 {
            return Err(ParamError::OutOfRange("homing.speed_rad_s"));
        }
        positive("homing.max_torque_nm", self.max_torque_nm)?;
        positive("homing.velocity_gain", self.velocity_gain_nm_s_per_rad)?;
        positive("homing.stall_s", self.stall_s)?;
        positive("homing.min_travel_rad", self.min_travel_rad)?;
        positive("homing.timeout_s", self.timeout_s)?;
        if !self.stop_angle_rad.is_finite() {
            return Err(ParamError::NotFinite("homing.stop_angle_rad"));
        }
        if !self.park_angle_rad.is_finite() {
            return Err(ParamError::NotFinite("homing.park_angle_rad"));
        }
        positive("homing.park_tolerance_rad", self.park_tolerance_rad)?;
        Ok(())
    }
}

/// Per-tick result of [`Homing::tick`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HomingStep {
    /// Still homing: drive these duties.
    Drive([f32; 3]),
    /// Done: add these offsets to the extended motor counts to get homed counts.
    Done([i32; 3]),
    /// Failed ([`crate::Flags::HOMING_FAILED`]).
    Failed,
}

/// The procedure's state.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Homing {
    spec: HomingSpec,
    /// Control rate, Hz.
    rate_hz: f32,
    /// Ticks without motion that count as a stall at the stop.
    stall_ticks: u32,
    /// Ticks after which homing fails.
    timeout_ticks: u32,
    /// Counts of travel before a stall may count (a stop right at power-up is not trusted).
    min_travel_counts: i64,
    /// The homed count of the stop angle: what the stop reads once homed.
    target_count: i32,
    /// Arm angle per motor count, rad.
    rad_per_count: f32,
    /// Low-pass coefficient of the velocity estimate.
    alpha: f32,
    /// False until the first tick.
    started: bool,
    /// Ticks since homing began.
    elapsed: u32,
    /// Motor counts at the first tick.
    start: [i32; 3],
    /// Motor counts at the previous tick.
    prev: [i32; 3],
    /// Counts where each arm last left its stall window (the window is measured from here).
    anchor: [i32; 3],
    /// Ticks each arm has stayed within the stall window.
    still: [u32; 3],
    /// Filtered arm speeds, rad/s.
    velocity: [f32; 3],
    /// Set when all three stops are found; then the arms park.
    offsets: Option<[i32; 3]>,
    zero_angle_rad: f32,
}

/// Position gain of the park loop: speed command per rad of error, 1/s.
const PARK_GAIN_PER_S: f32 = 10.0;

/// `x` limited to ±`m` (`m` ≥ 0); NaN → 0. Not `f32::clamp`, whose assertion would link panic
/// formatting.
fn limit(x: f32, m: f32) -> f32 {
    if x > m {
        m
    } else if x < -m {
        -m
    } else if x.is_nan() {
        0.0
    } else {
        x
    }
}

/// Seconds to ticks at `rate_hz`, rounded to nearest, at least 1, saturating.
pub fn ticks_for(seconds: f32, rate_hz: f32) -> u32 {
    let t = seconds * rate_hz + 0.5;
    if t.is_nan() || t < 1.0 {
        1
    } else if t >= u32::MAX as f32 {
        u32::MAX
    } else {
        t as u32
    }
}

impl Homing {
    /// A procedure for `device` at `rate_hz`; `spec` must be valid.
    pub fn new(spec: HomingSpec, device: &DeviceParams, rate_hz: f32) -> Self {
        let rad_per_count = device.arm_rad_per_motor_count();
        let target = (spec.stop_angle_rad - device.arm_angle_at_zero_count_rad) / rad_per_count;
        let wt = 2.0 * core::f32::consts::PI * 50.0 / rate_hz;
        Homing {
            spec,
            rate_hz,
            stall_ticks: ticks_for(spec.stall_s, rate_hz),
            timeout_ticks: ticks_for(spec.timeout_s, rate_hz),
            min_travel_counts: (spec.min_travel_rad / rad_per_count) as i64,
            target_count: round_i32(target),
            rad_per_count,
            alpha: wt / (1.0 + wt),
            started: false,
            elapsed: 0,
            start: [0; 3],
            prev: [0; 3],
            anchor: [0; 3],
            still: [0; 3],
            velocity: [0.0; 3],
            offsets: None,
            zero_angle_rad: device.arm_angle_at_zero_count_rad,
        }
    }

    /// Restart the procedure (the next tick's counts are its start).
    pub fn restart(&mut self) {
        self.started = false;
        self.elapsed = 0;
        self.still = [0; 3];
        self.velocity = [0.0; 3];
        self.offsets = None;
    }

    /// The offsets once all three stops are found (while parking), else `None`.
    pub const fn found_offsets(&self) -> Option<[i32; 3]> {
        self.offsets
    }

    /// The homed count at the stop.
    pub const fn target_count(&self) -> i32 {
        self.target_count
    }

    /// One tick with the extended motor counts (unhomed).
    pub fn tick(&mut self, counts: [i32; 3], device: &DeviceParams) -> HomingStep {
        if !self.started {
            self.started = true;
            self.start = counts;
            self.prev = counts;
            self.anchor = counts;
        }
        self.elapsed = self.elapsed.saturating_add(1);
        if self.elapsed > self.timeout_ticks {
            return HomingStep::Failed;
        }
        let scale = self.rad_per_count * self.rate_hz;
        for ((v, prev), c) in self.velocity.iter_mut().zip(&self.prev).zip(counts) {
            let v_raw = c.wrapping_sub(*prev) as f32 * scale;
            *v += (v_raw - *v) * self.alpha;
        }
        self.prev = counts;
        match self.offsets {
            None => self.seek(counts, device),
            Some(offsets) => self.park(counts, offsets, device),
        }
    }

    /// Velocity loop towards the stops; stall detection.
    fn seek(&mut self, counts: [i32; 3], device: &DeviceParams) -> HomingStep {
        let mut duties = [0.0f32; 3];
        let mut at_stop = 0;
        for i in 0..3 {
            if counts[i].wrapping_sub(self.anchor[i]).unsigned_abs() > self.spec.stall_window_counts
            {
                self.anchor[i] = counts[i];
                self.still[i] = 0;
            } else {
                self.still[i] = self.still[i].saturating_add(1);
            }
            let torque = if self.still[i] >= self.stall_ticks {
                let travel = i64::from(counts[i]) - i64::from(self.start[i]);
                if travel.abs() < self.min_travel_counts {
                    return HomingStep::Failed;
                }
                at_stop += 1;
                self.spec.max_torque_nm.copysign(self.spec.speed_rad_s)
            } else {
                let t = self.spec.velocity_gain_nm_s_per_rad
                    * (self.spec.speed_rad_s - self.velocity[i]);
                limit(t, self.spec.max_torque_nm)
            };
            duties[i] = device.arm_torque_to_duty(torque, self.velocity[i]);
        }
        if at_stop == 3 {
            self.offsets = Some(counts.map(|c| self.target_count.wrapping_sub(c)));
            self.still = [0; 3];
        }
        HomingStep::Drive(duties)
    }

    /// Position loop (through the velocity loop) to the park angle, with the homed counts.
    fn park(&mut self, counts: [i32; 3], offsets: [i32; 3], device: &DeviceParams) -> HomingStep {
        let mut duties = [0.0f32; 3];
        let mut settled = 0;
        let speed = self.spec.speed_rad_s.abs();
        for i in 0..3 {
            let homed = counts[i].wrapping_add(offsets[i]);
            let angle = self.zero_angle_rad + homed as f32 * self.rad_per_count;
            let error = self.spec.park_angle_rad - angle;
            self.still[i] = if error.abs() <= self.spec.park_tolerance_rad {
                self.still[i].saturating_add(1)
            } else {
                0
            };
            if self.still[i] >= self.stall_ticks {
                settled += 1;
            }
            let v_ref = limit(PARK_GAIN_PER_S * error, speed);
            let torque = limit(
                self.spec.velocity_gain_nm_s_per_rad * (v_ref - self.velocity[i]),
                self.spec.max_torque_nm,
            );
            duties[i] = device.arm_torque_to_duty(torque, self.velocity[i]);
        }
        if settled == 3 {
            HomingStep::Done(offsets)
        } else {
            HomingStep::Drive(duties)
        }
    }
}

/// Round to the nearest i32, saturating; NaN → 0.
pub fn round_i32(x: f32) -> i32 {
    if x.is_nan() {
        0
    } else {
        (x + 0.5f32.copysign(x)) as i32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::OMEGA_LIKE;

    const RATE: f32 = 10_000.0;

    fn homing() -> Homing {
        Homing::new(OMEGA_LIKE.homing, &OMEGA_LIKE.params, RATE)
    }

    /// Counts moving towards the stop by `speed` counts per tick for `moving` ticks, then still.
    fn run(
        h: &mut Homing,
        start: i32,
        speed: i32,
        moving: u32,
        max_ticks: u32,
    ) -> (u32, HomingStep) {
        let dev = OMEGA_LIKE.params;
        let mut c = start;
        for k in 1..=max_ticks {
            if k <= moving {
                c += speed;
            }
            let step = h.tick([c, c + 7, c - 3], &dev);
            if !matches!(step, HomingStep::Drive(_)) {
                return (k, step);
            }
        }
        (max_ticks, HomingStep::Drive([0.0; 3]))
    }

    #[test]
    fn derived_thresholds() {
        let h = homing();
        // 0.1 s stall, 5 s timeout at 10 kHz; travel 0.05 rad = 391 counts (0.128 mrad each).
        assert_eq!((h.stall_ticks, h.timeout_ticks), (1_000, 50_000));
        assert_eq!(h.min_travel_counts, 391);
        // −40° at 4096·12 counts per arm turn: −5461.3 → −5461.
        assert_eq!(h.target_count(), -5461);
    }

    #[test]
    fn stalls_after_travel_set_the_offsets_so_the_stop_reads_its_angle_then_park() {
        let dev = OMEGA_LIKE.params;
        let mut h = homing();
        // 400 ticks at −1 count/tick: 400 counts of travel (above 391), then still.
        let (k, step) = run(&mut h, 1000, -1, 400, 1_400);
        assert!(matches!(step, HomingStep::Drive(_)));
        assert_eq!(k, 1_400);
        // Found on the 1000th still tick.
        let c = 1000 - 400;
        let off = [-5461 - c, -5461 - (c + 7), -5461 - (c - 3)];
        assert_eq!(h.found_offsets(), Some(off));
        // Parking: at the stop the arms are driven towards the park angle (θ increasing).
        let at_stop = [c, c + 7, c - 3];
        let HomingStep::Drive(d) = h.tick(at_stop, &dev) else {
            panic!("not parking")
        };
        assert!(d.iter().all(|&x| x > 0.0), "{d:?}");
        // Counts at the park angle (homed 0 ↔ 0 rad) for the stall time: done.
        let parked = off.map(|o| -o);
        let mut done = None;
        for k in 1..=1_000 {
            if let HomingStep::Done(o) = h.tick(parked, &dev) {
                done = Some((k, o));
                break;
            }
        }
        assert_eq!(done, Some((1_000, off)));
    }

    #[test]
    fn park_tolerance_is_bracketed() {
        let dev = OMEGA_LIKE.params;
        // 0.03 rad is 234.7 counts: 234 counts off is parked, 236 is not.
        for (off_counts, parks) in [(234, true), (236, false)] {
            let mut h = homing();
            let _ = run(&mut h, 1000, -1, 400, 1_400);
            let off = h.found_offsets().unwrap_or_default();
            let near = off.map(|o| -o + off_counts);
            let parked = (0..2_000).any(|_| matches!(h.tick(near, &dev), HomingStep::Done(_)));
            assert_eq!(parked, parks, "{off_counts}");
        }
    }

    #[test]
    fn a_stall_before_the_minimum_travel_fails() {
        let mut h = homing();
        let (_, step) = run(&mut h, 0, -1, 390, 10_000);
        assert_eq!(step, HomingStep::Failed);
        // An arm that never moves (dead encoder, or already held at the stop) fails too.
        let mut h = homing();
        let (k, step) = run(&mut h, 0, 0, 0, 10_000);
        assert_eq!((k, step), (1_000, HomingStep::Failed));
    }

    #[test]
    fn jitter_within_the_window_is_still_a_stall_and_beyond_it_is_motion() {
        let dev = OMEGA_LIKE.params;
        for (jitter, stalls) in [(2, true), (3, false)] {
            let mut h = homing();
            let mut c = 0;
            for _ in 0..500 {
                c -= 1;
                let _ = h.tick([c; 3], &dev);
            }
            let base = c;
            let mut done = false;
            for k in 0..3_000 {
                let x = if k % 2 == 0 { base } else { base - jitter };
                let _ = h.tick([x; 3], &dev);
                if h.found_offsets().is_some() {
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
        // Always moving: never stalls.
        let (k, step) = run(&mut h, 0, -1, u32::MAX, 60_000);
        assert_eq!((k, step), (50_001, HomingStep::Failed));
    }

    #[test]
    fn drive_pushes_towards_the_stop_within_the_torque_limit() {
        let dev = OMEGA_LIKE.params;
        let mut h = homing();
        // At rest the velocity loop asks for the full torque towards θ decreasing.
        let HomingStep::Drive(d) = h.tick([0; 3], &dev) else {
            panic!("not driving")
        };
        let expect = dev.arm_torque_to_duty(-0.15, 0.0);
        assert_eq!(d, [expect; 3]);
        assert!(expect < 0.0 && expect > -0.1, "{expect}");
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
}
