//! The few f64 3-vector and 3×3 matrix operations the plant needs, written out so that the
//! plant runs fast in unoptimised test builds too (a generic linear-algebra crate costs ~10× more
//! per sub-step there).

use std::ops::{Add, AddAssign, Mul, Neg, Sub};

/// A 3-vector of f64.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct V3(pub [f64; 3]);

impl V3 {
    pub const ZERO: V3 = V3([0.0; 3]);

    pub const fn new(x: f64, y: f64, z: f64) -> V3 {
        V3([x, y, z])
    }
    pub fn x(self) -> f64 {
        self.0[0]
    }
    pub fn y(self) -> f64 {
        self.0[1]
    }
    pub fn z(self) -> f64 {
        self.0[2]
    }
    pub fn dot(self, o: V3) -> f64 {
        self.0[0] * o.0[0] + self.0[1] * o.0[1] + self.0[2] * o.0[2]
    }
    pub fn cross(self, o: V3) -> V3 {
        let [a, b, c] = self.0;
        let [d, e, f] = o.0;
        V3([b * f - c * e, c * d - a * f, a * e - b * d])
    }
    pub fn norm_squared(self) -> f64 {
        self.dot(self)
    }
    pub fn norm(self) -> f64 {
        self.norm_squared().sqrt()
    }
}

impl From<[f64; 3]> for V3 {
    fn from(a: [f64; 3]) -> V3 {
        V3(a)
    }
}
impl From<V3> for [f64; 3] {
    fn from(v: V3) -> [f64; 3] {
        v.0
    }
}
impl Add for V3 {
    type Output = V3;
    fn add(self, o: V3) -> V3 {
        V3([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }
}
impl AddAssign for V3 {
    fn add_assign(&mut self, o: V3) {
        *self = *self + o;
    }
}
impl Sub for V3 {
    type Output = V3;
    fn sub(self, o: V3) -> V3 {
        V3([self.0[0] - o.0[0], self.0[1] - o.0[1], self.0[2] - o.0[2]])
    }
}
impl Mul<f64> for V3 {
    type Output = V3;
    fn mul(self, s: f64) -> V3 {
        V3([self.0[0] * s, self.0[1] * s, self.0[2] * s])
    }
}
impl Neg for V3 {
    type Output = V3;
    fn neg(self) -> V3 {
        self * -1.0
    }
}

/// A 3×3 matrix stored as three rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct M3(pub [V3; 3]);

impl M3 {
    pub fn from_rows(rows: [V3; 3]) -> M3 {
        M3(rows)
    }
    pub fn from_columns(cols: [V3; 3]) -> M3 {
        M3(cols).transpose()
    }
    pub fn identity() -> M3 {
        M3([
            V3::new(1.0, 0.0, 0.0),
            V3::new(0.0, 1.0, 0.0),
            V3::new(0.0, 0.0, 1.0),
        ])
    }
    pub fn transpose(self) -> M3 {
        let r = self.0;
        M3([0, 1, 2].map(|j| V3([r[0].0[j], r[1].0[j], r[2].0[j]])))
    }
    /// Row i, column j.
    pub fn at(self, i: usize, j: usize) -> f64 {
        self.0[i].0[j]
    }
    pub fn column(self, j: usize) -> V3 {
        V3([self.0[0].0[j], self.0[1].0[j], self.0[2].0[j]])
    }
    pub fn mul_vec(self, v: V3) -> V3 {
        V3([self.0[0].dot(v), self.0[1].dot(v), self.0[2].dot(v)])
    }
    pub fn mul_mat(self, o: M3) -> M3 {
        let cols = [0, 1, 2].map(|j| self.mul_vec(o.column(j)));
        M3::from_columns(cols)
    }
    pub fn scale(self, s: f64) -> M3 {
        M3(self.0.map(|r| r * s))
    }
    pub fn plus(self, o: M3) -> M3 {
        M3([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }
    pub fn determinant(self) -> f64 {
        self.0[0].dot(self.0[1].cross(self.0[2]))
    }
    /// Inverse by the adjugate (its columns are r₁×r₂, r₂×r₀, r₀×r₁ over det); None if det = 0.
    pub fn inverse(self) -> Option<M3> {
        let [r0, r1, r2] = self.0;
        let det = self.determinant();
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = 1.0 / det;
        Some(M3::from_columns([
            r1.cross(r2) * inv,
            r2.cross(r0) * inv,
            r0.cross(r1) * inv,
        ]))
    }
    /// Solve A·x = b for symmetric positive definite A by Cholesky; None if A is not SPD.
    pub fn solve_spd(self, b: V3) -> Option<V3> {
        let a = |i: usize, j: usize| self.at(i, j);
        let l00 = a(0, 0);
        if l00 <= 0.0 {
            return None;
        }
        let l00 = l00.sqrt();
        let l10 = a(1, 0) / l00;
        let l20 = a(2, 0) / l00;
        let d1 = a(1, 1) - l10 * l10;
        if d1 <= 0.0 {
            return None;
        }
        let l11 = d1.sqrt();
        let l21 = (a(2, 1) - l20 * l10) / l11;
        let d2 = a(2, 2) - l20 * l20 - l21 * l21;
        if d2 <= 0.0 {
            return None;
        }
        let l22 = d2.sqrt();
        // L·y = b, then Lᵀ·x = y.
        let y0 = b.x() / l00;
        let y1 = (b.y() - l10 * y0) / l11;
        let y2 = (b.z() - l20 * y0 - l21 * y1) / l22;
        let x2 = y2 / l22;
        let x1 = (y1 - l21 * x2) / l11;
        let x0 = (y0 - l10 * x1 - l20 * x2) / l00;
        let x = V3([x0, x1, x2]);
        x.0.iter().all(|v| v.is_finite()).then_some(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Vector3};

    fn na(m: M3) -> Matrix3<f64> {
        Matrix3::from_fn(|i, j| m.at(i, j))
    }

    #[test]
    fn operations_match_nalgebra() {
        let a = M3::from_rows([
            V3::new(2.0, -1.0, 0.5),
            V3::new(0.3, 4.0, -2.0),
            V3::new(1.0, 0.7, 3.0),
        ]);
        let b = V3::new(0.2, -1.5, 2.5);
        let nb = Vector3::new(0.2, -1.5, 2.5);
        // Exact-arithmetic identities evaluated in f64. The products, the SPD solve and the
        // cross product measured identical to nalgebra's, the determinant too; the bound is 4 ulp
        // of each value rather than equality, as the two libraries may order the sums
        // differently. The inverse measured 1.4e-17 off nalgebra's and A·A⁻¹ 2.2e-16 off I:
        // bounds 3×.
        let ulps = |x: f64, y: f64| (x - y).abs() <= 4.0 * f64::EPSILON * y.abs();
        let close = |x: V3, y: Vector3<f64>| (0..3).all(|k| ulps(x.0[k], y[k]));
        assert!(close(a.mul_vec(b), na(a) * nb));
        assert!(ulps(a.determinant(), na(a).determinant()));
        let inv = a.inverse().unwrap();
        let ninv = na(a).try_inverse().unwrap();
        assert!((na(inv) - ninv).abs().max() < 4.2e-17);
        assert!((na(a.mul_mat(inv)) - Matrix3::identity()).abs().max() < 6.7e-16);
        assert!((na(a.transpose()) - na(a).transpose()).abs().max() == 0.0);
        let spd = a.transpose().mul_mat(a).plus(M3::identity().scale(0.1));
        let x = spd.solve_spd(b).unwrap();
        let nx = na(spd).cholesky().unwrap().solve(&nb);
        assert!(close(x, nx));
        let not_spd = M3::identity().scale(-1.0);
        assert_eq!(not_spd.solve_spd(b), None);
        assert_eq!(M3([V3::ZERO; 3]).inverse(), None);
        assert!(close(
            V3::new(1.0, 2.0, 3.0).cross(V3::new(-1.0, 0.5, 2.0)),
            Vector3::new(1.0, 2.0, 3.0).cross(&Vector3::new(-1.0, 0.5, 2.0))
        ));
    }
}
