//! The scalar kernels against closed forms: special angles of sin/cos, atan2 in all four quadrants
//! and on the axes, sqrt of perfect squares, and the trait's contract at 0 and below.

use crate::accuracy::Accuracy;
use core::f32::consts::{FRAC_PI_2, FRAC_PI_3, FRAC_PI_4, FRAC_PI_6, PI};
use core::hint::black_box as bb;
use softfinger_mcu_bench::check::Checker;

/// √3/2 and √2/2, correctly rounded to f32.
const SQRT3_2: f32 = 0.866_025_4;
const SQRT2_2: f32 = core::f32::consts::FRAC_1_SQRT_2;

pub fn checks<M: Accuracy>(c: &mut Checker) {
    // The f32 constants π/6, π/4, ... are off the true angles by ≤ half an ulp (≤ 1.2e-7 at π/2, the
    // largest here); |d sin/dx| ≤ 1, so that adds ≤ 1.2e-7 to the backend's error.
    let t = M::TRIG + 1.2e-7;
    c.close("sin(pi/6) = 1/2", M::sin(bb(FRAC_PI_6)), 0.5, t);
    c.close("sin(pi/2) = 1", M::sin(bb(FRAC_PI_2)), 1.0, t);
    c.close("sin(-pi/4) = -sqrt2/2", M::sin(bb(-FRAC_PI_4)), -SQRT2_2, t);
    c.close("sin(0) = 0", M::sin(bb(0.0)), 0.0, M::TRIG);
    c.close("cos(pi/3) = 1/2", M::cos(bb(FRAC_PI_3)), 0.5, t);
    c.close("cos(0) = 1", M::cos(bb(0.0)), 1.0, M::TRIG);
    // f32 π is 8.7e-8 below π; cos is flat there (error ~ 4e-15).
    c.close("cos(pi) = -1", M::cos(bb(PI)), -1.0, t);
    c.close("cos(-2pi/3) = -1/2", M::cos(bb(-2.0 * FRAC_PI_3)), -0.5, t);
    let (s, co) = M::sin_cos(bb(FRAC_PI_6));
    c.close_all(
        "sin_cos(pi/6) = (1/2, sqrt3/2)",
        &[s, co],
        &[0.5, SQRT3_2],
        t,
    );
    let (s, co) = M::sin_cos(bb(-3.0 * FRAC_PI_4));
    c.close_all("sin_cos(-3pi/4)", &[s, co], &[-SQRT2_2, -SQRT2_2], t);
    // Range reduction: π/6 + 16π ≈ 51.3 is stored with an error ≤ half an ulp = 1.9e-6.
    let big = FRAC_PI_6 + 16.0 * PI;
    c.close(
        "sin(pi/6 + 16 pi) = 1/2",
        M::sin(bb(big)),
        0.5,
        M::TRIG + 2.0e-6,
    );

    // atan2 results up to π; the f32 constants are within half an ulp (1.2e-7) of the true angles.
    let a = M::ATAN2 + 1.2e-7;
    c.close(
        "atan2(1, 1) = pi/4",
        M::atan2(bb(1.0), bb(1.0)),
        FRAC_PI_4,
        a,
    );
    c.close(
        "atan2(1, -1) = 3pi/4",
        M::atan2(bb(1.0), bb(-1.0)),
        3.0 * FRAC_PI_4,
        a,
    );
    c.close(
        "atan2(-1, -1) = -3pi/4",
        M::atan2(bb(-1.0), bb(-1.0)),
        -3.0 * FRAC_PI_4,
        a,
    );
    c.close(
        "atan2(-1, 1) = -pi/4",
        M::atan2(bb(-1.0), bb(1.0)),
        -FRAC_PI_4,
        a,
    );
    c.close(
        "atan2(sqrt3, 1) = pi/3",
        M::atan2(bb(1.732_050_8), bb(1.0)),
        FRAC_PI_3,
        a,
    );
    c.close(
        "atan2(1, 0) = pi/2",
        M::atan2(bb(1.0), bb(0.0)),
        FRAC_PI_2,
        a,
    );
    c.close(
        "atan2(-1, 0) = -pi/2",
        M::atan2(bb(-1.0), bb(0.0)),
        -FRAC_PI_2,
        a,
    );
    c.close("atan2(0, 1) = 0", M::atan2(bb(0.0), bb(1.0)), 0.0, a);
    // atan2(+0, -1) is +π in IEEE/C; the contract's range is (-π, π], so -π would be wrong.
    c.close("atan2(+0, -1) = pi", M::atan2(bb(0.0), bb(-1.0)), PI, a);
    c.ok(
        "atan2(0, 0) = 0 exactly (contract)",
        M::atan2(bb(0.0), bb(0.0)) == 0.0,
    );

    // Perfect squares: the exact root times (1 ± SQRT_REL).
    for (x, r) in [
        (4.0f32, 2.0f32),
        (0.25, 0.5),
        (2.0, core::f32::consts::SQRT_2),
        (9.0e6, 3.0e3),
    ] {
        c.close("sqrt of a known square", M::sqrt(bb(x)), r, r * M::SQRT_REL);
    }
    c.ok("sqrt(0) = 0 (contract)", M::sqrt(bb(0.0)) == 0.0);
    c.ok("sqrt(-1) = 0 (contract)", M::sqrt(bb(-1.0)) == 0.0);
}
