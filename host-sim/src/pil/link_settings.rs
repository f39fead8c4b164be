//! `--link-check`'s settings stage: the firmware's settings store (`softfinger_app::persist`, over
//! the emulated board's flash with the STM32G474's pages and write unit) through the host link,
//! and the tick meanwhile: a blank store at power-on, a change, a save (the tick's statistics in
//! the samples streamed during it: no overrun, within the period), the change read back as saved,
//! the device info's settings flags; and, once armed, a save refused naming why.

use super::link_client::{Client, LinkError, ANSWER_TIMEOUT};
use super::link_report::LinkReport;
use softfinger_protocol::config::{ConfigSection, ConfigValue, StoreStatus};
use softfinger_protocol::{AckResult, DeviceMsg, Request, StateSample};
use softfinger_store::boot::{FLAG_ABSENT, FLAG_DEFAULTS, FLAG_NO_CALIBRATION};

/// The name the stage saves.
const NAME: &str = "pil-board";

/// A settings or update request's answer (other messages, the stream's, are passed over).
fn answer(c: &mut Client, req: Request) -> Result<DeviceMsg, LinkError> {
    let seq = c.request(req)?;
    loop {
        match c.next(ANSWER_TIMEOUT)? {
            m @ (DeviceMsg::Config { seq: s, .. }
            | DeviceMsg::ConfigRefused { seq: s, .. }
            | DeviceMsg::Ack { seq: s, .. }
            | DeviceMsg::Info { seq: s, .. }
            | DeviceMsg::Update { seq: s, .. }
            | DeviceMsg::UpdateRefused { seq: s, .. })
                if s == seq =>
            {
                return Ok(m)
            }
            _ => {}
        }
    }
}

/// The settings flags the device info reports.
fn settings_flags(c: &mut Client) -> Result<u8, LinkError> {
    match answer(c, Request::GetInfo)? {
        DeviceMsg::Info { info, .. } => Ok(info.settings_flags),
        other => Err(LinkError::unexpected("device info", &other)),
    }
}

/// The tick's figures in the samples `during` a flash operation that began after the sample
/// at `first_tick`: every sample without an overrun and within the period, the longest tick
/// (ns), and the board time the window spans (ticks).
fn tick_window(during: &[StateSample], first_tick: Option<u64>, rate_hz: u32) -> (bool, u32, u64) {
    let period_ns = 1e9 / f64::from(rate_hz);
    let calm = during
        .iter()
        .all(|s| s.tick_stats.overruns == 0 && f64::from(s.tick_stats.max_duration_ns) < period_ns);
    let longest = during
        .iter()
        .map(|s| s.tick_stats.max_duration_ns)
        .max()
        .unwrap_or(0);
    let ticks = first_tick
        .zip(during.last().map(|s| s.tick))
        .map_or(0, |(a, b)| b.saturating_sub(a));
    (calm, longest, ticks)
}

/// Before homing: blank store, change, save with the tick's figures meanwhile, read back.
pub(super) fn check_disarmed(
    c: &mut Client,
    rate_hz: u32,
    r: &mut LinkReport,
) -> Result<(), LinkError> {
    let status = answer(c, Request::ConfigGet(ConfigSection::Status))?;
    r.check(
        "settings: a blank store at power-on (defaults, absent)",
        matches!(
            status,
            DeviceMsg::Config {
                value: ConfigValue::Status {
                    store: StoreStatus::Absent,
                    unsaved: false,
                    ..
                },
                ..
            }
        ),
        format!("{status:?}"),
    );
    let flags = settings_flags(c)?;
    r.check(
        "settings: device info flags defaults, absent, no calibration",
        flags == FLAG_DEFAULTS | FLAG_ABSENT | FLAG_NO_CALIBRATION,
        format!("{flags:#x}"),
    );
    let mut identity = softfinger_store::Settings::default().identity;
    identity.name = heapless::String::try_from(NAME).unwrap_or_default();
    let set = answer(
        c,
        Request::ConfigSet(ConfigValue::Identity(identity.clone())),
    )?;
    r.check(
        "settings: a change accepted",
        matches!(
            set,
            DeviceMsg::Ack {
                result: AckResult::Ok,
                ..
            }
        ),
        format!("{set:?}"),
    );
    let before = c.states.len();
    let first_tick = c.states.last().map(|s| s.tick);
    let saved = answer(c, Request::ConfigSave)?;
    // The samples streamed while the link task wrote the flash, and the next one after.
    c.wait_states(c.states.len() + 1)?;
    let during = &c.states[before..];
    let period_ns = 1e9 / f64::from(rate_hz);
    let (calm, longest, ticks) = tick_window(during, first_tick, rate_hz);
    r.check(
        "settings: saved, the tick running meanwhile (no overrun, every sample within the period)",
        matches!(saved, DeviceMsg::Ack { result: AckResult::Ok, .. }) && calm && !during.is_empty(),
        format!(
            "{saved:?}; {} samples from the request to the answer and one after ({ticks} ticks of board time), longest tick {longest} ns of {period_ns:.0} ns",
            during.len()
        ),
    );
    let back = answer(c, Request::ConfigGet(ConfigSection::Identity))?;
    r.check(
        "settings: the change reads back",
        matches!(&back, DeviceMsg::Config { value: ConfigValue::Identity(i), .. } if *i == identity),
        format!("{back:?}"),
    );
    let status = answer(c, Request::ConfigGet(ConfigSection::Status))?;
    let flags = settings_flags(c)?;
    r.check(
        "settings: read from the store now, nothing unsaved; flags: no calibration only",
        matches!(
            status,
            DeviceMsg::Config {
                value: ConfigValue::Status {
                    store: StoreStatus::Read,
                    unsaved: false,
                    ..
                },
                ..
            }
        ) && flags == FLAG_NO_CALIBRATION,
        format!("{status:?}, flags {flags:#x}"),
    );
    Ok(())
}

/// Once armed: a save is refused, naming the store and why.
pub(super) fn check_armed(c: &mut Client, r: &mut LinkReport) -> Result<(), LinkError> {
    let saved = answer(c, Request::ConfigSave)?;
    r.check(
        "settings: a save while armed is refused, naming why",
        matches!(&saved, DeviceMsg::ConfigRefused { refusal, .. }
            if refusal.key.as_str() == "store" && refusal.reason.contains("armed")),
        format!("{saved:?}"),
    );
    Ok(())
}

/// A 3 000-byte image with a version trailer, signed with the development key (`sign_with`:
/// another key's seed gives a signature the board must refuse).
fn signed_image(sign_with: &[u8; 32]) -> (Vec<u8>, [u8; 64]) {
    let mut x: u32 = 0x9E37_79B9;
    let mut img: Vec<u8> = (0..3000)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x as u8
        })
        .collect();
    if let Ok(t) = softfinger_update::package::ImageTrailer::new("pil 9.9.9", 0) {
        img.extend_from_slice(&t.to_bytes());
    }
    let sig = softfinger_update::package::sign(&img, sign_with);
    (img, sig)
}

/// The development key's secret (public in the repository, `update/keys`).
fn dev_seed() -> [u8; 32] {
    softfinger_update::keys::parse_hex_key(
        include_str!("../../../update/keys/dev-signing-key.hex").trim(),
    )
}

/// Send `img` with `sig`: begin, every chunk with its CRC; returns the finish's answer.
fn send_update(c: &mut Client, img: &[u8], sig: &[u8; 64]) -> Result<DeviceMsg, LinkError> {
    use softfinger_protocol::update::{UpdateChunk, UPDATE_CHUNK_LEN};
    let signature = heapless::Vec::from_slice(sig).unwrap_or_default();
    let begun = answer(
        c,
        Request::UpdateBegin {
            len: img.len() as u32,
            signature,
        },
    )?;
    if !matches!(begun, DeviceMsg::Update { .. }) {
        return Ok(begun);
    }
    for (i, data) in img.chunks(UPDATE_CHUNK_LEN).enumerate() {
        let chunk = UpdateChunk {
            offset: (i * UPDATE_CHUNK_LEN) as u32,
            crc: softfinger_update::session::chunk_crc(data),
            data: heapless::Vec::from_slice(data).unwrap_or_default(),
        };
        let r = answer(c, Request::UpdateChunk(chunk))?;
        if !matches!(r, DeviceMsg::Update { .. }) {
            return Ok(r);
        }
    }
    answer(c, Request::UpdateFinish)
}

/// Before homing: an update signed with another key is refused at the finish; one signed with
/// the development key is verified and marked, the tick running meanwhile (the ed25519 check
/// over the image's SHA-512 runs on the emulated Cortex-M4F, in the link task).
pub(super) fn check_update(
    c: &mut Client,
    rate_hz: u32,
    r: &mut LinkReport,
) -> Result<u64, LinkError> {
    use softfinger_protocol::update::{UpdatePhase, UpdateRefusal};
    let other_key = [7u8; 32];
    let (img, bad) = signed_image(&other_key);
    let refused = send_update(c, &img, &bad)?;
    r.check(
        "update: an image signed with another key is refused at the finish",
        matches!(
            refused,
            DeviceMsg::UpdateRefused {
                refusal: UpdateRefusal::BadSignature,
                ..
            }
        ),
        format!("{refused:?}"),
    );
    let (img, good) = signed_image(&dev_seed());
    let before = c.states.len();
    let first_tick = c.states.last().map(|s| s.tick);
    let done = send_update(c, &img, &good)?;
    // The stream's backlog of the busy time drains after the answer: 100 samples more.
    c.wait_states(c.states.len() + 100)?;
    let during = &c.states[before..];
    let period_ns = 1e9 / f64::from(rate_hz);
    let (calm, longest, ticks) = tick_window(during, first_tick, rate_hz);
    let calm = calm && during.iter().all(|s| s.flags == 0);
    // The link task is blocked while it writes and checks: the samples the tick could not
    // queue are lost, and the next sample sent says how many.
    let divisor = during
        .windows(2)
        .map(|w| w[1].tick - w[0].tick)
        .min()
        .unwrap_or(1)
        .max(1);
    let missing: u64 = during
        .windows(2)
        .map(|w| (w[1].tick - w[0].tick) / divisor - 1)
        .sum();
    let counted = match (c.states[..before].last(), during.last()) {
        (Some(a), Some(b)) => u64::from(b.dropped.saturating_sub(a.dropped)),
        _ => 0,
    };
    r.check(
        "update: the samples lost while the link task was busy are the ones counted as dropped",
        missing == counted,
        format!("{missing} missing between the samples received, {counted} counted by the board"),
    );
    r.check(
        "update: a signed image verified and marked on the board, the tick running meanwhile (no overrun, no flag)",
        matches!(&done, DeviceMsg::Update { status, .. } if status.phase == UpdatePhase::Verified) && calm,
        format!(
            "{done:?}; {} samples over the transfer, the check and 100 after ({ticks} ticks of board time), longest tick {longest} ns of {period_ns:.0} ns, flags seen {:#x}",
            during.len(),
            during.iter().fold(0, |a, s| a | s.flags)
        ),
    );
    Ok(during.last().map_or(0, |s| s.tick))
}
