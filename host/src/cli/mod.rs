//! The `softfinger` command line: parsing and dispatch. Errors print one line on stderr and exit
//! with status 2 (130 after Ctrl-C); nothing is left half written.

mod bench;
mod config;
mod control;
mod home;
mod interrupt;
mod params;
mod refusal;
mod session;
mod status;
mod stream;
mod update;
mod view;

use clap::{Parser, Subcommand};
use softfinger_host::{Device, LinkError, Target};
use std::ffi::OsString;

/// Talk to a softfinger haptic device (USB) or the virtual device of `host-sim serve` (TCP).
#[derive(Debug, Parser)]
#[command(name = "softfinger", version, about)]
pub struct Cli {
    /// The device: `usb` (the first softfinger USB device), `usb:/dev/ttyACM0`, or
    /// `tcp:HOST:PORT` (the virtual device).
    #[arg(long, default_value = "usb", global = true)]
    pub connect: String,
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Device description and the device's link counters (all connections).
    Info {
        /// As JSON.
        #[arg(long)]
        json: bool,
    },
    /// Mode, local model, flags and latched faults.
    Status(status::Args),
    /// Find the encoders' reference (needed before arming); waits for the outcome.
    Home(home::Args),
    /// Start rendering force (ramped in); re-arms the watchdog. The device lets go when no
    /// connection talks to it: `session` or `stream --arm` hold it.
    Arm,
    /// Stop rendering force.
    Disarm,
    /// Clear latched faults (the device is then disarmed).
    Clear,
    /// Scenes (host-sim's scene files).
    Scene {
        #[command(subcommand)]
        cmd: control::SceneCmd,
    },
    /// Contact parameters.
    Params {
        #[command(subcommand)]
        cmd: params::ParamsCmd,
    },
    /// Hold the device armed until Ctrl-C (homes it first if needed); disarms at the end.
    Session(session::Args),
    /// Record the state stream to CSV (progress shown; reconnects if the device goes away).
    Stream(stream::Args),
    /// A live view: force and spin torque over the last seconds, mode, model, flags (q quits).
    View(view::Args),
    /// Measure the link on a virtual device over loopback: stream rate and gaps, round-trip
    /// times, local-model switches at 1 kHz, watchdog fade, bad input.
    Bench(bench::Args),
    /// The device's persistent settings: get, set, save, reset, export, import.
    Config {
        #[command(subcommand)]
        cmd: config::ConfigCmd,
    },
    /// Install a signed firmware update (progress, verification, version before and after).
    Update(update::Args),
}

/// Connect to the `--connect` target.
pub fn connect(spec: &str) -> Result<Device, LinkError> {
    let target: Target = spec.parse()?;
    Device::connect(&target)
}

/// Parse `argv` and run; the exit code.
pub fn run<I, T>(argv: I) -> u8
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli: Cli = match host_sim::cli::parse_or_exit_code(argv) {
        Ok(c) => c,
        Err(code) => return code,
    };
    let result = match &cli.command {
        Command::Info { json } => control::info(&cli.connect, *json),
        Command::Status(a) => status::main(&cli.connect, a),
        Command::Home(a) => home::main(&cli.connect, a),
        Command::Arm => control::arm(&cli.connect),
        Command::Disarm => control::simple(&cli.connect, "disarm", |d| d.disarm()),
        Command::Clear => control::simple(&cli.connect, "clear", |d| d.clear_faults()),
        Command::Scene { cmd } => control::scene(&cli.connect, cmd),
        Command::Params { cmd } => params::main(&cli.connect, cmd),
        Command::Session(a) => session::main(&cli.connect, a),
        Command::Stream(a) => stream::main(&cli.connect, a),
        Command::View(a) => view::main(&cli.connect, a),
        Command::Bench(a) => bench::main(&cli.connect, a),
        Command::Config { cmd } => config::main(&cli.connect, cmd),
        Command::Update(a) => update::main(&cli.connect, a),
    };
    let code = host_sim::cli::exit_code("softfinger", result);
    if code != 0 && interrupt::requested() {
        return interrupt::EXIT_INTERRUPTED;
    }
    code
}
