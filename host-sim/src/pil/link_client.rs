//! One connection to the emulated board's UART0 for `host-sim pil --link-check`: frames sent,
//! device messages decoded (state samples kept aside in arrival order), and waits with wall-clock
//! timeouts for an answer, an acknowledgement, a mode or a condition on the state stream.

use crate::error::FileError;
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

/// Why the conversation on the board's UART0 stopped.
#[derive(Debug, thiserror::Error)]
pub enum LinkError {
    /// The socket could not be connected or configured.
    #[error(transparent)]
    Socket(#[from] FileError),
    /// Writing to the UART failed.
    #[error("UART write: {0}")]
    Write(std::io::Error),
    /// Reading from the UART failed.
    #[error("UART read: {0}")]
    Read(std::io::Error),
    /// The board closed the UART.
    #[error("UART closed")]
    Closed,
    /// A message too large for a frame.
    #[error("the message does not fit in one frame")]
    TooLarge,
    /// No answer within the timeout, s.
    #[error("no answer within {0} s")]
    NoAnswer(u64),
    /// An answer other than the one expected (the message received, as decoded).
    #[error("expected {expected}, got {got}")]
    Unexpected {
        /// What was expected.
        expected: String,
        /// What arrived.
        got: String,
    },
    /// The state stream did not show the expected condition in time.
    #[error("the state stream did not show what was expected within {seconds} s (last {last})")]
    StreamTimeout {
        /// The timeout, s.
        seconds: u64,
        /// The last state received, as decoded.
        last: String,
    },
    /// No state sample in the expected mode in time.
    #[error("no {mode} state in {seconds} s (last {last})")]
    NoMode {
        /// The mode waited for.
        mode: String,
        /// The timeout, s.
        seconds: u64,
        /// The last mode received.
        last: String,
    },
    /// A step needs a state sample and none has arrived.
    #[error("no state yet")]
    NoState,
    /// A ping was refused.
    #[error("a ping was refused")]
    PingRefused,
    /// The communication watchdog never timed out.
    #[error("no timeout")]
    NoTimeout,
}

impl LinkError {
    /// An answer other than `expected`.
    pub(super) fn unexpected(expected: impl Into<String>, got: &impl std::fmt::Debug) -> LinkError {
        LinkError::Unexpected {
            expected: expected.into(),
            got: format!("{got:?}"),
        }
    }
}

/// A frame holding `msg` (the protocol refuses only messages too large for a frame).
pub(super) fn frame(msg: &HostMsg) -> Result<Vec<u8>, LinkError> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = encode_frame(msg, &mut buf).map_err(|_| LinkError::TooLarge)?;
    Ok(buf[..n].to_vec())
}

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
    pub(super) fn connect(path: &Path) -> Result<Client, LinkError> {
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            match UnixStream::connect(path) {
                Ok(stream) => {
                    stream
                        .set_read_timeout(Some(Duration::from_millis(50)))
                        .map_err(FileError::on(path, "cannot set a read timeout"))?;
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
                Err(e) => return Err(FileError::on(path, "cannot connect")(e).into()),
            }
        }
    }

    pub(super) fn send_raw(&mut self, bytes: &[u8]) -> Result<(), LinkError> {
        self.stream.write_all(bytes).map_err(LinkError::Write)
    }

    pub(super) fn send(&mut self, msg: &HostMsg) -> Result<(), LinkError> {
        self.send_raw(&frame(msg)?)
    }

    /// Send request `req`; returns its sequence number.
    pub(super) fn request(&mut self, req: Request) -> Result<u16, LinkError> {
        self.seq = self.seq.wrapping_add(1);
        let seq = self.seq;
        self.send(&HostMsg::Request { seq, req })?;
        Ok(seq)
    }

    /// Read what arrived; state frames are kept aside.
    pub(super) fn pump(&mut self) -> Result<(), LinkError> {
        let mut buf = [0u8; 1024];
        let n = match self.stream.read(&mut buf) {
            Ok(0) => return Err(LinkError::Closed),
            Ok(n) => n,
            Err(e)
                if e.kind() == std::io::ErrorKind::WouldBlock
                    || e.kind() == std::io::ErrorKind::TimedOut =>
            {
                return Ok(())
            }
            Err(e) => return Err(LinkError::Read(e)),
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
    pub(super) fn next(&mut self, timeout: Duration) -> Result<DeviceMsg, LinkError> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(m) = self.inbox.pop_front() {
                return Ok(m);
            }
            if Instant::now() > deadline {
                return Err(LinkError::NoAnswer(timeout.as_secs()));
            }
            self.pump()?;
        }
    }

    /// Wait for the acknowledgement of `seq`.
    pub(super) fn ack(&mut self, seq: u16) -> Result<AckResult, LinkError> {
        match self.next(ANSWER_TIMEOUT)? {
            DeviceMsg::Ack { seq: s, result } if s == seq => Ok(result),
            other => Err(LinkError::unexpected(format!("the ack of {seq}"), &other)),
        }
    }

    /// Wait until `done` holds for the states received, up to [`ANSWER_TIMEOUT`].
    pub(super) fn wait_for(
        &mut self,
        done: impl Fn(&[StateSample]) -> bool,
    ) -> Result<(), LinkError> {
        let deadline = Instant::now() + ANSWER_TIMEOUT;
        while !done(&self.states) {
            if Instant::now() > deadline {
                return Err(LinkError::StreamTimeout {
                    seconds: ANSWER_TIMEOUT.as_secs(),
                    last: format!("{:?}", self.states.last()),
                });
            }
            self.pump()?;
        }
        Ok(())
    }

    /// Wait until `n` states have arrived; all of them.
    pub(super) fn wait_states(&mut self, n: usize) -> Result<&[StateSample], LinkError> {
        self.wait_for(|s| s.len() >= n)?;
        Ok(&self.states)
    }

    /// Wait for a state sample in `mode`, up to `timeout`.
    pub(super) fn wait_mode(
        &mut self,
        mode: Mode,
        timeout: Duration,
    ) -> Result<StateSample, LinkError> {
        let deadline = Instant::now() + timeout;
        let mut seen = 0;
        loop {
            if let Some(s) = self.states[seen..].iter().find(|s| s.mode == mode) {
                return Ok(*s);
            }
            seen = self.states.len();
            if Instant::now() > deadline {
                let last = self.states.last().map(|s| s.mode);
                return Err(LinkError::NoMode {
                    mode: format!("{mode:?}"),
                    seconds: timeout.as_secs(),
                    last: format!("{last:?}"),
                });
            }
            self.pump()?;
        }
    }
}
