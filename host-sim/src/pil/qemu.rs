//! QEMU for the processor-in-the-loop run: the work directory with the plant link's FIFOs, the
//! emulator process under `-icount`, and a monitor that unblocks the host when QEMU exits or the
//! wall-clock limit passes.
//!
//! Both FIFOs are opened read-write by the host, which on Linux never blocks on open; the board
//! opens them by name (semihosting, QEMU's working directory is the work directory), also after
//! a watchdog reset. When QEMU exits the monitor writes an `Exited` message into the board's FIFO,
//! so a host blocked on a read always wakes.

use super::wire::{KIND_EXITED, MSG_LEN};
use crate::error::FileError;
use std::fs::{File, OpenOptions};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Virtual time per guest instruction: `-icount shift=3` is 2^3 ns, i.e. 125 M instructions/s.
pub const ICOUNT_SHIFT: u32 = 3;
/// Guest instructions per second of virtual time.
pub const INSTRUCTIONS_PER_SECOND: u64 = 1_000_000_000 >> ICOUNT_SHIFT;

/// The FIFO the board writes to.
pub const TO_PLANT: &str = "pil-to-plant";
/// The FIFO the board reads from.
pub const FROM_PLANT: &str = "pil-from-plant";
/// The file the board's defmt log reader appends to.
pub const DEFMT_LOG: &str = "pil-defmt.raw";

/// A running emulator and its link.
pub struct Emulator {
    from_board: File,
    to_board: File,
    monitor: Option<JoinHandle<()>>,
    status: Arc<Mutex<Option<Result<ExitStatus, Stopped>>>>,
    stderr: PathBuf,
}

/// Why the emulator could not be started, talked to, or did not end normally.
#[derive(Debug, thiserror::Error)]
pub enum EmulatorError {
    /// `mkfifo` could not be run.
    #[error("cannot run mkfifo: {0}")]
    Mkfifo(std::io::Error),
    /// `mkfifo` refused the path.
    #[error("mkfifo {} failed", .0.display())]
    MkfifoFailed(PathBuf),
    /// A FIFO or log file could not be opened or created.
    #[error(transparent)]
    File(#[from] FileError),
    /// QEMU could not be started.
    #[error("cannot start {qemu}: {source}")]
    Start {
        /// The QEMU executable.
        qemu: String,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// Reading the plant link failed.
    #[error("plant link read: {0}")]
    LinkRead(std::io::Error),
    /// Writing the plant link failed.
    #[error("plant link write: {0}")]
    LinkWrite(std::io::Error),
    /// The monitor thread panicked.
    #[error("monitor failed")]
    Monitor,
    /// QEMU was stopped or could not be waited for (with its stderr, if any).
    #[error("{reason}{}", stderr_note(stderr))]
    Stopped {
        /// Why.
        reason: Stopped,
        /// QEMU's stderr.
        stderr: String,
    },
    /// The monitor recorded no status (with QEMU's stderr, if any).
    #[error("QEMU status unknown{}", stderr_note(.0))]
    Unknown(String),
}

/// Why the monitor stopped QEMU or lost it.
#[derive(Debug, thiserror::Error)]
pub enum Stopped {
    /// The wall-clock limit, s, was reached.
    #[error("QEMU stopped after the {0} s wall-clock limit")]
    TimeLimit(u64),
    /// Waiting for the child failed.
    #[error("waiting for QEMU: {0}")]
    Wait(std::io::Error),
}

fn mkfifo(path: &Path) -> Result<(), EmulatorError> {
    let ok = Command::new("mkfifo")
        .arg(path)
        .status()
        .map_err(EmulatorError::Mkfifo)?
        .success();
    if ok {
        Ok(())
    } else {
        Err(EmulatorError::MkfifoFailed(path.to_path_buf()))
    }
}

fn open_rw(path: &Path) -> Result<File, FileError> {
    OpenOptions::new()
        .read(true)
        .write(true)
        .open(path)
        .map_err(FileError::on(path, "cannot open"))
}

impl Emulator {
    /// Create the FIFOs in `dir` (which must exist and be empty) and start QEMU on `elf`.
    pub fn start(
        qemu: &str,
        elf: &Path,
        dir: &Path,
        limit: Duration,
    ) -> Result<Emulator, EmulatorError> {
        Emulator::start_with_serial(qemu, elf, dir, limit, "none")
    }

    /// [`Emulator::start`] with UART0 connected to `serial` (a QEMU `-serial` argument, e.g.
    /// `unix:PATH,server=on,wait=off`).
    pub fn start_with_serial(
        qemu: &str,
        elf: &Path,
        dir: &Path,
        limit: Duration,
        serial: &str,
    ) -> Result<Emulator, EmulatorError> {
        mkfifo(&dir.join(TO_PLANT))?;
        mkfifo(&dir.join(FROM_PLANT))?;
        let log = dir.join(DEFMT_LOG);
        File::create(&log).map_err(FileError::on(&log, "cannot create"))?;
        let from_board = open_rw(&dir.join(TO_PLANT))?;
        let to_board = open_rw(&dir.join(FROM_PLANT))?;
        let stderr = dir.join("qemu.stderr");
        let child = Command::new(qemu)
            .args(["-machine", "mps2-an386", "-cpu", "cortex-m4"])
            .args(["-icount", &format!("shift={ICOUNT_SHIFT},sleep=off")])
            .args(["-semihosting-config", "enable=on,target=native"])
            .args(["-nographic", "-monitor", "none", "-serial", serial])
            .arg("-kernel")
            .arg(elf)
            .current_dir(dir)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(File::create(&stderr).map_err(FileError::on(&stderr, "cannot create"))?)
            .spawn()
            .map_err(|source| EmulatorError::Start {
                qemu: qemu.to_string(),
                source,
            })?;
        let status = Arc::new(Mutex::new(None));
        let to_plant = dir.join(TO_PLANT);
        let wake = from_board
            .try_clone()
            .map_err(FileError::on(&to_plant, "cannot clone"))?;
        let monitor = {
            let status = Arc::clone(&status);
            std::thread::spawn(move || monitor(child, wake, limit, status))
        };
        Ok(Emulator {
            from_board,
            to_board,
            monitor: Some(monitor),
            status,
            stderr,
        })
    }

    /// The next message from the board (blocks).
    pub fn receive(&mut self) -> Result<[u8; MSG_LEN], EmulatorError> {
        let mut m = [0u8; MSG_LEN];
        self.from_board
            .read_exact(&mut m)
            .map_err(EmulatorError::LinkRead)?;
        Ok(m)
    }

    /// Send one reply to the board.
    pub fn reply(&mut self, r: &[u8]) -> Result<(), EmulatorError> {
        self.to_board.write_all(r).map_err(EmulatorError::LinkWrite)
    }

    /// Wait for QEMU to end; its exit status, or why it was stopped, with its stderr.
    pub fn finish(mut self) -> Result<ExitStatus, EmulatorError> {
        if let Some(m) = self.monitor.take() {
            let _ = m.join();
        }
        let status = self
            .status
            .lock()
            .map_err(|_| EmulatorError::Monitor)?
            .take();
        let stderr = std::fs::read_to_string(&self.stderr).unwrap_or_default();
        match status {
            Some(Ok(s)) => Ok(s),
            Some(Err(reason)) => Err(EmulatorError::Stopped { reason, stderr }),
            None => Err(EmulatorError::Unknown(stderr)),
        }
    }
}

fn stderr_note(s: &str) -> String {
    if s.trim().is_empty() {
        String::new()
    } else {
        format!(" (QEMU: {})", s.trim())
    }
}

/// Wait for the child (killing it after `limit`), record how it ended, wake the reader.
fn monitor(
    mut child: Child,
    mut wake: File,
    limit: Duration,
    status: Arc<Mutex<Option<Result<ExitStatus, Stopped>>>>,
) {
    let start = Instant::now();
    let result = loop {
        match child.try_wait() {
            Ok(Some(s)) => break Ok(s),
            Ok(None) if start.elapsed() > limit => {
                let _ = child.kill();
                let _ = child.wait();
                break Err(Stopped::TimeLimit(limit.as_secs()));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => break Err(Stopped::Wait(e)),
        }
    };
    if let Ok(mut s) = status.lock() {
        *s = Some(result);
    }
    let mut m = [0u8; MSG_LEN];
    m[0] = KIND_EXITED;
    let _ = wake.write_all(&m);
}
