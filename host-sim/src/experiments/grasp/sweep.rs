//! The paper's point, measured: the external torque about the grasp axis swept across the two
//! contacts' combined torsional limit 2·τ_max, torsion on and off, each point a whole grasp run
//! (no gravity, no lift: the twist alone).

use super::simulate::{run, ConfigError, GraspConfig};
use super::verdict::judge;

/// One point of the sweep.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SweepPoint {
    /// External torque, N·m.
    pub torque_nm: f64,
    /// Turn after settling, rad.
    pub rotation_rad: f64,
    /// Whether the grasp held.
    pub held: bool,
}

/// The sweep: `points` torques from 0 to `top` × the combined limit, torsion on and off. Returns
/// (on, off, combined limit in N·m).
pub fn sweep(
    base: &GraspConfig,
    points: usize,
    top: f64,
) -> Result<(Vec<SweepPoint>, Vec<SweepPoint>, f64), ConfigError> {
    let mut on = Vec::new();
    let mut off = Vec::new();
    let mut limit = 0.0;
    for torsion in [true, false] {
        let probe = GraspConfig {
            torsion: true,
            gravity_m_s2: 0.0,
            lift_mm: 0.0,
            torque_nm: 0.0,
            ..*base
        };
        let r0 = run(&GraspConfig {
            duration_s: 0.001,
            ..probe
        })?;
        limit = r0.tau_max_nm[0] + r0.tau_max_nm[1];
        for k in 0..points {
            let torque = limit * top * k as f64 / (points - 1).max(1) as f64;
            let c = GraspConfig {
                torsion,
                torque_nm: torque,
                ..probe
            };
            let v = judge(&run(&c)?);
            let p = SweepPoint {
                torque_nm: torque,
                rotation_rad: v.rotation_rad,
                held: v.held,
            };
            if torsion {
                on.push(p)
            } else {
                off.push(p)
            }
        }
    }
    Ok((on, off, limit))
}
