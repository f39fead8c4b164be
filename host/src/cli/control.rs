//! `info`, `arm`/`disarm`/`clear`, `scene set`.

use super::{connect, refusal};
use clap::Subcommand;
use softfinger_host::{Device, LinkError};
use std::time::Duration;

#[derive(Debug, Subcommand)]
pub enum SceneCmd {
    /// Render a scene's surface and contact parameters (a host-sim scene file or built-in name).
    Set {
        /// Scene TOML file (host-sim/scenes/*.toml) or built-in name.
        file: String,
    },
}

/// Connect and run `f` (the command `action`); a refusal names the device's mode and need.
pub fn simple(
    spec: &str,
    action: &str,
    f: impl FnOnce(&mut Device) -> Result<(), LinkError>,
) -> Result<(), String> {
    let mut d = connect(spec).map_err(|e| e.to_string())?;
    f(&mut d).map_err(|e| refusal::message(action, e, &mut d))?;
    println!("ok");
    Ok(())
}

/// `arm`: arm, then warn when the device's watchdog will let go once this process has left.
pub fn arm(spec: &str) -> Result<(), String> {
    let mut d = connect(spec).map_err(|e| e.to_string())?;
    d.arm().map_err(|e| refusal::message("arm", e, &mut d))?;
    let info = d.info().map_err(|e| e.to_string())?;
    println!("armed");
    if info.watchdog_ms != 0 {
        let others = d
            .counters()
            .map(|c| c.connections.saturating_sub(1))
            .unwrap_or(0);
        eprintln!(
            "warning: the device's watchdog ({} ms) fades the force to zero and latches comm-timeout once no connection talks to it; this command has ended ({others} other connection(s) open now). To hold the device armed use `softfinger session`, or arm on the recording's own link with `softfinger stream --arm`",
            info.watchdog_ms
        );
    }
    Ok(())
}

pub fn info(spec: &str, json: bool) -> Result<(), String> {
    let mut d = connect(spec).map_err(|e| e.to_string())?;
    let info = d.info().map_err(|e| e.to_string())?;
    let c = d.counters().map_err(|e| e.to_string())?;
    if json {
        let v = serde_json::json!({
            "name": info.name.as_str(),
            "firmware_version": info.firmware_version.as_str(),
            "protocol_version": info.protocol_version,
            "virtual_device": info.virtual_device,
            "control_rate_hz": info.control_rate_hz,
            "max_force_n": info.max_force_n,
            "min_stream_divisor": info.min_stream_divisor,
            "surfaces": info.surfaces.iter().map(|s| format!("{s:?}").to_lowercase()).collect::<Vec<_>>(),
            "watchdog_ms": info.watchdog_ms,
            "settings_flags": softfinger_protocol::info::settings_flag_names(info.settings_flags).collect::<Vec<_>>(),
            "reset_cause": info.reset_cause.as_str(),
            "link": {
                "rx_frames": c.rx_frames, "rx_errors": c.rx_errors, "rx_cobs": c.rx_cobs,
                "rx_crc": c.rx_crc, "rx_version": c.rx_version, "rx_decode": c.rx_decode,
                "rx_oversized": c.rx_oversized, "tx_frames": c.tx_frames,
                "tx_dropped": c.tx_dropped, "connections": c.connections,
            },
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
    } else {
        println!(
            "{} ({}, protocol {}{})",
            info.name,
            info.firmware_version,
            info.protocol_version,
            if info.virtual_device { ", virtual" } else { "" }
        );
        println!(
            "control {} Hz, force limit {} N, fastest stream {} Hz, watchdog {}",
            info.control_rate_hz,
            info.max_force_n,
            info.control_rate_hz / info.min_stream_divisor.max(1) as u32,
            if info.watchdog_ms == 0 {
                "off".to_string()
            } else {
                format!("{} ms", info.watchdog_ms)
            }
        );
        let surfaces: Vec<String> = info
            .surfaces
            .iter()
            .map(|s| format!("{s:?}").to_lowercase())
            .collect();
        println!("surfaces: {}", surfaces.join(", "));
        let flags: Vec<&str> =
            softfinger_protocol::info::settings_flag_names(info.settings_flags).collect();
        println!(
            "settings: {}; last reset: {}",
            if flags.is_empty() {
                "read from the store".to_string()
            } else {
                flags.join(", ")
            },
            info.reset_cause
        );
        println!(
            "link: rx_frames {} rx_errors {} (cobs {} crc {} version {} decode {} oversized {}), tx_frames {} tx_dropped {}, connections {}",
            c.rx_frames, c.rx_errors, c.rx_cobs, c.rx_crc, c.rx_version, c.rx_decode, c.rx_oversized,
            c.tx_frames, c.tx_dropped, c.connections
        );
    }
    Ok(())
}

/// The sequence number of the model the device renders now (from one state sample).
pub fn current_model_seq(d: &mut Device) -> Result<u32, LinkError> {
    d.set_stream(100)?;
    let s = d.next_state(Duration::from_secs(1))?;
    d.set_stream(0)?;
    s.map(|s| s.model_seq).ok_or(LinkError::Timeout)
}

pub fn scene(spec: &str, cmd: &SceneCmd) -> Result<(), String> {
    let SceneCmd::Set { file } = cmd;
    // Read and check the file before touching the device.
    softfinger_host::scene::load(file, 0)?;
    let mut d = connect(spec).map_err(|e| e.to_string())?;
    let seq = current_model_seq(&mut d)
        .map_err(|e| e.to_string())?
        .wrapping_add(1);
    let (params, model) = softfinger_host::scene::load(file, seq)?;
    let now = d.contact_params().map_err(|e| e.to_string())?;
    if now != params {
        d.set_contact_params(params)
            .map_err(|e| refusal::message("scene set", e, &mut d))?;
    }
    d.set_local_model(model).map_err(|e| e.to_string())?;
    println!("scene '{file}' set (model {seq})");
    Ok(())
}
