//! The exact stability limit of the linear sampled wall (bilateral spring) of [`super`]:
//! the one-period transition matrix for any output delay, its spectral radius, and the K where
//! that reaches 1.

use super::{periods, Loop, Zoh};
use nalgebra::DMatrix;

/// The one-period transition matrix of the linear (bilateral spring) loop without the
/// passivity stage, state (x[k], v[k], x[k−1], …, x[k−n−2]) for a delay d = n + f.
pub fn transition(l: &Loop, k: f64) -> DMatrix<f64> {
    let (n, frac) = l.delay_parts();
    let t = l.period_s;
    let m = n + 2; // oldest position kept: x[k − m]
    let dim = 2 + m;
    // Index of x[k − j] in the state.
    let ix = |j: usize| if j == 0 { 0 } else { 1 + j };
    let bt = l.b_virtual / t;
    // F[k − i] = −(K + B/T)·x[k − i] + (B/T)·x[k − i − 1] as a row over the state.
    let force_row = |i: usize| {
        let mut r = vec![0.0; dim];
        r[ix(i)] += -k - bt;
        r[ix(i + 1)] += bt;
        r
    };
    let (za, zb) = (
        Zoh::new(&l.device, frac * t),
        Zoh::new(&l.device, (1.0 - frac) * t),
    );
    // (x, v) after the two pieces: Φb·Φa·(x, v) + Φb·Γa·F[k−n−1] + Γb·F[k−n].
    let phi = |z: &Zoh| [[1.0, z.cxv], [0.0, z.cvv]];
    let (pa, pb) = (phi(&za), phi(&zb));
    let mul = |p: [[f64; 2]; 2], q: [[f64; 2]; 2]| {
        let mut r = [[0.0; 2]; 2];
        for i in 0..2 {
            for j in 0..2 {
                r[i][j] = p[i][0] * q[0][j] + p[i][1] * q[1][j];
            }
        }
        r
    };
    let pp = if frac > 0.0 { mul(pb, pa) } else { pb };
    let ga = [za.cxf, za.cvf];
    let gba = [
        pb[0][0] * ga[0] + pb[0][1] * ga[1],
        pb[1][0] * ga[0] + pb[1][1] * ga[1],
    ];
    let gb = [zb.cxf, zb.cvf];
    let (fa, fb) = (force_row(n + 1), force_row(n));
    let mut mat = DMatrix::zeros(dim, dim);
    for r in 0..2 {
        mat[(r, 0)] += pp[r][0];
        mat[(r, 1)] += pp[r][1];
        for j in 0..dim {
            if frac > 0.0 {
                mat[(r, j)] += gba[r] * fa[j];
            }
            mat[(r, j)] += gb[r] * fb[j];
        }
    }
    // Shift the history: x[k+1−1] = x[k], x[k+1−j] = x[k−(j−1)].
    mat[(ix(1), ix(0))] = 1.0;
    for j in 2..=m {
        mat[(ix(j), ix(j - 1))] = 1.0;
    }
    mat
}

/// Spectral radius of the loop's transition matrix at stiffness `k`.
pub fn spectral_radius(l: &Loop, k: f64) -> f64 {
    transition(l, k)
        .complex_eigenvalues()
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max)
}

/// The exact stability limit of the linear sampled loop: the K where the spectral radius reaches
/// 1, by bisection to 1e-9 relative. Searched in [1e-2, 1e9] N/m.
pub fn eigen_kmax(l: &Loop) -> Option<f64> {
    let unstable = |k: f64| spectral_radius(l, k) > 1.0 + 1e-12;
    let mut hi = 1e-2;
    while !unstable(hi) {
        hi *= 1.25;
        if hi > 1e9 {
            return None;
        }
    }
    let mut lo = hi / 1.25;
    while hi / lo > 1.0 + 1e-9 {
        let mid = (lo * hi).sqrt();
        if unstable(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(lo)
}

/// The K at which the simulation's criterion switches in the linear regime: where the spectral
/// radius equals 0.5^(1/N), N the periods in `duration_s` (see the module doc). Used to state the
/// detection's resolution against [`eigen_kmax`].
pub fn criterion_kmax(l: &Loop, duration_s: f64) -> Option<f64> {
    let target = (0.5f64.ln() / periods(l, duration_s) as f64).exp();
    let top = eigen_kmax(l)?;
    let (mut lo, mut hi) = (top * 0.5, top);
    if spectral_radius(l, lo) > target {
        return None;
    }
    while hi / lo > 1.0 + 1e-9 {
        let mid = (lo * hi).sqrt();
        if spectral_radius(l, mid) > target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(lo)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiments::stability::haptic::{delayed_estimate_kmax, Device};

    /// For a fractional delay the exact limit follows 2b/((1 + 2d)T) to first order (relative
    /// difference O(bT/m): measured 1.7e-4 to 2.8e-4 at 10 kHz for d = 0 … 1; bound 1e-3), and it
    /// falls monotonically with d between the integer cases.
    #[test]
    fn fractional_delay_limit_follows_the_estimate() {
        let (rate, t) = (10_000.0, 1e-4);
        let mut prev = f64::INFINITY;
        for d in [0.0, 0.25, 0.5, 0.75, 1.0] {
            let e = eigen_kmax(&Loop::wall(Device::DEFAULT, rate, d, 0.0)).unwrap();
            let est = delayed_estimate_kmax(2.0, 0.0, t, d * t);
            assert!((e / est - 1.0).abs() < 1e-3, "d {d}: {e} vs {est}");
            assert!(e < prev, "d {d}");
            prev = e;
        }
    }
}
