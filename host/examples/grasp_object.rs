//! Two devices hold one object: the application runs the object, each device renders its surface.
//!
//! ```sh
//! cargo run --release -p host-sim -- serve --devices 2 --auto-arm --scene finger-on-sphere &
//! cargo run --release -p softfinger-host --example grasp_object -- \
//!     tcp:127.0.0.1:7700 tcp:127.0.0.1:7701 [--model-hz 1000] [--latency-ms 0] [--duration-s 2] [--json]
//! ```
//!
//! The architecture's split: the object (a 0.1 kg, 30 mm sphere) lives here, stepped at 1 kHz
//! by the core's `Grasp` (its models go out at `--model-hz`, 100 Hz–1 kHz), whose two soft-finger contacts take the
//! fingertips the devices stream; after each step both devices get the sphere's pose as their
//! local model (predicted ahead by the delay until they render it), and render it at their
//! control rate with the same contact model. The devices stand upright; the application maps
//! device 0's base frame onto the +x side of the world, pressing towards −x, and device 1 onto
//! −x (`DeviceMount`). On the virtual devices the simulated hand squeezes (`DriveHand`); on real
//! ones the user does.
//!
//! `--latency-ms` delays everything both ways by that much (the samples this loop uses and the
//! models it sends): a slower link. Measured while the weight is held (from 0.2 s after the
//! support lets go to the end): whether it held (the object moves < 0.1 mm relative to the
//! fingertips' midpoint and turns < 0.01 rad), the object's jitter (standard deviation of that
//! relative position), and the force steps at model updates (each device streams every control
//! tick: the largest tick-to-tick change of its rendered force at the ticks a new model took
//! effect, and at the other ticks).
#![allow(dead_code)] // the test includes this file for `run`; `main` is the example's own

use softfinger_core::contact::surface::Sphere;
use softfinger_core::contact::ContactParams;
use softfinger_core::control::local_model::{LocalModelSpec, ModelKind};
use softfinger_core::grasp::{BodyParams, BodyState, DeviceContact, DeviceMount, Grasp, Wrench};
use softfinger_core::{Fast, Quat, Vec3};
use softfinger_host::protocol::{HandTarget, LocalModel, Mode, StateSample};
use softfinger_host::{Device, Target};
use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// Where the object's first contact is in each device's base frame, m: the top of the sphere
/// 10 mm below the Omega-like design workspace's centre (0, 0, −0.165), as in host-sim's scenes.
pub const TOP_Z_M: f32 = -0.175;
/// The object's radius, m.
pub const RADIUS_M: f32 = 0.03;
/// The object's mass, kg.
pub const MASS_KG: f32 = 0.1;
/// Each hand's squeeze, N.
pub const GRIP_N: f64 = 5.0;
/// The virtual hand's spring (host-sim's plant), N/m: the squeeze target is grip/k inside.
pub const HAND_STIFFNESS: f64 = 300.0;
/// The effector's mass the virtual hand carries, kg (its target sits m·g/k higher).
pub const EFFECTOR_KG: f64 = 0.15;
/// Time the hands get to close on the object, s.
pub const CLOSE_S: f64 = 1.2;
/// The weight ramps in over this once the hands have closed, s.
pub const RAMP_S: f64 = 0.15;
/// Judged from this long after the weight starts to ramp in, s.
pub const SETTLE_S: f64 = 0.2;

/// What a run takes.
#[derive(Clone, Debug)]
pub struct Options {
    /// The two devices.
    pub targets: [Target; 2],
    /// The object's step and model rate, Hz.
    pub model_hz: f64,
    /// Injected one-way delay, each way, ms.
    pub latency_ms: f64,
    /// How long the weight is held, s.
    pub hold_s: f64,
}

/// What a run measured.
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    /// Moved < 0.1 mm and turned < 0.01 rad relative to the fingertips after settling.
    pub held: bool,
    /// Largest displacement relative to the fingertips' midpoint after settling, mm.
    pub slip_mm: f64,
    /// Largest turn about the grasp axis after settling, rad.
    pub rotation_rad: f64,
    /// Standard deviation of the position relative to the fingertips' midpoint, µm.
    pub jitter_um: f64,
    /// Largest tick-to-tick change of a device's rendered force at a model update, N.
    pub force_step_at_update_n: f64,
    /// The same at the other ticks, N.
    pub force_step_between_n: f64,
    /// Each contact's mean normal force while judged, N.
    pub normal_force_n: [f64; 2],
    /// Models sent to each device.
    pub models_sent: u64,
    /// Object steps that started more than one period late.
    pub late_steps: u64,
    /// Samples received per device.
    pub samples: [u64; 2],
}

fn mounts(top_z_m: f32) -> [DeviceMount; 2] {
    let mk = |sign: f32| {
        let q = Quat::from_axis_angle::<Fast>(Vec3::Y, sign * core::f32::consts::FRAC_PI_2);
        let c = q.rotate(Vec3::new(0.0, 0.0, top_z_m - RADIUS_M));
        DeviceMount {
            origin_m: -c,
            orientation: q,
        }
    };
    [mk(1.0), mk(-1.0)]
}

fn v3(a: [f32; 3]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

fn contact_of(s: &StateSample) -> DeviceContact {
    DeviceContact {
        force_n: v3(s.force_n),
        spin_torque_nm: s.spin_torque_nm,
        contact_point_m: v3(s.contact_point_m),
        probe_m: v3(s.probe_m),
        probe_vel_m_s: v3(s.probe_vel_m_s),
    }
}

fn spec(
    seq: u32,
    pose_of: &DeviceMount,
    body: &BodyState,
    lead_s: f32,
    cp: &ContactParams,
) -> LocalModel {
    LocalModel::of(&LocalModelSpec {
        seq,
        kind: ModelKind::Sphere { radius_m: RADIUS_M },
        pose: pose_of.model_pose_ahead::<Fast>(body, lead_s),
        stiffness_n_per_m: cp.normal_stiffness,
        damping_n_s_per_m: cp.normal_damping,
        mu_s: cp.mu_s,
        mu_k: cp.mu_k,
        spin_stiffness_nm_per_rad: cp.spin_stiffness,
        max_age_s: 0.0,
    })
}

/// The rate the object is stepped at, Hz: the model rate, or 1 kHz when models go out more
/// slowly (an explicit step of the stiff contacts at 5 ms diverges).
pub fn object_hz(model_hz: f64) -> f64 {
    model_hz.max(1000.0)
}

fn err(what: &str) -> impl Fn(softfinger_host::LinkError) -> String + '_ {
    move |e| format!("{what}: {e}")
}

/// Connect, close the hands, hold the object for `hold_s` and measure.
pub fn run(o: &Options) -> Result<Outcome, String> {
    if !(100.0..=1000.0).contains(&o.model_hz) {
        return Err(format!("--model-hz {}: must be in 100..=1000", o.model_hz));
    }
    if !(o.latency_ms.is_finite() && (0.0..=1000.0).contains(&o.latency_ms)) {
        return Err(format!(
            "--latency-ms {}: must be in 0..=1000",
            o.latency_ms
        ));
    }
    let mut devs = Vec::new();
    for t in &o.targets {
        let mut d = Device::connect(t).map_err(err("connect"))?;
        d.set_heartbeat(true);
        devs.push(d);
    }
    let divisor = devs[0]
        .info()
        .map_err(err("info"))?
        .min_stream_divisor
        .max(1);
    let mut cp = ContactParams::DEFAULT;
    // The grasp's contact: the same as `host-sim grasp` (tangential 3000 N/m and 10 N·s/m,
    // spin 0.2 N·m/rad); the material goes to the devices with each model, the rest with
    // SetContactParams.
    cp.tangential_stiffness = 3000.0;
    cp.tangential_damping = 10.0;
    cp.spin_stiffness = 0.2;
    cp.max_force_n = 12.0;
    let top = TOP_Z_M;
    let mounts = mounts(top);
    let mut body = BodyState::default();
    let mut grasp: Grasp<Fast, Sphere> = Grasp::new(
        {
            let mut b = BodyParams::solid_sphere(MASS_KG, RADIUS_M);
            let i = b.inertia_kg_m2.x;
            b.angular_damping = (2.0 * cp.spin_stiffness * i).sqrt();
            b
        },
        body,
        Sphere::new(RADIUS_M),
        [cp; 2],
        Vec3::ZERO,
        (1.0 / object_hz(o.model_hz)) as f32,
    )
    .map_err(|e| format!("grasp: {e}"))?;
    // Each model must be newer than the one in force on either device.
    let mut seq = 0_u32;
    for d in devs.iter_mut() {
        seq = seq.max(d.status().map_err(err("status"))?.model.seq);
    }
    seq = seq.wrapping_add(1);
    for (d, m) in devs.iter_mut().zip(&mounts) {
        if d.status().map_err(err("status"))?.mode != Mode::Armed {
            d.home_and_wait(Duration::from_secs(30))
                .map_err(err("home"))?;
            d.arm().map_err(err("arm"))?;
        }
        d.set_contact_params(softfinger_host::protocol::ContactParamsWire::of(&cp))
            .map_err(err("contact params"))?;
        d.set_local_model(spec(seq, m, &body, 0.0, &cp))
            .map_err(err("model"))?;
        d.set_stream(divisor).map_err(err("stream"))?;
        let squeeze =
            f64::from(top) + 0.010 - GRIP_N / HAND_STIFFNESS + EFFECTOR_KG * 9.81 / HAND_STIFFNESS;
        d.drive_hand(HandTarget {
            position_m: [0.0, 0.0, squeeze as f32],
            wrist_rad: [0.0; 3],
        })
        .map_err(err("drive hand"))?;
    }
    std::thread::sleep(Duration::from_secs_f64(CLOSE_S));
    let queues: Vec<_> = devs.iter().map(|d| d.state_queue()).collect();
    for q in &queues {
        while let Ok(Some(_)) = q.next(Duration::ZERO) {}
    }
    let period = Duration::from_secs_f64(1.0 / object_hz(o.model_hz));
    let every = (object_hz(o.model_hz) / o.model_hz).round().max(1.0) as u64;
    let delay = Duration::from_secs_f64(o.latency_ms * 1e-3);
    let lead = (o.latency_ms * 1e-3 + 0.5 / o.model_hz + 0.001) as f32;
    let mut inbox: [VecDeque<(Instant, StateSample)>; 2] = Default::default();
    let mut outbox: VecDeque<(Instant, [LocalModel; 2])> = VecDeque::new();
    let mut latest: [Option<StateSample>; 2] = [None, None];
    let mut last_force: [Option<[f32; 3]>; 2] = [None, None];
    let mut last_seq = [0_u32; 2];
    let mut out = Outcome::default();
    let (mut rel, mut fn_sum, mut fn_n) = (Vec::new(), [0.0; 2], 0.0);
    let mut q_ref: Option<Quat> = None;
    let start = Instant::now();
    let total = RAMP_S + SETTLE_S + o.hold_s;
    let mut k = 0_u64;
    loop {
        let due = start + period * k as u32;
        let now = Instant::now();
        if now < due {
            std::thread::sleep(due - now);
        } else if now > due + period {
            out.late_steps += 1;
        }
        let t = start.elapsed().as_secs_f64();
        if t > total {
            break;
        }
        let judged = t >= RAMP_S + SETTLE_S;
        // Everything the devices streamed since the last step, delayed by the injected latency.
        for i in 0..2 {
            while let Ok(Some(s)) = queues[i].next(Duration::ZERO) {
                out.samples[i] += 1;
                if let Some(f) = last_force[i] {
                    let df = (0..3)
                        .map(|a| (s.force_n[a] - f[a]).powi(2))
                        .sum::<f32>()
                        .sqrt();
                    if judged {
                        if s.model_seq != last_seq[i] {
                            out.force_step_at_update_n = out.force_step_at_update_n.max(df.into());
                        } else {
                            out.force_step_between_n = out.force_step_between_n.max(df.into());
                        }
                    }
                }
                last_force[i] = Some(s.force_n);
                last_seq[i] = s.model_seq;
                inbox[i].push_back((Instant::now() + delay, s));
            }
            while inbox[i]
                .front()
                .is_some_and(|(at, _)| *at <= Instant::now())
            {
                latest[i] = inbox[i].pop_front().map(|(_, s)| s);
            }
        }
        let (Some(s0), Some(s1)) = (latest[0], latest[1]) else {
            k += 1;
            continue;
        };
        let c = [contact_of(&s0), contact_of(&s1)];
        let ramp = (t / RAMP_S).clamp(0.0, 1.0);
        let ramp = 0.5 - 0.5 * (std::f64::consts::PI * ramp).cos();
        let weight = Wrench {
            force_n: Vec3::new(0.0, 0.0, -(ramp * f64::from(MASS_KG) * 9.81) as f32),
            torque_nm: Vec3::ZERO,
        };
        let tips = [
            Some(mounts[0].fingertip(&c[0])),
            Some(mounts[1].fingertip(&c[1])),
        ];
        let step = grasp.step(tips, weight);
        body = grasp.body.state;
        if k.is_multiple_of(every) {
            seq = seq.wrapping_add(1);
            outbox.push_back((
                Instant::now() + delay,
                [
                    spec(seq, &mounts[0], &body, lead, &cp),
                    spec(seq, &mounts[1], &body, lead, &cp),
                ],
            ));
        }
        while outbox.front().is_some_and(|(at, _)| *at <= Instant::now()) {
            if let Some((_, models)) = outbox.pop_front() {
                for (d, m) in devs.iter_mut().zip(models) {
                    d.set_local_model(m).map_err(err("model"))?;
                }
                out.models_sent += 1;
            }
        }
        if judged {
            let mid = (tips[0].map_or(Vec3::ZERO, |f| f.pos_m)
                + tips[1].map_or(Vec3::ZERO, |f| f.pos_m))
                * 0.5;
            rel.push(body.pos_m - mid);
            let q0 = *q_ref.get_or_insert(body.q);
            let turn = (q0.conjugate() * body.q).to_rotation_vector::<Fast>();
            out.rotation_rad = out.rotation_rad.max(f64::from(turn.x.abs()));
            for (i, r) in step.contacts.iter().enumerate() {
                fn_sum[i] += f64::from(r.normal_force_n);
            }
            fn_n += 1.0;
        }
        k += 1;
    }
    for d in devs.iter_mut() {
        let _ = d.release_hand();
        let _ = d.set_stream(0);
    }
    if rel.is_empty() {
        return Err("no samples while judged: are both devices streaming?".into());
    }
    let n = rel.len() as f32;
    let mean = rel.iter().fold(Vec3::ZERO, |a, r| a + *r) * (1.0 / n);
    let r0 = rel[0];
    out.slip_mm = rel
        .iter()
        .map(|r| f64::from((*r - r0).norm::<Fast>()) * 1e3)
        .fold(0.0, f64::max);
    out.jitter_um = (rel
        .iter()
        .map(|r| f64::from((*r - mean).norm_squared()))
        .sum::<f64>()
        / f64::from(n))
    .sqrt()
        * 1e6;
    out.normal_force_n = [fn_sum[0] / fn_n, fn_sum[1] / fn_n];
    out.held = out.slip_mm < 0.1 && out.rotation_rad < 0.01 && body.pos_m.is_finite();
    Ok(out)
}

fn main() {
    let mut args = std::env::args().skip(1);
    let mut targets = Vec::new();
    let (mut model_hz, mut latency_ms, mut hold_s, mut json) = (1000.0, 0.0, 2.0, false);
    while let Some(a) = args.next() {
        let mut num = |name: &str| -> f64 {
            match args.next().and_then(|v| v.parse::<f64>().ok()) {
                Some(v) => v,
                None => {
                    eprintln!("grasp_object: {name} needs a number");
                    std::process::exit(2);
                }
            }
        };
        match a.as_str() {
            "--model-hz" => model_hz = num("--model-hz"),
            "--latency-ms" => latency_ms = num("--latency-ms"),
            "--duration-s" => hold_s = num("--duration-s"),
            "--json" => json = true,
            t => match t.parse::<Target>() {
                Ok(t) => targets.push(t),
                Err(e) => {
                    eprintln!("grasp_object: {t}: {e}");
                    std::process::exit(2);
                }
            },
        }
    }
    if targets.is_empty() {
        targets = vec![
            "tcp:127.0.0.1:7700".parse().expect("a valid target"),
            "tcp:127.0.0.1:7701".parse().expect("a valid target"),
        ];
    }
    let [a, b]: [Target; 2] = match targets.try_into() {
        Ok(t) => t,
        Err(_) => {
            eprintln!("grasp_object: give two targets (one per fingertip)");
            std::process::exit(2);
        }
    };
    let o = Options {
        targets: [a, b],
        model_hz,
        latency_ms,
        hold_s,
    };
    match run(&o) {
        Ok(r) => {
            if json {
                println!(
                    "{{\"held\": {}, \"slip_mm\": {:.4}, \"rotation_rad\": {:.5}, \"jitter_um\": {:.2}, \
                     \"force_step_at_update_n\": {:.4}, \"force_step_between_n\": {:.4}, \
                     \"normal_force_n\": [{:.3}, {:.3}], \"model_hz\": {}, \"latency_ms\": {}, \
                     \"models_sent\": {}, \"late_steps\": {}, \"samples\": [{}, {}]}}",
                    r.held, r.slip_mm, r.rotation_rad, r.jitter_um, r.force_step_at_update_n,
                    r.force_step_between_n, r.normal_force_n[0], r.normal_force_n[1], o.model_hz,
                    o.latency_ms, r.models_sent, r.late_steps, r.samples[0], r.samples[1]
                );
            } else {
                println!(
                    "grasp over the link ({} Hz object, {} ms each way): held {}, slip {:.4} mm, turn {:.5} rad, \
                     jitter {:.2} um, force step at model updates {:.4} N (between {:.4} N), normal forces {:.2} N / {:.2} N, \
                     {} models sent, {} late steps",
                    o.model_hz, o.latency_ms, r.held, r.slip_mm, r.rotation_rad, r.jitter_um,
                    r.force_step_at_update_n, r.force_step_between_n, r.normal_force_n[0],
                    r.normal_force_n[1], r.models_sent, r.late_steps
                );
            }
            if !r.held {
                std::process::exit(1);
            }
        }
        Err(e) => {
            eprintln!("grasp_object: {e}");
            std::process::exit(1);
        }
    }
}
