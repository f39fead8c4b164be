//! QEMU for the processor-in-the-loop run: the work directory with the plant link's FIFOs, the
//! emulator process under `-icount`, and a monitor that unblocks the host when QEMU exits or the
//! wall-clock limit passes.
//!
//! Both FIFOs are opened read-write by the host, which on Linux never blocks on open; the board
//! opens them by name (semihosting, QEMU's working directory is the work directory), also after
//! a watchdog reset. When QEMU exits the monitor writes an `Exited` message into the board's FIFO,
//! so a host blocked on a read always wakes.

use super::wire::{KIND_EXITED, MSG_LEN};
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
    status: Arc<Mutex<Option<Result<ExitStatus, String>>>>,
    stderr: PathBuf,
}

fn mkfifo(path: &Path) -> Result<(), String> {
    let ok = Command::new("mkfifo")
        .arg(path)
        .status()
        .map_err(|e| format!("cannot run mkfifo: {e}"))?
        .success();
    if ok {
        Ok(())
    } else {
        Err(format!("mkfifo {} failed", path.display()))
    }
}

fn open_rw(path: &Path) -> Result<File, String> {
    OpenOptions::new()
        .read(true)
        .write(true)
        .open(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

impl Emulator {
    /// Create the FIFOs in `dir` (which must exist and be empty) and start QEMU on `elf`.
    pub fn start(qemu: &str, elf: &Path, dir: &Path, limit: Duration) -> Result<Emulator, String> {
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
    ) -> Result<Emulator, String> {
        mkfifo(&dir.join(TO_PLANT))?;
        mkfifo(&dir.join(FROM_PLANT))?;
        File::create(dir.join(DEFMT_LOG)).map_err(|e| format!("{DEFMT_LOG}: {e}"))?;
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
            .stderr(File::create(&stderr).map_err(|e| format!("qemu.stderr: {e}"))?)
            .spawn()
            .map_err(|e| format!("cannot start {qemu}: {e}"))?;
        let status = Arc::new(Mutex::new(None));
        let wake = from_board
            .try_clone()
            .map_err(|e| format!("{TO_PLANT}: {e}"))?;
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
    pub fn receive(&mut self) -> Result<[u8; MSG_LEN], String> {
        let mut m = [0u8; MSG_LEN];
        self.from_board
            .read_exact(&mut m)
            .map_err(|e| format!("plant link read: {e}"))?;
        Ok(m)
    }

    /// Send one reply to the board.
    pub fn reply(&mut self, r: &[u8]) -> Result<(), String> {
        self.to_board
            .write_all(r)
            .map_err(|e| format!("plant link write: {e}"))
    }

    /// Wait for QEMU to end; its exit status, or why it was stopped, with its stderr.
    pub fn finish(mut self) -> Result<ExitStatus, String> {
        if let Some(m) = self.monitor.take() {
            let _ = m.join();
        }
        let status = self.status.lock().map_err(|_| "monitor failed")?.take();
        let stderr = std::fs::read_to_string(&self.stderr).unwrap_or_default();
        match status {
            Some(Ok(s)) => Ok(s),
            Some(Err(e)) => Err(format!("{e}{}", stderr_note(&stderr))),
            None => Err(format!("QEMU status unknown{}", stderr_note(&stderr))),
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
    status: Arc<Mutex<Option<Result<ExitStatus, String>>>>,
) {
    let start = Instant::now();
    let result = loop {
        match child.try_wait() {
            Ok(Some(s)) => break Ok(s),
            Ok(None) if start.elapsed() > limit => {
                let _ = child.kill();
                let _ = child.wait();
                break Err(format!(
                    "QEMU stopped after the {} s wall-clock limit",
                    limit.as_secs()
                ));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => break Err(format!("waiting for QEMU: {e}")),
        }
    };
    if let Ok(mut s) = status.lock() {
        *s = Some(result);
    }
    let mut m = [0u8; MSG_LEN];
    m[0] = KIND_EXITED;
    let _ = wake.write_all(&m);
}
