//! `params get [--json]` and `params set --FIELD VALUE ...`: the contact parameters the wire
//! carries, with their units. Setting is allowed in every mode (the device applies the new
//! values at its next tick; while armed the force ramps in again over the arming ramp, so a
//! change never steps the force). A value the device refuses comes back with the field and the
//! range it accepts, printed with the option that set it.

use super::connect;
use clap::{Args as ClapArgs, Subcommand};
use softfinger_host::error::range_text;
use softfinger_host::protocol::{ContactParamsWire, FieldRange};
use softfinger_host::LinkError;

#[derive(Debug, Subcommand)]
pub enum ParamsCmd {
    /// Change some contact parameters (the others keep the device's values). Allowed in every
    /// mode: applied at the next control tick; while armed the force ramps in again.
    Set(ParamsSet),
    /// Print the contact parameters in force, with units.
    Get {
        /// As JSON (field names as on the wire, values in the units listed under "units").
        #[arg(long)]
        json: bool,
    },
}

/// Fields to change: at least one.
#[derive(Debug, ClapArgs)]
#[group(required = true, multiple = true)]
pub struct ParamsSet {
    /// Normal stiffness, N/m.
    #[arg(long, allow_negative_numbers = true)]
    pub stiffness: Option<f32>,
    /// Normal damping, N·s/m.
    #[arg(long, allow_negative_numbers = true)]
    pub damping: Option<f32>,
    /// Static friction coefficient.
    #[arg(long, allow_negative_numbers = true)]
    pub mu_s: Option<f32>,
    /// Kinetic friction coefficient (at most the static one).
    #[arg(long, allow_negative_numbers = true)]
    pub mu_k: Option<f32>,
    /// Spin stiffness, N·m/rad.
    #[arg(long, allow_negative_numbers = true)]
    pub spin_stiffness: Option<f32>,
    /// Fingertip radius, m.
    #[arg(long, allow_negative_numbers = true)]
    pub fingertip_radius: Option<f32>,
    /// Tangential stiffness, N/m.
    #[arg(long, allow_negative_numbers = true)]
    pub tangential_stiffness: Option<f32>,
    /// Tangential damping, N·s/m.
    #[arg(long, allow_negative_numbers = true)]
    pub tangential_damping: Option<f32>,
    /// Force limit, N (at most the device's limit, `softfinger info`).
    #[arg(long, allow_negative_numbers = true)]
    pub max_force: Option<f32>,
}

/// One wire field: its name, the option that sets it, its unit.
pub struct Field {
    pub wire: &'static str,
    pub option: &'static str,
    pub unit: &'static str,
    pub get: fn(&ContactParamsWire) -> f32,
    pub set: fn(&mut ContactParamsWire, f32),
    pub arg: fn(&ParamsSet) -> Option<f32>,
}

/// Every field the wire carries, in the order `params get` prints them.
pub const FIELDS: [Field; 9] = [
    Field {
        wire: "normal_stiffness",
        option: "--stiffness",
        unit: "N/m",
        get: |p| p.normal_stiffness,
        set: |p, v| p.normal_stiffness = v,
        arg: |a| a.stiffness,
    },
    Field {
        wire: "normal_damping",
        option: "--damping",
        unit: "N·s/m",
        get: |p| p.normal_damping,
        set: |p, v| p.normal_damping = v,
        arg: |a| a.damping,
    },
    Field {
        wire: "mu_s",
        option: "--mu-s",
        unit: "",
        get: |p| p.mu_s,
        set: |p, v| p.mu_s = v,
        arg: |a| a.mu_s,
    },
    Field {
        wire: "mu_k",
        option: "--mu-k",
        unit: "",
        get: |p| p.mu_k,
        set: |p, v| p.mu_k = v,
        arg: |a| a.mu_k,
    },
    Field {
        wire: "spin_stiffness",
        option: "--spin-stiffness",
        unit: "N·m/rad",
        get: |p| p.spin_stiffness,
        set: |p, v| p.spin_stiffness = v,
        arg: |a| a.spin_stiffness,
    },
    Field {
        wire: "fingertip_radius_m",
        option: "--fingertip-radius",
        unit: "m",
        get: |p| p.fingertip_radius_m,
        set: |p, v| p.fingertip_radius_m = v,
        arg: |a| a.fingertip_radius,
    },
    Field {
        wire: "tangential_stiffness",
        option: "--tangential-stiffness",
        unit: "N/m",
        get: |p| p.tangential_stiffness,
        set: |p, v| p.tangential_stiffness = v,
        arg: |a| a.tangential_stiffness,
    },
    Field {
        wire: "tangential_damping",
        option: "--tangential-damping",
        unit: "N·s/m",
        get: |p| p.tangential_damping,
        set: |p, v| p.tangential_damping = v,
        arg: |a| a.tangential_damping,
    },
    Field {
        wire: "max_force_n",
        option: "--max-force",
        unit: "N",
        get: |p| p.max_force_n,
        set: |p, v| p.max_force_n = v,
        arg: |a| a.max_force,
    },
];

fn field(wire: &str) -> Option<&'static Field> {
    FIELDS.iter().find(|f| f.wire == wire)
}

fn with_unit(v: f32, unit: &str) -> String {
    if unit.is_empty() {
        format!("{v}")
    } else {
        format!("{v} {unit}")
    }
}

/// The message for a value the device refused: the option and value sent, the field and the
/// range it accepts, in the field's unit.
pub fn refused(r: &FieldRange, sent: &ContactParamsWire) -> String {
    match field(r.field.as_str()) {
        Some(f) => format!(
            "the device refused {} {}: {} must be within {}{}",
            f.option,
            (f.get)(sent),
            f.wire,
            range_text(r),
            if f.unit.is_empty() {
                String::new()
            } else {
                format!(" {}", f.unit)
            }
        ),
        None => format!(
            "the device refused {}: it must be within {}",
            r.field,
            range_text(r)
        ),
    }
}

/// The parameters as text, one per line: name, value with unit, the option that sets it.
pub fn text(p: &ContactParamsWire) -> String {
    FIELDS
        .iter()
        .map(|f| {
            format!(
                "{:<22} {:>14}   {}\n",
                f.wire,
                with_unit((f.get)(p), f.unit),
                f.option
            )
        })
        .collect()
}

/// The parameters as JSON: each wire field, and its unit under "units".
pub fn json(p: &ContactParamsWire) -> serde_json::Value {
    let mut values = serde_json::Map::new();
    let mut units = serde_json::Map::new();
    for f in &FIELDS {
        values.insert(f.wire.into(), serde_json::json!((f.get)(p)));
        units.insert(f.wire.into(), serde_json::json!(f.unit));
    }
    values.insert("units".into(), serde_json::Value::Object(units));
    serde_json::Value::Object(values)
}

pub fn main(spec: &str, cmd: &ParamsCmd) -> Result<(), String> {
    let mut d = connect(spec).map_err(|e| e.to_string())?;
    let now = d.contact_params().map_err(|e| e.to_string())?;
    let s = match cmd {
        ParamsCmd::Get { json: true } => {
            let v = json(&now);
            println!(
                "{}",
                serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
            );
            return Ok(());
        }
        ParamsCmd::Get { json: false } => {
            print!("{}", text(&now));
            return Ok(());
        }
        ParamsCmd::Set(s) => s,
    };
    let mut p = now;
    for f in &FIELDS {
        if let Some(v) = (f.arg)(s) {
            (f.set)(&mut p, v);
        }
    }
    let limit = d.info().map_err(|e| e.to_string())?.max_force_n;
    if let Some(v) = s.max_force {
        if v.is_nan() || v > limit {
            return Err(format!(
                "--max-force {v} N is above the device's force limit of {limit} N"
            ));
        }
    }
    match d.set_contact_params(p) {
        Ok(()) => {}
        Err(LinkError::Rejected { field, .. }) => return Err(refused(&field, &p)),
        Err(e) => return Err(format!("params set: {e}")),
    }
    for f in &FIELDS {
        if (f.arg)(s).is_some() {
            println!(
                "{} {} (was {})",
                f.wire,
                with_unit((f.get)(&p), f.unit),
                with_unit((f.get)(&now), f.unit)
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use softfinger_core::contact::params::ContactParams;

    #[test]
    fn a_refusal_names_the_option_the_field_and_its_range() {
        let mut p = ContactParamsWire::of(&ContactParams::DEFAULT);
        p.normal_stiffness = -100.0;
        let r = FieldRange::new("normal_stiffness", 0.0, false, 1e7);
        assert_eq!(
            refused(&r, &p),
            "the device refused --stiffness -100: normal_stiffness must be within [0, 10000000] N/m"
        );
        let r = FieldRange::new("mu_k", 0.0, true, 0.3);
        assert!(refused(&r, &p).ends_with("mu_k must be within (0, 0.3]"));
    }

    #[test]
    fn every_wire_field_is_listed_once_with_its_unit() {
        let p = ContactParamsWire::of(&ContactParams::DEFAULT);
        let t = text(&p);
        assert_eq!(t.lines().count(), 9);
        assert!(
            t.contains("normal_stiffness") && t.contains("2000 N/m"),
            "{t}"
        );
        let j = json(&p);
        assert_eq!(j["max_force_n"], 12.0);
        assert_eq!(j["units"]["max_force_n"], "N");
    }
}
