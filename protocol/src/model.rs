//! What an application asks the device to render: the local model (a surface with its pose and
//! material), the contact parameters, and (virtual device only) where the simulated hand goes.
//!
//! Values are carried as sent; the device validates them and answers with a typed
//! [`crate::ErrorCode`]. Nothing here is clamped.

use serde::{Deserialize, Serialize};

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

/// A surface with its size, in its own object frame.
///
/// - `Plane`: the plane z = 0, outward normal +z.
/// - `Sphere`: centred at the object frame's origin.
/// - `Bowl`: the inside of a sphere centred at the object frame's origin (bottom at (0, 0, −R));
///   its radius must exceed the fingertip's.
/// - `Cylinder`: its axis along the object frame's x axis through the origin.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SurfaceShape {
    /// The plane z = 0 of the object frame.
    Plane,
    /// A sphere of radius `radius_m` (m) centred at the object frame's origin.
    Sphere {
        /// Radius, m.
        radius_m: f32,
    },
    /// The inside of a sphere of radius `radius_m` (m) centred at the object frame's origin.
    Bowl {
        /// Radius, m.
        radius_m: f32,
    },
    /// A cylinder of radius `radius_m` (m) along the object frame's x axis.
    Cylinder {
        /// Radius, m.
        radius_m: f32,
    },
}

impl SurfaceShape {
    /// The kind of this shape.
    pub const fn kind(&self) -> SurfaceKind {
        match self {
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

/// The contact parameters an application may change (the rest keep the device's values).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ContactParamsWire {
    /// Fingertip sphere radius, m.
    pub fingertip_radius_m: f32,
    /// Normal stiffness, N/m.
    pub normal_stiffness: f32,
    /// Normal damping, N·s/m.
    pub normal_damping: f32,
    /// Tangential coupling stiffness, N/m.
    pub tangential_stiffness: f32,
    /// Tangential coupling damping, N·s/m.
    pub tangential_damping: f32,
    /// Static friction coefficient.
    pub mu_s: f32,
    /// Kinetic friction coefficient.
    pub mu_k: f32,
    /// Spin stiffness, N·m/rad.
    pub spin_stiffness: f32,
    /// Largest force the model may ask for, N.
    pub max_force_n: f32,
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
