//! Part 1: where the decompositions fail.
//!
//! Every (method, math backend) pair decomposes the rotation by angle γ about the unit axis
//! a = (sin α·cos β, sin α·sin β, cos α), where α is the angle of the axis from the contact normal z
//! ("tilt of the axis": α = 0 is a pure spin, α = π/2 a pure rolling about a tangent axis) and β
//! the azimuth of the axis about z.
//!
//! - **Reference** (f64): q = `UnitQuaternion::from_scaled_axis(γ·a)`, w = `q.scaled_axis()`: the
//!   rotation vector that the exact rolling and spin updates need.
//! - **Result** (f32): q rounded to f32, decomposed with [`decompose`]; the result vector is
//!   (δψ, δθ, δφ) (x, y, z components).
//! - **Error**: |(δψ, δθ, δφ) − w| in rad. A flagged result returns zero angles, so its error is
//!   |w|: exactly what a rolling step that skips the increment loses.
//! - **Failure**: the result carries [`Flags::SINGULAR`] or [`Flags::GIMBAL_LOCK`].
//!
//! The magnitude grid is log-spaced over [1e-7, π] and additionally contains γ = π/2 exactly,
//! because the RPY pole (δθ = ±π/2) is reached only by a rotation of exactly π/2 about the y axis
//! (its guard band is |cos δθ| < 1e-4): a log grid alone would step over it. The tilt grid is
//! uniform over [0, π] and contains α = π/2; the azimuth grid is uniform over [0, 2π) and contains
//! β = π/2 and 3π/2 (the ±y axes). Each map cell keeps the worst error over the azimuths and the
//! fraction of azimuths whose result was flagged.

use crate::sim::backend::{dispatch, Backend, MathBackend};
use nalgebra::{UnitQuaternion, Vector3};
use softfinger_core::contact::decompose::{decompose, Method};
use softfinger_core::{Flags, Math, Quat};
use std::f64::consts::{FRAC_PI_2, PI};

/// The math backends compared.
pub const BACKENDS: [Backend; 3] = [Backend::Libm, Backend::Fast, Backend::Micromath];

/// Smallest rotation magnitude swept, rad.
pub const MAG_MIN: f64 = 1e-7;

/// Grid sizes of the sweep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Grid {
    /// Log-spaced magnitudes over [1e-7, π] (π/2 is added on top).
    pub n_mag: usize,
    /// Axis tilts from the normal over [0, π].
    pub n_tilt: usize,
    /// Azimuths over [0, 2π); a multiple of 4 so that ±y are on it.
    pub n_az: usize,
}

impl Grid {
    /// The default: 64 magnitudes (+π/2), 33 tilts (5.6° apart), 16 azimuths (22.5° apart).
    pub const DEFAULT: Grid = Grid {
        n_mag: 64,
        n_tilt: 33,
        n_az: 16,
    };

    /// Magnitudes, rad, ascending: log-spaced over [1e-7, π] plus π/2.
    pub fn magnitudes(&self) -> Vec<f64> {
        let n = self.n_mag.max(2);
        let (l0, l1) = (MAG_MIN.ln(), PI.ln());
        let mut v: Vec<f64> = (0..n)
            .map(|i| (l0 + (l1 - l0) * i as f64 / (n - 1) as f64).exp())
            .collect();
        // Make the end points exact (exp(ln x) may differ from x by an ulp).
        v[0] = MAG_MIN;
        v[n - 1] = PI;
        v.push(FRAC_PI_2);
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    }

    /// Tilts of the axis from the normal, rad, over [0, π].
    pub fn tilts(&self) -> Vec<f64> {
        let n = self.n_tilt.max(2);
        (0..n).map(|i| PI * i as f64 / (n - 1) as f64).collect()
    }

    /// Azimuths of the axis, rad, over [0, 2π).
    pub fn azimuths(&self) -> Vec<f64> {
        let n = self.n_az.max(4);
        (0..n).map(|i| 2.0 * PI * i as f64 / n as f64).collect()
    }
}

/// The unit axis at tilt `alpha` from z and azimuth `beta`. Components that are zero in exact
/// arithmetic (cos(π/2) = 6e-17 in f64) are snapped to zero, so "about y" means exactly y.
pub fn axis(alpha: f64, beta: f64) -> Vector3<f64> {
    let snap = |x: f64| if x.abs() < 1e-15 { 0.0 } else { x };
    let (sa, ca) = (snap(alpha.sin()), snap(alpha.cos()));
    let (sb, cb) = (snap(beta.sin()), snap(beta.cos()));
    Vector3::new(sa * cb, sa * sb, ca)
}

/// One decomposition against the reference: (error in rad, flagged?).
pub fn sample<M: Math>(method: Method, axis: Vector3<f64>, angle: f64) -> (f64, bool) {
    let q = UnitQuaternion::from_scaled_axis(axis * angle);
    let w = q.scaled_axis();
    let q32 = Quat::new(q.w as f32, q.i as f32, q.j as f32, q.k as f32);
    let (a, flags) = decompose::<M>(method, q32);
    let got = Vector3::new(a.psi as f64, a.theta as f64, a.phi as f64);
    let failed = flags.intersects(Flags::SINGULAR | Flags::GIMBAL_LOCK);
    ((got - w).norm(), failed)
}

/// One cell of a map: worst over the azimuths.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cell {
    /// Worst error over the azimuths, rad.
    pub worst_err: f64,
    /// Fraction of the azimuths whose result was flagged, in [0, 1].
    pub fail_frac: f64,
}

/// The map of one (method, backend) pair: `cells[tilt][magnitude]`.
#[derive(Clone, Debug)]
pub struct MethodMap {
    pub method: Method,
    pub backend: Backend,
    pub cells: Vec<Vec<Cell>>,
}

/// Sweep one (method, backend).
pub fn sweep<M: MathBackend>(method: Method, grid: &Grid) -> MethodMap {
    let (mags, tilts, azs) = (grid.magnitudes(), grid.tilts(), grid.azimuths());
    let cells = tilts
        .iter()
        .map(|&alpha| {
            mags.iter()
                .map(|&gamma| {
                    let mut cell = Cell::default();
                    for &beta in &azs {
                        let (e, failed) = sample::<M>(method, axis(alpha, beta), gamma);
                        cell.worst_err = cell.worst_err.max(e);
                        if failed {
                            cell.fail_frac += 1.0;
                        }
                    }
                    cell.fail_frac /= azs.len() as f64;
                    cell
                })
                .collect()
        })
        .collect();
    MethodMap {
        method,
        backend: M::BACKEND,
        cells,
    }
}

/// All methods × backends, in the order `Method::ALL` × [`BACKENDS`].
pub fn sweep_all(grid: &Grid) -> Vec<MethodMap> {
    let mut out = Vec::new();
    for m in Method::ALL {
        for b in BACKENDS {
            out.push(dispatch!(b, M => sweep::<M>(m, grid)));
        }
    }
    out
}

impl MethodMap {
    /// Worst error over all tilts, per magnitude (the line chart).
    pub fn worst_per_magnitude(&self) -> Vec<f64> {
        let n = self.cells.first().map_or(0, Vec::len);
        (0..n)
            .map(|j| {
                self.cells
                    .iter()
                    .map(|row| row[j].worst_err)
                    .fold(0.0, f64::max)
            })
            .collect()
    }

    /// Worst error and failure fraction over the magnitudes in [lo, hi), all tilts and azimuths.
    /// `None` when no grid magnitude falls in the interval.
    pub fn summary(&self, mags: &[f64], lo: f64, hi: f64) -> Option<(f64, f64)> {
        let cols: Vec<usize> = (0..mags.len())
            .filter(|&j| mags[j] >= lo && mags[j] < hi)
            .collect();
        if cols.is_empty() {
            return None;
        }
        let (mut worst, mut fail, mut n) = (0.0f64, 0.0, 0usize);
        for row in &self.cells {
            for &j in &cols {
                worst = worst.max(row[j].worst_err);
                fail += row[j].fail_frac;
                n += 1;
            }
        }
        Some((worst, fail / n as f64))
    }
}

/// The decade bins of the table: [1e-7, 1e-6), ..., [1, π·(1 + ε)) (the last one closes at π).
pub fn decades() -> Vec<(f64, f64, String)> {
    let mut v: Vec<(f64, f64, String)> = (-7..0)
        .map(|e| {
            (
                10f64.powi(e),
                10f64.powi(e + 1),
                format!("1e{e}..1e{}", e + 1),
            )
        })
        .collect();
    v.push((1.0, PI * (1.0 + 1e-12), "1..pi".to_string()));
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use softfinger_core::Libm;

    fn col(mags: &[f64], x: f64) -> usize {
        mags.iter()
            .position(|&m| (m - x).abs() <= 1e-12 * x)
            .unwrap()
    }

    #[test]
    fn grid_holds_the_pole_and_both_ends() {
        let g = Grid::DEFAULT;
        let m = g.magnitudes();
        assert!(m.len() >= 60);
        assert_eq!((m[0], *m.last().unwrap()), (MAG_MIN, PI));
        assert!(m.contains(&FRAC_PI_2));
        assert!(m.windows(2).all(|w| w[0] < w[1]));
        assert!(g.tilts().contains(&FRAC_PI_2) && g.tilts().len() >= 30);
        assert!(g.azimuths().contains(&FRAC_PI_2));
        assert_eq!(axis(FRAC_PI_2, FRAC_PI_2), Vector3::new(0.0, 1.0, 0.0));
    }

    /// Paper-verbatim divides by sin δθ: flagged for every pure spin (tilt 0, any magnitude) and
    /// for every axis once γ·sin α < 1e-6 (its guard); tilted by more than that it is not flagged.
    #[test]
    fn paper_verbatim_is_singular_at_small_tilt() {
        let g = Grid::DEFAULT;
        let map = sweep::<Libm>(Method::PaperVerbatim, &g);
        let (mags, tilts) = (g.magnitudes(), g.tilts());
        // Pure spin: all magnitudes up to π (exclusive: at π the spin axis flips the normal).
        for (j, &m) in mags.iter().enumerate().filter(|(_, &m)| m < 3.0) {
            assert_eq!(map.cells[0][j].fail_frac, 1.0, "tilt 0, |w| = {m}");
        }
        // 1e-7 rad about any axis: sin δθ ≤ 1e-7 < 1e-6 everywhere.
        assert!(map.cells.iter().all(|row| row[0].fail_frac == 1.0));
        // Rolling about a tangent axis by 1 mrad: sin δθ = 1e-3, well clear of the guard.
        let t = tilts.iter().position(|&a| a == FRAC_PI_2).unwrap();
        let j = mags.iter().position(|&m| m > 1e-3).unwrap();
        assert_eq!(map.cells[t][j].fail_frac, 0.0);
    }

    /// RPY is flagged at the pole (π/2 about ±y) and nowhere below magnitude 1 rad: with the axis
    /// anywhere else on the grid cos δθ stays far above its 1e-4 guard.
    #[test]
    fn rpy_is_flagged_near_the_pole_only() {
        let g = Grid::DEFAULT;
        let (mags, tilts) = (g.magnitudes(), g.tilts());
        let map = sweep::<Libm>(Method::Rpy, &g);
        let t = tilts.iter().position(|&a| a == FRAC_PI_2).unwrap();
        let j = col(&mags, FRAC_PI_2);
        // Azimuths π/2 and 3π/2 (±y) of 16 are flagged: 2/16.
        assert_eq!(map.cells[t][j].fail_frac, 2.0 / 16.0);
        let (_, f) = sample::<Libm>(Method::Rpy, Vector3::y(), FRAC_PI_2);
        assert!(f);
        for row in &map.cells {
            for (k, c) in row.iter().enumerate() {
                if mags[k] < 1.0 {
                    assert_eq!(c.fail_frac, 0.0, "|w| = {}", mags[k]);
                }
            }
        }
    }

    /// Exact never fails, and its error stays at the f32 rounding floor: components of the f32
    /// quaternion carry 6e-8 relative rounding and 2·atan2 doubles it. Measured at most
    /// 9.4e-8·(1 + |w|) rad over the cells with libm (3.9e-7 rad at |w| = 3.1); bound 3×:
    /// 2.8e-7·(1 + |w|).
    #[test]
    fn exact_never_fails_and_stays_at_the_f32_floor() {
        let g = Grid::DEFAULT;
        let mags = g.magnitudes();
        let map = sweep::<Libm>(Method::Exact, &g);
        for row in &map.cells {
            for (k, c) in row.iter().enumerate() {
                assert_eq!(c.fail_frac, 0.0);
                assert!(
                    c.worst_err <= 2.8e-7 * (1.0 + mags[k]),
                    "|w| = {}: {}",
                    mags[k],
                    c.worst_err
                );
            }
        }
    }

    /// RPY differs from the rotation vector at second order: for 0.1 rad about (1,1,1)/√3 the
    /// Z-Y-X angles are w + ½(w_z·w_y, −w_z·w_x, w_x·w_y) + O(|w|³) (from the BCH product of the three
    /// elementary rotations), i.e. an error of ½·|w|²/3·√3 ≈ 2.9e-3 rad; the third-order remainder
    /// measured 7.3e-5 rad here; bound 3×: 2.2e-4 rad (13× below the second-order term).
    #[test]
    fn rpy_error_is_second_order() {
        let a = Vector3::new(1.0, 1.0, 1.0).normalize();
        let (e, f) = sample::<Libm>(Method::Rpy, a, 0.1);
        assert!(!f);
        let expected = 0.5 * 0.01 / 3.0 * 3f64.sqrt();
        assert!((e - expected).abs() < 2.2e-4, "{e} vs {expected}");
    }

    #[test]
    fn summary_bins_cover_the_grid() {
        let mags = Grid::DEFAULT.magnitudes();
        let total: usize = decades()
            .iter()
            .map(|(lo, hi, _)| mags.iter().filter(|&&m| m >= *lo && m < *hi).count())
            .sum();
        assert_eq!(total, mags.len());
    }
}
