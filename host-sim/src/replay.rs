//! `host-sim replay`: recorded fingertip orientations through the core's rolling model.
//!
//! Input CSV, header `t_s,qw,qx,qy,qz`: one row per sample; unit quaternion (Hamilton, scalar first)
//! mapping the fingertip sphere's body frame to the plane's frame; time non-decreasing. A
//! quaternion whose norm is off unity by more than 1e-3 is an error; within that it is normalised.
//!
//! Physics (`--surface`, object radius R = `--object-radius-m`, fingertip radius r = `--radius-m`):
//! - `plane`: z = 0, normal +z;
//! - `sphere`: centred at the object origin, radius R, the contact starting at (0, 0, R);
//! - `bowl`: the inside of a spherical shell of radius R > r centred at the origin, the contact
//!   starting at (0, 0, −R);
//! - `cylinder`: radius R, axis along object x through the origin, the contact starting at (0, 0, R).
//!
//! The normal at the start is +z (towards the fingertip) on every surface. Between samples the
//! fingertip turns at constant angular velocity in the object frame and rolls without slip. The
//! spin torque uses the default contact parameters and a nominal normal force (`--normal-force-n`)
//! for the torsional limit, since a log of orientations carries no force.
//!
//! Output CSV, header [`OUTPUT_HEADER`], one row per input row: `plane_x_m, plane_y_m` are the
//! object contact point's x and y (the plane's contact point on the plane), `sphere_*` and
//! `finger_*` the contact point on the fingertip (fingertip frame), `object_*` the contact point on
//! the object (object frame). Row 0 is the initial contact. `state` is `rolling`, or the method's
//! failure on that row (`singular`, `gimbal-lock`).
//!
//! Bad input: a one-line error naming the line on stderr, exit code 2, and no output file.

use crate::atomic_file::AtomicFile;
use softfinger_core::contact::decompose::Method;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::rolling::Rolling;
use softfinger_core::contact::spin::{torsion_limit, SpinSpring};
use softfinger_core::contact::surface::{Bowl, Cylinder, Plane, Sphere, Surface};
use softfinger_core::{Flags, Libm, Quat};
use std::io::Write;
use std::path::PathBuf;

/// Largest accepted |‖q‖ − 1| in the input.
pub const NORM_TOLERANCE: f64 = 1e-3;

/// The input header, exactly.
pub const INPUT_HEADER: [&str; 5] = ["t_s", "qw", "qx", "qy", "qz"];

/// The output header.
pub const OUTPUT_HEADER: &str = "t_s,plane_x_m,plane_y_m,sphere_x_m,sphere_y_m,sphere_z_m,spin_rad,tau_n_nm,state,object_x_m,object_y_m,object_z_m,finger_x_m,finger_y_m,finger_z_m";

/// The object surface of a replay.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SurfaceKind {
    Plane,
    Sphere,
    Bowl,
    Cylinder,
}

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Input CSV (t_s,qw,qx,qy,qz).
    #[arg(long)]
    pub input: PathBuf,
    /// Output CSV.
    #[arg(long)]
    pub out: PathBuf,
    /// Decomposition method: exact, rpy or paper-verbatim.
    #[arg(long, default_value = "exact", value_parser = parse_method)]
    pub method: Method,
    /// Fingertip sphere radius, m (the paper's 10 mm by default).
    #[arg(long, default_value_t = 0.01)]
    pub radius_m: f64,
    /// Nominal normal force for the torsional friction limit, N.
    #[arg(long, default_value_t = 1.0)]
    pub normal_force_n: f64,
    /// The object: plane, sphere, bowl or cylinder (conventions in the module doc).
    #[arg(long, value_enum, default_value_t = SurfaceKind::Plane)]
    pub surface: SurfaceKind,
    /// Object radius R for sphere, bowl and cylinder, m (bowl: larger than --radius-m).
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    pub object_radius_m: f64,
}

fn parse_method(s: &str) -> Result<Method, String> {
    Method::from_name(s)
        .ok_or_else(|| format!("unknown method '{s}' (expected exact, rpy or paper-verbatim)"))
}

/// One parsed input row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub t_s: f64,
    pub q: [f64; 4],
}

/// Read and check the whole input. Errors name the file and the line.
pub fn read_samples(path: &std::path::Path) -> Result<Vec<Sample>, String> {
    let name = path.display();
    let file = std::fs::File::open(path).map_err(|e| format!("{name}: cannot open: {e}"))?;
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(file);
    let mut samples = Vec::new();
    let mut prev_t = f64::NEG_INFINITY;
    for (i, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| {
            let line = e.position().map(|p| p.line()).unwrap_or(i as u64 + 1);
            format!("{name} line {line}: unreadable CSV: {e}")
        })?;
        let line = rec.position().map(|p| p.line()).unwrap_or(i as u64 + 1);
        if i == 0 {
            let got: Vec<&str> = rec.iter().collect();
            if got != INPUT_HEADER {
                return Err(format!(
                    "{name} line {line}: header must be '{}', found '{}'",
                    INPUT_HEADER.join(","),
                    got.join(",")
                ));
            }
            continue;
        }
        if rec.len() != 5 {
            return Err(format!(
                "{name} line {line}: expected 5 fields (t_s,qw,qx,qy,qz), found {}",
                rec.len()
            ));
        }
        let mut v = [0.0f64; 5];
        for (k, field) in rec.iter().enumerate() {
            let x: f64 = field.parse().map_err(|_| {
                format!(
                    "{name} line {line}: field '{}' is not a number: '{field}'",
                    INPUT_HEADER[k]
                )
            })?;
            if !x.is_finite() {
                return Err(format!(
                    "{name} line {line}: field '{}' is not finite: '{field}'",
                    INPUT_HEADER[k]
                ));
            }
            v[k] = x;
        }
        let norm = (v[1] * v[1] + v[2] * v[2] + v[3] * v[3] + v[4] * v[4]).sqrt();
        if norm == 0.0 {
            return Err(format!("{name} line {line}: zero quaternion"));
        }
        if (norm - 1.0).abs() > NORM_TOLERANCE {
            return Err(format!("{name} line {line}: quaternion norm {norm:.6} is off unity by more than {NORM_TOLERANCE}"));
        }
        if v[0] < prev_t {
            return Err(format!(
                "{name} line {line}: time goes back ({} after {prev_t})",
                v[0]
            ));
        }
        prev_t = v[0];
        samples.push(Sample {
            t_s: v[0],
            q: [v[1] / norm, v[2] / norm, v[3] / norm, v[4] / norm],
        });
    }
    if samples.is_empty() {
        return Err(format!(
            "{name}: no samples (a header and at least one row are needed)"
        ));
    }
    Ok(samples)
}

/// One output row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    pub t_s: f64,
    pub plane: [f32; 2],
    pub sphere: [f32; 3],
    pub object: [f32; 3],
    pub spin_rad: f32,
    pub tau_n_nm: f32,
    pub state: &'static str,
}

/// The name written in the `state` column for a step's flags.
fn state_name(flags: Flags) -> &'static str {
    if flags.contains(Flags::SINGULAR) {
        "singular"
    } else if flags.contains(Flags::GIMBAL_LOCK) {
        "gimbal-lock"
    } else {
        "rolling"
    }
}

/// Run the samples through the core on the plane (libm backend, f32).
pub fn replay(samples: &[Sample], method: Method, radius_m: f32, normal_force_n: f32) -> Vec<Row> {
    replay_on(Plane::default(), samples, method, radius_m, normal_force_n)
}

/// Run the samples through the core on `surface` (libm backend, f32).
pub fn replay_on<S: Surface>(
    surface: S,
    samples: &[Sample],
    method: Method,
    radius_m: f32,
    normal_force_n: f32,
) -> Vec<Row> {
    let params = ContactParams::DEFAULT;
    let tau_max = torsion_limit(params.mu_s, normal_force_n, params.patch_radius_m);
    let to_q = |s: &Sample| Quat::new(s.q[0] as f32, s.q[1] as f32, s.q[2] as f32, s.q[3] as f32);
    let mut rolling = Rolling::new(surface, radius_m, to_q(&samples[0]), method);
    let mut spin = SpinSpring::default();
    let mut rows = Vec::with_capacity(samples.len());
    let mut push = |t_s: f64, r: &Rolling<S>, spin: &SpinSpring, tau: f32, state| {
        let p = r.surface().contact_point();
        let f = r.finger_point();
        rows.push(Row {
            t_s,
            plane: [p.x, p.y],
            sphere: [f.x, f.y, f.z],
            object: [p.x, p.y, p.z],
            spin_rad: spin.accumulated_rad,
            tau_n_nm: tau,
            state,
        });
    };
    push(samples[0].t_s, &rolling, &spin, 0.0, "rolling");
    for s in &samples[1..] {
        let step = rolling.step::<Libm>(to_q(s));
        let (tau, _) = spin.update(step.angles.phi, params.spin_stiffness, tau_max);
        push(s.t_s, &rolling, &spin, tau, state_name(step.flags));
    }
    rows
}

/// Check the radii and run the replay on the surface `args` asks for.
fn replay_args(args: &Args, samples: &[Sample]) -> Result<Vec<Row>, String> {
    let big = args.object_radius_m;
    if !(big.is_finite() && big > 0.0) {
        return Err(format!(
            "--object-radius-m must be a positive number, got {big}"
        ));
    }
    if args.surface == SurfaceKind::Bowl && big <= args.radius_m {
        return Err(format!(
            "--object-radius-m ({big}) must be larger than --radius-m ({}) for a bowl",
            args.radius_m
        ));
    }
    let (r, f, m) = (
        args.radius_m as f32,
        args.normal_force_n as f32,
        args.method,
    );
    let big = big as f32;
    Ok(match args.surface {
        SurfaceKind::Plane => replay(samples, m, r, f),
        SurfaceKind::Sphere => replay_on(Sphere::new(big), samples, m, r, f),
        SurfaceKind::Bowl => replay_on(Bowl::new(big), samples, m, r, f),
        SurfaceKind::Cylinder => replay_on(Cylinder::new(big), samples, m, r, f),
    })
}

pub fn main(args: &Args) -> Result<(), String> {
    if !(args.radius_m.is_finite() && args.radius_m > 0.0) {
        return Err(format!(
            "--radius-m must be a positive number, got {}",
            args.radius_m
        ));
    }
    if !(args.normal_force_n.is_finite() && args.normal_force_n >= 0.0) {
        return Err(format!(
            "--normal-force-n must be a non-negative number, got {}",
            args.normal_force_n
        ));
    }
    let samples = read_samples(&args.input)?;
    let rows = replay_args(args, &samples)?;
    let out = args.out.display();
    let mut file =
        AtomicFile::create(&args.out).map_err(|e| format!("{out}: cannot create: {e}"))?;
    let w = file.writer();
    let io = |e: std::io::Error| format!("{out}: write failed: {e}");
    writeln!(w, "{OUTPUT_HEADER}").map_err(io)?;
    for r in &rows {
        let vals = [
            r.plane[0],
            r.plane[1],
            r.sphere[0],
            r.sphere[1],
            r.sphere[2],
            r.spin_rad,
            r.tau_n_nm,
            r.object[0],
            r.object[1],
            r.object[2],
        ];
        if vals.iter().any(|v| !v.is_finite()) {
            return Err(format!(
                "internal error: non-finite output at t = {} s (nothing written)",
                r.t_s
            ));
        }
        writeln!(
            w,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.t_s,
            vals[0],
            vals[1],
            vals[2],
            vals[3],
            vals[4],
            vals[5],
            vals[6],
            r.state,
            vals[7],
            vals[8],
            vals[9],
            vals[2],
            vals[3],
            vals[4]
        )
        .map_err(io)?;
    }
    file.commit()
        .map_err(|e| format!("{out}: cannot publish: {e}"))?;
    eprintln!(
        "host-sim replay: {} rows, method {}, surface {:?}, written to {out}",
        rows.len(),
        args.method.name(),
        args.surface
    );
    Ok(())
}
