//! What `host-sim run` records: one row per tick of the scene, and the run around them. The charts
//! ([`super::charts`]) and the limit-surface path ([`super::limit_path`]) read these; the command
//! ([`super`]) writes them.

use crate::sim::closed_loop::Prepared;
use crate::sim::scene::Scene;
use softfinger_core::contact::state::ContactState;
use softfinger_core::Flags;

/// One recorded tick.
#[derive(Debug, Clone, Copy)]
pub struct Row {
    pub t_s: f64,
    pub phase: &'static str,
    pub state: ContactState,
    pub flags: Flags,
    /// Probe position, base frame, m.
    pub probe_m: [f32; 3],
    /// Rendered force, base frame, N.
    pub force_n: [f32; 3],
    pub tau_n_nm: f32,
    pub spin_rad: f32,
    /// Contact point on the object, object frame, m.
    pub object_point_m: [f32; 3],
    /// Contact point on the fingertip, fingertip frame, m.
    pub finger_point_m: [f32; 3],
    /// Contact normal (unit, towards the fingertip), object frame, which is parallel to the base
    /// frame in every scene.
    pub normal: [f32; 3],
    pub duties: [f32; 3],
    /// The hand's force on the handle (plant truth), N.
    pub hand_force_n: [f64; 3],
}

/// What a run produced.
#[derive(Debug, Clone)]
pub struct RunResult {
    pub scene: Scene,
    pub rows: Vec<Row>,
    pub ns_per_tick: f64,
    /// The operator's session before the scene (homing, arming).
    pub prepared: Prepared,
}
