//! Contact surfaces with orthogonal charts and their geometric parameters (Montana 1988; Murray, Li & Sastry,
//! *A Mathematical Introduction to Robotic Manipulation* (MLS), §5.2).
//!
//! For a chart `c(α)`, `α = (α₁, α₂)`, with `c_α₁ ⊥ c_α₂`, the Gauss frame at `c(α)` is
//! `x = c_α₁/|c_α₁|`, `y = c_α₂/|c_α₂|`, `z = x × y`, and every chart here is oriented so that `z` is the
//! **outward** normal. The geometric parameters are
//! - metric `M = diag(|c_α₁|, |c_α₂|)` (length per unit of coordinate),
//! - curvature `K = [xᵀ; yᵀ]·[z_α₁/|c_α₁|, z_α₂/|c_α₂|]` (1/length; positive for a convex body),
//! - torsion `T = yᵀ·[x_α₁/|c_α₁|, x_α₂/|c_α₂|]` (1/length).
//!
//! All vectors are in the frame of the body that owns the surface; lengths in metres, angles in radians.

use nalgebra::{Matrix2, Matrix3, Rotation3, RowVector2, Unit, Vector3};

/// A surface of a rigid body with its chart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    /// The plane `z = 0` of the body's frame, chart `c(x, y) = (x, y, 0)` (α in metres); outward normal `+z`.
    /// `M = I`, `K = 0`, `T = 0`. No singularity.
    Plane,
    /// A sphere of radius `radius` (m) centred at the body's origin, with the longitude/latitude chart
    /// `c(u, v) = radius · A · (cos v cos u, cos v sin u, sin v)`, where `A = chart` rotates chart
    /// coordinates into the body frame. `u` is the longitude, `v` the latitude (rad). Then
    /// `x = A(−sin u, cos u, 0)` (east), `y = A(−sin v cos u, −sin v sin u, cos v)` (north),
    /// `z = x × y = A(cos v cos u, cos v sin u, sin v)` (outward), and
    /// `M = diag(radius·cos v, radius)`, `K = I/radius`, `T = [tan v / radius, 0]`.
    /// The chart is singular at the poles `v = ±π/2` (the chart's `±z` axis); the chart's origin
    /// `(u, v) = (0, 0)` is the body-frame direction `A·e_x`, see [`Surface::sphere_centred`].
    Sphere { radius: f64, chart: Rotation3<f64> },
}

impl Surface {
    /// A sphere whose chart origin `(0, 0)` is the body-frame direction `centre` and whose east direction
    /// (`x` of the Gauss frame) there is the component of `east` perpendicular to `centre`, so a contact
    /// moving along `east` travels along the equator, as far from the poles as possible. If `east` is
    /// (nearly) parallel to `centre`, any perpendicular direction is used.
    pub fn sphere_centred(radius: f64, centre: &Unit<Vector3<f64>>, east: &Vector3<f64>) -> Self {
        let c = centre.into_inner();
        let mut e = east - c * c.dot(east);
        if e.norm() < 1e-9 * east.norm().max(1.0) {
            // Any perpendicular: cross with the coordinate axis least aligned with `centre`.
            let a = c.abs();
            let axis = if a.x <= a.y && a.x <= a.z {
                Vector3::x()
            } else if a.y <= a.z {
                Vector3::y()
            } else {
                Vector3::z()
            };
            e = c.cross(&axis);
        }
        let e = e.normalize();
        let pole = c.cross(&e);
        let chart = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[c, e, pole]));
        Surface::Sphere { radius, chart }
    }

    /// The point `c(α)` (m, body frame).
    pub fn point(&self, a: [f64; 2]) -> Vector3<f64> {
        match self {
            Surface::Plane => Vector3::new(a[0], a[1], 0.0),
            Surface::Sphere { radius, chart } => chart * unit_sphere(a) * *radius,
        }
    }

    /// The Gauss frame at `c(α)`: columns `x`, `y`, `z` (outward normal) in the body frame.
    pub fn frame(&self, a: [f64; 2]) -> Matrix3<f64> {
        match self {
            Surface::Plane => Matrix3::identity(),
            Surface::Sphere { chart, .. } => {
                let (su, cu) = a[0].sin_cos();
                let (sv, cv) = a[1].sin_cos();
                let x = Vector3::new(-su, cu, 0.0);
                let y = Vector3::new(-sv * cu, -sv * su, cv);
                let z = Vector3::new(cv * cu, cv * su, sv);
                chart.matrix() * Matrix3::from_columns(&[x, y, z])
            }
        }
    }

    /// Metric tensor `M` (m per unit of coordinate).
    pub fn metric(&self, a: [f64; 2]) -> Matrix2<f64> {
        match self {
            Surface::Plane => Matrix2::identity(),
            Surface::Sphere { radius, .. } => Matrix2::new(radius * a[1].cos(), 0.0, 0.0, *radius),
        }
    }

    /// Curvature form `K` (1/m).
    pub fn curvature(&self, _a: [f64; 2]) -> Matrix2<f64> {
        match self {
            Surface::Plane => Matrix2::zeros(),
            Surface::Sphere { radius, .. } => Matrix2::identity() / *radius,
        }
    }

    /// Torsion form `T` (1/m).
    pub fn torsion(&self, a: [f64; 2]) -> RowVector2<f64> {
        match self {
            Surface::Plane => RowVector2::zeros(),
            Surface::Sphere { radius, .. } => RowVector2::new(a[1].tan() / radius, 0.0),
        }
    }

    /// Chart coordinates of the surface point nearest to the body-frame point `p` (for the sphere: the
    /// point in the direction of `p`; `p` must not be the centre).
    pub fn coords(&self, p: &Vector3<f64>) -> [f64; 2] {
        match self {
            Surface::Plane => [p.x, p.y],
            Surface::Sphere { chart, .. } => {
                let s = chart.inverse() * p.normalize();
                [s.y.atan2(s.x), s.z.atan2(s.x.hypot(s.y))]
            }
        }
    }

    /// How close `α` is to a chart singularity: `|latitude|` (rad) for the sphere, 0 for the plane.
    pub fn pole_proximity(&self, a: [f64; 2]) -> f64 {
        match self {
            Surface::Plane => 0.0,
            Surface::Sphere { .. } => a[1].abs(),
        }
    }
}

/// `(cos v cos u, cos v sin u, sin v)`.
fn unit_sphere(a: [f64; 2]) -> Vector3<f64> {
    let (su, cu) = a[0].sin_cos();
    let (sv, cv) = a[1].sin_cos();
    Vector3::new(cv * cu, cv * su, sv)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn test_sphere() -> Surface {
        Surface::Sphere {
            radius: 0.01,
            chart: Rotation3::from_scaled_axis(Vector3::new(0.3, -0.7, 1.1)),
        }
    }

    /// Central difference of the chart (step 1e-6 rad: truncation ~1e-12 relative, round-off ~1e-10
    /// relative for |c| = 1e-2 m, so derived quantities are good to ~1e-8 relative).
    fn partials(s: &Surface, a: [f64; 2]) -> (Vector3<f64>, Vector3<f64>) {
        let h = 1e-6;
        let d = |i: usize| {
            let mut p = a;
            let mut m = a;
            p[i] += h;
            m[i] -= h;
            (s.point(p) - s.point(m)) / (2.0 * h)
        };
        (d(0), d(1))
    }

    #[test]
    fn sphere_frame_metric_curvature_torsion_match_the_chart() {
        // Independent check by finite differences of c(α) and of the frame, against the closed forms.
        let s = test_sphere();
        for a in [[0.0, 0.0], [0.4, -0.3], [-2.0, 0.9], [3.0, -1.2]] {
            let (cu, cv) = partials(&s, a);
            let f = s.frame(a);
            let (x, y, z) = (f.column(0), f.column(1), f.column(2));
            // Gauss frame from the chart's partials (good to ~1e-10 relative, see `partials`); z outward.
            assert!((cu.normalize() - x).norm() < 1e-8);
            assert!((cv.normalize() - y).norm() < 1e-8);
            assert!((x.cross(&y) - z).norm() < 1e-12);
            assert!((s.point(a).normalize() - z).norm() < 1e-12);
            assert!(cu.dot(&cv).abs() < 1e-12, "chart must be orthogonal");
            // Metric.
            let m = s.metric(a);
            assert!((m[(0, 0)] - cu.norm()).abs() < 1e-10);
            assert!((m[(1, 1)] - cv.norm()).abs() < 1e-10);
            // Curvature and torsion from differences of the unit frame vectors: round-off ~1e-16/1e-6 = 1e-10
            // per component, divided by |c_u| ≥ 0.01·cos(1.2) ≈ 3.6e-3 m gives ≤ ~3e-8 1/m; K = 100 1/m.
            // Asserted within 1e-5 1/m (1e-7 relative).
            let h = 1e-6;
            let dframe = |i: usize| {
                let mut p = a;
                let mut q = a;
                p[i] += h;
                q[i] -= h;
                (s.frame(p) - s.frame(q)) / (2.0 * h)
            };
            let (fu, fv) = (dframe(0), dframe(1));
            let k = Matrix2::new(
                x.dot(&fu.column(2)) / cu.norm(),
                x.dot(&fv.column(2)) / cv.norm(),
                y.dot(&fu.column(2)) / cu.norm(),
                y.dot(&fv.column(2)) / cv.norm(),
            );
            assert!((k - s.curvature(a)).abs().max() < 1e-5, "K at {a:?}");
            let t = RowVector2::new(
                y.dot(&fu.column(0)) / cu.norm(),
                y.dot(&fv.column(0)) / cv.norm(),
            );
            assert!((t - s.torsion(a)).abs().max() < 1e-5, "T at {a:?}");
        }
    }

    #[test]
    fn coords_inverts_point() {
        let s = test_sphere();
        for a in [[0.0, 0.0], [0.4, -0.3], [-2.0, 0.9], [3.0, -1.2]] {
            let b = s.coords(&s.point(a));
            assert!((b[0] - a[0]).abs() < 1e-12 && (b[1] - a[1]).abs() < 1e-12);
        }
        assert_eq!(
            Surface::Plane.coords(&Vector3::new(1.0, 2.0, 0.0)),
            [1.0, 2.0]
        );
    }

    #[test]
    fn sphere_centred_puts_origin_and_east_where_asked() {
        let c = Unit::new_normalize(Vector3::new(0.2, -0.5, -1.0));
        let east = Vector3::new(1.0, 0.3, 0.0);
        let s = Surface::sphere_centred(0.01, &c, &east);
        assert!((s.point([0.0, 0.0]) - c.into_inner() * 0.01).norm() < 1e-15);
        let x = s.frame([0.0, 0.0]).column(0).into_owned();
        let e_perp = (east - c.into_inner() * c.dot(&east)).normalize();
        assert!((x - e_perp).norm() < 1e-14);
        // Degenerate east (parallel to centre): still a valid rotation.
        if let Surface::Sphere { chart, .. } = Surface::sphere_centred(0.01, &c, &c.into_inner()) {
            let m = chart.matrix();
            assert!((m.transpose() * m - Matrix3::identity()).norm() < 1e-14);
            assert!((m.determinant() - 1.0).abs() < 1e-14);
        } else {
            unreachable!()
        }
    }

    #[test]
    fn plane_parameters() {
        let p = Surface::Plane;
        assert_eq!(p.metric([1.0, 2.0]), Matrix2::identity());
        assert_eq!(p.curvature([1.0, 2.0]), Matrix2::zeros());
        assert_eq!(p.torsion([1.0, 2.0]), RowVector2::zeros());
        assert_eq!(p.frame([1.0, 2.0]), Matrix3::identity());
        assert_eq!(p.point([1.0, 2.0]), Vector3::new(1.0, 2.0, 0.0));
    }
}
