//! Test motions for the references and the core's rolling: rotation axes covering every direction,
//! and orientation sequences about them, fixed or wandering. Used by the reference's own tests and by
//! the cross-crate rolling test (`tests/rolling_reference.rs`).

use nalgebra::{UnitQuaternion, Vector3};

/// 26 unit directions: the faces, edges and corners of a cube.
pub fn cube_axes() -> Vec<Vector3<f64>> {
    let unit =
        |d: &softfinger_core::Vec3| Vector3::new(d.x as f64, d.y as f64, d.z as f64).normalize();
    softfinger_core::Vec3::CUBE_DIRECTIONS
        .iter()
        .map(unit)
        .collect()
}

/// `n` orientation samples from the identity (where the references start their charts), each turning
/// by `step` rad about `axis` (object frame), or, when `wander`, about `axis` turned by a slowly
/// changing offset.
pub fn motion(axis: &Vector3<f64>, step: f64, n: usize, wander: bool) -> Vec<UnitQuaternion<f64>> {
    let mut q = UnitQuaternion::identity();
    let mut qs = vec![q];
    for k in 1..n {
        let t = k as f64;
        let a = if wander {
            (axis + Vector3::new((0.3 * t).sin(), (0.2 * t).cos(), 0.5 * (0.1 * t).sin()) * 0.6)
                .normalize()
        } else {
            *axis
        };
        q = UnitQuaternion::from_scaled_axis(a * step) * q;
        qs.push(q);
    }
    qs
}
