//! Scenes as the protocol's messages: the scene's surface becomes a local model and its contact
//! overrides become contact parameters.

use crate::file::Scene;
use crate::model::scene_model;
use softfinger_core::control::local_model::LocalModelSpec;
use softfinger_protocol::{ContactParamsWire, LocalModel};

/// A core model spec as the wire message, the inverse of [`LocalModel::spec`]: the maximum age
/// rounded to whole ms, saturating at 0 and 65 535 ms.
pub fn to_wire(s: &LocalModelSpec) -> LocalModel {
    let q = s.pose.orientation;
    LocalModel {
        seq: s.seq,
        shape: s.kind,
        position_m: s.pose.position_m.to_array(),
        orientation: [q.w, q.x, q.y, q.z],
        stiffness_n_per_m: s.stiffness_n_per_m,
        damping_n_s_per_m: s.damping_n_s_per_m,
        mu_s: s.mu_s,
        mu_k: s.mu_k,
        spin_stiffness_nm_per_rad: s.spin_stiffness_nm_per_rad,
        max_age_ms: (s.max_age_s * 1000.0).round().clamp(0.0, u16::MAX as f32) as u16,
    }
}

/// The contact parameters and local model (sequence `seq`) of a scene file or built-in name.
pub fn load(name_or_path: &str, seq: u32) -> Result<(ContactParamsWire, LocalModel), String> {
    let scene = Scene::load(name_or_path).map_err(|e| e.to_string())?;
    let (contact, spec) = scene_model(&scene).map_err(|e| e.to_string())?;
    let model = to_wire(&LocalModelSpec { seq, ..spec });
    Ok((ContactParamsWire::of(&contact), model))
}

#[cfg(test)]
mod tests {
    use super::*;
    use softfinger_protocol::SurfaceShape;

    /// Wire → core → wire keeps every field.
    #[test]
    fn built_in_scenes_convert_both_ways() {
        for name in ["finger-on-plane", "finger-on-sphere"] {
            let (_, m) = load(name, 7).unwrap();
            assert_eq!(m.seq, 7);
            assert_eq!(to_wire(&m.spec()), m);
        }
        let (_, s) = load("finger-on-sphere", 1).unwrap();
        assert_eq!(s.shape, SurfaceShape::Sphere { radius_m: 0.05 });
        assert!(load("no-such-scene", 1).is_err());
    }
}
