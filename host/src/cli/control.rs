//! `info`, `home`/`arm`/`disarm`/`clear`, `scene set`, `params set`.

use super::connect;
use clap::{Args as ClapArgs, Subcommand};
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

#[derive(Debug, Subcommand)]
pub enum ParamsCmd {
    /// Change some contact parameters (the others keep the device's values). Disarm first.
    Set(ParamsSet),
    /// Print the contact parameters in force.
    Get,
}

/// Fields to change; each optional.
#[derive(Debug, ClapArgs)]
pub struct ParamsSet {
    /// Normal stiffness, N/m.
    #[arg(long)]
    pub stiffness: Option<f32>,
    /// Normal damping, N·s/m.
    #[arg(long)]
    pub damping: Option<f32>,
    /// Static friction coefficient.
    #[arg(long)]
    pub mu_s: Option<f32>,
    /// Kinetic friction coefficient.
    #[arg(long)]
    pub mu_k: Option<f32>,
    /// Spin stiffness, N·m/rad.
    #[arg(long)]
    pub spin_stiffness: Option<f32>,
    /// Fingertip radius, m.
    #[arg(long)]
    pub fingertip_radius: Option<f32>,
    /// Tangential stiffness, N/m.
    #[arg(long)]
    pub tangential_stiffness: Option<f32>,
    /// Tangential damping, N·s/m.
    #[arg(long)]
    pub tangential_damping: Option<f32>,
    /// Force limit, N.
    #[arg(long)]
    pub max_force: Option<f32>,
}

pub fn simple(
    spec: &str,
    f: impl FnOnce(&mut Device) -> Result<(), LinkError>,
) -> Result<(), String> {
    let mut d = connect(spec).map_err(|e| e.to_string())?;
    f(&mut d).map_err(|e| e.to_string())?;
    println!("ok");
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
        d.set_contact_params(params).map_err(|e| match e {
            LinkError::Refused(softfinger_host::protocol::ErrorCode::WrongMode) => {
                "the scene changes contact parameters: disarm first".to_string()
            }
            e => e.to_string(),
        })?;
    }
    d.set_local_model(model).map_err(|e| e.to_string())?;
    println!("scene '{file}' set (model {seq})");
    Ok(())
}

pub fn params(spec: &str, cmd: &ParamsCmd) -> Result<(), String> {
    let mut d = connect(spec).map_err(|e| e.to_string())?;
    let mut p = d.contact_params().map_err(|e| e.to_string())?;
    let s = match cmd {
        ParamsCmd::Get => {
            println!("{p:#?}");
            return Ok(());
        }
        ParamsCmd::Set(s) => s,
    };
    let set = |field: &mut f32, v: Option<f32>| {
        if let Some(v) = v {
            *field = v;
        }
    };
    set(&mut p.normal_stiffness, s.stiffness);
    set(&mut p.normal_damping, s.damping);
    set(&mut p.mu_s, s.mu_s);
    set(&mut p.mu_k, s.mu_k);
    set(&mut p.spin_stiffness, s.spin_stiffness);
    set(&mut p.fingertip_radius_m, s.fingertip_radius);
    set(&mut p.tangential_stiffness, s.tangential_stiffness);
    set(&mut p.tangential_damping, s.tangential_damping);
    set(&mut p.max_force_n, s.max_force);
    d.set_contact_params(p).map_err(|e| e.to_string())?;
    println!("ok");
    Ok(())
}
