//! One friction budget for sliding and twisting: the soft finger's limit surface.
//!
//! A contact patch of radius a pressed with f_N can resist a tangential force f_t and a torque τn
//! about the normal together only inside its limit surface (Howe and Cutkosky 1996; the soft-finger
//! proxy of Barbagli et al. 2004; the limit curve of Frisoli et al. 2006). We use the usual
//! ellipsoidal approximation
//!
//! (|f_t|/f_max)² + (τn/τ_max)² ≤ 1,  f_max = μ·f_N,  τ_max = (3π/16)·μ·f_N·a,
//!
//! whose error against the true limit surface of a Hertzian pressure distribution (integrated
//! numerically in f64 by `host-sim limit-surface`) is reported there.
//!
//! Slip direction (maximum dissipation): on the limit surface the slip (tangential slip velocity
//! v, spin rate ω) is along the surface normal, (v, ω) ∝ (f_t/f_max², τn/τ_max²).
//! [`project`] is the elastic-plastic return of a trial (f_t, τn) from a tangential spring K_t
//! and a torsion spring k_z: the closest point of the ellipse in the springs' energy norm, for
//! which the slip (f_trial − f)/K_t, (τ_trial − τ)/k_z is exactly λ·(f/f_max², τ/τ_max²).
//!
//! The patch radius grows with the normal force: a = a_ref·(f_N/f_ref)^γ ([`patch_radius`]); Hertz
//! gives γ = 1/3, human fingertips about 0.2-0.3 (Xydas and Kao 1999).

/// The patch radius a = a_ref·(f_N/f_ref)^γ, m. Zero for f_N ≤ 0 (and for non-finite input).
/// `a_ref` (m) at `f_ref` (N, > 0), exponent `gamma` in [0, 1] (see [`crate::contact::params`]).
pub fn patch_radius(f_n: f32, a_ref: f32, f_ref: f32, gamma: f32) -> f32 {
    if !(f_n > 0.0 && f_ref > 0.0 && f_n.is_finite()) {
        return 0.0;
    }
    let a = a_ref * pow(f_n / f_ref, gamma);
    if a.is_finite() {
        a
    } else {
        0.0
    }
}

/// x^y for x > 0 (finite) and |y·log2 x| < 126, as 2^(y·log2 x) with short series (about 40
/// instructions on the M4F, where libm's powf costs several hundred): log2 of the mantissa m in
/// [1, 2) by the atanh series of t = (m − 1)/(m + 1) to t⁹ (truncation below 2e-6), 2^f
/// for |f| ≤ ½ by Taylor to degree 6 (below 2e-7), the integer part into the exponent bits.
/// Relative error ≤ 5e-6 (tested against f64 over the patch law's range).
pub fn pow(x: f32, y: f32) -> f32 {
    let bits = x.to_bits();
    let e = ((bits >> 23) & 0xff) as i32 - 127;
    let m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    let t = (m - 1.0) / (m + 1.0);
    let t2 = t * t;
    // 2/ln 2 · (t + t³/3 + t⁵/5 + t⁷/7 + t⁹/9)
    let log2m =
        2.885_39 * t * (1.0 + t2 * (1.0 / 3.0 + t2 * (0.2 + t2 * (1.0 / 7.0 + t2 * (1.0 / 9.0)))));
    let l = y * (e as f32 + log2m);
    let in_range = l.abs() < 126.0; // false for NaN too
    if !in_range {
        return if l > 0.0 { f32::INFINITY } else { 0.0 };
    }
    let n = if l >= 0.0 {
        (l + 0.5) as i32
    } else {
        (l - 0.5) as i32
    };
    let f = (l - n as f32) * core::f32::consts::LN_2;
    let p = 1.0
        + f * (1.0
            + f * (0.5
                + f * (1.0 / 6.0 + f * (1.0 / 24.0 + f * (1.0 / 120.0 + f * (1.0 / 720.0))))));
    p * f32::from_bits(((n + 127) as u32) << 23)
}

/// Is (|f_t|² = `ft2`, τ) strictly outside the ellipse with semi-axes `f_max`, `tau_max` scaled by
/// `scale`? No division or square root: ft2·T² + τ²·F² > scale²·F²·T². Degenerate axes (0) admit
/// only zero load.
#[inline]
pub fn outside(ft2: f32, tau: f32, f_max: f32, tau_max: f32, scale: f32) -> bool {
    let (f2, t2) = (f_max * f_max, tau_max * tau_max);
    ft2 * t2 + tau * tau * f2 > scale * scale * f2 * t2
}

/// The closest point of the ellipse (|f|/f_max)² + (τ/τ_max)² ≤ 1 to the trial (|f| = `f_trial`,
/// `tau_trial`) in the norm |Δf|²/K_t + Δτ²/k_z, returned as the factors (s_f, s_τ) in [0, 1] by
/// which the trial force and torque are scaled (1, 1 inside). f = f_trial/(1 + λ·K_t/f_max²),
/// τ = τ_trial/(1 + λ·k_z/τ_max²), λ ≥ 0 the root of the constraint, found by Newton's method
/// from λ = 0 (the constraint is convex and decreasing in λ, so the iterates increase
/// monotonically to the root; 8 iterations reach f32 precision for trials up to 10⁴ times the
/// limit). A zero axis gives zero on that axis.
pub fn project(
    f_trial: f32,
    tau_trial: f32,
    f_max: f32,
    tau_max: f32,
    k_t: f32,
    k_z: f32,
) -> (f32, f32) {
    if !outside(f_trial * f_trial, tau_trial, f_max, tau_max, 1.0) {
        return (1.0, 1.0);
    }
    // Comparisons with NaN are false: a NaN axis or spring counts as none.
    let (tangential, torsional) = (f_max > 0.0 && k_t > 0.0, tau_max > 0.0 && k_z > 0.0);
    if !tangential {
        // No tangential budget (or no spring): the torque alone meets its limit.
        let s = if tau_trial.abs() > tau_max && tau_trial != 0.0 {
            tau_max / tau_trial.abs()
        } else {
            1.0
        };
        return (0.0, s);
    }
    if !torsional {
        let s = if f_trial > f_max {
            f_max / f_trial
        } else {
            1.0
        };
        return (s, 0.0);
    }
    let a = k_t / (f_max * f_max);
    let b = k_z / (tau_max * tau_max);
    let (x2, y2) = (
        (f_trial / f_max) * (f_trial / f_max),
        (tau_trial / tau_max) * (tau_trial / tau_max),
    );
    let mut lam = 0.0f32;
    for _ in 0..8 {
        let (da, db) = (1.0 + lam * a, 1.0 + lam * b);
        let (ga, gb) = (x2 / (da * da), y2 / (db * db));
        let g = ga + gb - 1.0;
        let dg = -2.0 * (ga * a / da + gb * b / db);
        let decreasing = dg < 0.0;
        if !decreasing {
            break;
        }
        let next = lam - g / dg;
        let advanced = next > lam;
        if !advanced {
            break;
        }
        lam = next;
    }
    (1.0 / (1.0 + lam * a), 1.0 / (1.0 + lam * b))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`pow`] against libm's powf (f64 reference: `f64::powf`) over forces from 1e-4 to 1e4
    /// times f_ref and exponents 0 to 1: measured 1.5e-6 relative at worst; bound 5e-6.
    #[test]
    fn pow_matches_the_reference() {
        let mut worst = 0.0f64;
        for i in 0..2000 {
            let x = 10f64.powf(-4.0 + 8.0 * i as f64 / 1999.0) as f32;
            for j in 0..=20 {
                let y = j as f32 / 20.0;
                let r = (x as f64).powf(y as f64);
                worst = worst.max((pow(x, y) as f64 / r - 1.0).abs());
            }
        }
        assert!(worst < 5e-6, "{worst:e}");
        assert_eq!(pow(1.0, 0.3), 1.0);
    }

    /// Hertz: a ∝ f^(1/3); doubling the force grows the patch by 2^(1/3) = 1.259921; γ = 0 is
    /// constant. Measured 1.19e-7 and 5.96e-8 relative; bounds 3x. γ = 0 measured exact.
    #[test]
    fn patch_radius_follows_the_power_law() {
        let a = patch_radius(4.0, 0.005, 2.0, 1.0 / 3.0);
        assert!((a / 0.005 - 1.259_921).abs() < 3.6e-7, "{a}");
        let b = patch_radius(0.5, 0.005, 2.0, 0.25) / (0.005 * 0.25f32.powf(0.25));
        assert!((b - 1.0).abs() < 1.8e-7, "{b}");
        assert_eq!(patch_radius(3.0, 0.005, 2.0, 0.0), 0.005);
        assert_eq!(patch_radius(0.0, 0.005, 2.0, 0.3), 0.0);
        assert_eq!(patch_radius(-1.0, 0.005, 2.0, 0.3), 0.0);
        assert_eq!(patch_radius(f32::NAN, 0.005, 2.0, 0.3), 0.0);
        assert_eq!(patch_radius(f32::INFINITY, 0.005, 2.0, 0.3), 0.0);
    }

    /// The ellipse test just inside and just outside, on both axes and on the diagonal.
    #[test]
    fn outside_is_the_ellipse() {
        let (f, t) = (1.6f32, 0.004f32);
        assert!(!outside(f * f * 0.999, 0.0, f, t, 1.0));
        assert!(outside(f * f * 1.001, 0.0, f, t, 1.0));
        assert!(!outside(0.0, t * 0.999, f, t, 1.0));
        assert!(outside(0.0, t * 1.001, f, t, 1.0));
        let d = core::f32::consts::FRAC_1_SQRT_2;
        assert!(!outside((f * d * 0.999).powi(2), t * d * 0.999, f, t, 1.0));
        assert!(outside((f * d * 1.001).powi(2), t * d * 1.001, f, t, 1.0));
        // Twisting while pushing sideways slips sooner: 80 % of each limit alone is inside, together
        // outside (0.64 + 0.64 > 1).
        assert!(outside((0.8 * f).powi(2), 0.8 * t, f, t, 1.0));
    }

    /// The projection lands on the ellipse and the slip is along its normal, against a brute-force
    /// f64 search over the ellipse (10⁵ points) for the closest point in the energy norm.
    /// Measured over the five trials: on the ellipse to 2.38e-7; slip off the normal 2.5e-7 of its
    /// scale; the brute-force point 9.8e-6·f_max and 1.2e-5·τ_max away (the search's grid);
    /// s_τ 2.98e-8 off 0.4. Bounds 3x.
    #[test]
    fn projection_is_the_closest_point_and_slips_along_the_normal() {
        let (fm, tm, kt, kz) = (1.6f32, 0.004f32, 1000.0f32, 0.01f32);
        for &(ft, tt) in &[
            (2.0f32, 0.003f32),
            (1.0, 0.006),
            (3.0, 0.0),
            (0.0, 0.01),
            (1.5, -0.004),
        ] {
            let (sf, st) = project(ft, tt, fm, tm, kt, kz);
            let (f, t) = (ft * sf, tt * st);
            let on = (f / fm).powi(2) + (t / tm).powi(2);
            assert!((on - 1.0).abs() < 7.2e-7, "({ft}, {tt}): {on}");
            // Slip ∝ normal: (Δf/K_t)·(t/T²) = (Δτ/k_z)·(f/F²).
            let (sv, sw) = ((ft - f) / kt, (tt - t) / kz);
            let cross = sv as f64 * (t / (tm * tm)) as f64 - sw as f64 * (f / (fm * fm)) as f64;
            let scale = (sv.abs() as f64 * (t.abs() / (tm * tm)) as f64).max(1e-30);
            assert!(
                cross.abs() <= 7.6e-7 * scale.max(sw.abs() as f64 * (f / (fm * fm)) as f64),
                "({ft}, {tt})"
            );
            // Brute force.
            let mut best = (f64::INFINITY, 0.0, 0.0);
            for k in 0..100_000 {
                let th = k as f64 / 100_000.0 * std::f64::consts::TAU;
                let (bf, bt) = (fm as f64 * th.cos(), tm as f64 * th.sin());
                let e = (bf - ft as f64).powi(2) / kt as f64 + (bt - tt as f64).powi(2) / kz as f64;
                if e < best.0 {
                    best = (e, bf, bt);
                }
            }
            assert!(
                (best.1 - f as f64).abs() < 3e-5 * fm as f64,
                "({ft}, {tt}) f {f} vs {}",
                best.1
            );
            assert!(
                (best.2 - t as f64).abs() < 3.7e-5 * tm as f64,
                "({ft}, {tt}) t {t} vs {}",
                best.2
            );
        }
        assert_eq!(project(1.0, 0.001, fm, tm, kt, kz), (1.0, 1.0));
        let (sf, st) = project(1.0, 0.01, 0.0, tm, kt, kz);
        assert!(sf == 0.0 && (st - 0.4).abs() < 9e-8, "{st}");
    }
}
