//! A scene as the core's contact parameters and local model.
//!
//! Base frame, metres: the first contact point of every built-in surface (the plane, the top of
//! the sphere or the cylinder, the bottom of the bowl) is [`surface_top_z_m`] above the base
//! origin, on its z axis.

use crate::file::{Scene, SceneProblem, SurfaceSpec};
use softfinger_core::contact::params::{ContactParams, ParamError};
use softfinger_core::control::local_model::{LocalModelSpec, ModelKind, ModelPose};
use softfinger_core::device::delta::DeltaGeometry;
use softfinger_core::Vec3;

/// Why a scene has no valid contact parameters.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// The scene names an unknown method.
    #[error(transparent)]
    Scene(#[from] SceneProblem),
    /// The scene's contact parameters were rejected.
    #[error("scene '{scene}': contact parameters: {source}")]
    Contact {
        /// Scene name.
        scene: String,
        /// The rejected field.
        source: ParamError,
    },
}

/// Height (base frame, m) of the first contact point in every built-in scene: 10 mm below the
/// workspace centre, so a 10 mm fingertip touches with its centre there.
pub fn surface_top_z_m() -> f64 {
    DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M.z as f64 - 0.010
}

/// The scene's contact parameters: the defaults with the scene's overrides.
pub fn contact_params(scene: &Scene) -> Result<ContactParams, ModelError> {
    let c = &scene.contact;
    let d = ContactParams::DEFAULT;
    let p = ContactParams {
        method: scene.method()?,
        fingertip_radius_m: c.fingertip_radius_m.unwrap_or(d.fingertip_radius_m),
        normal_stiffness: c.normal_stiffness.unwrap_or(d.normal_stiffness),
        normal_damping: c.normal_damping.unwrap_or(d.normal_damping),
        tangential_stiffness: c.tangential_stiffness.unwrap_or(d.tangential_stiffness),
        tangential_damping: c.tangential_damping.unwrap_or(d.tangential_damping),
        mu_s: c.mu_s.unwrap_or(d.mu_s),
        mu_k: c.mu_k.unwrap_or(d.mu_k),
        spin_stiffness: c.spin_stiffness.unwrap_or(d.spin_stiffness),
        ..d
    };
    p.validate().map_err(|source| ModelError::Contact {
        scene: scene.name.clone(),
        source,
    })?;
    Ok(p)
}

/// The scene's contact parameters and its surface as a local model (sequence 0): the object's
/// origin placed so the first contact is at [`surface_top_z_m`].
pub fn scene_model(scene: &Scene) -> Result<(ContactParams, LocalModelSpec), ModelError> {
    let contact = contact_params(scene)?;
    let top = surface_top_z_m() as f32;
    let (kind, z) = match scene.surface {
        SurfaceSpec::Plane => (ModelKind::Plane, top),
        SurfaceSpec::Sphere { radius_m } => (
            ModelKind::Sphere {
                radius_m: radius_m as f32,
            },
            top - radius_m as f32,
        ),
        // The bowl's centre is its radius above its bottom (the first contact); the local model
        // checks that it holds the fingertip.
        SurfaceSpec::Bowl { radius_m } => (
            ModelKind::Bowl {
                radius_m: radius_m as f32,
            },
            top + radius_m as f32,
        ),
        // The cylinder's axis (object x, along base x) is its radius below its top.
        SurfaceSpec::Cylinder { radius_m } => (
            ModelKind::Cylinder {
                radius_m: radius_m as f32,
            },
            top - radius_m as f32,
        ),
    };
    let spec = LocalModelSpec {
        kind,
        ..LocalModelSpec::plane(0, ModelPose::at(Vec3::new(0.0, 0.0, z)), &contact)
    };
    Ok((contact, spec))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each built-in surface's first contact lands at the top height; an unknown method and a
    /// rejected contact field are errors naming what is wrong.
    #[test]
    fn built_in_surfaces_touch_at_the_top() {
        let top = surface_top_z_m() as f32;
        for (name, text) in crate::file::BUILT_IN {
            let scene = Scene::parse(text, name).unwrap();
            let (_, spec) = scene_model(&scene).unwrap();
            let z = spec.pose.position_m.z;
            let first = match spec.kind {
                ModelKind::Plane => z,
                ModelKind::Sphere { radius_m } | ModelKind::Cylinder { radius_m } => z + radius_m,
                ModelKind::Bowl { radius_m } => z - radius_m,
            };
            assert!((first - top).abs() < 1e-6, "{name}: {first} vs {top}");
        }
        let mut s = Scene::default_scene();
        s.method = "nope".into();
        assert!(matches!(scene_model(&s), Err(ModelError::Scene(_))));
        let mut s = Scene::default_scene();
        s.contact.mu_s = Some(-1.0);
        let e = scene_model(&s).unwrap_err();
        assert!(e.to_string().contains("contact parameters"), "{e}");
    }
}
