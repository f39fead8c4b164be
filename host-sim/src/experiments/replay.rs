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
use crate::error::FileError;
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

fn parse_method(s: &str) -> Result<Method, ReplayError> {
    Method::from_name(s).ok_or_else(|| ReplayError::UnknownMethod(s.to_string()))
}

/// Why a replay failed. Input errors name the file and the line.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    /// `--method` names no decomposition method.
    #[error("unknown method '{0}' (expected exact, rpy or paper-verbatim)")]
    UnknownMethod(String),
    /// The input file is malformed.
    #[error("{}{}: {problem}", path.display(), line.map(|l| format!(" line {l}")).unwrap_or_default())]
    Input {
        /// The input file.
        path: PathBuf,
        /// 1-based line, when the problem is on one line.
        line: Option<u64>,
        /// What is wrong.
        problem: InputProblem,
    },
    /// A command-line option is out of range.
    #[error("{0}")]
    Option(OptionProblem),
    /// The replay produced a non-finite value at this time, s (a bug; nothing is written).
    #[error("internal error: non-finite output at t = {0} s (nothing written)")]
    NonFiniteOutput(f64),
    /// A file could not be opened or written.
    #[error(transparent)]
    File(#[from] FileError),
}

/// What is wrong with an input file.
#[derive(Debug, thiserror::Error)]
pub enum InputProblem {
    /// The CSV reader failed.
    #[error("unreadable CSV: {0}")]
    Csv(csv::Error),
    /// The first line is not [`INPUT_HEADER`].
    #[error("header must be '{}', found '{found}'", INPUT_HEADER.join(","))]
    Header {
        /// The header found.
        found: String,
    },
    /// A row without 5 fields.
    #[error("expected 5 fields (t_s,qw,qx,qy,qz), found {0}")]
    FieldCount(usize),
    /// A field that does not parse as a number.
    #[error("field '{field}' is not a number: '{text}'")]
    NotNumber {
        /// Column name.
        field: &'static str,
        /// The text found.
        text: String,
    },
    /// A field that is NaN or infinite.
    #[error("field '{field}' is not finite: '{text}'")]
    NotFinite {
        /// Column name.
        field: &'static str,
        /// The text found.
        text: String,
    },
    /// All four quaternion components zero.
    #[error("zero quaternion")]
    ZeroQuaternion,
    /// A quaternion norm further from 1 than [`NORM_TOLERANCE`].
    #[error("quaternion norm {0:.6} is off unity by more than {NORM_TOLERANCE}")]
    Norm(f64),
    /// A time before the previous row's.
    #[error("time goes back ({t} after {previous})")]
    TimeGoesBack {
        /// This row's time, s.
        t: f64,
        /// The previous row's time, s.
        previous: f64,
    },
    /// A header and no rows.
    #[error("no samples (a header and at least one row are needed)")]
    NoSamples,
}

/// A command-line option out of range.
#[derive(Debug, thiserror::Error)]
pub enum OptionProblem {
    /// `--radius-m` not positive.
    #[error("--radius-m must be a positive number, got {0}")]
    Radius(f64),
    /// `--normal-force-n` negative.
    #[error("--normal-force-n must be a non-negative number, got {0}")]
    NormalForce(f64),
    /// `--object-radius-m` not positive.
    #[error("--object-radius-m must be a positive number, got {0}")]
    ObjectRadius(f64),
    /// A bowl no larger than the fingertip.
    #[error("--object-radius-m ({object}) must be larger than --radius-m ({finger}) for a bowl")]
    BowlTooSmall {
        /// Object radius, m.
        object: f64,
        /// Fingertip radius, m.
        finger: f64,
    },
}

/// One parsed input row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub t_s: f64,
    pub q: [f64; 4],
}

/// Read and check the whole input. Errors name the file and the line.
pub fn read_samples(path: &std::path::Path) -> Result<Vec<Sample>, ReplayError> {
    let file = std::fs::File::open(path).map_err(FileError::on(path, "cannot open"))?;
    let bad = |line: Option<u64>, problem| ReplayError::Input {
        path: path.to_path_buf(),
        line,
        problem,
    };
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
            bad(Some(line), InputProblem::Csv(e))
        })?;
        let line = rec.position().map(|p| p.line()).unwrap_or(i as u64 + 1);
        if i == 0 {
            let got: Vec<&str> = rec.iter().collect();
            if got != INPUT_HEADER {
                return Err(bad(
                    Some(line),
                    InputProblem::Header {
                        found: got.join(","),
                    },
                ));
            }
            continue;
        }
        if rec.len() != 5 {
            return Err(bad(Some(line), InputProblem::FieldCount(rec.len())));
        }
        let mut v = [0.0f64; 5];
        for (k, field) in rec.iter().enumerate() {
            let text = || field.to_string();
            let field_name = INPUT_HEADER[k];
            let x: f64 = field.parse().map_err(|_| {
                bad(
                    Some(line),
                    InputProblem::NotNumber {
                        field: field_name,
                        text: text(),
                    },
                )
            })?;
            if !x.is_finite() {
                return Err(bad(
                    Some(line),
                    InputProblem::NotFinite {
                        field: field_name,
                        text: text(),
                    },
                ));
            }
            v[k] = x;
        }
        let norm = (v[1] * v[1] + v[2] * v[2] + v[3] * v[3] + v[4] * v[4]).sqrt();
        if norm == 0.0 {
            return Err(bad(Some(line), InputProblem::ZeroQuaternion));
        }
        if (norm - 1.0).abs() > NORM_TOLERANCE {
            return Err(bad(Some(line), InputProblem::Norm(norm)));
        }
        if v[0] < prev_t {
            return Err(bad(
                Some(line),
                InputProblem::TimeGoesBack {
                    t: v[0],
                    previous: prev_t,
                },
            ));
        }
        prev_t = v[0];
        samples.push(Sample {
            t_s: v[0],
            q: [v[1] / norm, v[2] / norm, v[3] / norm, v[4] / norm],
        });
    }
    if samples.is_empty() {
        return Err(bad(None, InputProblem::NoSamples));
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
fn replay_args(args: &Args, samples: &[Sample]) -> Result<Vec<Row>, ReplayError> {
    let big = args.object_radius_m;
    if !(big.is_finite() && big > 0.0) {
        return Err(ReplayError::Option(OptionProblem::ObjectRadius(big)));
    }
    if args.surface == SurfaceKind::Bowl && big <= args.radius_m {
        return Err(ReplayError::Option(OptionProblem::BowlTooSmall {
            object: big,
            finger: args.radius_m,
        }));
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

pub fn main(args: &Args) -> Result<(), ReplayError> {
    if !(args.radius_m.is_finite() && args.radius_m > 0.0) {
        return Err(ReplayError::Option(OptionProblem::Radius(args.radius_m)));
    }
    if !(args.normal_force_n.is_finite() && args.normal_force_n >= 0.0) {
        return Err(ReplayError::Option(OptionProblem::NormalForce(
            args.normal_force_n,
        )));
    }
    let samples = read_samples(&args.input)?;
    let rows = replay_args(args, &samples)?;
    let out = args.out.display();
    let mut file =
        AtomicFile::create(&args.out).map_err(FileError::on(&args.out, "cannot create"))?;
    let w = file.writer();
    let io = |e| FileError::on(&args.out, "write failed")(e);
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
            return Err(ReplayError::NonFiniteOutput(r.t_s));
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
        .map_err(FileError::on(&args.out, "cannot publish"))?;
    eprintln!(
        "host-sim replay: {} rows, method {}, surface {:?}, written to {out}",
        rows.len(),
        args.method.name(),
        args.surface
    );
    Ok(())
}
