//! The grasp scene: a body between two fingertips driven by simulated hands ([`super::hand`]),
//! gravity, a lift and an external torque about the grasp axis, run through the core's
//! [`Grasp`] at the control rate.
//!
//! Timeline: t = 0 the fingertips touch the body pressed in by grip/K (so the squeeze is at the
//! grip force from the first tick); the body's weight is handed over from a support and the
//! external torque ramps in, both over [`TORQUE_RAMP_S`] (raised cosine: a load applied at once
//! would overshoot the springs' static deflection and slip a grasp that holds the same load
//! applied slowly); the hands lift the body by `lift_mm` from [`LIFT_START_S`]
//! over [`LIFT_S`] (raised cosine); `release_s` (optional) opens both hands.
//!
//! World frame: z up, the grasp axis along x (fingertip 0 on +x, fingertip 1 on −x). The sphere
//! is centred on its body origin; the cylinder's axis (body x) stands vertical.

use super::hand::{v64, Hand};
use nalgebra::Vector3;
use softfinger_core::contact::state::Reason;
use softfinger_core::contact::surface::{Cylinder, Sphere, Surface};
use softfinger_core::contact::{ContactParams, ContactState, Full, Parts};
use softfinger_core::grasp::{
    BodyParams, BodyState, Fingertip, Grasp, GraspError, GraspFlags, GraspStep, Wrench,
};
use softfinger_core::{Fast, Flags, Quat, Vec3};

/// The weight and the external torque ramp in over this, s.
pub const TORQUE_RAMP_S: f64 = 0.15;
/// The lift starts at, s.
pub const LIFT_START_S: f64 = 0.3;
/// The lift lasts, s (slow: its peak acceleration lift·π²/(2·T²) is 1 % of g for 20 mm).
pub const LIFT_S: f64 = 1.0;
/// The grasp is judged from this time on (the settling before is elastic), s.
pub const SETTLE_S: f64 = 0.2;

/// The held object's shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Shape {
    /// A solid sphere of radius 30 mm.
    Sphere,
    /// A solid vertical cylinder of radius 25 mm and length 80 mm, pinched across its axis.
    Cylinder,
}

/// Radius of the sphere, m.
pub const SPHERE_RADIUS_M: f32 = 0.03;
/// Radius and length of the cylinder, m.
pub const CYLINDER_RADIUS_M: f32 = 0.025;
/// Length of the cylinder, m (for its inertia).
pub const CYLINDER_LENGTH_M: f32 = 0.08;

/// Everything a grasp run takes.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct GraspConfig {
    /// The object.
    pub shape: Shape,
    /// Object mass, kg.
    pub mass_kg: f64,
    /// Each hand's squeeze, N.
    pub grip_n: f64,
    /// Static friction coefficient of both contacts (μ_k = 0.75·μ_s).
    pub mu_s: f64,
    /// External torque about the grasp axis (world x), N·m.
    pub torque_nm: f64,
    /// Soft-finger torsion (false: point contacts, k_z = 0).
    pub torsion: bool,
    /// Gravity, m/s² (acting along −z).
    pub gravity_m_s2: f64,
    /// How far the hands lift the object, mm.
    pub lift_mm: f64,
    /// Run length, s.
    pub duration_s: f64,
    /// Control rate, Hz.
    pub rate_hz: f64,
    /// The hands open at this time, s (none: they hold to the end).
    pub release_s: Option<f64>,
}

impl Default for GraspConfig {
    fn default() -> Self {
        GraspConfig {
            shape: Shape::Sphere,
            mass_kg: 0.1,
            grip_n: 5.0,
            mu_s: 0.8,
            torque_nm: 0.0,
            torsion: true,
            gravity_m_s2: 9.81,
            lift_mm: 20.0,
            duration_s: 1.5,
            rate_hz: 10_000.0,
            release_s: None,
        }
    }
}

/// Why a configuration was rejected: the option and the reason.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ConfigError {
    /// A value out of its range.
    #[error("{0} {1}")]
    Value(&'static str, &'static str),
    /// The core rejected the grasp.
    #[error("grasp rejected: {0}")]
    Grasp(String),
}

impl GraspConfig {
    /// Check every option; the first bad one is named.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let pos = |name, v: f64, max: f64| {
            if !v.is_finite() {
                Err(ConfigError::Value(name, "must be finite"))
            } else if v <= 0.0 {
                Err(ConfigError::Value(name, "must be > 0"))
            } else if v > max {
                Err(ConfigError::Value(name, "is beyond its range"))
            } else {
                Ok(())
            }
        };
        pos("--mass-kg", self.mass_kg, 100.0)?;
        pos("--grip-n", self.grip_n, 100.0)?;
        pos("--mu-s", self.mu_s, 10.0)?;
        pos("--duration-s", self.duration_s, 600.0)?;
        pos("--rate-hz", self.rate_hz, 100_000.0)?;
        if self.rate_hz < 100.0 {
            return Err(ConfigError::Value("--rate-hz", "must be >= 100"));
        }
        if !self.torque_nm.is_finite() || self.torque_nm.abs() > 10.0 {
            return Err(ConfigError::Value(
                "--torque-nm",
                "must be finite, |torque| <= 10 N·m",
            ));
        }
        if !self.gravity_m_s2.is_finite() || !(0.0..=100.0).contains(&self.gravity_m_s2) {
            return Err(ConfigError::Value(
                "--gravity-m-s2",
                "must be finite, in [0, 100]",
            ));
        }
        if !self.lift_mm.is_finite() || self.lift_mm.abs() > 200.0 {
            return Err(ConfigError::Value(
                "--lift-mm",
                "must be finite, |lift| <= 200 mm",
            ));
        }
        if let Some(r) = self.release_s {
            if !r.is_finite() || r < 0.0 {
                return Err(ConfigError::Value("--release-s", "must be finite and >= 0"));
            }
        }
        Ok(())
    }

    /// The contact parameters of both fingertips: the project's defaults with this μ_s
    /// (μ_k = 0.75·μ_s), a grasp-scale spin stiffness (0.2 N·m/rad, 0 without torsion), the
    /// tangential damper at [`TANGENTIAL_DAMPING`] (the held object's sag settles in the first
    /// 0.2 s) and room for the grip in the force limit.
    pub fn contact_params(&self) -> ContactParams {
        let mut p = ContactParams::DEFAULT;
        p.mu_s = self.mu_s as f32;
        p.mu_k = 0.75 * self.mu_s as f32;
        p.spin_stiffness = if self.torsion { SPIN_STIFFNESS } else { 0.0 };
        p.tangential_damping = TANGENTIAL_DAMPING;
        p.tangential_stiffness = TANGENTIAL_STIFFNESS;
        p.max_force_n = (4.0 * self.grip_n as f32).max(p.max_force_n);
        p
    }

    /// The object's rigid-body parameters.
    pub fn body_params(&self) -> BodyParams {
        let m = self.mass_kg as f32;
        let mut b = match self.shape {
            Shape::Sphere => BodyParams::solid_sphere(m, SPHERE_RADIUS_M),
            Shape::Cylinder => {
                BodyParams::solid_cylinder_x(m, CYLINDER_RADIUS_M, CYLINDER_LENGTH_M)
            }
        };
        // The damping of the object's turn in the fingertips' pulp, lumped on the body: ζ ≈ 0.5 of
        // the spin spring's mode, so a held twist settles in the first 0.2 s. At rest it adds no
        // torque, so it moves no threshold.
        let i_axis = b
            .inertia_kg_m2
            .y
            .min(b.inertia_kg_m2.z)
            .min(b.inertia_kg_m2.x);
        b.angular_damping = (2.0 * SPIN_STIFFNESS * i_axis).sqrt();
        b.linear_damping = 0.0;
        b
    }
}

/// The tangential damper of each contact, N·s/m: with the hands' hold in series, a 0.8 kg object
/// (at the default grip's lift limit) sags with a damping ratio of about 0.5.
pub const TANGENTIAL_DAMPING: f32 = 10.0;

/// The tangential stiffness of each contact, N/m (a fingertip pad pinching at a few newtons).
pub const TANGENTIAL_STIFFNESS: f32 = 3000.0;

/// k_z of each contact with torsion on, N·m/rad.
pub const SPIN_STIFFNESS: f32 = 0.2;

/// One tick, what the charts and the verdict read.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample {
    /// Time at the end of the tick, s.
    pub t_s: f64,
    /// Object centre, world, m.
    pub pos_m: [f64; 3],
    /// Object orientation (w, x, y, z), body → world.
    pub q: [f64; 4],
    /// Fingertip centres, world, m.
    pub tips_m: [[f64; 3]; 2],
    /// Each contact's normal force, N.
    pub f_n: [f64; 2],
    /// Each contact's tangential force |f_t|, N.
    pub f_t: [f64; 2],
    /// Each contact's spin torque τn, N·m.
    pub tau_n: [f64; 2],
    /// Each contact's static limits at this tick (μ_s·f_N, τ_max(f_N)).
    pub limits: [(f64, f64); 2],
    /// Each contact's state.
    pub state: [ContactState; 2],
    /// Why each contact is in its state (a transition's cause, or kept).
    pub reason: [Reason; 2],
    /// Flags of the tick.
    pub flags: Flags,
    /// Grasp-level flags of the tick.
    pub grasp_flags: GraspFlags,
}

/// A run: the samples, and each contact's static limits at the grip force.
#[derive(Clone, Debug)]
pub struct GraspRun {
    /// The configuration run.
    pub config: GraspConfig,
    /// One sample per tick.
    pub samples: Vec<Sample>,
    /// Each contact's torsional limit at the grip force, N·m (as the model computes it).
    pub tau_max_nm: [f64; 2],
    /// Each contact's tangential friction limit μ_s·F_grip, N.
    pub f_max_n: [f64; 2],
    /// Host time per grasp tick (both contacts and the body; the hands excluded), ns.
    pub tick_ns: f64,
}

/// Run the scene of `config`.
pub fn run(config: &GraspConfig) -> Result<GraspRun, ConfigError> {
    run_observed::<Full>(config, |_, _, _| {})
}

/// Run the scene of `config` with both contacts of the model of parts `P`, handing each tick's
/// fingertips, external wrench and [`GraspStep`] to `observe` (after the body's step).
pub fn run_observed<P: Parts>(
    config: &GraspConfig,
    observe: impl FnMut(&[Option<Fingertip>; 2], &Wrench, &GraspStep),
) -> Result<GraspRun, ConfigError> {
    config.validate()?;
    match config.shape {
        Shape::Sphere => run_on::<_, P>(
            config,
            Sphere::new(SPHERE_RADIUS_M),
            SPHERE_RADIUS_M,
            Quat::IDENTITY,
            observe,
        ),
        Shape::Cylinder => {
            // Body x (the cylinder's axis) to world z: a turn of −90° about y.
            let q = Quat::from_axis_angle::<Fast>(Vec3::Y, -core::f32::consts::FRAC_PI_2);
            run_on::<_, P>(
                config,
                Cylinder::new(CYLINDER_RADIUS_M),
                CYLINDER_RADIUS_M,
                q,
                observe,
            )
        }
    }
}

/// A raised-cosine step from 0 to 1 over `len` s from `start`: (value, rate in 1/s).
pub(crate) fn smooth_step(t: f64, start: f64, len: f64) -> (f64, f64) {
    if t <= start {
        (0.0, 0.0)
    } else if t >= start + len {
        (1.0, 0.0)
    } else {
        let x = (t - start) / len;
        let pi = std::f64::consts::PI;
        (0.5 - 0.5 * (pi * x).cos(), 0.5 * pi * (pi * x).sin() / len)
    }
}

fn run_on<S: Surface, P: Parts>(
    config: &GraspConfig,
    surface: S,
    radius_m: f32,
    q0: Quat,
    mut observe: impl FnMut(&[Option<Fingertip>; 2], &Wrench, &GraspStep),
) -> Result<GraspRun, ConfigError> {
    let cp = config.contact_params();
    let dt = 1.0 / config.rate_hz;
    let r = f64::from(radius_m + cp.fingertip_radius_m);
    let state = BodyState {
        q: q0,
        ..BodyState::default()
    };
    // Gravity is applied as the external force while the support hands the weight over.
    let mut grasp: Grasp<Fast, S, P> = Grasp::with_parts(
        config.body_params(),
        state,
        surface,
        [cp; 2],
        Vec3::ZERO,
        dt as f32,
    )
    .map_err(|e: GraspError| ConfigError::Grasp(e.to_string()))?;
    let pen = config.grip_n / f64::from(cp.normal_stiffness);
    let mut hands = [
        Hand::new(
            Vector3::new(r - pen, 0.0, 0.0),
            -Vector3::x(),
            config.grip_n,
        ),
        Hand::new(
            Vector3::new(-(r - pen), 0.0, 0.0),
            Vector3::x(),
            config.grip_n,
        ),
    ];
    let limits = grasp.contacts()[0].limits_at(config.grip_n as f32);
    // A point contact (torsion off) has no torsional limit.
    let limits = (limits.0, if config.torsion { limits.1 } else { 0.0 });
    let n = (config.duration_s * config.rate_hz).round() as usize;
    let mut samples = Vec::with_capacity(n);
    let mut grasp_time = std::time::Duration::ZERO;
    for k in 0..n {
        let t = k as f64 * dt;
        let (ramp, _) = smooth_step(t, 0.0, TORQUE_RAMP_S);
        let (s, sv) = smooth_step(t, LIFT_START_S, LIFT_S);
        let lift = Vector3::new(0.0, 0.0, s * config.lift_mm * 1e-3);
        let lift_vel = Vector3::new(0.0, 0.0, sv * config.lift_mm * 1e-3);
        let open = config.release_s.is_some_and(|r| t >= r);
        let weight = (ramp * config.mass_kg * config.gravity_m_s2) as f32;
        let external = Wrench {
            force_n: Vec3::new(0.0, 0.0, -weight),
            torque_nm: Vec3::new((ramp * config.torque_nm) as f32, 0.0, 0.0),
        };
        let tips = [Some(hands[0].fingertip()), Some(hands[1].fingertip())];
        let t0 = std::time::Instant::now();
        let step = grasp.step(tips, external);
        grasp_time += t0.elapsed();
        observe(&tips, &external, &step);
        for (h, c) in hands.iter_mut().zip(&step.contacts) {
            h.step(lift, lift_vel, c.on_fingertip.force_n, open, dt);
        }
        let b = grasp.body.state;
        let c = &step.contacts;
        samples.push(Sample {
            t_s: t + dt,
            pos_m: v64(b.pos_m).into(),
            q: [b.q.w, b.q.x, b.q.y, b.q.z].map(f64::from),
            tips_m: [hands[0].pos.into(), hands[1].pos.into()],
            f_n: [c[0].normal_force_n, c[1].normal_force_n].map(f64::from),
            f_t: [c[0].tangential_force_n, c[1].tangential_force_n].map(f64::from),
            tau_n: [c[0].output.tau_n_nm, c[1].output.tau_n_nm].map(f64::from),
            limits: [
                (f64::from(c[0].f_max_n), f64::from(c[0].tau_max_nm)),
                (f64::from(c[1].f_max_n), f64::from(c[1].tau_max_nm)),
            ],
            state: [c[0].output.state, c[1].output.state],
            reason: [c[0].output.reason, c[1].output.reason],
            flags: step.flags,
            grasp_flags: step.grasp_flags,
        });
    }
    Ok(GraspRun {
        config: *config,
        samples,
        tau_max_nm: [f64::from(limits.1); 2],
        f_max_n: [f64::from(limits.0); 2],
        tick_ns: grasp_time.as_nanos() as f64 / n.max(1) as f64,
    })
}
