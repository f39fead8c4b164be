//! Quadrature counter extension: 16-bit hardware counters to 32-bit positions.
//!
//! The MCU's timers count quadrature edges in a 16-bit register that wraps silently. Sampling it
//! once per control tick and taking the *wrapping* difference to the previous sample recovers the
//! true motion as long as the encoder moves less than half the counter range (32 767 counts) per
//! tick. The difference is accumulated into a 32-bit position.
//!
//! Conventions:
//! - Positions are in encoder counts (quadrature edges, i.e. 4 × lines for ×4 decoding), relative to
//!   the raw reading handed to [`CountExtender::new`], which defines position 0.
//! - A positive difference is the timer counting up.
//! - The 32-bit position wraps (two's complement) after ±2³¹ counts of net motion in one direction;
//!   at 100 000 counts/s of sustained one-way motion that is about 6 hours. The device's links
//!   swing back and forth within a few turns, so in practice it never wraps.
//!
//! Glitch detection: a difference whose magnitude exceeds `max_counts_per_tick` is physically
//! impossible for the mechanism (noise on an encoder line, a missed sample, a counter reset). It is
//! still applied — the hardware counter is the only truth left, modulo 2¹⁶ — but the update raises
//! [`Flags::ENCODER_GLITCH`] so the firmware can latch a fault and stop driving the motors.

use crate::flags::Flags;

/// Extends one 16-bit quadrature counter to a 32-bit position. Pure logic, no hardware access.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CountExtender {
    last_raw: u16,
    position: i32,
    max_counts_per_tick: u16,
}

/// Result of one [`CountExtender::update`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Extended {
    /// Extended position after this sample, counts.
    pub position: i32,
    /// Motion since the previous sample, counts, in [-32768, 32767].
    pub delta: i32,
    /// [`Flags::ENCODER_GLITCH`] when `|delta| > max_counts_per_tick`, else empty.
    pub flags: Flags,
}

impl CountExtender {
    /// Start extending from `first_raw`, which becomes position 0.
    ///
    /// `max_counts_per_tick` is the largest plausible motion between two samples, counts. Values of
    /// 32 768 or more can never be exceeded by a wrapping 16-bit difference, so they disable glitch
    /// detection.
    pub const fn new(first_raw: u16, max_counts_per_tick: u16) -> Self {
        CountExtender {
            last_raw: first_raw,
            position: 0,
            max_counts_per_tick,
        }
    }

    /// Feed the next raw counter sample; returns the extended position and the glitch flag.
    #[inline]
    pub fn update(&mut self, raw: u16) -> Extended {
        // Reinterpreting the modular difference as i16 maps it into [-32768, 32767]: the shortest
        // way round the 16-bit circle.
        let delta = i32::from(raw.wrapping_sub(self.last_raw) as i16);
        self.last_raw = raw;
        self.position = self.position.wrapping_add(delta);
        let flags = if delta.unsigned_abs() > u32::from(self.max_counts_per_tick) {
            Flags::ENCODER_GLITCH
        } else {
            Flags::NONE
        };
        Extended {
            position: self.position,
            delta,
            flags,
        }
    }

    /// The current extended position, counts.
    #[inline]
    pub const fn position(&self) -> i32 {
        self.position
    }

    /// The last raw sample seen.
    #[inline]
    pub const fn last_raw(&self) -> u16 {
        self.last_raw
    }
}

/// `N` counters sampled together each tick (the firmware uses six: three motors, three wrist axes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct EncoderBank<const N: usize> {
    extenders: [CountExtender; N],
}

impl<const N: usize> EncoderBank<N> {
    /// Start all counters at position 0 from their first raw readings; one glitch limit for all.
    pub fn new(first_raw: [u16; N], max_counts_per_tick: u16) -> Self {
        EncoderBank {
            extenders: first_raw.map(|raw| CountExtender::new(raw, max_counts_per_tick)),
        }
    }

    /// Feed one raw sample per counter; returns the positions (counts) and the union of the flags.
    #[must_use]
    pub fn update(&mut self, raw: [u16; N]) -> ([i32; N], Flags) {
        let mut positions = [0i32; N];
        let flags = self.update_into(raw, &mut positions);
        (positions, flags)
    }

    /// [`Self::update`] writing the positions (counts) into `positions` in place (no array
    /// returned and copied: the control tick's way); returns the union of the flags.
    #[inline]
    #[must_use]
    pub fn update_into(&mut self, raw: [u16; N], positions: &mut [i32; N]) -> Flags {
        let mut flags = Flags::NONE;
        for ((ext, r), p) in self.extenders.iter_mut().zip(raw).zip(positions.iter_mut()) {
            let e = ext.update(r);
            *p = e.position;
            flags |= e.flags;
        }
        flags
    }

    /// The current positions, counts.
    pub fn positions(&self) -> [i32; N] {
        self.extenders.map(|e| e.position())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What a 16-bit hardware counter reads after `true_position` counts of net motion from a start
    /// reading `start`: the true position modulo 2^16 (independent of the extender's arithmetic).
    fn counter_reading(start: u16, true_position: i64) -> u16 {
        (i64::from(start) + true_position).rem_euclid(65_536) as u16
    }

    /// `last_raw` is the last sample fed, wrapped or not (the start reading before any).
    #[test]
    fn last_raw_is_the_last_sample_fed() {
        let mut e = CountExtender::new(65_530, 100);
        assert_eq!(e.last_raw(), 65_530);
        for raw in [65_535u16, 3, 2, 40] {
            e.update(raw);
            assert_eq!(e.last_raw(), raw);
        }
    }

    #[test]
    fn first_sample_is_position_zero() {
        let mut e = CountExtender::new(40_000, 100);
        assert_eq!(e.position(), 0);
        let x = e.update(40_000);
        assert_eq!(
            x,
            Extended {
                position: 0,
                delta: 0,
                flags: Flags::NONE
            }
        );
    }

    #[test]
    fn crosses_the_top_wrap_upwards() {
        // 65 530 -> 4 is +10 counts across the 0xFFFF -> 0 wrap.
        let mut e = CountExtender::new(65_530, 100);
        let x = e.update(4);
        assert_eq!(x.delta, 10);
        assert_eq!(x.position, 10);
        assert!(x.flags.is_empty());
    }

    #[test]
    fn crosses_the_bottom_wrap_downwards() {
        // 3 -> 65 533 is -6 counts across the 0 -> 0xFFFF wrap.
        let mut e = CountExtender::new(3, 100);
        let x = e.update(65_533);
        assert_eq!(x.delta, -6);
        assert_eq!(x.position, -6);
        assert!(x.flags.is_empty());
    }

    #[test]
    fn largest_unambiguous_steps_are_recovered_both_ways() {
        // ±32 767 is the largest motion a wrapping 16-bit difference resolves unambiguously.
        let mut e = CountExtender::new(0, u16::MAX);
        assert_eq!(e.update(32_767).delta, 32_767);
        assert_eq!(e.update(0).delta, -32_767);
        assert_eq!(e.position(), 0);
    }

    #[test]
    fn glitch_flag_marks_jumps_beyond_the_limit_only() {
        let mut e = CountExtender::new(1000, 50);
        assert!(
            e.update(1050).flags.is_empty(),
            "exactly the limit is plausible"
        );
        assert!(
            e.update(1000).flags.is_empty(),
            "exactly minus the limit is plausible"
        );
        let up = e.update(1051);
        assert_eq!(up.flags, Flags::ENCODER_GLITCH);
        // The jump is still applied: the counter is the only truth left.
        assert_eq!(up.position, 51);
        let down = e.update(999);
        assert_eq!(down.flags, Flags::ENCODER_GLITCH);
        assert_eq!(down.position, -1);
        // Back to a plausible step: the flag is per update, not latched here.
        assert!(e.update(1000).flags.is_empty());
    }

    #[test]
    fn glitch_across_the_wrap_is_detected() {
        // 65 000 -> 500 is +1036 counts through the wrap, far above a limit of 200.
        let mut e = CountExtender::new(65_000, 200);
        let x = e.update(500);
        assert_eq!(x.delta, 1036);
        assert_eq!(x.flags, Flags::ENCODER_GLITCH);
    }

    #[test]
    fn limit_of_32768_or_more_disables_detection() {
        let mut e = CountExtender::new(0, 32_768);
        // -32 768 is the extreme a wrapping difference can produce.
        let x = e.update(32_768);
        assert_eq!(x.delta, -32_768);
        assert!(x.flags.is_empty());
    }

    /// Hours of motion: a sinusoidal swing of ±3 turns plus a slow drift, sampled at 10 kHz for one
    /// simulated hour (36 million ticks), with the counter starting near its wrap point. The
    /// extended position must equal the independently computed true position at every tick (exact:
    /// integer arithmetic, no tolerance).
    #[test]
    fn one_hour_of_back_and_forth_motion_at_10_khz_tracks_exactly() {
        const RATE_HZ: i64 = 10_000;
        const TICKS: i64 = 3600 * RATE_HZ;
        let start: u16 = 65_500;
        let mut e = CountExtender::new(start, 2_000);
        // Integer-only trajectory so the reference is exact: a triangle wave of amplitude 24 000
        // counts (±3 turns of a 2000-line ×4 encoder) with period 2 s, plus a drift of 1 count per
        // 10 ticks (so about 3.6 million counts, i.e. dozens of 16-bit wraps, over the hour).
        let amplitude = 24_000i64;
        let half_period = RATE_HZ; // 1 s up, 1 s down
        let slope_num = 2 * amplitude; // counts per half period, up or down
        let mut prev = 0i64;
        for k in 1..=TICKS {
            let phase = k % (2 * half_period);
            let tri = if phase < half_period {
                -amplitude + slope_num * phase / half_period
            } else {
                amplitude - slope_num * (phase - half_period) / half_period
            };
            let truth = tri + amplitude + k / 10;
            let x = e.update(counter_reading(start, truth));
            // Each tick moves at most 2·amplitude/half_period + 1 = 5.8 counts: never a glitch.
            assert!(x.flags.is_empty(), "tick {k}");
            assert_eq!(i64::from(x.position), truth, "tick {k}");
            assert_eq!(i64::from(x.delta), truth - prev, "tick {k}");
            prev = truth;
        }
        assert!(
            prev > 3 * 65_536,
            "the drift must have wrapped the counter many times"
        );
    }

    /// Fast continuous rotation in both directions: 30 000 counts per tick (just under the
    /// ambiguity limit) for 100 000 ticks each way, i.e. 3·10⁹ counts, which also wraps the 32-bit
    /// position. The extended position must equal the true position modulo 2³².
    #[test]
    fn fast_rotation_both_directions_tracks_modulo_2_pow_32() {
        for step in [30_000i64, -30_000] {
            let mut e = CountExtender::new(123, u16::MAX);
            let mut truth = 0i64;
            for _ in 0..100_000 {
                truth += step;
                let x = e.update(counter_reading(123, truth));
                assert_eq!(i64::from(x.delta), step);
                assert_eq!(x.position, truth as i32, "position wraps like an i32");
            }
        }
    }

    #[test]
    fn bank_updates_every_counter_and_unions_flags() {
        let mut b = EncoderBank::new([0, 100, 65_535, 7, 8, 9], 10);
        let (pos, flags) = b.update([5, 95, 2, 7, 8, 9]);
        assert_eq!(pos, [5, -5, 3, 0, 0, 0]);
        assert!(flags.is_empty());
        let (pos, flags) = b.update([5, 95, 2, 7, 8, 30]);
        assert_eq!(pos, [5, -5, 3, 0, 0, 21]);
        assert_eq!(flags, Flags::ENCODER_GLITCH);
        assert_eq!(b.positions(), pos);
    }
}
