//! Homing: find the encoder zero of the three arms by driving each, with a bounded torque, to
//! both of its mechanical stops, and check the range between them against the mechanism's.
//!
//! Each arm is driven by a velocity loop with the torque limited to `max_torque_nm`, first
//! toward its **far** stop (`far_stop_angle_rad`, opposite to `speed_rad_s`), then toward its
//! **reference** stop (`stop_angle_rad`); it is at a stop when its count has stayed within
//! `stall_window_counts` for `stall_s`, and the next leg starts once all three are there. At the
//! reference stops each arm's measured travel from its far stop must be the mechanism's range
//! `|stop_angle_rad − far_stop_angle_rad|` within `range_tolerance_rad`: a stall anywhere else
//! (a hand on the handle, an obstruction, a slipping capstan, a dead encoder) fails homing with
//! no zero taken. Then the offsets are set from the reference stop and the arms **park**: with
//! the same torque limit they are driven to `park_angle_rad` and homing ends when all three
//! have stayed within `park_tolerance_rad` of it for the stall time. The wrist's zero is the
//! pose of the handle (resting in its calibration pose, hands off) when `Home` is given. Why
//! this procedure, and why the park: docs/design.md#homing.

use crate::device::DeviceParams;
use crate::validate::{positive, ParamError};

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
    /// Travel required on the reference leg before a stall is accepted, rad.
    pub min_travel_rad: f32,
    /// Arm angle at the far stop (the one homing visits first), rad (the arm-angle convention of
    /// `crate::device::delta`).
    pub far_stop_angle_rad: f32,
    /// Largest difference between the measured stop-to-stop travel and the mechanism's range, rad.
    pub range_tolerance_rad: f32,
    /// Give up (HOMING_FAILED) after this long, s.
    pub timeout_s: f32,
    /// Arm angle at the stop under the homing torque, rad (the arm-angle convention of `crate::device::delta`).
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
        if !self.far_stop_angle_rad.is_finite() {
            return Err(ParamError::NotFinite("homing.far_stop_angle_rad"));
        }
        // The far stop lies opposite to the homing direction, further than the tolerance.
        let range = (self.far_stop_angle_rad - self.stop_angle_rad) * -self.speed_rad_s.signum();
        positive("homing.range_tolerance_rad", self.range_tolerance_rad)?;
        if range.is_nan() || range <= self.range_tolerance_rad {
            return Err(ParamError::OutOfRange("homing.far_stop_angle_rad"));
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
    /// Counts of travel on the reference leg before a stall may count.
    min_travel_counts: i64,
    /// The mechanism's stop-to-stop range, counts.
    range_counts: f32,
    /// Tolerance on the measured range, counts.
    range_tolerance_counts: f32,
    /// The reference leg has begun (the far stops are found).
    on_reference_leg: bool,
    /// Motor counts at the far stops.
    far: [i32; 3],
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
            range_counts: ((spec.stop_angle_rad - spec.far_stop_angle_rad) / rad_per_count).abs(),
            range_tolerance_counts: spec.range_tolerance_rad / rad_per_count,
            on_reference_leg: false,
            far: [0; 3],
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
        self.on_reference_leg = false;
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

    /// The measured stop-to-stop travel of each arm, counts, once the reference leg has begun
    /// (for logs and tests).
    pub fn far_stop_counts(&self) -> Option<[i32; 3]> {
        self.on_reference_leg.then_some(self.far)
    }

    /// Velocity loop towards this leg's stops; stall detection; the range check.
    fn seek(&mut self, counts: [i32; 3], device: &DeviceParams) -> HomingStep {
        let mut duties = [0.0f32; 3];
        let mut at_stop = 0;
        let speed = if self.on_reference_leg {
            self.spec.speed_rad_s
        } else {
            -self.spec.speed_rad_s
        };
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
                if self.on_reference_leg && travel.abs() < self.min_travel_counts {
                    return HomingStep::Failed;
                }
                at_stop += 1;
                self.spec.max_torque_nm.copysign(speed)
            } else {
                let t = self.spec.velocity_gain_nm_s_per_rad * (speed - self.velocity[i]);
                limit(t, self.spec.max_torque_nm)
            };
            duties[i] = device.arm_torque_to_duty(torque, self.velocity[i]);
        }
        if at_stop == 3 {
            if !self.on_reference_leg {
                self.on_reference_leg = true;
                self.far = counts;
                self.start = counts;
                self.anchor = counts;
                self.still = [0; 3];
            } else {
                for (c, f) in counts.iter().zip(&self.far) {
                    let travel = (i64::from(*c) - i64::from(*f)).unsigned_abs() as f32;
                    if (travel - self.range_counts).abs() > self.range_tolerance_counts {
                        return HomingStep::Failed;
                    }
                }
                self.offsets = Some(counts.map(|c| self.target_count.wrapping_sub(c)));
                self.still = [0; 3];
            }
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
mod tests;
