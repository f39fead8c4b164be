//! The virtual device's loop: the device core against the plant in real time, the clients'
//! requests applied at tick boundaries, the state stream to each client at its own divisor.
//!
//! Each client's link is the protocol's device side, a `DeviceEndpoint` per connection as on the
//! firmware: it decodes the client's bytes, counts frames and errors, answers hello, frame errors
//! and the stream divisor, and streams the samples ([`StateSample::rendered`] from what the
//! pipeline rendered) at the divisor; the requests it hands on are answered here, the link
//! counters over every connection since the device started among them.
//!
//! Real time: the loop runs the ticks that are due by the wall clock (`elapsed · rate`), in
//! batches when the OS wakes it late. If it falls more than [`MAX_BACKLOG_S`] behind (a stalled
//! machine), the backlog is skipped rather than raced through, and those ticks are counted as
//! overruns.

use crate::serve::core::PipelineCore;
use crate::serve::hand::{self, HandMode};
use crate::serve::link::{Event, Outbox};
use crate::serve::log::EventLog;
use crate::sim::plant::{HandScript, Plant, Waypoint};
use softfinger_core::contact::params::ContactParams;
use softfinger_core::contact::Parts;
use softfinger_core::control::pipeline::{Command, CommandError};
use softfinger_core::device::DeviceParams;
use softfinger_core::Flags;
use softfinger_protocol::{
    AckResult, ContactParamsWire, DeviceEndpoint, DeviceInfo, DeviceMsg, DeviceStatus, ErrorCode,
    FieldRange, LinkCounters, LocalModel, Mode, RenderedTick, Request, StateSample, SurfaceKind,
    TickStatsWire, PROTOCOL_VERSION,
};
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Largest backlog of ticks run in a burst, s.
pub const MAX_BACKLOG_S: f64 = 0.05;
/// A tick run more than this after its time counts as an overrun, s (the host OS wakes the loop
/// every 0.1-0.2 ms, so batches of a few ticks are normal, not overruns).
pub const LATE_S: f64 = 0.001;

/// One connected client: the protocol's device side of its link, and its outgoing queue.
#[derive(Debug)]
struct Client {
    endpoint: DeviceEndpoint,
    out: Outbox,
}

impl Client {
    /// Encode `msg` through the endpoint (which counts it sent or dropped) into the queue.
    fn send(&mut self, msg: &DeviceMsg) -> bool {
        let out = &self.out;
        self.endpoint.send(msg, &mut |f: &[u8]| out.push(f, false))
    }
}

/// Tick timing over a window.
#[derive(Debug, Default)]
struct TickTiming {
    max_ns: u32,
    sum_ns: u64,
    n: u32,
    last: TickStatsWire,
}

impl TickTiming {
    fn record(&mut self, ns: u32, window: u32) {
        self.max_ns = self.max_ns.max(ns);
        self.sum_ns += ns as u64;
        self.n += 1;
        if self.n >= window {
            self.last.max_duration_ns = self.max_ns;
            self.last.mean_duration_ns = (self.sum_ns / self.n as u64) as u32;
            (self.max_ns, self.sum_ns, self.n) = (0, 0, 0);
        }
    }
}

/// The device: core (rendering with the contact model of parts `P`), plant, hand and clients.
pub struct DeviceLoop<P: Parts> {
    core: PipelineCore<P>,
    device: DeviceParams,
    plant: Plant,
    scene_script: HandScript,
    hand: HandMode,
    /// Homing against the plant is running: the hand has let go of the handle.
    homing: bool,
    /// Where a client asked the hand to hold the handle (None: the scene's script); applied at
    /// once, or when homing ends.
    hand_target: Option<Waypoint>,
    clients: BTreeMap<u32, Client>,
    /// The link counters of the connections that have closed.
    closed: LinkCounters,
    info: DeviceInfo,
    tick: u64,
    timing: TickTiming,
    last: RenderedTick,
    /// The largest force limit a client may set, N: the one the device started with.
    force_limit_n: f32,
    log: EventLog,
    /// Faults latched and watchdog/model flags raised at the previous tick (logged on change).
    noted: Flags,
    /// The flash: settings store and firmware update (see [`super::persist`]).
    persist: super::persist::Persist,
}

impl<P: Parts> std::fmt::Debug for DeviceLoop<P> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DeviceLoop")
            .field("tick", &self.tick)
            .finish()
    }
}

impl<P: Parts> DeviceLoop<P> {
    /// A device running `core` against `plant`, whose hand plays `scene_script`.
    pub fn new(
        core: PipelineCore<P>,
        device: DeviceParams,
        plant: Plant,
        scene_script: HandScript,
    ) -> DeviceLoop<P> {
        let rate = core.rate_hz();
        let mut info = DeviceInfo {
            protocol_version: PROTOCOL_VERSION,
            name: heapless::String::new(),
            firmware_version: heapless::String::new(),
            virtual_device: true,
            control_rate_hz: rate as u32,
            max_force_n: core.contact_params().max_force_n,
            min_stream_divisor: 1,
            surfaces: heapless::Vec::from_slice(&SurfaceKind::ALL).unwrap_or_default(),
            watchdog_ms: 0,
            settings_flags: 0,
            reset_cause: heapless::String::new(),
        };
        let _ = info.reset_cause.push_str("virtual");
        let force_limit_n = info.max_force_n;
        let _ = info.name.push_str("virtual omega-like");
        let _ = info
            .firmware_version
            .push_str(concat!("host-sim ", env!("CARGO_PKG_VERSION")));
        DeviceLoop {
            core,
            device,
            plant,
            scene_script,
            hand: HandMode::Script,
            homing: false,
            hand_target: None,
            clients: BTreeMap::new(),
            closed: LinkCounters::default(),
            info,
            tick: 0,
            timing: TickTiming::default(),
            last: RenderedTick::default(),
            force_limit_n,
            log: EventLog::new(rate, None),
            noted: Flags::NONE,
            persist: super::persist::Persist::in_ram(),
        }
    }

    /// The same device with `persist` as its flash.
    pub fn with_persist(mut self, persist: super::persist::Persist) -> DeviceLoop<P> {
        self.persist = persist;
        self.apply_boot_defaults();
        self
    }

    /// What the settings loaded at boot change, as the firmware applies them before its first
    /// tick (`softfinger_app::boot_defaults`): the host watchdog here, the stream at each
    /// connection.
    fn apply_boot_defaults(&mut self) {
        let defaults = self.persist.boot_defaults();
        if let Err(e) = defaults.apply(self.core.pipeline_mut()) {
            self.log.line(
                self.tick,
                format_args!("stored watchdog.timeout_ms refused ({e}): the built-in one stays"),
            );
        }
    }

    /// Log each connection, mode change, model or parameter change and fault into `out` (one
    /// line each, with the device time); `None`: silent.
    pub fn with_log(mut self, out: Option<crate::serve::log::LogSink>) -> DeviceLoop<P> {
        self.log = EventLog::new(self.core.rate_hz(), out);
        self
    }

    /// Run in real time until `stop` is set or `events` closes.
    pub fn run(mut self, events: Receiver<Event>, stop: Arc<AtomicBool>) {
        let rate = self.core.rate_hz() as f64;
        let mut start = Instant::now();
        let mut overruns: u32 = 0;
        while !stop.load(Ordering::Relaxed) {
            let due = (start.elapsed().as_secs_f64() * rate) as u64;
            if due <= self.tick {
                std::thread::sleep(Duration::from_micros(100));
                continue;
            }
            let backlog = due - self.tick;
            if backlog as f64 > MAX_BACKLOG_S * rate {
                let skip = backlog - 1;
                start += Duration::from_secs_f64(skip as f64 / rate);
                overruns = overruns.saturating_add(skip as u32);
                continue;
            }
            let late = backlog.saturating_sub((LATE_S * rate) as u64);
            overruns = overruns.saturating_add(late as u32);
            for _ in 0..backlog {
                if !self.drain(&events) {
                    return;
                }
                self.one_tick(overruns);
            }
        }
    }

    /// Apply every pending event; false when the event channel is closed.
    fn drain(&mut self, events: &Receiver<Event>) -> bool {
        loop {
            match events.try_recv() {
                Ok(Event::Connected { id, out }) => {
                    self.log.line(
                        self.tick,
                        format_args!("connection {id} opened ({} open)", self.clients.len() + 1),
                    );
                    let mut endpoint = DeviceEndpoint::one_of_several(self.info.min_stream_divisor);
                    // The stored stream default (never faster than the link allows).
                    let _ =
                        endpoint.set_divisor(self.persist.boot_defaults().stream_divisor(
                            self.info.control_rate_hz,
                            self.info.min_stream_divisor,
                        ));
                    self.clients.insert(id, Client { endpoint, out });
                }
                Ok(Event::Disconnected { id }) => {
                    if let Some(c) = self.clients.remove(&id) {
                        self.closed = self.closed.plus(&c.endpoint.counters());
                    }
                    self.log.line(
                        self.tick,
                        format_args!("connection {id} closed ({} open)", self.clients.len()),
                    );
                }
                Ok(Event::Bytes { id, bytes }) => self.receive(id, &bytes),
                Err(TryRecvError::Empty) => return true,
                Err(TryRecvError::Disconnected) => return false,
            }
        }
    }

    fn one_tick(&mut self, overruns: u32) {
        let rate = self.core.rate_hz();
        let t0 = Instant::now();
        let tick_out = self.core.tick(&mut self.plant);
        let ns = t0.elapsed().as_nanos().min(u32::MAX as u128) as u32;
        let out = self.core.rendered(&tick_out);
        self.timing.record(ns, (rate / 10.0) as u32);
        self.timing.last.overruns = overruns;
        let before = self.last.mode;
        self.last = out;
        self.tick += 1;
        if out.mode != before {
            self.log.mode(self.tick, before, out.mode, out.flags);
        }
        let noted = self.core.latched() | (out.flags & EventLog::NOTED);
        if noted != self.noted {
            self.log
                .flags_raised(self.tick, noted.0 & !self.noted.0, out.mode);
            self.noted = noted;
        }
        if self.homing && out.mode != Mode::Homing {
            // Homing ended (done, aborted or failed): the hand takes the handle again.
            self.homing = false;
            self.plant.grasp_hand();
            let _ = self.take_handle();
        } else if !self.homing
            && self.hand == HandMode::Script
            && self.plant.time_s() >= self.plant.script().duration_s()
        {
            let p = hand::following(&self.plant, &self.scene_script, self.device);
            if self.rehand(p, HandMode::Script) != AckResult::Ok {
                // The handle is somewhere no script can start from: it stays held where it is.
                self.hand = HandMode::Driven;
            }
        }
        self.stream();
    }

    /// Send a sample to every client whose divisor divides this tick.
    fn stream(&mut self) {
        let sample = StateSample::rendered(self.tick, &self.last, self.timing.last);
        for c in self.clients.values_mut() {
            let out = &c.out;
            c.endpoint
                .offer_state(&sample, &mut |f: &[u8]| out.push(f, true));
        }
    }

    fn reply(&mut self, id: u32, msg: DeviceMsg) {
        if let Some(c) = self.clients.get_mut(&id) {
            c.send(&msg);
        }
    }

    /// The link counters over every connection since the device started, `connections` the
    /// ones open now.
    fn counters(&self) -> LinkCounters {
        let all = self
            .clients
            .values()
            .fold(self.closed, |sum, c| sum.plus(&c.endpoint.counters()));
        LinkCounters {
            connections: self.clients.len().min(u16::MAX as usize) as u16,
            ..all
        }
    }

    /// Bytes from client `id`, through its endpoint: every valid frame feeds the communication
    /// watchdog; the requests the endpoint hands on are handled at once, in order.
    fn receive(&mut self, id: u32, bytes: &[u8]) {
        for &b in bytes {
            let Some(c) = self.clients.get_mut(&id) else {
                return;
            };
            // A frame ends at a zero byte: only then can the decoder count a valid one.
            let frames = (b == 0).then(|| c.endpoint.counters().rx_frames);
            let out = &c.out;
            let request = c.endpoint.receive(b, &mut |f: &[u8]| out.push(f, false));
            if frames.is_some_and(|n| n != c.endpoint.counters().rx_frames) {
                self.core.message_received();
            }
            if let Some((seq, req)) = request {
                self.handle(id, seq, req);
            }
        }
    }

    /// One client request the endpoint handed on, at a tick boundary.
    fn handle(&mut self, id: u32, seq: u16, req: Request) {
        let armed = matches!(self.last.mode, Mode::Armed | Mode::Homing);
        if let Some(reply) = self.persist.handle(seq, &req, armed) {
            if matches!(req, Request::Reboot) {
                // The virtual device's reset reloaded the store: its boot defaults again.
                self.apply_boot_defaults();
            }
            return self.reply(id, reply);
        }
        let result = match &req {
            Request::GetInfo => {
                self.info.watchdog_ms = (self.core.watchdog_s() * 1000.0).round() as u16;
                self.info.settings_flags = self.persist.settings_flags();
                let mut info = self.info.clone();
                if let Some(name) = self.persist.device_name() {
                    // Both hold 24 bytes (`softfinger_store::schema::NAME_LEN`).
                    info.name = heapless::String::try_from(name).unwrap_or_default();
                }
                return self.reply(id, DeviceMsg::Info { seq, info });
            }
            Request::GetCounters => {
                let counters = self.counters();
                return self.reply(id, DeviceMsg::Counters { seq, counters });
            }
            Request::GetStatus => {
                let status = DeviceStatus {
                    tick: self.tick,
                    mode: self.core.mode(),
                    flags: self.last.flags.0,
                    latched: self.core.latched().0,
                    model: LocalModel::of(&self.core.model()),
                };
                return self.reply(id, DeviceMsg::Status { seq, status });
            }
            Request::GetContactParams => {
                let params = ContactParamsWire::of(&self.core.contact_params());
                return self.reply(id, DeviceMsg::ContactParams { seq, params });
            }
            Request::Ping => AckResult::Ok,
            Request::DriveHand(t) => {
                let target = Waypoint {
                    position_m: t.position_m.map(f64::from),
                    wrist_rad: t.wrist_rad.map(f64::from),
                };
                // Checked now (reachable, finite) even while homing, applied when it ends.
                match hand::holding(&self.plant, target, self.device) {
                    Err(_) => AckResult::Err(ErrorCode::InvalidValue),
                    Ok(_) => {
                        self.hand_target = Some(target);
                        self.take_handle()
                    }
                }
            }
            Request::ReleaseHand => {
                self.hand_target = None;
                self.take_handle()
            }
            other => match other.command(&self.core.contact_params()) {
                Some(r) => match self.command(id, r) {
                    Ok(()) => AckResult::Ok,
                    Err((code, Some(field))) => {
                        return self.reply(id, DeviceMsg::Rejected { seq, code, field });
                    }
                    Err((code, None)) => AckResult::Err(code),
                },
                None => AckResult::Err(ErrorCode::Unsupported),
            },
        };
        self.reply(id, DeviceMsg::Ack { seq, result });
    }

    /// A pipeline command from client `id`: done, or refused with its code and, for a value out
    /// of range, the field and the range the device accepts. A force limit above the one the
    /// device started with is refused here (the hardware's limit, whatever the core allows).
    fn command(
        &mut self,
        id: u32,
        command: Command,
    ) -> Result<(), (ErrorCode, Option<FieldRange>)> {
        if let Command::SetContactParams(p) = &command {
            if p.max_force_n.is_finite() && p.max_force_n > self.force_limit_n {
                let range = FieldRange::new(
                    "max_force_n",
                    ContactParams::MIN_MAX_FORCE_N,
                    false,
                    self.force_limit_n,
                );
                return Err((ErrorCode::InvalidValue, Some(range)));
            }
        }
        match self.core.request(command) {
            Ok(()) => {}
            Err(e) => {
                let field = match (&e, &command) {
                    (CommandError::InvalidParams(pe), Command::SetContactParams(p)) => {
                        FieldRange::of_param_error(pe, p, self.force_limit_n)
                    }
                    _ => None,
                };
                return Err((e.into(), field));
            }
        }
        match command {
            Command::Home => {
                // The real homing against the plant: the hand lets go of the handle until the
                // arms have found their stops.
                self.homing = true;
                self.plant.release_hand();
            }
            Command::SetLocalModel(m) => self.log.model(self.tick, id, &m),
            Command::SetContactParams(p) => self.log.params(self.tick, id, &p),
            _ => {}
        }
        Ok(())
    }

    /// The hand holds the handle where a client asked, or plays the scene's script; while
    /// homing it keeps off the handle (applied when homing ends).
    fn take_handle(&mut self) -> AckResult {
        if self.homing {
            return AckResult::Ok;
        }
        match self.hand_target {
            Some(t) => {
                let p = hand::holding(&self.plant, t, self.device);
                self.rehand(p, HandMode::Driven)
            }
            None => {
                let p = hand::following(&self.plant, &self.scene_script, self.device);
                self.rehand(p, HandMode::Script)
            }
        }
    }

    fn rehand(&mut self, plant: Result<Plant, hand::HandError>, mode: HandMode) -> AckResult {
        match plant {
            Ok(mut p) => {
                p.continue_counters_from(&self.plant);
                self.plant = p;
                self.hand = mode;
                AckResult::Ok
            }
            Err(_) => AckResult::Err(ErrorCode::InvalidValue),
        }
    }
}
