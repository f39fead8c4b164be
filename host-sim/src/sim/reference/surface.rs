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
//! "Outward" means out of the body, towards the other body in contact: for the bowl (the inside of a
//! sphere) it points to the sphere's centre, so the bowl's `K` is negative.

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
    /// A bowl: the inside of a sphere of radius `radius` (m) centred at the body's origin, with the
    /// mirrored longitude/latitude chart `c(u, v) = radius · A · (cos v cos u, −cos v sin u, sin v)`
    /// (the longitude runs the other way, so that `z = x × y` points inwards, out of the bowl's material
    /// and towards a fingertip inside it). Then `x = A(−sin u, −cos u, 0)`, `y = A(−sin v cos u,
    /// sin v sin u, cos v)`, `z = A(−cos v cos u, cos v sin u, −sin v) = −c/radius`, and
    /// `M = diag(radius·cos v, radius)`, `K = −I/radius` (`z_α = −c_α/radius`), `T = [tan v / radius, 0]`.
    /// Singular at the poles `v = ±π/2`, like the sphere; the chart's origin is the direction `A·e_x`,
    /// see [`Surface::bowl_centred`].
    Bowl { radius: f64, chart: Rotation3<f64> },
    /// A cylinder of radius `radius` (m) whose axis is the body's `x` axis, chart
    /// `c(u, v) = (u, radius·sin v, radius·cos v)`: `u` (m) along the axis, `v` (rad) around it from `+z`
    /// towards `+y`. Then `x = (1, 0, 0)`, `y = (0, cos v, −sin v)`, `z = (0, sin v, cos v)` (outward),
    /// `M = diag(1, radius)`, `K = diag(0, 1/radius)` (flat along the axis, curved around it: the
    /// curvature seen by a rolling contact depends on its direction), `T = 0`. No singularity (`v` is
    /// periodic); `(0, 0)` is the point `(0, 0, radius)` with normal `+z`.
    Cylinder { radius: f64 },
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

    /// A bowl whose chart origin `(0, 0)` is the body-frame direction `centre` (from the bowl's centre to
    /// the point) and whose `x` direction there is the component of `east` perpendicular to `centre`
    /// (any perpendicular if `east` is parallel to `centre`), as [`Surface::sphere_centred`].
    pub fn bowl_centred(radius: f64, centre: &Unit<Vector3<f64>>, east: &Vector3<f64>) -> Self {
        let Surface::Sphere { chart, .. } = Surface::sphere_centred(radius, centre, east) else {
            unreachable!("sphere_centred returns a sphere")
        };
        // The sphere's chart has A·e_y = east and A·e_z = centre × east; the bowl's x at the origin is
        // −A·e_y and its y is A·e_z, so flip the second and third columns (a rotation by π about e_x).
        let m = chart.matrix();
        let flipped =
            Matrix3::from_columns(&[m.column(0).into_owned(), -m.column(1), -m.column(2)]);
        Surface::Bowl {
            radius,
            chart: Rotation3::from_matrix_unchecked(flipped),
        }
    }

    /// The point `c(α)` (m, body frame).
    pub fn point(&self, a: [f64; 2]) -> Vector3<f64> {
        match self {
            Surface::Plane => Vector3::new(a[0], a[1], 0.0),
            Surface::Sphere { radius, chart } => chart * unit_sphere(a) * *radius,
            Surface::Bowl { radius, chart } => chart * unit_sphere([-a[0], a[1]]) * *radius,
            Surface::Cylinder { radius } => {
                let (sv, cv) = a[1].sin_cos();
                Vector3::new(a[0], radius * sv, radius * cv)
            }
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
            Surface::Bowl { chart, .. } => {
                let (su, cu) = a[0].sin_cos();
                let (sv, cv) = a[1].sin_cos();
                let x = Vector3::new(-su, -cu, 0.0);
                let y = Vector3::new(-sv * cu, sv * su, cv);
                let z = Vector3::new(-cv * cu, cv * su, -sv);
                chart.matrix() * Matrix3::from_columns(&[x, y, z])
            }
            Surface::Cylinder { .. } => {
                let (sv, cv) = a[1].sin_cos();
                Matrix3::new(1.0, 0.0, 0.0, 0.0, cv, sv, 0.0, -sv, cv)
            }
        }
    }

    /// Metric tensor `M` (m per unit of coordinate).
    pub fn metric(&self, a: [f64; 2]) -> Matrix2<f64> {
        match self {
            Surface::Plane => Matrix2::identity(),
            Surface::Sphere { radius, .. } | Surface::Bowl { radius, .. } => {
                Matrix2::new(radius * a[1].cos(), 0.0, 0.0, *radius)
            }
            Surface::Cylinder { radius } => Matrix2::new(1.0, 0.0, 0.0, *radius),
        }
    }

    /// Curvature form `K` (1/m).
    pub fn curvature(&self, _a: [f64; 2]) -> Matrix2<f64> {
        match self {
            Surface::Plane => Matrix2::zeros(),
            Surface::Sphere { radius, .. } => Matrix2::identity() / *radius,
            Surface::Bowl { radius, .. } => -Matrix2::identity() / *radius,
            Surface::Cylinder { radius } => Matrix2::new(0.0, 0.0, 0.0, 1.0 / radius),
        }
    }

    /// Torsion form `T` (1/m).
    pub fn torsion(&self, a: [f64; 2]) -> RowVector2<f64> {
        match self {
            Surface::Plane | Surface::Cylinder { .. } => RowVector2::zeros(),
            Surface::Sphere { radius, .. } | Surface::Bowl { radius, .. } => {
                RowVector2::new(a[1].tan() / radius, 0.0)
            }
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
            Surface::Bowl { chart, .. } => {
                let s = chart.inverse() * p.normalize();
                [(-s.y).atan2(s.x), s.z.atan2(s.x.hypot(s.y))]
            }
            Surface::Cylinder { .. } => [p.x, p.y.atan2(p.z)],
        }
    }

    /// How close `α` is to a chart singularity: `|latitude|` (rad) for the sphere and the bowl, 0 for
    /// the plane and the cylinder (no singularity).
    pub fn pole_proximity(&self, a: [f64; 2]) -> f64 {
        match self {
            Surface::Plane | Surface::Cylinder { .. } => 0.0,
            Surface::Sphere { .. } | Surface::Bowl { .. } => a[1].abs(),
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

    fn test_bowl() -> Surface {
        Surface::Bowl {
            radius: 0.05,
            chart: Rotation3::from_scaled_axis(Vector3::new(-0.6, 0.2, 0.9)),
        }
    }

    #[test]
    fn sphere_frame_metric_curvature_torsion_match_the_chart() {
        // Measured at worst over the four points: frame x 5.3e-11, y 7.7e-11, x × y − z 2.6e-16,
        // c_u·c_v 6.8e-15 m², metric 6.5e-13 and 7.8e-13 m, curvature 4.0e-9 1/m, torsion
        // 3.8e-9 1/m. Bounds 3×.
        frame_metric_curvature_torsion_match_the_chart(
            test_sphere(),
            ChartBounds {
                frame_x: 1.6e-10,
                frame_y: 2.3e-10,
                right_handed: 7.9e-16,
                orthogonal: 2e-14,
                metric_u: 1.9e-12,
                metric_v: 2.3e-12,
                curvature: 1.2e-8,
                torsion: 1.2e-8,
            },
        );
        let s = test_sphere();
        let a = [0.4, -0.3];
        let z = s.frame(a).column(2).into_owned();
        // Measured 1.2e-16; bound 3×.
        assert!((z - s.point(a).normalize()).norm() < 3.7e-16);
    }

    #[test]
    fn bowl_centred_puts_origin_and_x_where_asked() {
        let c = Unit::new_normalize(Vector3::new(0.2, -0.5, -1.0));
        let east = Vector3::new(1.0, 0.3, 0.0);
        // Measured exact (0) for the origin, the frame's x and z and the chart's determinant: the
        // chart's columns are these very vectors (sin 0 and cos 0 are exact), so equality.
        let b = Surface::bowl_centred(0.05, &c, &east);
        assert_eq!(b.point([0.0, 0.0]), c.into_inner() * 0.05);
        let f = b.frame([0.0, 0.0]);
        let e_perp = (east - c.into_inner() * c.dot(&east)).normalize();
        assert_eq!(f.column(0), e_perp);
        assert_eq!(f.column(2), -c.into_inner());
        if let Surface::Bowl { chart, .. } = b {
            assert_eq!(chart.matrix().determinant(), 1.0);
        } else {
            unreachable!()
        }
    }

    #[test]
    fn bowl_frame_metric_curvature_torsion_match_the_chart() {
        // Measured at worst over the four points: frame x 4.8e-11, y 1.05e-10, x × y − z 1.6e-16,
        // c_u·c_v 1.2e-13 m², metric 2.2e-12 and 4.7e-12 m, curvature 8.8e-10 1/m, torsion
        // 2.3e-9 1/m. Bounds 3×.
        frame_metric_curvature_torsion_match_the_chart(
            test_bowl(),
            ChartBounds {
                frame_x: 1.4e-10,
                frame_y: 3.1e-10,
                right_handed: 4.7e-16,
                orthogonal: 3.7e-13,
                metric_u: 6.5e-12,
                metric_v: 1.4e-11,
                curvature: 2.7e-9,
                torsion: 7e-9,
            },
        );
        // The normal points to the centre (into the bowl's hollow): measured 2.5e-16; bound 3×.
        let b = test_bowl();
        let a = [0.4, -0.3];
        let z = b.frame(a).column(2).into_owned();
        assert!((z + b.point(a).normalize()).norm() < 7.6e-16);
    }

    #[test]
    fn cylinder_frame_metric_curvature_torsion_match_the_chart() {
        // Measured at worst over the four points: frame y 3.1e-11, metric 1.0e-12 and 6.8e-12 m,
        // curvature 1.3e-10 1/m; bounds 3×. The axis direction is exact: x, x × y − z, c_u·c_v and
        // the torsion (the x column is constant) measured 0, asserted 0.
        frame_metric_curvature_torsion_match_the_chart(
            Surface::Cylinder { radius: 0.05 },
            ChartBounds {
                frame_x: 0.0,
                frame_y: 9.3e-11,
                right_handed: 0.0,
                orthogonal: 0.0,
                metric_u: 3e-12,
                metric_v: 2e-11,
                curvature: 4e-10,
                torsion: 0.0,
            },
        );
        let c = Surface::Cylinder { radius: 0.05 };
        assert_eq!(c.point([0.0, 0.0]), Vector3::new(0.0, 0.0, 0.05));
        assert_eq!(c.frame([0.0, 0.0]), Matrix3::identity());
        // Outward: the normal is the radial direction in the y-z plane (measured 1.1e-16; bound 3×).
        let a = [0.03, 2.2];
        let p = c.point(a);
        let radial = Vector3::new(0.0, p.y, p.z).normalize();
        assert!((c.frame(a).column(2) - radial).norm() < 3.3e-16);
    }

    /// Each surface's measured worst differences, ×3 (`<=`, so 0 asserts exactness).
    struct ChartBounds {
        /// |c_u/|c_u| − x| and |c_v/|c_v| − y|.
        frame_x: f64,
        frame_y: f64,
        /// |x × y − z|.
        right_handed: f64,
        /// |c_u·c_v|, m².
        orthogonal: f64,
        /// |m_uu − |c_u||, |m_vv − |c_v||, m (or 1 for the cylinder's length coordinate).
        metric_u: f64,
        metric_v: f64,
        /// Largest element of K and T against the finite differences, 1/m.
        curvature: f64,
        torsion: f64,
    }

    /// Independent check by finite differences of `c(α)` and of the frame, against the closed forms.
    fn frame_metric_curvature_torsion_match_the_chart(s: Surface, b: ChartBounds) {
        let points = match s {
            // The cylinder's first coordinate is a length (m): points within a few cm of the origin.
            Surface::Cylinder { .. } => [[0.0, 0.0], [0.02, -0.3], [-0.04, 0.9], [0.03, 3.0]],
            _ => [[0.0, 0.0], [0.4, -0.3], [-2.0, 0.9], [3.0, -1.2]],
        };
        for a in points {
            let (cu, cv) = partials(&s, a);
            let f = s.frame(a);
            let (x, y, z) = (f.column(0), f.column(1), f.column(2));
            // Gauss frame from the chart's partials (good to ~1e-10 relative, see `partials`); z outward.
            assert!((cu.normalize() - x).norm() <= b.frame_x, "x at {a:?}");
            assert!((cv.normalize() - y).norm() <= b.frame_y, "y at {a:?}");
            assert!((x.cross(&y) - z).norm() <= b.right_handed, "z at {a:?}");
            assert!(
                cu.dot(&cv).abs() <= b.orthogonal,
                "chart must be orthogonal"
            );
            // Metric.
            let m = s.metric(a);
            assert!((m[(0, 0)] - cu.norm()).abs() <= b.metric_u, "m_uu at {a:?}");
            assert!((m[(1, 1)] - cv.norm()).abs() <= b.metric_v, "m_vv at {a:?}");
            // Curvature and torsion from differences of the unit frame vectors: round-off ~1e-16/1e-6 = 1e-10
            // per component, divided by |c_u| ≥ 0.01·cos(1.2) ≈ 3.6e-3 m gives ≤ ~3e-8 1/m; K = 100 1/m.
            // Measured ≤ 4e-9 1/m (each surface's figure at its call).
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
            assert!(
                (k - s.curvature(a)).abs().max() <= b.curvature,
                "K at {a:?}"
            );
            let t = RowVector2::new(
                y.dot(&fu.column(0)) / cu.norm(),
                y.dot(&fv.column(0)) / cv.norm(),
            );
            assert!((t - s.torsion(a)).abs().max() <= b.torsion, "T at {a:?}");
        }
    }

    #[test]
    fn coords_inverts_point() {
        for s in [
            test_sphere(),
            test_bowl(),
            Surface::Cylinder { radius: 0.05 },
        ] {
            // Measured 4.4e-16 and 2.2e-16 at worst; bounds 3×.
            for a in [[0.0, 0.0], [0.4, -0.3], [-2.0, 0.9], [3.0, -1.2]] {
                let b = s.coords(&s.point(a));
                assert!((b[0] - a[0]).abs() < 1.3e-15 && (b[1] - a[1]).abs() < 6.7e-16);
            }
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
        // The origin and the frame's x measured exact (the chart's columns are these vectors).
        let s = Surface::sphere_centred(0.01, &c, &east);
        assert_eq!(s.point([0.0, 0.0]), c.into_inner() * 0.01);
        let x = s.frame([0.0, 0.0]).column(0).into_owned();
        let e_perp = (east - c.into_inner() * c.dot(&east)).normalize();
        assert_eq!(x, e_perp);
        // Degenerate east (parallel to centre): still a valid rotation. Measured 2.5e-16 off
        // orthonormal (bound 3×) and a determinant of exactly 1.
        if let Surface::Sphere { chart, .. } = Surface::sphere_centred(0.01, &c, &c.into_inner()) {
            let m = chart.matrix();
            assert!((m.transpose() * m - Matrix3::identity()).norm() < 7.5e-16);
            assert_eq!(m.determinant(), 1.0);
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
