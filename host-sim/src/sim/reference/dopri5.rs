//! One Dormand–Prince 5(4) step (the tableau of Dormand & Prince 1980, First-Same-As-Last), its
//! continuous extension (Matlab's `ntrp45`) and a fixed-step integration used to check the
//! method's order. The adaptive integrator built on them is [`super::rk45::Rk45`].

// Dormand–Prince 5(4) tableau (stage 6 at c = 1; the 7th stage is the next step's first: FSAL).
/// Nodes `c_2 … c_5`.
const C: [f64; 4] = [1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0];
/// Rows 2 to 6 of `A` (one coefficient per earlier stage).
const A2: [f64; 1] = [1.0 / 5.0];
const A3: [f64; 2] = [3.0 / 40.0, 9.0 / 40.0];
const A4: [f64; 3] = [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0];
const A5: [f64; 4] = [
    19372.0 / 6561.0,
    -25360.0 / 2187.0,
    64448.0 / 6561.0,
    -212.0 / 729.0,
];
const A6: [f64; 5] = [
    9017.0 / 3168.0,
    -355.0 / 33.0,
    46732.0 / 5247.0,
    49.0 / 176.0,
    -5103.0 / 18656.0,
];
/// 5th-order weights `b_1 … b_6` (`b_2 = 0`; also the 7th stage's row: FSAL).
const B: [f64; 6] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
];
/// Error weights `e = b(5th) − b*(4th)`, `e_2 = 0`, with b* = (5179/57600, 0, 7571/16695, 393/640,
/// −92097/339200, 187/2100, 1/40).
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// `y + h·Σ c_j k_j` componentwise.
pub(super) fn combine<const N: usize>(
    y: &[f64; N],
    h: f64,
    terms: &[(f64, &[f64; N])],
) -> [f64; N] {
    let mut out = *y;
    for (i, o) in out.iter_mut().enumerate() {
        let s: f64 = terms.iter().map(|(c, k)| c * k[i]).sum();
        *o += h * s;
    }
    out
}

/// One Dormand–Prince step: the 5th-order solution, the error estimate and the seven stages
/// (`k[6] = f(t+h, y_new)`, the FSAL stage).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step<const N: usize> {
    /// 5th-order solution at `t + h`.
    pub y_new: [f64; N],
    /// Error estimate `h·Σ e_j k_j` (difference to the embedded 4th-order solution).
    pub err: [f64; N],
    /// Stages `k_1 … k_7`.
    pub k: [[f64; N]; 7],
}

/// One Dormand–Prince step of size `h` from `(t, y)` with first stage `k1 = f(t, y)`.
/// Costs 6 evaluations of `f`.
pub fn dopri5_step<const N: usize, F>(
    f: &mut F,
    t: f64,
    y: &[f64; N],
    h: f64,
    k1: &[f64; N],
) -> Step<N>
where
    F: FnMut(f64, &[f64; N]) -> [f64; N],
{
    let k2 = f(t + C[0] * h, &combine(y, h, &[(A2[0], k1)]));
    let k3 = f(t + C[1] * h, &combine(y, h, &[(A3[0], k1), (A3[1], &k2)]));
    let k4 = f(
        t + C[2] * h,
        &combine(y, h, &[(A4[0], k1), (A4[1], &k2), (A4[2], &k3)]),
    );
    let k5 = f(
        t + C[3] * h,
        &combine(
            y,
            h,
            &[(A5[0], k1), (A5[1], &k2), (A5[2], &k3), (A5[3], &k4)],
        ),
    );
    let k6 = f(
        t + h,
        &combine(
            y,
            h,
            &[
                (A6[0], k1),
                (A6[1], &k2),
                (A6[2], &k3),
                (A6[3], &k4),
                (A6[4], &k5),
            ],
        ),
    );
    let y_new = combine(
        y,
        h,
        &[
            (B[0], k1),
            (B[2], &k3),
            (B[3], &k4),
            (B[4], &k5),
            (B[5], &k6),
        ],
    );
    let k7 = f(t + h, &y_new);
    let zero = [0.0; N];
    let err = combine(
        &zero,
        h,
        &[
            (E[0], k1),
            (E[2], &k3),
            (E[3], &k4),
            (E[4], &k5),
            (E[5], &k6),
            (E[6], &k7),
        ],
    );
    Step {
        y_new,
        err,
        k: [*k1, k2, k3, k4, k5, k6, k7],
    }
}

// Continuous extension of Matlab's `ntrp45` (Shampine 1986): y(t + s·h) = y + h·Σ_j k_j·(BI_j · [s, s², s³, s⁴]).
// Each row sums to the 5th-order weight b_j, so s = 1 reproduces y_new; 4th-order accurate in between.
const BI: [[f64; 4]; 7] = [
    [1.0, -183.0 / 64.0, 37.0 / 12.0, -145.0 / 128.0],
    [0.0, 0.0, 0.0, 0.0],
    [0.0, 1500.0 / 371.0, -1000.0 / 159.0, 1000.0 / 371.0],
    [0.0, -125.0 / 32.0, 125.0 / 12.0, -375.0 / 64.0],
    [0.0, 9477.0 / 3392.0, -729.0 / 106.0, 25515.0 / 6784.0],
    [0.0, -11.0 / 7.0, 11.0 / 3.0, -55.0 / 28.0],
    [0.0, 3.0 / 2.0, -4.0, 5.0 / 2.0],
];

/// The solution at `t + s·h` (`0 ≤ s ≤ 1`) inside a step taken from `(t, y)` with size `h`, by the
/// continuous extension Matlab's `ode45` uses for output between steps (4th order).
pub fn interpolate<const N: usize>(y: &[f64; N], h: f64, step: &Step<N>, s: f64) -> [f64; N] {
    let powers = [s, s * s, s * s * s, s * s * s * s];
    let mut out = *y;
    for (i, o) in out.iter_mut().enumerate() {
        let mut acc = 0.0;
        for (row, k) in BI.iter().zip(&step.k) {
            let w: f64 = row.iter().zip(&powers).map(|(b, p)| b * p).sum();
            acc += w * k[i];
        }
        *o += h * acc;
    }
    out
}

/// Integrates `[t0, t1]` with `n` equal Dormand–Prince steps (5th-order solution, no error control).
/// Used to check the order of the method. `n = 0` returns `y0`.
pub fn integrate_fixed<const N: usize, F>(
    mut f: F,
    t0: f64,
    t1: f64,
    n: u32,
    y0: [f64; N],
) -> [f64; N]
where
    F: FnMut(f64, &[f64; N]) -> [f64; N],
{
    let mut y = y0;
    if n == 0 {
        return y;
    }
    let h = (t1 - t0) / f64::from(n);
    for i in 0..n {
        let t = t0 + f64::from(i) * h;
        let k1 = f(t, &y);
        y = dopri5_step(&mut f, t, &y, h, &k1).y_new;
    }
    y
}
