//! Contact-path errors in the paper's form: the largest absolute difference along each axis (mm).

use crate::sim::reference::max_abs_diff_per_axis;

/// Largest |Δx|, |Δy|, |Δz| (mm) between two runs' contact paths, on the plane (object frame) and on the
/// sphere (fingertip frame). The paper reports "0.004 mm, 0.004 mm, 0.001 mm along x, y, z".
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PathErrors {
    /// Plane path, per axis, mm.
    pub plane_mm: [f64; 3],
    /// Sphere path, per axis, mm.
    pub sphere_mm: [f64; 3],
}

impl PathErrors {
    /// Errors of paths `(plane, sphere)` (m) against reference paths (m). Paths of different lengths
    /// count as infinitely wrong.
    pub fn between(
        plane: &[[f64; 3]],
        sphere: &[[f64; 3]],
        ref_plane: &[[f64; 3]],
        ref_sphere: &[[f64; 3]],
    ) -> PathErrors {
        if plane.len() != ref_plane.len() || sphere.len() != ref_sphere.len() {
            return PathErrors {
                plane_mm: [f64::INFINITY; 3],
                sphere_mm: [f64::INFINITY; 3],
            };
        }
        let mm = |v: [f64; 3]| v.map(|m| m * 1e3);
        PathErrors {
            plane_mm: mm(max_abs_diff_per_axis(plane, ref_plane)),
            sphere_mm: mm(max_abs_diff_per_axis(sphere, ref_sphere)),
        }
    }

    /// The single figure used to rank and chart: the largest of the six per-axis errors (mm). A NaN
    /// anywhere gives infinity (a broken run must not look accurate).
    pub fn max_mm(&self) -> f64 {
        self.plane_mm
            .iter()
            .chain(&self.sphere_mm)
            .fold(
                0.0f64,
                |m, &e| if e.is_nan() { f64::INFINITY } else { m.max(e) },
            )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn per_axis_in_millimetres_and_the_largest_of_six() {
        let p = [[0.0, 0.0, 0.0], [1e-3, 2e-3, 0.0]];
        let q = [[0.0, 0.0, 0.0], [1e-3, 2.5e-3, 0.0]];
        let s = [[0.0, 0.0, -0.01], [0.0, 0.0, -0.01]];
        let t = [[0.0, 0.0, -0.01], [1e-6, 0.0, -0.01]];
        let e = PathErrors::between(&p, &s, &q, &t);
        // 0.5e-3 m = 0.5 mm along y on the plane; 1e-6 m = 1e-3 mm along x on the sphere
        // (measured exact).
        assert_eq!((e.plane_mm[0], e.plane_mm[1]), (0.0, 0.5));
        assert_eq!(e.sphere_mm[0], 1e-3);
        assert_eq!(e.max_mm(), 0.5);
    }

    #[test]
    fn mismatched_lengths_and_nan_are_never_accurate() {
        let a = [[0.0; 3]];
        let e = PathErrors::between(&a, &a, &[], &a);
        assert_eq!(e.max_mm(), f64::INFINITY);
        let nan = PathErrors {
            plane_mm: [0.0, f64::NAN, 0.0],
            sphere_mm: [0.0; 3],
        };
        assert_eq!(nan.max_mm(), f64::INFINITY);
    }
}
