//! Spin torque about the contact normal, eq. (1) τn = k_z·δφ, with the torsional friction limit of
//! a soft finger.
//!
//! Model (elastic-perfectly-plastic torsion spring): the spin increments δφ wind a torsion spring of
//! stiffness k_z (N·m/rad); the torque τn = k_z·φ_el is limited to the torsional friction limit
//! τ_max, beyond which the patch slips and the spring stops winding (φ_el is clamped to τ_max/k_z).
//! For a circular contact patch of radius a with a Hertzian pressure distribution and Coulomb
//! friction μ, the limit is τ_max = (3π/16)·μ·f_N·a (Howe & Cutkosky, "Practical force-motion models
//! for sliding manipulation", IJRR 15(6), 1996; uniform pressure would give (2/3)·μ·f_N·a).
//! Sign (eq. 1 as printed): positive δφ is a right-handed rotation of the fingertip about the
//! outward normal and τn = +k_z·φ_el has the same sign; the moment the contact exerts on the
//! fingertip (what a 6-DoF device would render on the hand) is −τn.

use crate::math::fixed::Fixed;

/// Coefficient of the Hertzian torsional friction limit, 3π/16.
pub const HERTZ_TORSION_COEFF: f32 = 3.0 * core::f32::consts::PI / 16.0;

/// The spin sums hold an angle times 2⁻⁸ ([`Fixed`] units of 2⁻⁴⁴, so 2⁻³⁶ rad = 1.5e-11 rad per
/// unit, range ±1.2e8 rad): every increment below 2³¹ units (0.031 rad, 310 rad/s at 10 kHz)
/// converts with one instruction on the M4F (at 2⁻⁴⁴ rad, only those below 1.2e-4 rad did).
/// Scaling by a power of two is exact and odd, so the sums stay exactly reversible; the
/// truncation of each increment is below 1.5e-11 rad (1.5e-5 rad after 10⁶ ticks at worst).
const TO_SUM: f32 = 1.0 / 256.0;

/// An angle sum as f32, rad (exact scaling of [`Fixed::to_f32`]).
#[inline(always)]
fn from_sum(f: Fixed) -> f32 {
    f.to_f32() * 256.0
}

/// Relative margin inside the limit surface below which [`SpinSpring::update_within`] takes its
/// fast path (2⁻¹⁰; the roundings it must cover are below 1e-6).
pub const INSIDE_MARGIN: f32 = 1.0 / 1024.0;
/// Least τ_max (N·m) for the fast test of [`SpinSpring::update_within`]: every product of its
/// slow path stays normal above it.
const TAU_MAX_NORMAL: f32 = 1.0e-30;
/// Largest k_z (N·m/rad) for that fast test (the largest [`crate::contact::params`] accepts).
const K_Z_MAX: f32 = 1.0e3;

/// 0 < k_z ≤ [`K_Z_MAX`] (false for NaN) in one unsigned comparison of the bit patterns: positive
/// floats order as their bits, −0 and negatives have the sign bit (huge as unsigned), and +0
/// wraps to the largest value.
#[inline(always)]
fn k_z_in_range(k_z: f32) -> bool {
    k_z.to_bits().wrapping_sub(1) < K_Z_MAX.to_bits()
}

/// Whether the fast inside test of [`SpinSpring::update_within`] may be used for these k_z (N·m/rad)
/// and τ_max (N·m): 0 < k_z ≤ 1e3 and τ_max ≥ 1e-30 (false for NaN).
#[inline(always)]
pub fn fast_test_applies(k_z: f32, tau_max: f32) -> bool {
    k_z_in_range(k_z) && tau_max >= TAU_MAX_NORMAL
}

/// The torsional friction limit τ_max = (3π/16)·μ·f_N·a (N·m). Zero for f_N ≤ 0.
#[inline]
pub fn torsion_limit(mu: f32, normal_force_n: f32, patch_radius_m: f32) -> f32 {
    if normal_force_n > 0.0 {
        HERTZ_TORSION_COEFF * mu * normal_force_n * patch_radius_m
    } else {
        0.0
    }
}

/// The torsion spring's state.
///
/// The elastic twist is a fixed-point sum ([`Fixed`]) of the spin increments and the slip offset
/// (also fixed point) what the slips took from it, which only a slip changes, so the total spin
/// Σδφ is their exact sum: a zero δφ changes nothing, and a
/// fingertip that twists back by the exact negated increments returns its spin and, unless the
/// spring slipped meanwhile, its torque bit for bit. A spring that slipped keeps its offset: that
/// is friction, not creep.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SpinSpring {
    /// Elastic twist φ_el, rad (read-only: a cache of `elastic`).
    pub elastic_rad: f32,
    /// Total spin Σδφ since the contact began, rad (read-only: a cache of `elastic + offset`).
    pub accumulated_rad: f32,
    elastic: Fixed,
    offset: Fixed,
    /// `offset` as f32 (so the total needs no second conversion: total = φ_el + offset).
    offset_rad: f32,
}

impl SpinSpring {
    /// Wind the spring by `dphi` (rad) and return (τn in N·m, saturated?). `k_z` in N·m/rad,
    /// `tau_max` in N·m (≥ 0). Non-finite `dphi` is ignored (the caller flags it).
    pub fn update(&mut self, dphi: f32, k_z: f32, tau_max: f32) -> (f32, bool) {
        let el = self.wind(dphi);
        self.settle(el, k_z, tau_max)
    }

    /// [`SpinSpring::update`] with the torque limited to what a tangential load leaves of the
    /// static limit surface (see [`crate::contact::limit_surface`]): |τn| ≤ τ_max·√(1 − |f_t|²/f_max²),
    /// `ft2` = |f_t|² and `fmax2` = f_max² in N² (no tangential budget, `fmax2` ≤ 0: no torque).
    /// The same answer, bit for bit, as `update(dphi, k_z, tau_max·√(1 − ft2/fmax2))` with
    /// `M::sqrt` (tested), without the division and the square root while the load is clearly
    /// inside the ellipse, which is the common path.
    ///
    /// Requires 0 < k_z ≤ 1e3 N·m/rad (the parameters' range) and τ_max ≥ 1e-30 N·m; the fast test
    /// keeps a margin of [`INSIDE_MARGIN`]. Why it is safe: docs/design.md#spin-limit-the-fast-inside-test.
    #[inline(always)]
    pub fn update_within<M: crate::math::Math>(
        &mut self,
        dphi: f32,
        k_z: f32,
        tau_max: f32,
        ft2: f32,
        fmax2: f32,
    ) -> (f32, bool) {
        self.update_within_prechecked::<M>(
            dphi,
            k_z,
            tau_max,
            ft2,
            fmax2,
            fast_test_applies(k_z, tau_max),
        )
    }

    /// [`SpinSpring::update_within`] with its precondition test [`fast_test_applies`]`(k_z,
    /// tau_max)` passed in as `fast_ok`, so a caller whose k_z and τ_max change rarely evaluates it
    /// only when they do. The same answer bit for bit when `fast_ok` is that test's value.
    #[inline(always)]
    pub fn update_within_prechecked<M: crate::math::Math>(
        &mut self,
        dphi: f32,
        k_z: f32,
        tau_max: f32,
        ft2: f32,
        fmax2: f32,
        fast_ok: bool,
    ) -> (f32, bool) {
        let el = self.wind(dphi);
        let tau = k_z * el;
        let x = tau / tau_max;
        let u = ft2 / fmax2;
        if fast_ok && x * x + u < 1.0 - INSIDE_MARGIN {
            self.elastic_rad = el;
            self.accumulated_rad = el + self.offset_rad;
            return (tau, false);
        }
        self.settle_within::<M>(el, k_z, tau_max, ft2, fmax2)
    }

    /// The slow path of [`SpinSpring::update_within`]: the share of the limit left, then
    /// [`SpinSpring::settle`].
    #[cold]
    #[inline(never)]
    fn settle_within<M: crate::math::Math>(
        &mut self,
        el: f32,
        k_z: f32,
        tau_max: f32,
        ft2: f32,
        fmax2: f32,
    ) -> (f32, bool) {
        let used = if fmax2 > 0.0 { ft2 / fmax2 } else { 1.0 };
        let left = if used < 1.0 { M::sqrt(1.0 - used) } else { 0.0 };
        self.settle(el, k_z, tau_max * left)
    }

    /// Add `dphi` (rad) to the spin (non-finite: ignored) and return the elastic twist.
    #[inline(always)]
    fn wind(&mut self, dphi: f32) -> f32 {
        self.elastic.add_finite_f32(dphi * TO_SUM);
        from_sum(self.elastic)
    }

    /// Set the elastic twist to `el` (rad) and move the offset by what it lost, keeping the total
    /// spin exactly (friction). Not inlined: off the common path, and the firmware's fast code
    /// memory is small.
    #[inline(never)]
    fn slip(&mut self, el: f32) {
        let new = Fixed::from_f32(el * TO_SUM);
        self.offset = Fixed(self.offset.0.wrapping_add(self.elastic.minus(new).0));
        self.elastic = new;
        self.offset_rad = from_sum(self.offset);
        self.elastic_rad = from_sum(self.elastic);
    }

    /// Hold the elastic twist `el` (rad) within τ_max/k_z (slipping the offset beyond it) and
    /// return (τn, saturated?). Not inlined (see [`SpinSpring::slip`]).
    #[inline(never)]
    fn settle(&mut self, el: f32, k_z: f32, tau_max: f32) -> (f32, bool) {
        let limit = if k_z > 0.0 { tau_max / k_z } else { 0.0 };
        let saturated = el.abs() > limit;
        if saturated {
            // Slip: the elastic twist sits on the limit.
            self.slip(if el > 0.0 { limit } else { -limit });
        } else {
            self.elastic_rad = el;
        }
        // A function of the state alone (both terms are), so it returns when the state does.
        self.accumulated_rad = self.elastic_rad + self.offset_rad;
        (k_z * self.elastic_rad, saturated)
    }

    /// Slip the spring so its elastic twist is `el` (rad), keeping the total spin: the offset
    /// moves (friction). Used by the limit-surface projection of the sliding proxy.
    pub fn slip_to(&mut self, el: f32) {
        if el == self.elastic_rad || !el.is_finite() {
            return;
        }
        self.slip(el);
        self.accumulated_rad = self.elastic_rad + self.offset_rad;
    }

    /// Release the spring (contact broken).
    pub fn reset(&mut self) {
        *self = SpinSpring::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Math;

    #[test]
    fn linear_below_the_limit_eq_1() {
        let mut s = SpinSpring::default();
        let (tau, sat) = s.update(0.01, 0.05, 1.0);
        assert!(!sat);
        // Both measured exact.
        assert_eq!(tau, 0.0005, "τ = k_z·δφ, got {tau}");
        let (tau, _) = s.update(0.01, 0.05, 1.0);
        assert_eq!(tau, 0.001, "the spring winds up: {tau}");
    }

    #[test]
    fn saturates_at_the_hertzian_torsion_limit_and_unwinds_elastically() {
        // μ = 1, f_N = 2 N, a = 5 mm: τ_max = 0.589·1·2·0.005 = 5.89e-3 N·m.
        let tau_max = torsion_limit(1.0, 2.0, 0.005);
        // Measured 4.66e-10 N·m (the hand value's 7 digits); bound 3x. The saturated torque
        // measured exact, the total spin exact (bound 1 ulp of 1.01, 1.2e-7 rad, an ulp
        // argument), the unwound torque 4.66e-10 N·m off (bound 3x).
        assert!((tau_max - 5.890_486e-3).abs() < 1.4e-9);
        let mut s = SpinSpring::default();
        for _ in 0..100 {
            s.update(0.01, 0.05, tau_max);
        }
        let (tau, sat) = s.update(0.01, 0.05, tau_max);
        assert!(sat);
        assert_eq!(tau, tau_max);
        assert!((s.accumulated_rad - 1.01).abs() <= 1.2e-7);
        // Reversing unwinds from the limit immediately (no dead band).
        let (tau, sat) = s.update(-0.01, 0.05, tau_max);
        assert!(!sat);
        assert!((tau - (tau_max - 0.0005)).abs() < 1.4e-9);
    }

    #[test]
    fn no_normal_force_no_torque() {
        assert_eq!(torsion_limit(1.0, -1.0, 0.005), 0.0);
        let mut s = SpinSpring::default();
        let (tau, sat) = s.update(0.3, 0.05, 0.0);
        assert_eq!(tau, 0.0);
        assert!(sat);
        let (tau, _) = s.update(f32::NAN, 0.05, 1.0);
        assert!(tau.is_finite());
        // A non-finite increment moves nothing.
        let before = s;
        for d in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let _ = s.update(d, 0.05, 1.0);
            assert_eq!(s, before, "{d}");
        }
    }

    /// Twisting back by the exact negated increments returns the spin and the torque bit for bit;
    /// after a slip the spring keeps its offset (friction), and the total spin still returns.
    #[test]
    fn twisting_back_returns_exactly_and_a_slip_keeps_its_offset() {
        let incs: [f32; 5] = [3.1e-4, -1.7e-4, 2.9e-5, 4.4e-4, -6.0e-6];
        let mut s = SpinSpring::default();
        let _ = s.update(0.0123, 0.05, 1.0);
        let start = s;
        for _ in 0..10_000 {
            for d in incs {
                let _ = s.update(d, 0.05, 1.0);
            }
            for d in incs.iter().rev() {
                let _ = s.update(-*d, 0.05, 1.0);
            }
        }
        assert_eq!(s, start);
        // Slip: limit 1e-3 rad (τ_max 5e-5 N·m at k_z 0.05).
        let mut s = SpinSpring::default();
        let (_, sat) = s.update(0.004, 0.05, 5e-5);
        assert!(sat);
        // Back by the limit: the spring is unwound (to the rounding of τ_max/k_z = 1e-3 in f32 and
        // of the truncation to 2⁻⁴⁴ rad: measured 1.2e-10 rad; bound 4e-10), 3 mrad of slip stay
        // in the total.
        let (tau, sat) = s.update(-0.001, 0.05, 5e-5);
        assert!(!sat);
        assert!(
            s.elastic_rad.abs() < 4e-10 && tau.abs() < 0.05 * 4e-10,
            "{}",
            s.elastic_rad
        );
        assert!(
            // Measured exact; bound 1 ulp of 0.003 (2.3e-10 rad), an ulp argument.
            (s.accumulated_rad - 0.003).abs() <= 2.3e-10,
            "{}",
            s.accumulated_rad
        );
    }

    /// The bit-pattern range test against the float comparisons, on both sides of each end.
    #[test]
    fn k_z_range_test_is_the_float_one() {
        let up = |x: f32| f32::from_bits(x.to_bits() + 1);
        for k in [
            0.0f32,
            -0.0,
            f32::from_bits(1),
            1.0e-3,
            0.01,
            K_Z_MAX,
            up(K_Z_MAX),
            -1.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ] {
            assert_eq!(k_z_in_range(k), k > 0.0 && k <= K_Z_MAX, "{k}");
        }
    }

    /// The reference of [`SpinSpring::update_within`]: its old formulation, the share left by the
    /// tangential load through a division and a square root (libm), then `update`.
    fn within_reference(
        s: &mut SpinSpring,
        dphi: f32,
        k_z: f32,
        t: f32,
        ft2: f32,
        f2: f32,
    ) -> (f32, bool) {
        let used = if f2 > 0.0 { ft2 / f2 } else { 1.0 };
        let left = if used < 1.0 {
            crate::Libm::sqrt(1.0 - used)
        } else {
            0.0
        };
        s.update(dphi, k_z, t * left)
    }

    /// The fast path changes nothing: over loads swept across the limit surface (from far inside
    /// to outside, and within a few ulps of the margin's edge), stiffnesses on both sides of the
    /// fast test's range (0, 1e3, 2e3 N·m/rad), torsion limits on both sides of 1e-30 N·m, and
    /// NaN, the torque, the saturation and the whole spring equal the reference bit for bit.
    #[test]
    fn update_within_equals_the_square_root_formulation() {
        let mut x = 0x1234_5678u32;
        let mut rnd = move || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x as f32 / u32::MAX as f32
        };
        let (mut fast, mut slow) = (0u32, 0u32);
        for &k_z in &[0.01f32, 0.0, 1.0e3, 2.0e3, 1.0e-3] {
            for &t in &[4.7e-3f32, 1.0e-30, 0.99e-30, 0.0, 2.0, f32::NAN] {
                let (mut a, mut b) = (SpinSpring::default(), SpinSpring::default());
                for _ in 0..20_000 {
                    let f2 = 1.6f32 * 1.6;
                    // |f_t| from 0 to 1.1·f_max, the twist around the elastic limit.
                    let ft2 = (1.1 * rnd()).powi(2) * f2;
                    let dphi = if k_z > 0.0 {
                        (rnd() - 0.5) * 1.2 * t / k_z
                    } else {
                        rnd() - 0.5
                    };
                    let before = a;
                    let ra = a.update_within::<crate::Libm>(dphi, k_z, t, ft2, f2);
                    let rb = within_reference(&mut b, dphi, k_z, t, ft2, f2);
                    assert_eq!(
                        (ra.0.to_bits(), ra.1),
                        (rb.0.to_bits(), rb.1),
                        "k_z {k_z} t {t}"
                    );
                    assert_eq!(a, b, "k_z {k_z} t {t}");
                    let (x, u) = (k_z * a.elastic_rad / t, ft2 / f2);
                    if x * x + u < 1.0 - INSIDE_MARGIN && before.offset == a.offset {
                        fast += 1;
                    } else {
                        slow += 1;
                    }
                }
            }
        }
        // Right at the margin's edge: loads a few ulps either side of x² + u = 1 − m.
        let (k_z, t, f2) = (0.01f32, 4.7e-3f32, 2.56f32);
        for i in 0..2000 {
            let x = 0.5 + 0.5 * (i as f32 / 2000.0);
            let edge = 1.0 - INSIDE_MARGIN - x * x;
            for d in -4i32..=4 {
                let ft2 = f32::from_bits((edge * f2).to_bits().wrapping_add(d as u32));
                let el = x * t / k_z;
                let (mut a, mut b) = (SpinSpring::default(), SpinSpring::default());
                let ra = a.update_within::<crate::Libm>(el, k_z, t, ft2, f2);
                let rb = within_reference(&mut b, el, k_z, t, ft2, f2);
                assert_eq!(
                    (ra.0.to_bits(), ra.1, a),
                    (rb.0.to_bits(), rb.1, b),
                    "x {x} d {d}"
                );
            }
        }
        assert!(
            fast > 10_000 && slow > 10_000,
            "both paths exercised: {fast} fast, {slow} slow"
        );
    }
}
