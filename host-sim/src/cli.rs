//! The command line: parsing and dispatch. `run` is the default command.

use clap::{Parser, Subcommand};
use std::ffi::OsString;

/// Run the softfinger contact core against a software plant, replay bench logs, validate against
/// the classical rolling equations, and chart speed against accuracy.
#[derive(Debug, Parser)]
#[command(name = "host-sim", version, about)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a scene in closed loop with the plant (the default): summary, CSV and SVG charts.
    Run(crate::experiments::run::Args),
    /// Replay recorded fingertip orientations through the core (for tuning from bench logs).
    Replay(crate::experiments::replay::Args),
    /// Fault-injection campaign, closed loop with the plant: table, or JSON with --json.
    Faults(crate::experiments::faults::Args),
    /// Long closed-loop run repeating the touch script (release build; 10^8 ticks take about 8 min of CPU).
    Soak(crate::experiments::faults::soak::Args),
    /// Where the decompositions fail, f32 drift, virtual-wall stability and state chatter:
    /// charts (SVG) and tables.
    Stability(crate::experiments::stability::Args),
    /// The paper's §3.1 validation: every method x backend against the classical rolling equations
    /// (RK45), accuracy and time per step, with the paper's figures beside ours.
    Validate(crate::experiments::validate::Args),
    /// Processor in the loop: the firmware on an emulated Cortex-M4F (QEMU mps2-an386) in lock step
    /// with the plant, compared tick by tick with the in-process run (see scripts/pil).
    Pil(crate::pil::Args),
    /// Decode a raw defmt log against its firmware ELF (telemetry records as CSV).
    PilDecode(crate::pil::DecodeArgs),
    /// Speed against accuracy as SVG charts (per method x backend x sampling rate, RK45 at several
    /// tolerances, Pareto front), the paper's Fig. 3, and the MCU instruction counts against accuracy.
    Chart(crate::experiments::speed_accuracy::Args),
    /// The virtual device: the device core against the plant in real time, speaking the
    /// softfinger protocol over TCP to several clients at once.
    Serve(crate::serve::Args),
    /// Creep at rest (identical and dithering samples, held contact, closed-loop hold) for every
    /// method and backend on the plane.
    Creep(crate::experiments::creep::Args),
    /// The ellipsoidal limit surface against the numerically integrated Hertzian one.
    LimitSurface(crate::experiments::limit_surface::Args),
    /// Which contact model a scene needs: each choice of the model's parts against the full
    /// model on the scene (force, torque, path and state differences, cost), with the answer.
    Model(crate::experiments::model::Args),
    /// Two soft fingertips hold an object: lifted and twisted, torsion on or off; summary or
    /// JSON, charts and index.html.
    Grasp(crate::experiments::grasp::Args),
}

/// Parse `argv` as the command line `P`; on failure clap has printed its message and the exit
/// code is returned: 0 for `--help` and `--version`, 2 for a usage error.
pub fn parse_or_exit_code<P, I, T>(argv: I) -> Result<P, u8>
where
    P: Parser,
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    P::try_parse_from(argv).map_err(|e| {
        let _ = e.print();
        if e.use_stderr() {
            2
        } else {
            0
        }
    })
}

/// The exit code of a command's result: 0, or 2 with the error printed on stderr as one line
/// `PROGRAM: ERROR`.
pub fn exit_code<E: std::fmt::Display>(program: &str, result: Result<(), E>) -> u8 {
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("{program}: {e}");
            2
        }
    }
}

/// Parse `argv` and run. Returns the process exit code: 0 success, 2 bad input or failure
/// (clap's own usage errors also exit 2). Errors are printed on stderr as one line.
pub fn run<I, T>(argv: I) -> u8
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli: Cli = match parse_or_exit_code(argv) {
        Ok(c) => c,
        Err(code) => return code,
    };
    let result: Result<(), Box<dyn std::error::Error>> = match cli.command {
        Some(Command::Run(args)) => crate::experiments::run::main(&args).map_err(Into::into),
        Some(Command::Replay(args)) => crate::experiments::replay::main(&args).map_err(Into::into),
        Some(Command::Faults(args)) => crate::experiments::faults::main(&args).map_err(Into::into),
        Some(Command::Soak(args)) => {
            crate::experiments::faults::soak::main(&args).map_err(Into::into)
        }
        Some(Command::Validate(args)) => {
            crate::experiments::validate::main(&args).map_err(Into::into)
        }
        Some(Command::Chart(args)) => {
            crate::experiments::speed_accuracy::main(&args).map_err(Into::into)
        }
        Some(Command::Pil(args)) => crate::pil::main(&args).map_err(Into::into),
        Some(Command::PilDecode(args)) => crate::pil::decode_main(&args).map_err(Into::into),
        Some(Command::Creep(args)) => crate::experiments::creep::main(&args).map_err(Into::into),
        Some(Command::LimitSurface(args)) => {
            crate::experiments::limit_surface::main(&args).map_err(Into::into)
        }
        Some(Command::Stability(args)) => {
            crate::experiments::stability::main(&args).map_err(Into::into)
        }
        Some(Command::Serve(args)) => crate::serve::main(&args).map_err(Into::into),
        Some(Command::Model(args)) => crate::experiments::model::main(&args).map_err(Into::into),
        Some(Command::Grasp(args)) => crate::experiments::grasp::main(&args).map_err(Into::into),
        None => crate::experiments::run::main(&crate::experiments::run::Args::default())
            .map_err(Into::into),
    };
    exit_code("host-sim", result)
}

#[cfg(test)]
mod tests {
    use super::run;

    /// The command prints the worst error (the reference module tests its value), writes the
    /// chart, and rejects bad options with exit code 2 and no file.
    #[test]
    fn command_writes_the_chart_and_rejects_bad_options() {
        let dir = std::env::temp_dir().join(format!("softfinger-ls-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let svg = dir.join("ls.svg");
        let s = svg.to_str().unwrap();
        let argv = [
            "host-sim",
            "limit-surface",
            "--points",
            "8",
            "--cells",
            "40",
            "--svg",
            s,
        ];
        assert_eq!(run(argv), 0);
        assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
        let bad = dir.join("bad.svg");
        let b = bad.to_str().unwrap();
        assert_eq!(
            run(["host-sim", "limit-surface", "--points", "1", "--svg", b]),
            2
        );
        assert_eq!(
            run(["host-sim", "limit-surface", "--cells", "9", "--svg", b]),
            2
        );
        assert!(!bad.exists());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
