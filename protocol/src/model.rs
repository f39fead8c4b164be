//! What an application asks the device to render: the local model (a surface with its pose and
//! material), the contact parameters, and (virtual device only) where the simulated hand goes.
//!
//! Values are carried as sent; the device validates them and answers with a typed
//! [`crate::ErrorCode`]. Nothing here is clamped.

use serde::{Deserialize, Serialize};
use softfinger_core::contact::params::ContactParams;

/// The kinds of surface a device can render, as listed in [`crate::DeviceInfo::surfaces`].
///
/// New kinds are appended at the end (postcard encodes the variant index), so an older device
/// decodes a newer kind as a decode error, never as another kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SurfaceKind {
    /// An infinite plane.
    Plane,
    /// A sphere.
    Sphere,
    /// The inside of a sphere (appended, see [`crate::PROTOCOL_VERSION`]).
    Bowl,
    /// A cylinder (appended).
    Cylinder,
}

/// A surface with its size, in its own object frame: the core's
/// [`ModelKind`](softfinger_core::control::local_model::ModelKind) itself, encoded as its variant index
/// then its radius (postcard), so its variants are only ever appended (the recorded frames of
/// the protocol's tests pin the encoding).
pub use softfinger_core::control::local_model::ModelKind as SurfaceShape;

impl SurfaceKind {
    /// Every kind, in wire order.
    pub const ALL: [SurfaceKind; 4] = [
        SurfaceKind::Plane,
        SurfaceKind::Sphere,
        SurfaceKind::Bowl,
        SurfaceKind::Cylinder,
    ];

    /// The kind of `shape`.
    pub const fn of(shape: &SurfaceShape) -> SurfaceKind {
        match shape {
            SurfaceShape::Plane => SurfaceKind::Plane,
            SurfaceShape::Sphere { .. } => SurfaceKind::Sphere,
            SurfaceShape::Bowl { .. } => SurfaceKind::Bowl,
            SurfaceShape::Cylinder { .. } => SurfaceKind::Cylinder,
        }
    }
}

/// The local model: the surface the device renders until the next update.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LocalModel {
    /// Sequence number chosen by the application; the device ignores a model whose sequence is not
    /// newer than the one in force (wrapping comparison, see `softfinger_core::control::local_model`).
    pub seq: u32,
    /// Shape and size.
    pub shape: SurfaceShape,
    /// Origin of the object frame in the device base frame, m.
    pub position_m: [f32; 3],
    /// Orientation of the object frame: unit quaternion `[w, x, y, z]` mapping object-frame
    /// vectors to the base frame.
    pub orientation: [f32; 4],
    /// Normal stiffness, N/m.
    pub stiffness_n_per_m: f32,
    /// Normal damping, N·s/m.
    pub damping_n_s_per_m: f32,
    /// Static friction coefficient μ_s.
    pub mu_s: f32,
    /// Kinetic friction coefficient μ_k (≤ μ_s).
    pub mu_k: f32,
    /// Spin stiffness k_z, N·m/rad.
    pub spin_stiffness_nm_per_rad: f32,
    /// The model is stale this long after the device received it unless a newer one came, ms;
    /// its force then fades to zero. 0: never stale (a static scene).
    pub max_age_ms: u16,
}

/// Defines a wire struct carrying some fields of [`ContactParams`], each of the same name, unit
/// and `f32` type, in the order listed (the wire order), with its two conversions: one list for
/// the layout and both directions.
macro_rules! contact_params_subset {
    ($(#[$attr:meta])* pub struct $name:ident { $($field:ident,)+ }) => {
        $(#[$attr])*
        #[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        pub struct $name {
            $(
                #[doc = concat!("[`ContactParams::", stringify!($field), "`], in its unit.")]
                pub $field: f32,
            )+
        }

        impl $name {
            /// The wire view of `p`.
            pub fn of(p: &ContactParams) -> $name {
                $name { $($field: p.$field,)+ }
            }

            /// These values over `base` (the fields the wire does not carry keep `base`'s). Not
            /// checked here: the pipeline refuses invalid parameters (`Pipeline::command`).
            pub fn over(&self, base: &ContactParams) -> ContactParams {
                ContactParams { $($field: self.$field,)+ ..*base }
            }
        }
    };
}

contact_params_subset! {
    /// The contact parameters an application may change (the rest keep the device's values).
    pub struct ContactParamsWire {
        fingertip_radius_m,
        normal_stiffness,
        normal_damping,
        tangential_stiffness,
        tangential_damping,
        mu_s,
        mu_k,
        spin_stiffness,
        max_force_n,
    }
}

/// Where the virtual device's simulated hand should hold the handle (base frame). Real devices
/// answer [`crate::ErrorCode::Unsupported`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HandTarget {
    /// Handle centre, base frame, m.
    pub position_m: [f32; 3],
    /// Wrist joint angles, rad.
    pub wrist_rad: [f32; 3],
}
