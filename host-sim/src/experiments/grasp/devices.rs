//! The grasp rendered on two devices: each fingertip is a device plant (the Omega-like delta,
//! its motors, encoders, bridges and the user's hand, [`crate::sim::plant`]) running the one control
//! pipeline on the local-model scene (what `host-sim serve` and the firmware run), and the object
//! is stepped by the application at 1 kHz ([`LinkConfig::object_hz`]), its surface sent to each
//! device as that device's local model every `model_hz` period (100 Hz–1 kHz). Between the two is
//! [`softfinger_core::grasp::remote`]: each device's rendered contact is the body's wrench, the
//! body's pose each device's model pose.
//!
//! Per control tick (the board's rate) each device runs `closed_loop::step`; every object period
//! the application reads each device's latest contact (as old as `latency_ms`), steps the body
//! under the contacts, gravity and the external torque, and every model period it sends each
//! device the new pose (applied `latency_ms` later; the device slews to it
//! over its blend time). So the link latency acts both ways, as over a real link.
//!
//! The devices stand upright on the desk and render their fingertip pressing along their own −z;
//! the application maps each device's base frame into the world ([`DeviceMount`]): device 0 on
//! +x pressing towards −x, device 1 on −x pressing towards +x, so the grasp axis is world x as in
//! the ideal scene ([`super::simulate`]). The user's hand on each handle is the plant's hand (a
//! 0.4 kg mass on a 300 N/m spring-damper towards its reference): it squeezes by holding its
//! reference `grip / 300 N/m` inside the object and lifts by moving it. Each plant stands
//! upright (gravity along its own −z: the device's homing needs it so); the application's mounts
//! map the two workspaces into the world, as dual-device setups do, and the hand holds the handle
//! against the effector's weight. The devices have no wrist
//! actuator: the spin torque acts on the object, not on the user.
//!
//! Timeline: the operator's session on each device (power-up, homing, arming, as
//! [`crate::sim::closed_loop::prepare`]), the hands close on the object held by its support over
//! [`APPROACH_S`] and settle for [`SQUEEZE_SETTLE_S`]; then the scene's t = 0, from which on it is
//! the ideal scene's timeline (weight and torque ramp in, the lift from `LIFT_START_S` over
//! `LIFT_S`).

use super::simulate::smooth_step;
use super::simulate::{
    ConfigError, GraspConfig, GraspRun, Sample, Shape, CYLINDER_RADIUS_M, LIFT_S, LIFT_START_S,
    SETTLE_S, SPHERE_RADIUS_M, TORQUE_RAMP_S,
};
use crate::sim::closed_loop;
use crate::sim::plant::{HandScript, Phase, Plant, PlantParams, Waypoint};
use softfinger_core::contact::surface::{Cylinder, Sphere};
use softfinger_core::contact::ContactParams;
use softfinger_core::control::local_model::{LocalModelEnvironment, LocalModelSpec, ModelKind};
use softfinger_core::control::pipeline::{Command, Mode, Pipeline, PipelineConfig};
use softfinger_core::grasp::{
    BodyState, DeviceContact, DeviceMount, Fingertip, FingertipContact, Grasp, GraspFlags,
    RigidBody, Wrench,
};
use softfinger_core::omega_like::OMEGA_LIKE;
use softfinger_core::{Fast, Flags, Quat, Vec3};
use std::collections::VecDeque;

/// The board's control rate for the devices, Hz (the firmware's).
pub const DEVICE_RATE_HZ: f64 = 10_000.0;
/// The hands close on the object over this, s.
pub const APPROACH_S: f64 = 0.5;
/// Then squeeze the object on its support this long before the scene starts, s.
pub const SQUEEZE_SETTLE_S: f64 = 0.3;
/// Where each hand waits before closing: this far out of contact along the squeeze axis, m.
pub const STANDOFF_M: f64 = 0.010;
/// Blend time of each device's model switches, s (`host-sim serve`'s default).
pub const BLEND_S: f32 = 0.0005;

/// The link between the application and the devices.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LinkConfig {
    /// Rate at which the application sends the models, Hz.
    pub model_hz: f64,
    /// One-way delay of the link, each way, ms.
    pub latency_ms: f64,
    /// Where the object's contact forces come from.
    pub design: ObjectDesign,
    /// Send each device the body's pose predicted ahead by the delay until it renders it
    /// ([`DeviceMount::model_pose_ahead`] with [`LinkConfig::lead_s`]); false: the pose itself.
    pub predict: bool,
}

impl LinkConfig {
    /// The rate the application steps the object at, Hz: the model rate, or 1 kHz when models
    /// go out more slowly (an explicit step of the stiff contacts at 5 ms diverges: measured, a
    /// 0.1 kg object at 200 Hz dropped).
    pub fn object_hz(&self) -> f64 {
        self.model_hz.max(1000.0)
    }

    /// How far ahead the application predicts the pose it sends, s: the downlink delay, half a
    /// model period (the device holds each model until the next) and half the blend (the device
    /// slews to a new pose over it). Zero without prediction.
    pub fn lead_s(&self) -> f64 {
        if self.predict {
            self.latency_ms * 1e-3 + 0.5 / self.model_hz + 0.5 * f64::from(BLEND_S)
        } else {
            0.0
        }
    }

    /// Check the options; the first bad one is named.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let m = self.model_hz;
        if !m.is_finite() || !(100.0..=DEVICE_RATE_HZ).contains(&m) {
            return Err(ConfigError::Value(
                "--model-hz",
                "must be in 100 ..= 10000 Hz",
            ));
        }
        if (DEVICE_RATE_HZ / m).fract() != 0.0 {
            return Err(ConfigError::Value(
                "--model-hz",
                "must divide the devices' 10000 Hz control rate",
            ));
        }
        let l = self.latency_ms;
        if !l.is_finite() || !(0.0..=1000.0).contains(&l) {
            return Err(ConfigError::Value(
                "--latency-ms",
                "must be finite, in 0 ..= 1000 ms",
            ));
        }
        Ok(())
    }
}

/// Where the application's object takes its contact forces from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ObjectDesign {
    /// The application runs its own copy of both soft-finger contacts (the core's `Grasp`) on
    /// the fingertips the devices report; each device renders the object's surface with the same
    /// model. The object's stiff contact modes stay inside the application's loop.
    HostContacts,
    /// The object takes the reaction of what each device renders (its state sample's force,
    /// spin torque and contact point): one model, but the object's contact modes close through
    /// the link's delay.
    DeviceWrench,
}

/// What the devices add to the report.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct DeviceFigures {
    /// The link run.
    pub link: LinkConfig,
    /// Standard deviation of the object's position relative to the fingertips' midpoint after
    /// settling (the scene's `SETTLE_S`), µm.
    pub jitter_um: f64,
    /// Largest tick-to-tick change of either device's rendered force at the ticks a new model
    /// took effect, N.
    pub force_step_at_update_n: f64,
    /// Largest tick-to-tick change of either device's rendered force at the other ticks after
    /// settling, N (for comparison).
    pub force_step_between_n: f64,
    /// Each contact's mean normal force after settling, N (the devices' squeeze: the hand's
    /// spring against the device's friction and the contact, not the set grip exactly).
    pub normal_force_n: [f64; 2],
    /// Both contacts' torsional limits summed at those normal forces, N·m (the twist the grasp
    /// can hold on these devices).
    pub combined_tau_max_nm: f64,
    /// Each device's time from power-up to armed, s.
    pub armed_at_s: [f64; 2],
    /// Flags either pipeline latched (hex).
    pub latched: String,
    /// Whether both devices stayed armed to the end.
    pub armed_throughout: bool,
}

/// One device: its plant, its pipeline, where it stands.
struct Device {
    plant: Plant,
    pipe: Pipeline<Fast, LocalModelEnvironment>,
    mount: DeviceMount,
    /// Samples not yet delivered to the application (delay line).
    up: VecDeque<DeviceContact>,
    /// Models not yet delivered to the device: (tick due, model).
    down: VecDeque<(u64, LocalModelSpec)>,
    last_force: Vec3,
}

fn a64(v: Vec3) -> [f64; 3] {
    [v.x, v.y, v.z].map(f64::from)
}

/// The mounts: device 0's base z along world +x, its origin so that the object's first contact
/// (the surface top of the one-device scenes) is where its fingertip starts; device 1 mirrored.
fn mounts(radius_m: f64) -> [DeviceMount; 2] {
    let top = closed_loop::surface_top_z_m();
    let half = core::f32::consts::FRAC_PI_2;
    let mk = |sign: f32| {
        let q = Quat::from_axis_angle::<Fast>(Vec3::Y, sign * half);
        // The object centre, (0, 0, top − R) in the base frame, is the world origin.
        let m = DeviceMount {
            origin_m: Vec3::ZERO,
            orientation: q,
        };
        let c_w = m.vector_to_world(Vec3::new(0.0, 0.0, (top - radius_m) as f32));
        DeviceMount {
            origin_m: -c_w,
            orientation: q,
        }
    };
    [mk(1.0), mk(-1.0)]
}

fn model_spec(
    seq: u32,
    kind: ModelKind,
    mount: &DeviceMount,
    body: &BodyState,
    cp: &ContactParams,
    lead_s: f32,
) -> LocalModelSpec {
    LocalModelSpec {
        seq,
        kind,
        pose: mount.model_pose_ahead::<Fast>(body, lead_s),
        stiffness_n_per_m: cp.normal_stiffness,
        damping_n_s_per_m: cp.normal_damping,
        mu_s: cp.mu_s,
        mu_k: cp.mu_k,
        spin_stiffness_nm_per_rad: cp.spin_stiffness,
        max_age_s: 0.0,
    }
}

fn setup_error(e: impl std::fmt::Display) -> ConfigError {
    ConfigError::Grasp(format!("device setup: {e}"))
}

/// Run the scene of `config` on two device plants over `link`.
pub fn run(
    config: &GraspConfig,
    link: &LinkConfig,
) -> Result<(GraspRun, DeviceFigures), ConfigError> {
    config.validate()?;
    link.validate()?;
    if config.release_s.is_some() {
        return Err(ConfigError::Value(
            "--release-s",
            "is not supported with --plant devices",
        ));
    }
    if config.rate_hz != DEVICE_RATE_HZ {
        return Err(ConfigError::Value(
            "--rate-hz",
            "must be 10000 with --plant devices (the board's control rate)",
        ));
    }
    let cp = config.contact_params();
    let (kind, radius, q0) = match config.shape {
        Shape::Sphere => (
            ModelKind::Sphere {
                radius_m: SPHERE_RADIUS_M,
            },
            SPHERE_RADIUS_M,
            Quat::IDENTITY,
        ),
        Shape::Cylinder => (
            ModelKind::Cylinder {
                radius_m: CYLINDER_RADIUS_M,
            },
            CYLINDER_RADIUS_M,
            Quat::from_axis_angle::<Fast>(Vec3::Y, -core::f32::consts::FRAC_PI_2),
        ),
    };
    let state0 = BodyState {
        q: q0,
        ..BodyState::default()
    };
    let mut body = RigidBody::new(config.body_params(), state0)
        .map_err(|e| ConfigError::Grasp(e.to_string()))?;
    let h_model = (1.0 / link.object_hz()) as f32;
    let grasp_err = |e: softfinger_core::grasp::GraspError| ConfigError::Grasp(e.to_string());
    let mut object = match config.shape {
        Shape::Sphere => HostObject::Sphere(
            Grasp::new(
                config.body_params(),
                state0,
                Sphere::new(SPHERE_RADIUS_M),
                [cp; 2],
                Vec3::ZERO,
                h_model,
            )
            .map_err(grasp_err)?,
        ),
        Shape::Cylinder => HostObject::Cylinder(
            Grasp::new(
                config.body_params(),
                state0,
                Cylinder::new(CYLINDER_RADIUS_M),
                [cp; 2],
                Vec3::ZERO,
                h_model,
            )
            .map_err(grasp_err)?,
        ),
    };
    let mounts = mounts(f64::from(radius));
    let timing = closed_loop::board_timing(DEVICE_RATE_HZ).map_err(setup_error)?;
    let top = closed_loop::surface_top_z_m();
    let r_tip = f64::from(cp.fingertip_radius_m);
    let hand_k = PlantParams::OMEGA_LIKE.hand_stiffness_n_per_m;
    let mut armed_at_s = [0.0; 2];
    let mut devices = Vec::with_capacity(2);
    for (i, mount) in mounts.iter().enumerate() {
        let initial = model_spec(1, kind, mount, &body.state, &cp, 0.0);
        let pipe_config = PipelineConfig {
            device: OMEGA_LIKE,
            timing,
            contact: cp,
            surface: LocalModelEnvironment {
                blend_s: BLEND_S,
                ..LocalModelEnvironment::new(initial)
            },
            object_origin_m: Vec3::ZERO,
            log_rate_hz: 0,
        };
        let mut pipe = Pipeline::new(pipe_config).map_err(setup_error)?;
        // The fingertip's centre touches at (0, 0, top) + its radius; it waits STANDOFF_M out.
        // The device stands upright (its homing needs gravity along its −z); the hand holds the
        // handle against the effector's weight, so each reference sits m·g/k above where the
        // handle should be.
        let plant_params = PlantParams::OMEGA_LIKE;
        let carry = |p: [f64; 3]| -> [f64; 3] {
            let m = plant_params.effector_mass_kg / hand_k;
            std::array::from_fn(|k| p[k] - plant_params.gravity_m_s2[k] * m)
        };
        let wait = Waypoint {
            position_m: carry([0.0, 0.0, top + r_tip + STANDOFF_M]),
            wrist_rad: [0.0; 3],
        };
        let mut plant = Plant::new(OMEGA_LIKE.params, plant_params, HandScript::new(wait))
            .map_err(setup_error)?;
        let prepared = closed_loop::prepare(&mut pipe, &mut plant).map_err(setup_error)?;
        armed_at_s[i] = prepared.armed_at_s;
        // The hand's script from where the handle is: close on the object, squeeze, lift, hold.
        let here = Waypoint {
            position_m: plant.effector_position_m(),
            wrist_rad: plant.wrist_angles_rad(),
        };
        let squeeze_z = top + r_tip - config.grip_n / hand_k;
        let squeeze = Waypoint {
            position_m: carry([0.0, 0.0, squeeze_z]),
            wrist_rad: here.wrist_rad,
        };
        let up = mount.vector_to_base(Vec3::new(0.0, 0.0, (config.lift_mm * 1e-3) as f32));
        let lifted = Waypoint {
            position_m: carry([
                f64::from(up.x),
                f64::from(up.y),
                squeeze_z + f64::from(up.z),
            ]),
            wrist_rad: here.wrist_rad,
        };
        let script = HandScript::new(here)
            .then(Phase::Approach, APPROACH_S, squeeze)
            .then(Phase::Hold, SQUEEZE_SETTLE_S + LIFT_START_S, squeeze)
            .then(Phase::Press, LIFT_S, lifted)
            .then(Phase::Hold, config.duration_s + 1.0, lifted);
        let mut p = Plant::new(OMEGA_LIKE.params, plant_params, script).map_err(setup_error)?;
        p.continue_counters_from(&plant);
        devices.push(Device {
            plant: p,
            pipe,
            mount: *mount,
            up: VecDeque::new(),
            down: VecDeque::new(),
            last_force: Vec3::ZERO,
        });
    }
    let dt = 1.0 / DEVICE_RATE_HZ;
    let div = (DEVICE_RATE_HZ / link.model_hz).round() as u64;
    let div_obj = (DEVICE_RATE_HZ / link.object_hz()).round() as u64;
    let h = (div_obj as f64 * dt) as f32;
    let lead = link.lead_s() as f32;
    let lat_ticks = (link.latency_ms * 1e-3 * DEVICE_RATE_HZ).round() as u64;
    let pre = ((APPROACH_S + SQUEEZE_SETTLE_S) * DEVICE_RATE_HZ).round() as u64;
    let n = (config.duration_s * DEVICE_RATE_HZ).round() as u64;
    let limiter = FingertipContact::<Fast, Sphere>::new(cp, Sphere::new(radius), dt as f32)
        .map_err(|e| ConfigError::Grasp(e.to_string()))?;
    let limits = limiter.limits_at(config.grip_n as f32);
    let limits = (limits.0, if config.torsion { limits.1 } else { 0.0 });
    let mut samples = Vec::with_capacity(n as usize);
    let (mut step_at_update, mut step_between) = (0.0_f64, 0.0_f64);
    let mut armed_throughout = true;
    let mut seq = 1_u32;
    let mut latest = [DeviceContact::default(); 2];
    for k in 0..pre + n {
        let scene_t = (k as f64 - pre as f64) * dt;
        let mut outs = Vec::with_capacity(2);
        for (i, d) in devices.iter_mut().enumerate() {
            // Models due at this tick take effect at its start.
            let mut updated = false;
            while d.down.front().is_some_and(|(due, _)| *due <= k) {
                if let Some((_, m)) = d.down.pop_front() {
                    updated |= d.pipe.command(Command::SetLocalModel(m)).is_ok();
                }
            }
            let (_, out, _) = closed_loop::step(&mut d.pipe, &mut d.plant, |_| {});
            if out.mode != Mode::Armed {
                armed_throughout = false;
            }
            let c = DeviceContact {
                force_n: out.control.force_n,
                spin_torque_nm: out.control.tau_n_nm,
                contact_point_m: d.pipe.controller().contact_point_m(),
                probe_m: out.control.probe_m,
                probe_vel_m_s: d.pipe.controller().probe_velocity(),
            };
            let df = f64::from((c.force_n - d.last_force).norm::<Fast>());
            d.last_force = c.force_n;
            if scene_t >= SETTLE_S {
                if updated {
                    step_at_update = step_at_update.max(df);
                } else {
                    step_between = step_between.max(df);
                }
            }
            d.up.push_back(c);
            while d.up.len() as u64 > lat_ticks {
                if let Some(s) = d.up.pop_front() {
                    latest[i] = s;
                }
            }
            outs.push((out, c));
        }
        // The application's object step, once the scene has started.
        if k >= pre && (k - pre).is_multiple_of(div_obj) {
            let (ramp, _) = smooth_step(scene_t, 0.0, TORQUE_RAMP_S);
            let weight = (ramp * config.mass_kg * config.gravity_m_s2) as f32;
            let mut wrench = Wrench {
                force_n: Vec3::new(0.0, 0.0, -weight),
                torque_nm: Vec3::new((ramp * config.torque_nm) as f32, 0.0, 0.0),
            };
            match link.design {
                ObjectDesign::DeviceWrench => {
                    for (d, c) in devices.iter().zip(&latest) {
                        let (w, _) = d.mount.wrench_on_body::<Fast>(c, &body.state);
                        wrench.force_n += w.force_n;
                        wrench.torque_nm += w.torque_nm;
                    }
                    body.step::<Fast>(wrench.force_n, wrench.torque_nm, h);
                }
                ObjectDesign::HostContacts => {
                    let tips = [
                        Some(devices[0].mount.fingertip(&latest[0])),
                        Some(devices[1].mount.fingertip(&latest[1])),
                    ];
                    body.state = object.step(tips, wrench);
                }
            }
            if (k - pre).is_multiple_of(div) {
                seq = seq.wrapping_add(1);
                for d in devices.iter_mut() {
                    let m = model_spec(seq, kind, &d.mount, &body.state, &cp, lead);
                    d.down.push_back((k + 1 + lat_ticks, m));
                }
            }
        }
        if k < pre {
            continue;
        }
        let b = body.state;
        let tip = |i: usize| a64(devices[i].mount.point_to_world(outs[i].1.probe_m));
        let report = |i: usize| {
            let (out, c) = &outs[i];
            let f_w = devices[i].mount.vector_to_world(c.force_n);
            let n_w = devices[i]
                .mount
                .vector_to_world(c.probe_m - c.contact_point_m);
            let len = n_w.norm::<Fast>();
            let f_n = if len > 1e-9 { f_w.dot(n_w) / len } else { 0.0 };
            let f_t = (f_w.norm_squared() - f_n * f_n).max(0.0).sqrt();
            (
                f_n.max(0.0),
                f_t,
                out.control.tau_n_nm,
                out.control.state,
                out.flags,
            )
        };
        let (r0, r1) = (report(0), report(1));
        let lim = |f_n: f32| {
            let (a, b) = limiter.limits_at(f_n);
            (f64::from(a), f64::from(b))
        };
        samples.push(Sample {
            t_s: scene_t + dt,
            pos_m: a64(b.pos_m),
            q: [b.q.w, b.q.x, b.q.y, b.q.z].map(f64::from),
            tips_m: [tip(0), tip(1)],
            f_n: [r0.0, r1.0].map(f64::from),
            f_t: [r0.1, r1.1].map(f64::from),
            tau_n: [r0.2, r1.2].map(f64::from),
            limits: [lim(r0.0), lim(r1.0)],
            state: [r0.3, r1.3],
            reason: Default::default(),
            flags: Flags(r0.4 .0 | r1.4 .0),
            grasp_flags: GraspFlags::NONE,
        });
    }
    let latched = devices.iter().fold(0u32, |a, d| a | d.pipe.latched().0);
    let jitter_um = jitter_um(&samples);
    let settled: Vec<&Sample> = samples.iter().filter(|s| s.t_s >= SETTLE_S).collect();
    let count = settled.len().max(1) as f64;
    let normal_force_n: [f64; 2] =
        std::array::from_fn(|i| settled.iter().map(|s| s.f_n[i]).sum::<f64>() / count);
    let combined_tau_max_nm = settled
        .iter()
        .map(|s| s.limits[0].1 + s.limits[1].1)
        .sum::<f64>()
        / count;
    let run = GraspRun {
        config: *config,
        samples,
        tau_max_nm: [f64::from(limits.1); 2],
        f_max_n: [f64::from(limits.0); 2],
        tick_ns: 0.0,
    };
    let figures = DeviceFigures {
        link: *link,
        jitter_um,
        force_step_at_update_n: step_at_update,
        force_step_between_n: step_between,
        normal_force_n,
        combined_tau_max_nm,
        armed_at_s,
        latched: format!("{latched:#x}"),
        armed_throughout,
    };
    Ok((run, figures))
}

/// The application's copy of the contacts on the object, per shape.
enum HostObject {
    Sphere(Grasp<Fast, Sphere>),
    Cylinder(Grasp<Fast, Cylinder>),
}

impl HostObject {
    /// One model period: both contacts on the given fingertips and the body; the body's state
    /// after it.
    fn step(&mut self, tips: [Option<Fingertip>; 2], external: Wrench) -> BodyState {
        match self {
            HostObject::Sphere(g) => {
                g.step(tips, external);
                g.body.state
            }
            HostObject::Cylinder(g) => {
                g.step(tips, external);
                g.body.state
            }
        }
    }
}

/// Standard deviation of the object's position relative to the fingertips' midpoint over the
/// samples after `SETTLE_S`, µm.
pub fn jitter_um(samples: &[Sample]) -> f64 {
    let rel: Vec<[f64; 3]> = samples
        .iter()
        .filter(|s| s.t_s >= SETTLE_S)
        .map(|s| std::array::from_fn(|k| s.pos_m[k] - 0.5 * (s.tips_m[0][k] + s.tips_m[1][k])))
        .collect();
    if rel.is_empty() {
        return 0.0;
    }
    let n = rel.len() as f64;
    let mean: [f64; 3] = std::array::from_fn(|k| rel.iter().map(|r| r[k]).sum::<f64>() / n);
    let var = rel
        .iter()
        .map(|r| (0..3).map(|k| (r[k] - mean[k]).powi(2)).sum::<f64>())
        .sum::<f64>()
        / n;
    var.sqrt() * 1e6
}
