//! The local model an application sends, and its validation.

use crate::contact::params::{ContactParams, Material};
use crate::contact::MAX_PROBE_M;
use crate::control::local_model::pose::ModelPose;
use crate::math::quat::{Quat, UNIT_TOLERANCE};
use crate::validate::{Checked, ParamError};

/// The kind of surface and its size, in the model's object frame.
///
/// The host link carries it as it is (`softfinger_protocol::SurfaceShape`): a new kind is
/// appended, never inserted.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ModelKind {
    /// The plane z = 0, outward normal +z.
    Plane,
    /// A sphere of radius `radius_m` (m) centred at the origin.
    Sphere {
        /// Radius, m.
        radius_m: f32,
    },
    /// The inside of a sphere of radius `radius_m` (m) centred at the origin (a concave bowl,
    /// bottom at (0, 0, −R)); the radius must exceed the fingertip's.
    Bowl {
        /// Radius, m.
        radius_m: f32,
    },
    /// A cylinder of radius `radius_m` (m) along the object x axis.
    Cylinder {
        /// Radius, m.
        radius_m: f32,
    },
}

impl ModelKind {
    /// The radius of a curved kind, m (None for the plane).
    pub fn radius_m(&self) -> Option<f32> {
        match *self {
            ModelKind::Plane => None,
            ModelKind::Sphere { radius_m }
            | ModelKind::Bowl { radius_m }
            | ModelKind::Cylinder { radius_m } => Some(radius_m),
        }
    }
}

/// Smallest sphere or cylinder radius accepted, m (1 mm: a tenth of the fingertip).
pub const MIN_SPHERE_RADIUS_M: f32 = 1.0e-3;
/// Largest sphere, bowl or cylinder radius accepted, m (beyond this a plane renders the same
/// contact).
pub const MAX_SPHERE_RADIUS_M: f32 = 100.0;
/// Longest declared maximum age, s.
pub const MAX_AGE_S: f32 = 60.0;

/// A local model: surface, pose, material, sequence number and maximum age.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LocalModelSpec {
    /// Chosen by the application; a model is accepted only if newer (wrapping) than the one in
    /// force.
    pub seq: u32,
    /// Kind and size.
    pub kind: ModelKind,
    /// Pose of the object frame in the base frame.
    pub pose: ModelPose,
    /// Normal stiffness, N/m.
    pub stiffness_n_per_m: f32,
    /// Normal damping, N·s/m.
    pub damping_n_s_per_m: f32,
    /// Static friction coefficient.
    pub mu_s: f32,
    /// Kinetic friction coefficient (≤ μ_s).
    pub mu_k: f32,
    /// Spin stiffness k_z, N·m/rad.
    pub spin_stiffness_nm_per_rad: f32,
    /// The model is stale this long after it was received, s; 0: never stale (a static scene).
    pub max_age_s: f32,
}

/// Why a model was rejected. Nothing changes when one is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ModelError {
    /// The sequence number is not newer than the one in force.
    StaleSequence,
    /// The pose is not finite, too far from the base frame's origin, or its quaternion is not
    /// unit within [`UNIT_TOLERANCE`].
    BadPose,
    /// The size is out of range for its kind.
    BadSize,
    /// The maximum age is negative, not finite, or above [`MAX_AGE_S`].
    BadAge,
    /// The material gives invalid contact parameters.
    Params(ParamError),
}

impl core::fmt::Display for ModelError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ModelError::StaleSequence => f.write_str("seq is not newer than the model in force"),
            ModelError::BadPose => f.write_str(
                "pose is not finite, too far from the base origin, or its quaternion is not unit",
            ),
            ModelError::BadSize => f.write_str("size is out of range for the model kind"),
            ModelError::BadAge => {
                write!(f, "max_age_s must be finite and in 0 ..= {MAX_AGE_S} s")
            }
            ModelError::Params(e) => write!(f, "material: {e}"),
        }
    }
}

impl core::error::Error for ModelError {}

impl LocalModelSpec {
    /// A plane at `pose` with the material of `params`, never stale.
    pub fn plane(seq: u32, pose: ModelPose, params: &ContactParams) -> LocalModelSpec {
        LocalModelSpec {
            seq,
            kind: ModelKind::Plane,
            pose,
            stiffness_n_per_m: params.normal_stiffness,
            damping_n_s_per_m: params.normal_damping,
            mu_s: params.mu_s,
            mu_k: params.mu_k,
            spin_stiffness_nm_per_rad: params.spin_stiffness,
            max_age_s: 0.0,
        }
    }

    /// This model's material.
    pub fn material(&self) -> Material {
        Material {
            normal_stiffness: self.stiffness_n_per_m,
            normal_damping: self.damping_n_s_per_m,
            mu_s: self.mu_s,
            mu_k: self.mu_k,
            spin_stiffness: self.spin_stiffness_nm_per_rad,
        }
    }

    /// `base` with this model's material.
    pub fn contact_params(&self, base: &ContactParams) -> ContactParams {
        base.with_material(&self.material())
    }

    /// Check everything but the sequence number; `base` supplies the parameters a model does not
    /// carry (fingertip radius, tangential coupling, force limit, state tolerances) and must be
    /// valid. The same as [`Self::check`] then [`Self::fits`].
    pub fn validate(&self, base: &ContactParams) -> Result<(), ModelError> {
        self.check()?;
        self.fits(base)
    }

    /// Every check that needs nothing but the model: pose, size, age and material (the
    /// sequence number and [`Self::fits`] depend on the renderer's state). Thread-mode work on
    /// the firmware: [`Self::checked`] where a host's model arrives.
    pub fn check(&self) -> Result<(), ModelError> {
        let p = self.pose;
        let q: Quat = p.orientation;
        let n2 = q.norm_squared();
        let pose_ok = p.position_m.is_finite()
            && p.position_m.norm_squared() <= MAX_PROBE_M * MAX_PROBE_M
            && q.is_finite()
            && (n2 - 1.0).abs() <= UNIT_TOLERANCE;
        if !pose_ok {
            return Err(ModelError::BadPose);
        }
        if let Some(radius_m) = self.kind.radius_m() {
            if !(MIN_SPHERE_RADIUS_M..=MAX_SPHERE_RADIUS_M).contains(&radius_m) {
                return Err(ModelError::BadSize);
            }
        }
        if !(0.0..=MAX_AGE_S).contains(&self.max_age_s) {
            return Err(ModelError::BadAge);
        }
        // The material's checks read only the material's fields.
        self.contact_params(&ContactParams::DEFAULT)
            .validate_material()
            .map_err(ModelError::Params)
    }

    /// A checked model fits the fingertip of `base`: a bowl must be wider than it (one compare:
    /// the tick's share of the validation).
    #[inline]
    pub fn fits(&self, base: &ContactParams) -> Result<(), ModelError> {
        match self.kind {
            ModelKind::Bowl { radius_m } if radius_m <= base.fingertip_radius_m => {
                Err(ModelError::BadSize)
            }
            _ => Ok(()),
        }
    }

    /// `self` after [`Self::check`] passed, as a [`Checked`] model.
    pub fn checked(self) -> Result<Checked<LocalModelSpec>, ModelError> {
        self.check()?;
        Ok(Checked::assume_checked(self))
    }

    /// True when `self` has the kind and size of `other`: the switch can then move the surface
    /// (slew) and blend the material in the one contact model, instead of cross-fading two.
    pub fn same_surface_as(&self, other: &LocalModelSpec) -> bool {
        self.kind == other.kind
    }

    /// True when `self` has the material of `other`.
    pub fn same_material_as(&self, other: &LocalModelSpec) -> bool {
        self.material() == other.material()
    }
}

/// True when `seq` is newer than `current` in wrapping order (within half the u32 range ahead).
#[inline]
pub fn is_newer(seq: u32, current: u32) -> bool {
    let d = seq.wrapping_sub(current);
    d != 0 && d < 1 << 31
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::vec3::Vec3;

    fn spec() -> LocalModelSpec {
        LocalModelSpec::plane(1, ModelPose::IDENTITY, &ContactParams::DEFAULT)
    }

    #[test]
    fn sequence_order_wraps() {
        assert!(is_newer(2, 1));
        assert!(!is_newer(1, 1));
        assert!(!is_newer(1, 2));
        assert!(is_newer(0, u32::MAX), "wraps");
        assert!(is_newer(1 << 30, 0));
        assert!(!is_newer(1 << 31, 0), "half the range ahead is behind");
    }

    /// Each threshold just inside and just outside.
    #[test]
    fn validation_brackets() {
        let b = ContactParams::DEFAULT;
        assert_eq!(spec().validate(&b), Ok(()));
        let sphere = |r| LocalModelSpec {
            kind: ModelKind::Sphere { radius_m: r },
            ..spec()
        };
        assert_eq!(sphere(1.0e-3).validate(&b), Ok(()));
        assert_eq!(sphere(0.99e-3).validate(&b), Err(ModelError::BadSize));
        assert_eq!(sphere(100.0).validate(&b), Ok(()));
        assert_eq!(sphere(100.01).validate(&b), Err(ModelError::BadSize));
        assert_eq!(sphere(f32::NAN).validate(&b), Err(ModelError::BadSize));
        // A bowl holds the 10 mm fingertip only if its radius is larger.
        let bowl = |r| LocalModelSpec {
            kind: ModelKind::Bowl { radius_m: r },
            ..spec()
        };
        let rho = b.fingertip_radius_m;
        assert_eq!(bowl(rho * 1.001).validate(&b), Ok(()));
        assert_eq!(bowl(rho).validate(&b), Err(ModelError::BadSize));
        assert_eq!(bowl(100.01).validate(&b), Err(ModelError::BadSize));
        let cyl = |r| LocalModelSpec {
            kind: ModelKind::Cylinder { radius_m: r },
            ..spec()
        };
        assert_eq!(cyl(1.0e-3).validate(&b), Ok(()));
        assert_eq!(cyl(0.99e-3).validate(&b), Err(ModelError::BadSize));
        let q = |s: f32| LocalModelSpec {
            pose: ModelPose {
                orientation: Quat::new(s, 0.0, 0.0, 0.0),
                ..ModelPose::IDENTITY
            },
            ..spec()
        };
        // |q|² = s²: tolerance 1e-3 on |q|² − 1.
        assert_eq!(q(1.0004).validate(&b), Ok(()));
        assert_eq!(q(1.0006).validate(&b), Err(ModelError::BadPose));
        let at = |z: f32| LocalModelSpec {
            pose: ModelPose {
                position_m: Vec3::new(0.0, 0.0, z),
                ..ModelPose::IDENTITY
            },
            ..spec()
        };
        assert_eq!(at(99.9).validate(&b), Ok(()));
        assert_eq!(at(100.1).validate(&b), Err(ModelError::BadPose));
        assert_eq!(at(f32::INFINITY).validate(&b), Err(ModelError::BadPose));
        let age = |a| LocalModelSpec {
            max_age_s: a,
            ..spec()
        };
        assert_eq!(age(60.0).validate(&b), Ok(()));
        assert_eq!(age(60.01).validate(&b), Err(ModelError::BadAge));
        assert_eq!(age(-0.001).validate(&b), Err(ModelError::BadAge));
        let mu = LocalModelSpec {
            mu_k: 0.9,
            ..spec()
        };
        assert_eq!(
            mu.validate(&b),
            Err(ModelError::Params(ParamError::KineticAboveStatic))
        );
    }

    /// The split of the validation: a bowl no wider than the fingertip passes the model's own
    /// check (it needs the fingertip to fail) and is refused by `fits`, just above it fits.
    #[test]
    fn check_and_fits_split_the_validation() {
        let b = ContactParams::DEFAULT;
        let rho = b.fingertip_radius_m;
        let bowl = |r| LocalModelSpec {
            kind: ModelKind::Bowl { radius_m: r },
            ..spec()
        };
        assert_eq!(bowl(rho).check(), Ok(()));
        assert_eq!(bowl(rho).fits(&b), Err(ModelError::BadSize));
        assert_eq!(bowl(rho * 1.001).fits(&b), Ok(()));
        assert!(bowl(rho).checked().is_ok());
        let soft = LocalModelSpec {
            mu_k: 0.9,
            ..spec()
        };
        assert_eq!(
            soft.check(),
            Err(ModelError::Params(ParamError::KineticAboveStatic))
        );
    }

    /// The message names the field and, for a material error, the contact parameter.
    #[test]
    fn display_names_the_field() {
        use std::string::ToString;
        let old_age = LocalModelSpec {
            max_age_s: MAX_AGE_S * 2.0,
            ..spec()
        };
        let e: &dyn core::error::Error = &old_age.validate(&ContactParams::DEFAULT).unwrap_err();
        assert_eq!(e.to_string(), "max_age_s must be finite and in 0 ..= 60 s");
        assert_eq!(
            ModelError::Params(ParamError::KineticAboveStatic).to_string(),
            "material: mu_k must not exceed mu_s"
        );
    }
}
