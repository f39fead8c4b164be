//! The host link over USB: a full-speed CDC-ACM function (embassy-usb) whose
//! bytes feed the board-independent [`softfinger_app::link`] session, in two low-priority tasks: the USB
//! device task and the link task. The USB interrupt (USB_LP) stays at the lowest priority set by
//! `board::stm32g474::prepare_core`; the tick (TIM6, priority 0) preempts all of it.
//!
//! A lost link lets go: a bus reset, a suspend (an unplug, without VBUS sensing), the
//! configuration dropped, DTR dropped by the host, a read error, or no write taken by the host for
//! [`WRITE_STALL_MS`] each call `tick::note_link_lost`; the tick then applies the core's link rule
//! (`Pipeline::link_lost`: a host-armed device fades to zero within 20 ms and latches
//! `COMM_TIMEOUT` until re-armed). Commands from the link go to the tick's link queue, where the
//! core's `Pipeline::link_command` applies them (an `Arm` from the link turns the communication
//! watchdog on).
//!
//! Nothing here can stall the tick: commands reach it through its lock-free link command queue,
//! outcomes come
//! back through a queue the supervisor forwards, stream points through a queue the tick fills
//! (full: dropped and counted), and a host that stops reading makes a write time out, which drops the bytes waiting
//! (the host's decoder counts the one cut frame and resynchronises at the next delimiter).

use embassy_futures::select::{select, Either};
use embassy_stm32::peripherals::USB;
use embassy_stm32::usb::Driver;
use embassy_time::{with_timeout, Duration, Instant, Timer};
use embassy_usb::class::cdc_acm::{CdcAcmClass, State};
use embassy_usb::{Builder, UsbDevice};
use heapless::spsc::Producer;
use softfinger_core::control::pipeline::CheckedCommand;

use softfinger_app::link::session::LinkSession;
use softfinger_app::link::task::LinkQueues;
use softfinger_app::persist::Persistence;

/// USB vendor id: pid.codes' open-source vendor id (host/src/usb.rs finds the device by it).
pub const USB_VID: u16 = 0x1209;
/// USB product id (host/src/usb.rs).
pub const USB_PID: u16 = 0x5F10;
/// Command outcomes queued for the link.
pub const LINK_QUEUE_LEN: usize = 8;
/// Bytes of frames the link holds for the host (about ten state frames).
pub const LINK_TX_BYTES: usize = 1024;
/// Full-speed bulk packet size, bytes.
const PACKET: usize = 64;
/// Bytes per IN packet: one less than a full packet, so every packet is short and ends a transfer
/// without a zero-length packet.
const TX_CHUNK: usize = PACKET - 1;
/// A write the host does not take within this long is abandoned, ms.
const WRITE_TIMEOUT_MS: u64 = 20;
/// How often the link looks at the tick's queues when nothing arrives, ms.
const POLL_MS: u64 = 1;

/// The STM32G474's USB driver.
pub type UsbDriver = Driver<'static, USB>;

/// How long the host may leave the device's writes untaken before the link counts as lost, ms
/// (each write is abandoned after [`WRITE_TIMEOUT_MS`]; the link is lost once none has been taken
/// for this long while there was something to send).
pub const WRITE_STALL_MS: u64 = 100;

/// The USB device's bus events that lose the link: a bus reset, a suspend (what an unplug looks
/// like without VBUS sensing), the configuration dropped. Runs in the USB device task.
struct LinkEvents;

impl embassy_usb::Handler for LinkEvents {
    fn reset(&mut self) {
        softfinger_app::tick::note_link_lost();
    }

    fn suspended(&mut self, suspended: bool) {
        if suspended {
            softfinger_app::tick::note_link_lost();
        }
    }

    fn configured(&mut self, configured: bool) {
        if !configured {
            softfinger_app::tick::note_link_lost();
        }
    }
}

/// The USB device and its CDC-ACM function: VID/PID above, product "softfinger", bus-powered
/// 100 mA. `None` if called twice.
pub fn build(
    driver: UsbDriver,
) -> Option<(
    UsbDevice<'static, UsbDriver>,
    CdcAcmClass<'static, UsbDriver>,
)> {
    let mut config = embassy_usb::Config::new(USB_VID, USB_PID);
    config.manufacturer = Some("softfinger");
    config.product = Some("softfinger");
    config.serial_number = Some("1");
    config.max_power = 100;
    config.max_packet_size_0 = PACKET as u8;
    let config_descriptor = cortex_m::singleton!(: [u8; 128] = [0; 128])?;
    let bos_descriptor = cortex_m::singleton!(: [u8; 32] = [0; 32])?;
    let control = cortex_m::singleton!(: [u8; 64] = [0; 64])?;
    let state = cortex_m::singleton!(: State<'static> = State::new())?;
    let mut builder = Builder::new(
        driver,
        config,
        config_descriptor,
        bos_descriptor,
        &mut [],
        control,
    );
    let class = CdcAcmClass::new(&mut builder, state, PACKET as u16);
    let events = cortex_m::singleton!(: LinkEvents = LinkEvents)?;
    builder.handler(events);
    Some((builder.build(), class))
}

/// The link over `class`: read packets into the session, forward the tick's news, write the
/// session's bytes back in short packets. Reconnects forever.
pub async fn run<const TX: usize, S: Persistence>(
    mut class: CdcAcmClass<'static, UsbDriver>,
    mut session: LinkSession<TX, S>,
    mut commands: Producer<'static, CheckedCommand>,
    mut q: LinkQueues,
) -> ! {
    let mut rx = [0u8; PACKET];
    let mut tx = [0u8; TX_CHUNK];
    loop {
        class.wait_connection().await;
        let mut dtr = class.dtr();
        let mut last_taken = Instant::now();
        loop {
            // The host closed the port (DTR dropped): the link is lost.
            let now_dtr = class.dtr();
            if dtr && !now_dtr {
                softfinger_app::tick::note_link_lost();
            }
            dtr = now_dtr;
            match select(class.read_packet(&mut rx), Timer::after_millis(POLL_MS)).await {
                Either::First(Ok(n)) => {
                    for &b in &rx[..n] {
                        if session.receive(b, &mut commands) {
                            softfinger_app::tick::note_link_activity();
                        }
                    }
                }
                // Disconnected (or the host reset the endpoint): the link is lost; wait for the
                // next connection.
                Either::First(Err(_)) => {
                    softfinger_app::tick::note_link_lost();
                    break;
                }
                Either::Second(()) => {}
            }
            q.forward_news(&mut session);
            while !session.tx().is_empty() {
                let n = session.tx().pop_into(&mut tx);
                let sent = with_timeout(
                    Duration::from_millis(WRITE_TIMEOUT_MS),
                    class.write_packet(&tx[..n]),
                )
                .await;
                if matches!(sent, Ok(Ok(()))) {
                    last_taken = Instant::now();
                } else {
                    while session.tx().pop().is_some() {}
                    if last_taken.elapsed() >= Duration::from_millis(WRITE_STALL_MS) {
                        softfinger_app::tick::note_link_lost();
                    }
                    break;
                }
            }
            // An accepted Reboot (disarmed only): its answer has gone out above; reset, and the
            // bootloader swaps in an image an update marked.
            if session.take_reset_request() {
                Timer::after_millis(RESET_DELAY_MS).await;
                crate::board::stm32g474::emergency_stop();
                cortex_m::peripheral::SCB::sys_reset();
            }
        }
    }
}

/// After an accepted Reboot, how long the link waits for the host to take the answer, ms.
const RESET_DELAY_MS: u64 = 20;
