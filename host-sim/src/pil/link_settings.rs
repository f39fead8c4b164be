//! `--link-check`'s settings stage: the firmware's settings store (`softfinger_app::persist`, over
//! the emulated board's flash with the STM32G474's pages and write unit) through the host link,
//! and the tick meanwhile: a blank store at power-on, a change, a save (the tick's statistics in
//! the samples streamed during it: no overrun, within the period), the change read back as saved,
//! the device info's settings flags; and, once armed, a save refused naming why.

use super::link_client::{Client, LinkError, ANSWER_TIMEOUT};
use super::link_report::LinkReport;
use softfinger_protocol::config::{ConfigSection, ConfigValue, StoreStatus};
use softfinger_protocol::{AckResult, DeviceMsg, Request};
use softfinger_store::boot::{FLAG_ABSENT, FLAG_DEFAULTS, FLAG_NO_CALIBRATION};

/// The name the stage saves.
const NAME: &str = "pil-board";

/// A settings request's answer.
fn answer(c: &mut Client, req: Request) -> Result<DeviceMsg, LinkError> {
    let seq = c.request(req)?;
    loop {
        match c.next(ANSWER_TIMEOUT)? {
            m @ (DeviceMsg::Config { seq: s, .. }
            | DeviceMsg::ConfigRefused { seq: s, .. }
            | DeviceMsg::Ack { seq: s, .. }
            | DeviceMsg::Info { seq: s, .. })
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
