//! Why a processor-in-the-loop run failed: bad options or scene, the emulator, the plant link, the
//! board's behaviour, the logs, or the `--check` verdict.

use super::link_client::LinkError;
use super::qemu::EmulatorError;
use crate::error::{ChartError, FileError, JsonError};
use crate::sim::closed_loop::ClosedLoopError;
use crate::sim::plant::PlantError;
use crate::sim::scene::SceneError;
use softfinger_core::control::pipeline::PipelineError;
use std::path::PathBuf;

/// Why `host-sim pil` or `pil-decode` failed.
#[derive(Debug, thiserror::Error)]
pub enum PilError {
    /// `--rate-hz` out of range for the board.
    #[error("--rate-hz {0}: must be within 1000..=20000 and divide 25 MHz")]
    Rate(u32),
    /// `--app-session` without the local-model scene (the application's updates are local
    /// models), or with `--link-check` (whose host owns the command queue).
    #[error("--app-session needs --local-model (the application sends local models) and no --link-check")]
    AppSessionNeedsLocalModel,
    /// `pil-decode --rate-hz 0`.
    #[error("--rate-hz must be positive")]
    DecodeRate,
    /// `--duration-s` out of range.
    #[error("--duration-s {0}: must be within (0, {max}]", max = super::MAX_DURATION_S)]
    Duration(f64),
    /// `--fault-at-s` outside the scene.
    #[error("--fault-at-s {at_s}: must be within the scene (0..{duration_s} s)")]
    FaultAt {
        /// The time asked for, s.
        at_s: f64,
        /// The scene's duration, s.
        duration_s: f64,
    },
    /// The scene needs a surface the firmware does not render.
    #[error("scene '{0}': the firmware renders a plane; this scene needs another surface")]
    NotPlane(String),
    /// The scene changes the contact parameters the firmware renders.
    #[error(
        "scene '{0}': the firmware renders the default contact parameters; this scene changes them"
    )]
    NotDefaultContact(String),
    /// The firmware ELF is missing.
    #[error(
        "{}: no firmware ELF (build it with scripts/pil, or cargo build --release \
         --no-default-features --features mps2-an386 in firmware/)",
        .0.display()
    )]
    NoElf(PathBuf),
    /// The scene could not be loaded.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The scene's configuration was rejected.
    #[error(transparent)]
    Config(#[from] ClosedLoopError),
    /// The plant refused its parameters.
    #[error("plant: {0}")]
    Plant(#[from] PlantError),
    /// The in-process pipeline refused its configuration.
    #[error("pipeline: {0}")]
    Pipeline(#[from] PipelineError),
    /// The emulator failed.
    #[error(transparent)]
    Emulator(#[from] EmulatorError),
    /// The plant link carried a message of unknown kind.
    #[error("plant link: unknown message kind {0}")]
    UnknownKind(u8),
    /// The board rebooted without announcing a watchdog reset.
    #[error("the board rebooted without a watchdog NMI")]
    Rebooted,
    /// The in-process reference run did not finish homing.
    #[error("in-process run: not homed in time")]
    ReferenceNotHomed,
    /// The board did not finish the scene.
    #[error(
        "the board did not finish the run (QEMU {status}, {samples} samples served){qemu}{log}"
    )]
    Unfinished {
        /// QEMU's exit status.
        status: std::process::ExitStatus,
        /// Plant samples served.
        samples: u64,
        /// "; QEMU: ..." with its stderr, or empty.
        qemu: String,
        /// "; board log ends: ..." with its last messages, or empty.
        log: String,
    },
    /// The board did not finish the link-check run.
    #[error("the board did not finish the run")]
    NotFinished,
    /// The board did not finish homing in time.
    #[error("the board did not finish homing in time")]
    HomingTimedOut,
    /// The link client thread panicked.
    #[error("the link client panicked")]
    ClientPanicked,
    /// A link check failed (the report shows which).
    #[error("host link check failed")]
    LinkCheckFailed,
    /// The conversation on the host link stopped.
    #[error(transparent)]
    Link(#[from] LinkError),
    /// The ELF's defmt table could not be read.
    #[error("ELF: {0}")]
    Elf(String),
    /// The ELF has no defmt table.
    #[error("the ELF has no defmt symbols (was it linked with -Tdefmt.x?)")]
    NoDefmt,
    /// Frames of the defmt log could not be decoded.
    #[error("{0} malformed frames in the log")]
    Malformed(usize),
    /// The budget file has no baseline for a figure at the run's rate.
    #[error("{}: no baseline for {figure} at {rate_hz} Hz", path.display())]
    NoBaseline {
        /// The budget file.
        path: PathBuf,
        /// The figure's name.
        figure: &'static str,
        /// The control rate, Hz.
        rate_hz: u32,
    },
    /// The budget file is not JSON.
    #[error("{}: {source}", path.display())]
    Budget {
        /// The budget file.
        path: PathBuf,
        /// The parser's reason.
        source: serde_json::Error,
    },
    /// `--check` found failures (all of them listed).
    #[error("pil --check failed: {}", .0.join("; "))]
    Check(Vec<String>),
    /// A failure after which the run's work directory was kept for inspection.
    #[error("{source} (work directory kept: {})", dir.display())]
    WorkDirKept {
        /// The failure.
        source: Box<PilError>,
        /// The work directory.
        dir: PathBuf,
    },
    /// A file could not be read or written.
    #[error(transparent)]
    File(#[from] FileError),
    /// A chart could not be drawn or written.
    #[error(transparent)]
    Chart(#[from] ChartError),
    /// The JSON could not be serialised.
    #[error(transparent)]
    Json(#[from] JsonError),
}
