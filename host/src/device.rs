//! [`Device`]: one connection to a device, with blocking request/reply calls and the state
//! stream on a queue.
//!
//! A reader thread decodes every frame the device sends: state samples go to a bounded queue
//! (when the application does not keep up, the oldest samples are kept and the newest counted as
//! dropped here) and to the latest-sample slot ([`LatestState`], what a servo loop polls),
//! everything else to the reply queue. Requests carry a sequence number and wait
//! for the reply with that number, skipping late replies to earlier requests.
//!
//! Heartbeat: while a `Device` is open, a thread sends a `Ping` every [`HEARTBEAT`] with the
//! reserved sequence number [`HEARTBEAT_SEQ`] (requests never use it; the reader drops its
//! acknowledgements), so the device's communication watchdog stays fed while the application
//! only reads the stream or thinks.

use crate::error::LinkError;
use crate::target::{self, Target};
use softfinger_protocol::{
    encode_frame, AckResult, ContactParamsWire, DeviceInfo, DeviceMsg, DeviceStatus, FrameDecoder,
    FrameErrorCounts, FrameErrorKind, HandTarget, HostMsg, LinkCounters, LocalModel, Mode, Request,
    StateSample, MAX_FRAME_LEN, PROTOCOL_VERSION,
};
use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering::Relaxed};
use std::sync::mpsc::{channel, sync_channel, Receiver, RecvTimeoutError, Sender, SyncSender};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::{Duration, Instant};

/// State samples queued before the newest are dropped (65 s of a 1 kHz stream).
pub const STATE_QUEUE: usize = 65_536;

/// Period of the heartbeat, 20 ms: a tenth of the virtual device's default 200 ms watchdog, so
/// several heartbeats can be late or lost before it fires.
pub const HEARTBEAT: Duration = Duration::from_millis(20);

/// Sequence number of the heartbeat's pings (requests skip it).
pub const HEARTBEAT_SEQ: u16 = 0;

type SharedWriter = Arc<Mutex<Box<dyn Write + Send>>>;

/// What the reader thread counted.
#[derive(Debug, Default)]
struct ReaderCounts {
    errors: Mutex<FrameErrorCounts>,
    states_dropped: AtomicU32,
}

/// The newest state sample, when it arrived and how many came before it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Latest {
    /// The sample.
    pub sample: StateSample,
    /// When the reader thread read the bytes that completed it.
    pub arrived: Instant,
    /// Samples received on this connection up to and including this one (1 for the first).
    pub count: u64,
}

/// The newest state sample of a connection, shared with the reader thread that writes it.
///
/// [`LatestState::get`] never waits for the device: it copies the sample under a lock that the
/// reader thread holds only for the same copy (about a hundred bytes), so a 1 kHz servo loop can
/// poll it from any thread while another thread makes requests.
#[derive(Debug, Default)]
pub struct LatestState {
    slot: Mutex<Option<Latest>>,
}

impl LatestState {
    /// The newest sample, `None` before the first.
    pub fn get(&self) -> Option<Latest> {
        match self.slot.lock() {
            Ok(g) => *g,
            // The reader thread cannot panic while holding the lock (a copy), but a poisoned
            // slot still holds a whole sample.
            Err(p) => *p.into_inner(),
        }
    }

    fn put(&self, sample: StateSample, arrived: Instant) {
        let mut g = match self.slot.lock() {
            Ok(g) => g,
            Err(p) => p.into_inner(),
        };
        let count = g.map_or(0, |l| l.count) + 1;
        *g = Some(Latest {
            sample,
            arrived,
            count,
        });
    }
}

/// The queue of state samples of one connection, in arrival order; clones share it.
#[derive(Clone, Debug)]
pub struct StateQueue(Arc<Mutex<Receiver<StateSample>>>);

impl StateQueue {
    /// The next state sample, waiting up to `timeout`; `Ok(None)` on timeout,
    /// [`LinkError::Disconnected`] once the connection is gone and the queue empty. Two threads
    /// taking from one queue take turns (each sample goes to one of them).
    pub fn next(&self, timeout: Duration) -> Result<Option<StateSample>, LinkError> {
        let deadline = Instant::now() + timeout;
        let rx = self.0.lock().map_err(|_| LinkError::Disconnected)?;
        match rx.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
            Ok(s) => Ok(Some(s)),
            Err(RecvTimeoutError::Timeout) => Ok(None),
            Err(RecvTimeoutError::Disconnected) => Err(LinkError::Disconnected),
        }
    }
}

/// A connection to a device.
pub struct Device {
    target: Option<Target>,
    /// The TCP socket, shut down on drop (see [`target::Link::tcp`]).
    tcp: Option<std::net::TcpStream>,
    writer: SharedWriter,
    /// Cleared when the connection is dropped: stops the heartbeat.
    alive: Arc<AtomicBool>,
    /// The heartbeat sends while set (see [`Device::set_heartbeat`]).
    beating: Arc<AtomicBool>,
    replies: Receiver<DeviceMsg>,
    states: StateQueue,
    latest: Arc<LatestState>,
    counts: Arc<ReaderCounts>,
    next_seq: u16,
    rejected_by_device: u32,
    timeout: Duration,
    divisor: u16,
    watchdog_ms: u16,
}

impl std::fmt::Debug for Device {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Device")
            .field("target", &self.target)
            .field("divisor", &self.divisor)
            .finish()
    }
}

fn spawn_reader(
    mut r: Box<dyn Read + Send>,
    replies: Sender<DeviceMsg>,
    states: SyncSender<StateSample>,
    latest: Arc<LatestState>,
    counts: Arc<ReaderCounts>,
) {
    thread::spawn(move || {
        let mut dec = FrameDecoder::new();
        let mut buf = [0u8; 4096];
        loop {
            let n = match r.read(&mut buf) {
                Ok(0) | Err(_) => return,
                Ok(n) => n,
            };
            let arrived = Instant::now();
            for &b in &buf[..n] {
                match dec.push::<DeviceMsg>(b) {
                    Some(Ok(DeviceMsg::State(s))) => {
                        latest.put(s, arrived);
                        // Full: the application is not taking samples; keep the older ones.
                        let _ = states.try_send(s).map_err(|_| {
                            counts.states_dropped.fetch_add(1, Relaxed);
                        });
                    }
                    Some(Ok(DeviceMsg::Ack {
                        seq: HEARTBEAT_SEQ, ..
                    })) => {}
                    Some(Ok(m)) => {
                        // The device went on talking after the application dropped us.
                        let Ok(()) = replies.send(m) else { return };
                    }
                    Some(Err(_)) => {
                        if let Ok(mut e) = counts.errors.lock() {
                            *e = dec.errors();
                        }
                    }
                    None => {}
                }
            }
        }
    });
}

/// Write a whole frame under the lock (frames of the heartbeat and of requests never interleave).
fn write_all(writer: &SharedWriter, bytes: &[u8]) -> Result<(), LinkError> {
    let mut w = writer.lock().map_err(|_| LinkError::Disconnected)?;
    w.write_all(bytes)?;
    w.flush()?;
    Ok(())
}

/// Ping every [`HEARTBEAT`] while `beating`, until `alive` is cleared or the stream fails.
fn spawn_heartbeat(writer: SharedWriter, alive: Arc<AtomicBool>, beating: Arc<AtomicBool>) {
    let mut frame = [0u8; MAX_FRAME_LEN];
    let ping = HostMsg::Request {
        seq: HEARTBEAT_SEQ,
        req: Request::Ping,
    };
    let Ok(n) = encode_frame(&ping, &mut frame) else {
        return;
    };
    thread::spawn(move || loop {
        thread::sleep(HEARTBEAT);
        if !alive.load(Relaxed) {
            return;
        }
        if beating.load(Relaxed) && write_all(&writer, &frame[..n]).is_err() {
            return;
        }
    });
}

impl Drop for Device {
    fn drop(&mut self) {
        self.alive.store(false, Relaxed);
        if let Some(s) = &self.tcp {
            let _ = s.shutdown(std::net::Shutdown::Both);
        }
    }
}

impl Device {
    /// Connect to `target` and agree on the protocol version.
    pub fn connect(target: &Target) -> Result<Device, LinkError> {
        let link = target::open_link(target)?;
        let (r, w) = link.halves;
        let tcp = link.tcp;
        let d = Device::over(r, w);
        if let (Err(_), Some(s)) = (&d, &tcp) {
            // No device speaking the protocol: do not leave the reader waiting on the socket.
            let _ = s.shutdown(std::net::Shutdown::Both);
        }
        let mut d = d?;
        d.target = Some(target.clone());
        d.tcp = tcp;
        Ok(d)
    }

    /// Talk over any byte stream (a fake transport in tests, a pipe, ...); agrees on the version.
    pub fn over(
        reader: Box<dyn Read + Send>,
        writer: Box<dyn Write + Send>,
    ) -> Result<Device, LinkError> {
        let (rtx, rrx) = channel();
        let (stx, srx) = sync_channel(STATE_QUEUE);
        let counts = Arc::new(ReaderCounts::default());
        let latest = Arc::new(LatestState::default());
        spawn_reader(reader, rtx, stx, latest.clone(), counts.clone());
        let writer: SharedWriter = Arc::new(Mutex::new(writer));
        let alive = Arc::new(AtomicBool::new(true));
        let beating = Arc::new(AtomicBool::new(true));
        spawn_heartbeat(writer.clone(), alive.clone(), beating.clone());
        let mut d = Device {
            target: None,
            tcp: None,
            writer,
            alive,
            beating,
            replies: rrx,
            states: StateQueue(Arc::new(Mutex::new(srx))),
            latest,
            counts,
            next_seq: 1,
            rejected_by_device: 0,
            timeout: Duration::from_secs(1),
            divisor: 0,
            watchdog_ms: 0,
        };
        d.hello()?;
        Ok(d)
    }

    /// Open the same target again (after the device went away) and restore this connection's
    /// stream divisor and watchdog. Fails if there is no target (a [`Device::over`] stream).
    pub fn reconnect(&mut self) -> Result<(), LinkError> {
        let target = self.target.clone().ok_or(LinkError::Disconnected)?;
        let fresh = Device::connect(&target)?;
        let (divisor, watchdog_ms) = (self.divisor, self.watchdog_ms);
        *self = fresh;
        if watchdog_ms != 0 {
            self.set_watchdog_ms(watchdog_ms)?;
        }
        if divisor != 0 {
            self.set_stream(divisor)?;
        }
        Ok(())
    }

    /// Keep the device's watchdog fed with a ping every [`HEARTBEAT`] (on by default). Off, the
    /// device hears only this connection's own requests (a test of its watchdog).
    pub fn set_heartbeat(&mut self, on: bool) {
        self.beating.store(on, Relaxed);
    }

    /// How long a request waits for its reply.
    pub fn set_timeout(&mut self, t: Duration) {
        self.timeout = t;
    }

    /// How long a request waits for its reply now.
    pub fn timeout(&self) -> Duration {
        self.timeout
    }

    /// Send raw bytes (tests of the device's handling of bad input).
    pub fn send_raw(&mut self, bytes: &[u8]) -> Result<(), LinkError> {
        write_all(&self.writer, bytes)
    }

    fn send(&mut self, msg: &HostMsg) -> Result<(), LinkError> {
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = encode_frame(msg, &mut buf).map_err(|e| LinkError::Protocol(format!("{e:?}")))?;
        self.send_raw(&buf[..n])
    }

    /// Wait for the next reply that `accept` takes (others are late replies: skipped).
    fn wait_for(
        &mut self,
        mut accept: impl FnMut(&DeviceMsg) -> bool,
    ) -> Result<DeviceMsg, LinkError> {
        let deadline = Instant::now() + self.timeout;
        let mut rejected: Option<FrameErrorKind> = None;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.replies.recv_timeout(left) {
                Ok(m) if accept(&m) => return Ok(m),
                Ok(DeviceMsg::FrameError { kind, .. }) => {
                    self.rejected_by_device += 1;
                    rejected = Some(kind);
                }
                Ok(_) => {}
                Err(RecvTimeoutError::Timeout) => {
                    return Err(rejected.map_or(LinkError::Timeout, LinkError::Frame))
                }
                Err(RecvTimeoutError::Disconnected) => return Err(LinkError::Disconnected),
            }
        }
    }

    fn hello(&mut self) -> Result<u8, LinkError> {
        self.send(&HostMsg::Hello {
            min_version: PROTOCOL_VERSION,
            max_version: PROTOCOL_VERSION,
        })?;
        match self.wait_for(|m| matches!(m, DeviceMsg::HelloReply { .. }))? {
            DeviceMsg::HelloReply {
                version: Some(v), ..
            } => Ok(v),
            DeviceMsg::HelloReply { device_version, .. } => Err(LinkError::Version {
                device: device_version,
            }),
            other => Err(LinkError::Protocol(format!("{other:?}"))),
        }
    }

    /// Send a request and wait for its reply. An `Ack` with an error becomes
    /// [`LinkError::Refused`], a refusal naming the value out of range
    /// [`LinkError::Rejected`].
    pub fn request(&mut self, req: Request) -> Result<DeviceMsg, LinkError> {
        let seq = self.next_seq;
        self.next_seq = self.next_seq.wrapping_add(1);
        if self.next_seq == HEARTBEAT_SEQ {
            self.next_seq = HEARTBEAT_SEQ.wrapping_add(1);
        }
        self.send(&HostMsg::Request { seq, req })?;
        let reply = self.wait_for(|m| match m {
            DeviceMsg::Ack { seq: s, .. }
            | DeviceMsg::Info { seq: s, .. }
            | DeviceMsg::Counters { seq: s, .. }
            | DeviceMsg::ContactParams { seq: s, .. }
            | DeviceMsg::Status { seq: s, .. }
            | DeviceMsg::Rejected { seq: s, .. }
            | DeviceMsg::Config { seq: s, .. }
            | DeviceMsg::ConfigRefused { seq: s, .. }
            | DeviceMsg::Update { seq: s, .. }
            | DeviceMsg::UpdateRefused { seq: s, .. } => *s == seq,
            _ => false,
        })?;
        match reply {
            DeviceMsg::Ack {
                result: AckResult::Err(code),
                ..
            } => Err(LinkError::Refused(code)),
            DeviceMsg::Rejected { code, field, .. } => Err(LinkError::Rejected { code, field }),
            other => Ok(other),
        }
    }

    /// A request answered by a plain acknowledgement.
    pub fn command(&mut self, req: Request) -> Result<(), LinkError> {
        match self.request(req)? {
            DeviceMsg::Ack { .. } => Ok(()),
            other => Err(LinkError::Protocol(format!("{other:?}"))),
        }
    }

    /// The device's description.
    pub fn info(&mut self) -> Result<DeviceInfo, LinkError> {
        match self.request(Request::GetInfo)? {
            DeviceMsg::Info { info, .. } => Ok(info),
            other => Err(LinkError::Protocol(format!("{other:?}"))),
        }
    }

    /// The device's link counters (all connections).
    pub fn counters(&mut self) -> Result<LinkCounters, LinkError> {
        match self.request(Request::GetCounters)? {
            DeviceMsg::Counters { counters, .. } => Ok(counters),
            other => Err(LinkError::Protocol(format!("{other:?}"))),
        }
    }

    /// The contact parameters in force.
    pub fn contact_params(&mut self) -> Result<ContactParamsWire, LinkError> {
        match self.request(Request::GetContactParams)? {
            DeviceMsg::ContactParams { params, .. } => Ok(params),
            other => Err(LinkError::Protocol(format!("{other:?}"))),
        }
    }

    /// The device's mode, flags, latched faults and the local model in force.
    pub fn status(&mut self) -> Result<DeviceStatus, LinkError> {
        match self.request(Request::GetStatus)? {
            DeviceMsg::Status { status, .. } => Ok(status),
            other => Err(LinkError::Protocol(format!("{other:?}"))),
        }
    }

    /// Round trip of a `Ping`.
    pub fn ping(&mut self) -> Result<Duration, LinkError> {
        let t0 = Instant::now();
        self.command(Request::Ping)?;
        Ok(t0.elapsed())
    }

    /// Home the device (returns once the device accepted; homing then takes a moment, see
    /// [`Device::home_and_wait`]).
    pub fn home(&mut self) -> Result<(), LinkError> {
        self.command(Request::Home)
    }

    /// Home the device and wait until it is homed ([`Mode::Disarmed`]), failed
    /// ([`LinkError::HomingFailed`]: it faulted) or `timeout` passed ([`LinkError::Timeout`]).
    ///
    /// The mode is read from the state stream, switched to the device's fastest rate for the
    /// wait and back to this connection's rate afterwards; if it was off, the samples of the
    /// wait are dropped from the queue (the latest-sample slot keeps the last).
    pub fn home_and_wait(&mut self, timeout: Duration) -> Result<(), LinkError> {
        let deadline = Instant::now() + timeout;
        let divisor = self.divisor;
        let fastest = self.info()?.min_stream_divisor.max(1);
        self.set_stream(fastest)?;
        let result = self.home().and_then(|()| self.wait_homed(deadline));
        // Restore the stream as it was; a homing failure is the answer that matters.
        let restored = self.set_stream(divisor);
        if divisor == 0 {
            // The samples of the wait were the library's, not the application's: drop them.
            while let Ok(Some(_)) = self.states.next(Duration::ZERO) {}
        }
        result.and(restored)
    }

    /// Wait until the stream shows homing, then the mode it ends in. (The device applies `Home`
    /// at a tick boundary after acknowledging it, so samples right after the acknowledgement
    /// may still show the mode before; homing takes many stream periods.)
    fn wait_homed(&self, deadline: Instant) -> Result<(), LinkError> {
        let mut seen_homing = false;
        let mut last = 0;
        loop {
            if let Some(l) = self.latest.get().filter(|l| l.count != last) {
                last = l.count;
                match l.sample.mode {
                    Mode::Homing => seen_homing = true,
                    Mode::Faulted => return Err(LinkError::HomingFailed),
                    Mode::Disarmed | Mode::Armed if seen_homing => return Ok(()),
                    _ => {}
                }
            }
            if Instant::now() >= deadline {
                return Err(LinkError::Timeout);
            }
            thread::sleep(Duration::from_micros(200));
        }
    }

    /// Arm (needs homing); re-arms the watchdog.
    pub fn arm(&mut self) -> Result<(), LinkError> {
        self.command(Request::Arm)
    }
    /// Disarm.
    pub fn disarm(&mut self) -> Result<(), LinkError> {
        self.command(Request::Disarm)
    }
    /// Clear latched faults (the device is then disarmed).
    pub fn clear_faults(&mut self) -> Result<(), LinkError> {
        self.command(Request::ClearFaults)
    }
    /// Replace the contact parameters.
    pub fn set_contact_params(&mut self, p: ContactParamsWire) -> Result<(), LinkError> {
        self.command(Request::SetContactParams(p))
    }
    /// Send a local model (applied at the device's next tick boundary, blended in).
    pub fn set_local_model(&mut self, m: LocalModel) -> Result<(), LinkError> {
        self.command(Request::SetLocalModel(m))
    }
    /// Stream a state sample every `divisor` control ticks (0: stop).
    pub fn set_stream(&mut self, divisor: u16) -> Result<(), LinkError> {
        self.command(Request::SetStream { divisor })?;
        self.divisor = divisor;
        Ok(())
    }
    /// Communication watchdog timeout, ms (0: off).
    pub fn set_watchdog_ms(&mut self, timeout_ms: u16) -> Result<(), LinkError> {
        self.command(Request::SetWatchdog { timeout_ms })?;
        self.watchdog_ms = timeout_ms;
        Ok(())
    }
    /// Virtual device: the simulated hand moves to `t` and holds it.
    pub fn drive_hand(&mut self, t: HandTarget) -> Result<(), LinkError> {
        self.command(Request::DriveHand(t))
    }
    /// Virtual device: the simulated hand follows the scene's script again.
    pub fn release_hand(&mut self) -> Result<(), LinkError> {
        self.command(Request::ReleaseHand)
    }

    /// The next state sample, waiting up to `timeout`; `Ok(None)` on timeout,
    /// [`LinkError::Disconnected`] once the connection is gone and the queue empty.
    pub fn next_state(&self, timeout: Duration) -> Result<Option<StateSample>, LinkError> {
        self.states.next(timeout)
    }

    /// The state queue itself, to take samples on another thread while this `Device` is used for
    /// requests elsewhere.
    pub fn state_queue(&self) -> StateQueue {
        self.states.clone()
    }

    /// The newest state sample, without waiting (`None` before the first; see [`LatestState`]).
    pub fn latest_state(&self) -> Option<StateSample> {
        self.latest.get().map(|l| l.sample)
    }

    /// The latest-sample slot itself, to poll from another thread while this `Device` is used
    /// for requests elsewhere. It stops changing when the connection goes.
    pub fn latest(&self) -> Arc<LatestState> {
        self.latest.clone()
    }

    /// Frames from the device this side could not decode, by kind.
    pub fn rx_errors(&self) -> FrameErrorCounts {
        self.counts.errors.lock().map(|e| *e).unwrap_or_default()
    }

    /// Frames of ours the device rejected (its `FrameError` answers seen while waiting for
    /// replies).
    pub fn rejected_by_device(&self) -> u32 {
        self.rejected_by_device
    }

    /// State samples dropped on this side because the application did not take them.
    pub fn states_dropped_here(&self) -> u32 {
        self.counts.states_dropped.load(Relaxed)
    }
}
