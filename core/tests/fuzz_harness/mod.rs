//! Fuzz harness shared by the cargo-fuzz targets (`fuzz/fuzz_targets/*.rs`, which include this
//! file with `#[path]`) and the corpus regression test (`core/tests/fuzz_regression.rs`): one
//! decoder from arbitrary bytes to parameters and input sequences, one set of invariants, so a
//! corpus file means exactly the same run in both places.
//!
//! Decoding never fails: a byte string that runs out reads as zeros, which decode to the nominal
//! parameters and a motionless probe. Every f32 the decoder produces can be any class the hardware
//! could hand us: NaN (quiet and signalling), ±inf, ±0, subnormals, ±f32::MAX, raw bit patterns,
//! and nominal values scaled by 2^-32 … 2^32 in both signs.
//!
//! Invariants (each run returns `Err(description)` at the first violation):
//! - no panic (the fuzzer catches those);
//! - parameters are accepted by `new()`/`set_contact_params` exactly when they meet the documented
//!   ranges (an independent oracle written from the field docs, see [`contact_params_valid`],
//!   [`limits_valid`]);
//! - every output is finite; |force| ≤ max_force_n; |duty| ≤ max_duty; the plane never pulls;
//! - a bad input is flagged (non-finite → NON_FINITE_INPUT; a quaternion off unit norm →
//!   NON_UNIT_QUAT / ZERO_AXIS / NON_FINITE_INPUT; a probe beyond 100 m or 100 m/s →
//!   OUT_OF_RANGE, ignored; an unreachable arm angle → OUT_OF_RANGE or
//!   KINEMATICS_SINGULAR with zero force and zero duties);
//! - faults: a driver fault, an encoder jump over the limit, an overrun streak each raise their
//!   flag; with any latching fault present duties are zero and `enable` is false, until
//!   `clear_faults`; a latched ENCODER_STUCK needs at least `TickLimits::stuck_ticks` ticks without a count.
#![allow(dead_code)] // each includer uses its own part

use softfinger_core::contact::decompose::Method;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::state::{ContactState, Tolerances};
use softfinger_core::contact::surface::{Plane, Sphere, Surface};
use softfinger_core::contact::{
    ContactInput, ContactModel, MAX_DT_S, MAX_PROBE_M, MAX_PROBE_SPEED_M_S, MIN_DT_S,
};
use softfinger_core::control::controller::{
    Controller, ControllerConfig, Limits, TickInput, LATCHING,
};
use softfinger_core::device::delta::DeltaGeometry;
use softfinger_core::device::DeviceParams;
use softfinger_core::{Fast, Flags, Libm, Math, Micromath, Quat, Vec3};

/// Most steps or ticks one input runs (keeps one execution short for the fuzzer).
pub const MAX_STEPS: usize = 512;

/// |F| may exceed max_force_n by the rounding of the rescale F·(max/√|F|²): three roundings of
/// 2^-24 each plus the f64 re-evaluation here, so 1e-6 relative is ~8 ulps of margin.
const FORCE_REL_TOL: f64 = 1e-6;

/// Reads the input bytes; past the end every read is zero.
#[derive(Debug)]
pub struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
}

/// The special values an f32 can take, indexed by a byte.
const SPECIALS: [f32; 20] = [
    f32::NAN,
    -f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    0.0,
    -0.0,
    f32::MIN_POSITIVE,
    -f32::MIN_POSITIVE,
    1.0e-45, // smallest subnormal
    -1.0e-45,
    1.175_494_1e-38, // largest subnormal
    f32::MAX,
    f32::MIN,
    f32::EPSILON,
    1.0,
    -1.0,
    1.0e30,
    -1.0e30,
    1.0e-30,
    3.0e38,
];

impl<'a> Bytes<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Bytes { data, pos: 0 }
    }

    /// True once every byte has been read.
    pub fn is_empty(&self) -> bool {
        self.pos >= self.data.len()
    }

    pub fn u8(&mut self) -> u8 {
        let b = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos += 1;
        b
    }

    pub fn i8(&mut self) -> i8 {
        self.u8() as i8
    }

    pub fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }

    pub fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }

    pub fn i32(&mut self) -> i32 {
        self.u32() as i32
    }

    /// A special value, or (one time in four) a signalling NaN / raw bit pattern.
    pub fn special(&mut self) -> f32 {
        let k = self.u8() as usize;
        if k >= 240 {
            // 0x7f80_0001 is a signalling NaN; other raw patterns cover everything else.
            if k == 255 {
                f32::from_bits(0x7f80_0001)
            } else {
                f32::from_bits(self.u32())
            }
        } else {
            SPECIALS[k % SPECIALS.len()]
        }
    }

    /// Any f32 at all: specials, raw bits, or a modest value in [-128, 128).
    pub fn any_f32(&mut self) -> f32 {
        match self.u8() {
            0..=63 => self.special(),
            64..=127 => f32::from_bits(self.u32()),
            _ => self.u16() as i16 as f32 / 256.0,
        }
    }

    /// A parameter near `nominal`: half the byte range keeps the nominal value, a third scales it
    /// by 2^(k/4), k in [-128, 127] (both signs), the rest is any special value.
    pub fn param(&mut self, nominal: f32) -> f32 {
        match self.u8() {
            0..=127 => nominal,
            b @ 128..=223 => {
                let scale = libm::exp2f(self.i8() as f32 / 4.0);
                if b < 192 {
                    nominal * scale
                } else {
                    -nominal * scale
                }
            }
            _ => self.special(),
        }
    }

    /// A positive integer parameter near `nominal`, or any value of the type.
    fn count_param(&mut self, nominal: u16) -> u16 {
        match self.u8() {
            0..=127 => nominal,
            128..=191 => self.u8() as u16,
            _ => self.u16(),
        }
    }

    /// A quaternion that can be anything: unit, scaled, zero, non-finite.
    pub fn any_quat(&mut self) -> Quat {
        Quat::new(
            self.any_f32(),
            self.any_f32(),
            self.any_f32(),
            self.any_f32(),
        )
    }

    /// A small rotation vector: each component in ±0.25 rad (steps of 2 mrad).
    fn small_rotation(&mut self) -> Vec3 {
        Vec3::new(
            self.i8() as f32 * 0.002,
            self.i8() as f32 * 0.002,
            self.i8() as f32 * 0.002,
        )
    }
}

/// Contact parameters, each field near its default or anything.
pub fn contact_params(b: &mut Bytes) -> ContactParams {
    let d = ContactParams::DEFAULT;
    ContactParams {
        method: Method::ALL[b.u8() as usize % 3],
        fingertip_radius_m: b.param(d.fingertip_radius_m),
        normal_stiffness: b.param(d.normal_stiffness),
        normal_damping: b.param(d.normal_damping),
        tangential_stiffness: b.param(d.tangential_stiffness),
        tangential_damping: b.param(d.tangential_damping),
        mu_s: b.param(d.mu_s),
        mu_k: b.param(d.mu_k),
        spin_stiffness: b.param(d.spin_stiffness),
        patch_radius_m: b.param(d.patch_radius_m),
        patch_ref_force_n: b.param(d.patch_ref_force_n),
        patch_exponent: b.param(d.patch_exponent),
        k_tau: b.param(d.k_tau),
        max_force_n: b.param(d.max_force_n),
        tolerances: Tolerances {
            force_eps_n: b.param(d.tolerances.force_eps_n),
            accel_eps: b.param(d.tolerances.accel_eps),
            normal_accel_tol: b.param(d.tolerances.normal_accel_tol),
            gap_eps_m: b.param(d.tolerances.gap_eps_m),
            stick_speed: b.param(d.tolerances.stick_speed),
            hysteresis: b.param(d.tolerances.hysteresis),
            make_force_n: b.param(d.tolerances.make_force_n),
            min_slide_s: b.param(d.tolerances.min_slide_s),
            min_broken_s: b.param(d.tolerances.min_broken_s),
        },
    }
}

/// Controller limits, each field near its default or anything.
pub fn limits(b: &mut Bytes) -> Limits {
    let d = Limits::OMEGA_LIKE;
    Limits {
        max_duty: b.param(d.max_duty),
        max_arm_torque_nm: b.param(d.max_arm_torque_nm),
        glitch_counts_per_s: b.param(d.glitch_counts_per_s),
        overrun_streak_s: b.param(d.overrun_streak_s),
        stuck_duty: b.param(d.stuck_duty),
        stuck_s: b.param(d.stuck_s),
        velocity_cutoff_hz: b.param(d.velocity_cutoff_hz),
        arm_angle_range_rad: [
            b.param(d.arm_angle_range_rad[0]),
            b.param(d.arm_angle_range_rad[1]),
        ],
    }
}

/// The device: nominal, or one field changed (validity is judged by `DeviceParams::validate`,
/// which also checks that the calibration pose assembles: no independent oracle for that).
pub fn device(b: &mut Bytes) -> DeviceParams {
    let mut d = DeviceParams::OMEGA_LIKE;
    let which = b.u8();
    if which < 224 {
        return d;
    }
    match which % 8 {
        0 => d.delta.upper_arm_m = b.param(d.delta.upper_arm_m),
        1 => d.delta.forearm_m = b.param(d.delta.forearm_m),
        2 => d.motor.capstan_ratio = b.param(d.motor.capstan_ratio),
        3 => d.motor.resistance_ohm = b.param(d.motor.resistance_ohm),
        4 => d.motor.back_emf_v_s_per_rad = b.param(d.motor.back_emf_v_s_per_rad),
        5 => d.supply_v = b.param(d.supply_v),
        6 => d.motor_encoder_counts_per_rev = b.count_param(4096) as u32,
        _ => d.arm_angle_at_zero_count_rad = b.param(0.1),
    }
    d
}

fn pos(x: f32) -> bool {
    x.is_finite() && x > 0.0
}

fn nonneg(x: f32) -> bool {
    x.is_finite() && x >= 0.0
}

/// The documented ranges of [`ContactParams`], written from its field docs and
/// [`ContactParams::MAX`] (not from `validate`).
pub fn contact_params_valid(p: &ContactParams) -> bool {
    let m = ContactParams::MAX;
    let within = |v: f32, max: f32| nonneg(v) && v <= max;
    let positive_within = |v: f32, max: f32| pos(v) && v <= max;
    positive_within(p.fingertip_radius_m, m.fingertip_radius_m)
        && p.fingertip_radius_m >= ContactParams::MIN_FINGERTIP_RADIUS_M
        && within(p.normal_stiffness, m.normal_stiffness)
        && within(p.normal_damping, m.normal_damping)
        && within(p.tangential_stiffness, m.tangential_stiffness)
        && within(p.tangential_damping, m.tangential_damping)
        && within(p.spin_stiffness, m.spin_stiffness)
        && within(p.patch_radius_m, m.patch_radius_m)
        && positive_within(p.patch_ref_force_n, m.patch_ref_force_n)
        && within(p.patch_exponent, m.patch_exponent)
        && within(p.tolerances.force_eps_n, m.tolerances.force_eps_n)
        && within(p.tolerances.accel_eps, m.tolerances.accel_eps)
        && within(p.tolerances.normal_accel_tol, m.tolerances.normal_accel_tol)
        && within(p.tolerances.gap_eps_m, m.tolerances.gap_eps_m)
        && within(p.tolerances.stick_speed, m.tolerances.stick_speed)
        && positive_within(p.mu_s, m.mu_s)
        && pos(p.mu_k)
        && p.mu_k <= p.mu_s
        && positive_within(p.k_tau, m.k_tau)
        && within(p.tolerances.make_force_n, m.tolerances.make_force_n)
        && p.tolerances.make_force_n >= p.tolerances.force_eps_n
        && within(p.tolerances.min_slide_s, m.tolerances.min_slide_s)
        && within(p.tolerances.min_broken_s, m.tolerances.min_broken_s)
        && positive_within(p.max_force_n, m.max_force_n)
        && p.max_force_n >= ContactParams::MIN_MAX_FORCE_N
        && nonneg(p.tolerances.hysteresis)
        && p.tolerances.hysteresis < 1.0
}

/// The documented ranges of [`Limits`].
pub fn limits_valid(l: &Limits) -> bool {
    let [lo, hi] = l.arm_angle_range_rad;
    pos(l.max_duty)
        && l.max_duty <= 1.0
        && pos(l.max_arm_torque_nm)
        && pos(l.glitch_counts_per_s)
        && pos(l.overrun_streak_s)
        && pos(l.stuck_duty)
        && pos(l.stuck_s)
        && pos(l.velocity_cutoff_hz)
        && lo.is_finite()
        && hi.is_finite()
        && lo < hi
}

/// What a run did, for the regression test's report.
#[derive(Clone, Debug, Default)]
pub struct Summary {
    /// The parameters were accepted and the sequence ran.
    pub accepted: bool,
    /// Steps or ticks run.
    pub steps: usize,
    /// Union of the flags raised.
    pub flags_seen: Flags,
    /// A valid configuration latched NON_FINITE_OUTPUT (safe, but an internal NaN).
    pub internal_non_finite: bool,
    /// The step or tick where that first happened, with the parameters.
    pub internal_non_finite_at: Option<String>,
}

fn norm64(v: Vec3) -> f64 {
    let (x, y, z) = (v.x as f64, v.y as f64, v.z as f64);
    (x * x + y * y + z * z).sqrt()
}

fn finite3(v: Vec3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

/// Whether a quaternion is far enough from unit norm that the core must flag it. The 2e-3 band
/// around 1 is twice the documented 1e-3 tolerance, so f32 rounding of the norm cannot matter.
fn quat_needs_flag(q: Quat) -> bool {
    let c = [q.w, q.x, q.y, q.z];
    if c.iter().any(|v| !v.is_finite()) {
        return true;
    }
    let n = c
        .iter()
        .map(|&v| (v as f64) * (v as f64))
        .sum::<f64>()
        .sqrt();
    !(0.998..=1.002).contains(&n)
}

const QUAT_FLAGS: Flags =
    Flags(Flags::NON_UNIT_QUAT.0 | Flags::ZERO_AXIS.0 | Flags::NON_FINITE_INPUT.0);

/// Fuzz target `contact_step`: parameters, then up to [`MAX_STEPS`] contact steps.
pub fn contact_step(data: &[u8]) -> Result<Summary, String> {
    let mut b = Bytes::new(data);
    let backend = b.u8() % 3;
    let sphere = b.u8() % 4 == 3;
    if sphere {
        // The Surface has no validation of its own (a radius of 3e38 m overflows the contact
        // point): only spheres of 1 mm to 8 m are exercised.
        let radius = 0.001 * (1u32 << (b.u8() % 14)) as f32;
        let s = Sphere::new(radius);
        match backend {
            0 => run_contact::<Libm, Sphere>(&mut b, s),
            1 => run_contact::<Micromath, Sphere>(&mut b, s),
            _ => run_contact::<Fast, Sphere>(&mut b, s),
        }
    } else {
        let s = Plane::default();
        match backend {
            0 => run_contact::<Libm, Plane>(&mut b, s),
            1 => run_contact::<Micromath, Plane>(&mut b, s),
            _ => run_contact::<Fast, Plane>(&mut b, s),
        }
    }
}

fn run_contact<M: Math, S: Surface>(b: &mut Bytes, surface: S) -> Result<Summary, String> {
    let params = contact_params(b);
    let dt = b.param(1.0e-4);
    let q0 = if b.u8() < 192 {
        Quat::IDENTITY
    } else {
        b.any_quat()
    };
    let valid = contact_params_valid(&params) && (MIN_DT_S..=MAX_DT_S).contains(&dt);
    let mut model = match (ContactModel::<M, S>::new(params, surface, q0, dt), valid) {
        (Ok(m), true) => m,
        (Err(_), false) => return Ok(Summary::default()),
        (Ok(_), false) => return Err(format!("accepted invalid {params:?} dt {dt}")),
        (Err(e), true) => return Err(format!("rejected valid {params:?} dt {dt}: {e:?}")),
    };
    let r = params.fingertip_radius_m;
    let plane = surface.curvature() == 0.0;
    // A plausible walk starts with the fingertip touching the surface.
    let mut probe = surface.contact_point() + surface.normal() * r;
    let mut q = Quat::IDENTITY;
    let mut summary = Summary {
        accepted: true,
        ..Summary::default()
    };
    while !b.is_empty() && summary.steps < MAX_STEPS {
        let mode = b.u8();
        let input = if mode < 200 {
            // Plausible: move by up to ±1.27 fingertip-radius percent per axis and step, turn by up
            // to 0.25 rad per axis and step.
            probe += Vec3::new(b.i8() as f32, b.i8() as f32, b.i8() as f32) * (r * 0.01);
            let (dq, _) = Quat::from_rotation_vector::<Libm>(b.small_rotation());
            q = dq * q;
            let vel = Vec3::new(b.i8() as f32, b.i8() as f32, b.i8() as f32) * 0.01;
            ContactInput {
                q,
                probe_m: probe,
                probe_vel: vel,
            }
        } else if mode < 228 {
            // Anything at all.
            ContactInput {
                q: b.any_quat(),
                probe_m: Vec3::new(b.any_f32(), b.any_f32(), b.any_f32()),
                probe_vel: Vec3::new(b.any_f32(), b.any_f32(), b.any_f32()),
            }
        } else {
            // A plausible pose with a quaternion scaled off unit norm (or to zero, or to inf).
            let s = b.param(1.0);
            ContactInput {
                q: Quat::new(q.w * s, q.x * s, q.y * s, q.z * s),
                probe_m: probe,
                probe_vel: Vec3::ZERO,
            }
        };
        let before = model.state();
        let out = model.contact_step(&input);
        summary.steps += 1;
        summary.flags_seen |= out.flags;
        let at = summary.steps;
        let ctx = || format!("step {at}: {input:?} -> {out:?} with {params:?}, dt {dt}");

        let outputs_finite = finite3(out.force_n)
            && out.tau_n_nm.is_finite()
            && out.spin_rad.is_finite()
            && finite3(out.object_point_m)
            && finite3(model.rolling().finger_point())
            && [out.angles.phi, out.angles.theta, out.angles.psi]
                .iter()
                .all(|a| a.is_finite());
        if !outputs_finite {
            return Err(format!("non-finite output, {}", ctx()));
        }
        let max = params.max_force_n as f64;
        if norm64(out.force_n) > max * (1.0 + FORCE_REL_TOL) {
            return Err(format!("|force| above {max} N, {}", ctx()));
        }
        if plane && out.force_n.z < 0.0 {
            return Err(format!("the plane pulls the finger in, {}", ctx()));
        }
        let input_finite =
            input.q.is_finite() && finite3(input.probe_m) && finite3(input.probe_vel);
        if !input_finite
            && (!out.flags.contains(Flags::NON_FINITE_INPUT)
                || out.force_n != Vec3::ZERO
                || out.state != before)
        {
            return Err(format!(
                "non-finite input not flagged or not ignored, {}",
                ctx()
            ));
        }
        // The contract (`ContactModel::contact_step`): the Euclidean norm, computed in f64 here.
        let far = |v: Vec3, max: f32| {
            let n2 = (v.x as f64).powi(2) + (v.y as f64).powi(2) + (v.z as f64).powi(2);
            n2 > (max as f64).powi(2)
        };
        let out_of_range = input_finite
            && (far(input.probe_m, MAX_PROBE_M) || far(input.probe_vel, MAX_PROBE_SPEED_M_S));
        if out_of_range
            && (!out.flags.contains(Flags::OUT_OF_RANGE)
                || out.force_n != Vec3::ZERO
                || out.state != before)
        {
            return Err(format!(
                "absurd probe not flagged or not ignored, {}",
                ctx()
            ));
        }
        // A rejected sample (out of range) is not looked at further: its quaternion need not be.
        if quat_needs_flag(input.q) && !out_of_range && !out.flags.intersects(QUAT_FLAGS) {
            return Err(format!("bad quaternion not flagged, {}", ctx()));
        }
        // Broken: no tangential contact and no spin torque; only the unilateral normal spring of a
        // probe pressed beyond the make force (the wall stays solid through the re-contact dwell).
        if out.state == ContactState::Broken {
            let (f_n, f_t) = model.rolling().surface().split(out.force_n);
            let tangential = norm64(f_t) > 1e-5 * norm64(out.force_n) + 1e-12;
            if out.tau_n_nm != 0.0 || f_n < 0.0 || tangential {
                return Err(format!("broken but more than the normal spring, {}", ctx()));
            }
        }
        if out.flags.contains(Flags::NON_FINITE_OUTPUT) && !summary.internal_non_finite {
            summary.internal_non_finite = true;
            summary.internal_non_finite_at = Some(ctx());
        }
    }
    Ok(summary)
}

/// Fuzz target `control_tick`: a configuration, then up to [`MAX_STEPS`] ticks with encoder
/// walks, holds, jumps, wild counts, driver faults, overruns, parameter changes and clears.
pub fn control_tick(data: &[u8]) -> Result<Summary, String> {
    let mut b = Bytes::new(data);
    let backend = b.u8() % 3;
    let sphere = b.u8() % 4 == 3;
    if sphere {
        let radius = 0.02 * (1 + b.u8() % 16) as f32;
        let s = Sphere::new(radius);
        match backend {
            0 => run_tick::<Libm, Sphere>(&mut b, s),
            1 => run_tick::<Micromath, Sphere>(&mut b, s),
            _ => run_tick::<Fast, Sphere>(&mut b, s),
        }
    } else {
        let s = Plane::default();
        match backend {
            0 => run_tick::<Libm, Plane>(&mut b, s),
            1 => run_tick::<Micromath, Plane>(&mut b, s),
            _ => run_tick::<Fast, Plane>(&mut b, s),
        }
    }
}

fn run_tick<M: Math, S: Surface>(b: &mut Bytes, surface: S) -> Result<Summary, String> {
    let contact = contact_params(b);
    let r_touch = if pos(contact.fingertip_radius_m) {
        contact.fingertip_radius_m
    } else {
        0.01
    };
    // The scene touches the fingertip with its centre at the workspace centre.
    let centre = DeltaGeometry::OMEGA_LIKE_WORKSPACE_CENTRE_M;
    let top = surface.contact_point() + surface.normal() * r_touch;
    let mut object_origin_m = centre - top;
    if b.u8() >= 240 {
        object_origin_m = Vec3::new(b.any_f32(), b.any_f32(), b.any_f32());
    }
    let config = ControllerConfig {
        rate_hz: b.param(10_000.0),
        device: device(b),
        contact,
        surface,
        object_origin_m,
        limits: limits(b),
    };
    let valid = pos(config.rate_hz)
        && (1_000.0..=40_000.0).contains(&config.rate_hz)
        && config.device.validate().is_ok()
        && contact_params_valid(&config.contact)
        && limits_valid(&config.limits)
        && finite3(config.object_origin_m);
    let mut ctrl = match (Controller::<M, S>::new(config), valid) {
        (Ok(c), true) => c,
        (Err(_), false) => return Ok(Summary::default()),
        (Ok(_), false) => return Err(format!("accepted invalid {config:?}")),
        (Err(e), true) => return Err(format!("rejected valid {config:?}: {e:?}")),
    };
    let dev = config.device;
    let lim = config.limits;
    // The thresholds in ticks, as documented on `TickLimits` (independent of the guard's code).
    let per_tick = lim.per_tick(config.rate_hz);
    let depth = b.i8() as f32 * 1.0e-4; // ±12.7 mm around touching
    let start = centre - Vec3::new(0.0, 0.0, depth);
    let m = dev.counts_at::<Libm>(start, [0; 3]).unwrap_or([0; 6]);
    let mut counts = [m[0], m[1], m[2], 0, 0, 0];

    // Independent model of what must be latched.
    let mut started = false;
    let mut prev = counts;
    let mut expect = Flags::NONE;
    let mut overruns: u32 = 0;
    let mut unchanged = [0u32; 3];
    let mut rejected_pending = false;
    let mut summary = Summary {
        accepted: true,
        ..Summary::default()
    };

    while !b.is_empty() && summary.steps < MAX_STEPS {
        let mode = b.u8();
        match mode {
            0..=159 => {
                // Plausible walk: every encoder moves by at most ±127 counts.
                for c in counts.iter_mut() {
                    *c = c.wrapping_add(b.i8() as i32);
                }
            }
            160..=191 => {} // everything holds still (a stuck encoder if the motors drive)
            192..=207 => {
                let i = b.u8() as usize % 6;
                counts[i] = counts[i].wrapping_add(b.i32() >> (b.u8() % 32));
            }
            208..=215 => {
                for c in counts.iter_mut() {
                    *c = b.i32();
                }
            }
            216..=231 => {
                let p = contact_params(b);
                // Checked where it arrives, as the pipeline does; a refusal raises the flag.
                let ok = match p.checked() {
                    Ok(c) => ctrl.set_contact_params(&c).is_ok(),
                    Err(_) => {
                        ctrl.params_refused();
                        false
                    }
                };
                if ok != contact_params_valid(&p) {
                    return Err(format!("set_contact_params({p:?}) returned ok={ok}"));
                }
                if !ok {
                    rejected_pending = true;
                }
            }
            232..=239 => {
                ctrl.clear_faults();
                started = false;
                expect = Flags::NONE;
                overruns = 0;
                unchanged = [0; 3];
                continue;
            }
            _ => {
                // Wrist whirl: up to ±32767 counts on each wrist axis.
                for c in counts[3..].iter_mut() {
                    *c = c.wrapping_add(b.u16() as i16 as i32);
                }
            }
        }
        let ev = b.u8();
        let input = TickInput {
            counts,
            driver_fault: ev & 0x0f == 0x0f,
            overrun: ev >= 0xc0,
        };

        // What the model says must be latched after this tick.
        if input.driver_fault {
            expect |= Flags::DRIVER_FAULT;
        }
        overruns = if input.overrun { overruns + 1 } else { 0 };
        if overruns >= per_tick.overrun_streak {
            expect |= Flags::OVERRUN;
        }
        if started {
            let jump = counts.iter().zip(prev.iter()).any(|(a, p)| {
                a.wrapping_sub(*p).unsigned_abs() > u32::from(per_tick.max_counts_per_tick)
            });
            if jump {
                expect |= Flags::ENCODER_GLITCH;
            }
            for i in 0..3 {
                unchanged[i] = if counts[i] == prev[i] {
                    unchanged[i] + 1
                } else {
                    0
                };
            }
        }
        let was_latched = ctrl.latched_faults();
        let out = ctrl.tick(&input);
        started = true;
        prev = counts;
        summary.steps += 1;
        summary.flags_seen |= out.flags;
        let at = summary.steps;
        let ctx = || format!("tick {at}: {input:?} -> {out:?} with {:?}", ctrl.config());

        let max_duty = lim.max_duty;
        if !out
            .duties
            .iter()
            .all(|d| d.is_finite() && d.abs() <= max_duty)
        {
            return Err(format!("duty non-finite or above {max_duty}, {}", ctx()));
        }
        if !(finite3(out.force_n) && finite3(out.probe_m) && out.tau_n_nm.is_finite()) {
            return Err(format!("non-finite output, {}", ctx()));
        }
        let max = ctrl.config().contact.max_force_n as f64;
        if norm64(out.force_n) > max * (1.0 + FORCE_REL_TOL) {
            return Err(format!("|force| above {max} N, {}", ctx()));
        }
        if !out.flags.contains(expect) {
            return Err(format!("expected {expect:?} raised, {}", ctx()));
        }
        let latched = ctrl.latched_faults();
        if latched != out.flags & LATCHING {
            return Err(format!("latched {latched:?} but flags differ, {}", ctx()));
        }
        if !latched.is_empty() && (out.enable || out.duties != [0.0; 3]) {
            return Err(format!("latched fault with drive enabled, {}", ctx()));
        }
        if latched.is_empty() != out.enable {
            return Err(format!("enable without a reason, {}", ctx()));
        }
        if !was_latched.is_empty() && !latched.contains(was_latched) {
            return Err(format!("a latched fault went away, {}", ctx()));
        }
        let unexplained = latched & !(expect | Flags::ENCODER_STUCK | Flags::NON_FINITE_OUTPUT);
        if !unexplained.is_empty() {
            return Err(format!("spurious fault {unexplained:?}, {}", ctx()));
        }
        if latched.contains(Flags::ENCODER_STUCK)
            && !was_latched.contains(Flags::ENCODER_STUCK)
            && unchanged.iter().all(|&u| u < per_tick.stuck_ticks)
        {
            return Err(format!("ENCODER_STUCK without a stuck encoder, {}", ctx()));
        }
        if rejected_pending {
            if !out.flags.contains(Flags::PARAM_REJECTED) {
                return Err(format!("rejected change not flagged, {}", ctx()));
            }
            rejected_pending = false;
        }
        // Arm angles the mechanism cannot reach: flagged, and no force.
        let [lo, hi] = lim.arm_angle_range_rad;
        let unreachable = counts[..3]
            .iter()
            .any(|&c| !(lo..=hi).contains(&dev.motor_counts_to_arm_angle_rad(c)));
        if unreachable
            && (!out
                .flags
                .intersects(Flags::OUT_OF_RANGE | Flags::KINEMATICS_SINGULAR)
                || out.force_n != Vec3::ZERO
                || out.duties != [0.0; 3])
        {
            return Err(format!("unreachable pose not flagged or driven, {}", ctx()));
        }
        if latched.contains(Flags::NON_FINITE_OUTPUT) && !summary.internal_non_finite {
            summary.internal_non_finite = true;
            summary.internal_non_finite_at = Some(ctx());
        }
        expect |= latched & (Flags::ENCODER_STUCK | Flags::NON_FINITE_OUTPUT);
    }
    Ok(summary)
}
