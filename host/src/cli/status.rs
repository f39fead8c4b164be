//! `status [--json]`: the device's mode, the local model in force, the flags of its last tick
//! and the faults it has latched.

use super::connect;
use host_sim::serve::log::shape;
use softfinger_host::flags;
use softfinger_host::protocol::{DeviceStatus, LocalModel};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// As JSON.
    #[arg(long)]
    pub json: bool,
}

/// The model in one line: kind and size, position (mm, base frame), material.
pub fn model_line(m: &LocalModel) -> String {
    let [x, y, z] = m.position_m;
    format!(
        "model {}: {} at ({:.1}, {:.1}, {:.1}) mm, {} N/m, {} N·s/m, mu_s {} mu_k {}, spin {} N·m/rad, max age {}",
        m.seq,
        shape(&m.shape),
        x * 1e3,
        y * 1e3,
        z * 1e3,
        m.stiffness_n_per_m,
        m.damping_n_s_per_m,
        m.mu_s,
        m.mu_k,
        m.spin_stiffness_nm_per_rad,
        if m.max_age_ms == 0 {
            "none".to_string()
        } else {
            format!("{} ms", m.max_age_ms)
        }
    )
}

/// One line per raised flag: name and meaning; `none` when there is none.
pub fn flag_lines(bits: u32) -> Vec<String> {
    let v: Vec<String> = flags::raised(bits)
        .map(|(n, m)| format!("{n}: {m}"))
        .collect();
    if v.is_empty() {
        vec!["none".into()]
    } else {
        v
    }
}

/// The status as text.
pub fn text(st: &DeviceStatus, rate_hz: u32) -> String {
    let mut out = format!(
        "mode {} at {:.3} s of device time\n{}\n",
        st.mode.name(),
        st.tick as f64 / f64::from(rate_hz.max(1)),
        model_line(&st.model)
    );
    for (title, bits) in [("flags", st.flags), ("latched faults", st.latched)] {
        let lines = flag_lines(bits);
        out += &format!("{title}: {}\n", lines.join("\n  "));
    }
    out
}

/// The status as JSON.
pub fn json(st: &DeviceStatus, rate_hz: u32) -> serde_json::Value {
    let names = |bits: u32| flags::raised(bits).map(|(n, _)| n).collect::<Vec<_>>();
    let m = &st.model;
    serde_json::json!({
        "mode": st.mode.name(),
        "tick": st.tick,
        "time_s": st.tick as f64 / f64::from(rate_hz.max(1)),
        "flags": names(st.flags),
        "latched": names(st.latched),
        "model": {
            "seq": m.seq,
            "shape": format!("{:?}", softfinger_host::protocol::SurfaceKind::of(&m.shape)).to_lowercase(),
            "radius_m": m.shape.radius_m(),
            "position_m": m.position_m,
            "orientation": m.orientation,
            "stiffness_n_per_m": m.stiffness_n_per_m,
            "damping_n_s_per_m": m.damping_n_s_per_m,
            "mu_s": m.mu_s,
            "mu_k": m.mu_k,
            "spin_stiffness_nm_per_rad": m.spin_stiffness_nm_per_rad,
            "max_age_ms": m.max_age_ms,
        },
    })
}

pub fn main(spec: &str, a: &Args) -> Result<(), String> {
    let mut d = connect(spec).map_err(|e| e.to_string())?;
    let rate = d.info().map_err(|e| e.to_string())?.control_rate_hz;
    let st = d.status().map_err(|e| format!("status: {e}"))?;
    if a.json {
        let v = json(&st, rate);
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
    } else {
        print!("{}", text(&st, rate));
    }
    Ok(())
}
