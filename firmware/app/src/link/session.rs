//! One connection: the protocol endpoint (framing, hello, counters, stream divisor) with the
//! firmware's answers around it. The link task feeds it received bytes, the tick's command
//! outcomes and stream points, publishes its stream divisor to the tick
//! ([`LinkSession::stream_divisor`]), and drains [`LinkSession::tx`] into its transport.

use heapless::spsc::Producer;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::control::pipeline::{CheckedCommand, Command, CommandError};
use softfinger_protocol::{
    AckResult, ContactParamsWire, DeviceEndpoint, DeviceMsg, ErrorCode, LinkCounters, Request,
    StateSample,
};

use super::acks::PendingAcks;
use super::info::{device_info, InfoSource};
use super::requests::{route, Route};
use super::state::StateBuilder;
use super::tx::TxRing;
use crate::persist::{NoStore, Persistence, ARM_REFUSED};
use crate::stream_point::StreamPoint;
use crate::tick::{published_mode, Applied};
use softfinger_core::control::pipeline::Mode;

/// Where the link's pipeline commands go, checked: the tick's command queue, never waiting.
pub trait CommandSink {
    /// Queue `command` for the tick; false when the queue is full (nothing queued).
    fn try_submit(&mut self, command: CheckedCommand) -> bool;
}

impl CommandSink for Producer<'_, CheckedCommand> {
    fn try_submit(&mut self, command: CheckedCommand) -> bool {
        self.enqueue(command).is_ok()
    }
}

/// What a session needs to know about the device.
#[derive(Clone, Copy, Debug)]
pub struct LinkConfig {
    /// The description answered to `GetInfo` (`max_force_n` is the contact parameters').
    pub info: InfoSource,
    /// The tick timer's clock, Hz (the stream's tick durations are in its counts).
    pub timer_clock_hz: u32,
    /// The contact parameters the pipeline starts with.
    pub contact: ContactParams,
}

/// One connection's state. `TX`: bytes of frames waiting for the transport; `S`: the device's
/// flash (its settings, update and reboot requests; [`NoStore`] on a board without one).
#[derive(Debug)]
pub struct LinkSession<const TX: usize, S: Persistence = NoStore> {
    endpoint: DeviceEndpoint,
    acks: PendingAcks,
    state: StateBuilder,
    info: InfoSource,
    contact: ContactParams,
    tx: TxRing<TX>,
    /// The tick of the last point offered (`None`: none yet since the stream started).
    last_tick: Option<u64>,
    /// State samples this connection lost (transmit ring full, or the tick's queue full).
    stream_dropped: u32,
    /// Valid frames received, as last seen (see [`LinkSession::receive`]).
    rx_frames: u32,
    store: S,
}

impl<const TX: usize> LinkSession<TX, NoStore> {
    /// A session with nothing received and no stream, on a board without a settings store.
    pub fn new(config: &LinkConfig) -> Self {
        Self::with_store(config, NoStore)
    }
}

impl<const TX: usize, S: Persistence> LinkSession<TX, S> {
    /// A session with nothing received, its stream at the store's default (`stream.rate_hz`,
    /// off by default), answering settings and update requests from `store`.
    pub fn with_store(config: &LinkConfig, store: S) -> Self {
        ARM_REFUSED.store(
            store.arm_refusal().is_some(),
            core::sync::atomic::Ordering::Relaxed,
        );
        let mut endpoint = DeviceEndpoint::new(config.info.min_stream_divisor);
        // The stored stream default (never faster than the link's fastest, so never refused).
        let _ = endpoint.set_divisor(
            store
                .boot_defaults()
                .stream_divisor(config.info.control_rate_hz, config.info.min_stream_divisor),
        );
        LinkSession {
            endpoint,
            acks: PendingAcks::new(),
            state: StateBuilder::new(config.timer_clock_hz),
            info: config.info,
            contact: config.contact,
            tx: TxRing::new(),
            last_tick: None,
            stream_dropped: 0,
            rx_frames: 0,
            store,
        }
    }

    /// Take one received byte; requests for the pipeline go to `sink`. Returns true when the
    /// byte completed a valid frame (any message, link-level ones included: the communication
    /// watchdog's food, which the caller passes on to the tick).
    pub fn receive(&mut self, byte: u8, sink: &mut impl CommandSink) -> bool {
        let tx = &mut self.tx;
        let mut send = |f: &[u8]| tx.push_frame(f);
        let request = self.endpoint.receive(byte, &mut send);
        let valid = byte == 0 && self.note_frames();
        if let Some((seq, req)) = request {
            self.request(seq, &req, sink);
        }
        valid
    }

    /// Whether the decoder counted a new valid frame since the last call.
    fn note_frames(&mut self) -> bool {
        let frames = self.endpoint.counters().rx_frames;
        let new = frames != self.rx_frames;
        self.rx_frames = frames;
        new
    }

    /// Answer or forward request `seq`.
    fn request(&mut self, seq: u16, req: &Request, sink: &mut impl CommandSink) {
        let tx = &mut self.tx;
        let mut send = |f: &[u8]| tx.push_frame(f);
        // Settings, update and reboot: the flash's, in this (thread-mode) task, never the tick's.
        let armed = matches!(published_mode(), Mode::Armed | Mode::Homing);
        if let Some(msg) = self.store.handle(seq, req, armed) {
            ARM_REFUSED.store(
                self.store.arm_refusal().is_some(),
                core::sync::atomic::Ordering::Relaxed,
            );
            self.endpoint.send(&msg, &mut send);
            return;
        }
        // Never arm on settings the device could not read (the store's arm check).
        if matches!(req, Request::Arm) && self.store.arm_refusal().is_some() {
            self.endpoint
                .reply(seq, AckResult::Err(ErrorCode::WrongMode), &mut send);
            return;
        }
        match route(req, &self.contact) {
            // Checked here, in thread mode: the tick only applies it. A refusal is answered at
            // once, naming why, and never reaches the tick.
            Route::Pipeline(command) => match command.check() {
                Err(e) => self.endpoint.reply(seq, AckResult::from(Err(e)), &mut send),
                Ok(checked) => {
                    let queued = self.acks.has_room() && sink.try_submit(checked);
                    if queued {
                        // Cannot fail: room was checked.
                        let _ = self.acks.push(seq, command);
                    } else {
                        self.endpoint
                            .reply(seq, AckResult::Err(ErrorCode::Busy), &mut send);
                    }
                }
            },
            Route::Info => {
                let mut info = device_info(
                    &InfoSource {
                        max_force_n: self.contact.max_force_n,
                        ..self.info
                    },
                    self.store.settings_flags(),
                );
                // The name the user gave the device (`config set identity.name=...`), if any.
                if let Some(name) = self.store.device_name() {
                    info.name = super::info::text(name);
                }
                self.endpoint
                    .send(&DeviceMsg::Info { seq, info }, &mut send);
            }
            Route::ContactParams => {
                let params = ContactParamsWire::of(&self.contact);
                self.endpoint
                    .send(&DeviceMsg::ContactParams { seq, params }, &mut send);
            }
            Route::Ping => self.endpoint.reply(seq, AckResult::Ok, &mut send),
            Route::Refuse(code) => self.endpoint.reply(seq, AckResult::Err(code), &mut send),
        }
    }

    /// The tick applied (or refused) a command: acknowledge the request a host command came
    /// from, and keep the contact parameters and the watchdog in force up to date (an operator's
    /// parameters come whole, a host's command is the one this link queued).
    pub fn outcome(&mut self, applied: &Applied, result: Result<(), CommandError>) {
        match applied {
            Applied::Operator(_) => {}
            Applied::OperatorParams(p) => {
                if result.is_ok() {
                    self.contact = *p;
                }
            }
            Applied::Link(key) => {
                if let Some((seq, command, ack)) = self.acks.resolve(*key, result) {
                    self.applied(&command, result);
                    let tx = &mut self.tx;
                    self.endpoint
                        .reply(seq, ack, &mut |f: &[u8]| tx.push_frame(f));
                }
            }
        }
    }

    /// What an applied `command` changes in what this link reports.
    fn applied(&mut self, command: &Command, result: Result<(), CommandError>) {
        match (command, result) {
            (Command::SetContactParams(p), Ok(())) => self.contact = *p,
            (Command::SetWatchdog { timeout_s }, Ok(())) => {
                // In range (the pipeline accepted it): 0..=60 s.
                self.info.watchdog_ms = (timeout_s * 1000.0 + 0.5) as u16;
            }
            _ => {}
        }
    }

    /// The stream divisor the host asked for (0: no stream): the link task hands it to the tick
    /// (`crate::stream::set_divisor`), which streams the ticks that are multiples of it.
    pub fn stream_divisor(&self) -> u16 {
        self.endpoint.divisor()
    }

    /// A stream point from the tick: sent as a state sample while a stream is on. A full
    /// transmit ring drops the sample, counted; so is every point missing between two that
    /// arrive (the tick's queue was full). The next sample sent reports how many this
    /// connection lost.
    pub fn stream(&mut self, point: &StreamPoint) {
        let sample = self.state.sample(point);
        let divisor = u64::from(self.endpoint.divisor());
        if divisor == 0 {
            self.last_tick = None;
            return;
        }
        if let Some(last) = self.last_tick {
            let missing = (sample.tick.saturating_sub(last) / divisor).saturating_sub(1);
            self.stream_dropped = self.stream_dropped.wrapping_add(missing as u32);
        }
        self.last_tick = Some(sample.tick);
        let tx = &mut self.tx;
        let msg = DeviceMsg::State(StateSample {
            dropped: self.stream_dropped,
            ..sample
        });
        if !self.endpoint.send(&msg, &mut |f: &[u8]| tx.push_frame(f)) {
            self.stream_dropped = self.stream_dropped.wrapping_add(1);
        }
    }

    /// The bytes waiting for the transport.
    pub fn tx(&mut self) -> &mut TxRing<TX> {
        &mut self.tx
    }

    /// The link counters (frames, errors by kind, frames dropped).
    pub fn counters(&self) -> LinkCounters {
        self.endpoint.counters()
    }

    /// Requests waiting for the tick's outcome.
    pub fn pending(&self) -> usize {
        self.acks.len()
    }

    /// A `Reboot` was accepted since the last call: the transport resets the device once the
    /// answer has gone out.
    pub fn take_reset_request(&mut self) -> bool {
        self.store.take_reset_request()
    }

    /// The device's flash, as this session answers for it.
    pub fn store(&self) -> &S {
        &self.store
    }

    /// End the session, giving its store back.
    pub fn into_store(self) -> S {
        self.store
    }
}
