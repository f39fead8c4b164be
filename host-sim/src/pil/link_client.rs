//! One connection to the emulated board's UART0 for `host-sim pil --link-check`: frames sent,
//! device messages decoded (state samples kept aside in arrival order), and waits with wall-clock
//! timeouts for an answer, an acknowledgement, a mode or a condition on the state stream.

use softfinger_protocol::{
    encode_frame, AckResult, DeviceMsg, FrameDecoder, HostMsg, Mode, Request, StateSample,
    MAX_FRAME_LEN,
};
use std::io::{Read, Write};
use std::os::unix::net::UnixStream;
use std::path::Path;
use std::time::{Duration, Instant};

/// Longest wait for one answer or state, wall clock (the emulated board runs about 6x slower
/// than real time under the lock-step plant, measured on the 10 kHz default scene).
pub(super) const ANSWER_TIMEOUT: Duration = Duration::from_secs(30);

/// One connection to the board's UART0.
pub(super) struct Client {
    stream: UnixStream,
    pub(super) decoder: FrameDecoder,
    /// Decoded messages not yet looked at.
    inbox: std::collections::VecDeque<DeviceMsg>,
    pub(super) states: Vec<StateSample>,
    seq: u16,
}

impl Client {
    pub(super) fn connect(path: &Path) -> Result<Client, String> {
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            match UnixStream::connect(path) {
                Ok(stream) => {
                    stream
                        .set_read_timeout(Some(Duration::from_millis(50)))
                        .map_err(|e| e.to_string())?;
                    return Ok(Client {
                        stream,
                        decoder: FrameDecoder::new(),
                        inbox: Default::default(),
                        states: Vec::new(),
                        seq: 0,
                    });
                }
                Err(_) if Instant::now() < deadline => {
                    std::thread::sleep(Duration::from_millis(20))
                }
                Err(e) => return Err(format!("{}: {e}", path.display())),
            }
        }
    }

    pub(super) fn send_raw(&mut self, bytes: &[u8]) -> Result<(), String> {
        self.stream
            .write_all(bytes)
            .map_err(|e| format!("UART write: {e}"))
    }

    pub(super) fn send(&mut self, msg: &HostMsg) -> Result<(), String> {
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = encode_frame(msg, &mut buf).map_err(|e| format!("{e:?}"))?;
        self.send_raw(&buf[..n])
    }

    /// Send request `req`; returns its sequence number.
    pub(super) fn request(&mut self, req: Request) -> Result<u16, String> {
        self.seq = self.seq.wrapping_add(1);
        let seq = self.seq;
        self.send(&HostMsg::Request { seq, req })?;
        Ok(seq)
    }

    /// Read what arrived; state frames are kept aside.
    pub(super) fn pump(&mut self) -> Result<(), String> {
        let mut buf = [0u8; 1024];
        let n = match self.stream.read(&mut buf) {
            Ok(0) => return Err("UART closed".into()),
            Ok(n) => n,
            Err(e)
                if e.kind() == std::io::ErrorKind::WouldBlock
                    || e.kind() == std::io::ErrorKind::TimedOut =>
            {
                return Ok(())
            }
            Err(e) => return Err(format!("UART read: {e}")),
        };
        for &b in &buf[..n] {
            match self.decoder.push::<DeviceMsg>(b) {
                Some(Ok(DeviceMsg::State(s))) => self.states.push(s),
                Some(Ok(m)) => self.inbox.push_back(m),
                Some(Err(_)) | None => {}
            }
        }
        Ok(())
    }

    /// The next non-state message, waiting up to `timeout`.
    pub(super) fn next(&mut self, timeout: Duration) -> Result<DeviceMsg, String> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(m) = self.inbox.pop_front() {
                return Ok(m);
            }
            if Instant::now() > deadline {
                return Err(format!("no answer within {} s", timeout.as_secs()));
            }
            self.pump()?;
        }
    }

    /// Wait for the acknowledgement of `seq`.
    pub(super) fn ack(&mut self, seq: u16) -> Result<AckResult, String> {
        match self.next(ANSWER_TIMEOUT)? {
            DeviceMsg::Ack { seq: s, result } if s == seq => Ok(result),
            other => Err(format!("expected the ack of {seq}, got {other:?}")),
        }
    }

    /// Wait until `done` holds for the states received, up to [`ANSWER_TIMEOUT`].
    pub(super) fn wait_for(&mut self, done: impl Fn(&[StateSample]) -> bool) -> Result<(), String> {
        let deadline = Instant::now() + ANSWER_TIMEOUT;
        while !done(&self.states) {
            if Instant::now() > deadline {
                return Err(format!(
                    "the state stream did not show what was expected within {} s (last {:?})",
                    ANSWER_TIMEOUT.as_secs(),
                    self.states.last()
                ));
            }
            self.pump()?;
        }
        Ok(())
    }

    /// Wait until `n` states have arrived; all of them.
    pub(super) fn wait_states(&mut self, n: usize) -> Result<&[StateSample], String> {
        self.wait_for(|s| s.len() >= n)?;
        Ok(&self.states)
    }

    /// Wait for a state sample in `mode`, up to `timeout`.
    pub(super) fn wait_mode(
        &mut self,
        mode: Mode,
        timeout: Duration,
    ) -> Result<StateSample, String> {
        let deadline = Instant::now() + timeout;
        let mut seen = 0;
        loop {
            if let Some(s) = self.states[seen..].iter().find(|s| s.mode == mode) {
                return Ok(*s);
            }
            seen = self.states.len();
            if Instant::now() > deadline {
                let last = self.states.last().map(|s| s.mode);
                return Err(format!(
                    "no {mode:?} state in {} s (last {last:?})",
                    timeout.as_secs()
                ));
            }
            self.pump()?;
        }
    }
}
