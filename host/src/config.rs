//! The device's persistent settings from the host: read them whole, change fields by their dotted
//! path (`presets.2.friction`, as [`to_json`] prints them), save, reset; export and import TOML.
//!
//! The device validates every change and refuses naming the key and the reason; the host checks
//! the same rules first ([`Settings::validate`]) so a bad value never reaches the link.

use crate::{Device, LinkError};
use serde_json::Value;
use softfinger_protocol::config::{ConfigSection, ConfigValue, StoreStatus};
use softfinger_protocol::{DeviceMsg, Request};
use softfinger_store::schema::PRESETS;
pub use softfinger_store::Settings;

/// The settings in force on the device and where they came from.
#[derive(Clone, Debug, PartialEq)]
pub struct DeviceConfig {
    /// The settings.
    pub settings: Settings,
    /// What the device's boot found in its store.
    pub store: StoreStatus,
    /// The schema version the device writes.
    pub schema_version: u16,
    /// Whether the store lets the device arm (false while it holds settings the device could not
    /// read, until they are saved over or erased).
    pub may_arm: bool,
    /// Changed since the last save.
    pub unsaved: bool,
}

fn refused(msg: DeviceMsg) -> LinkError {
    match msg {
        DeviceMsg::ConfigRefused { refusal, .. } => {
            LinkError::Context(format!("{}: {}", refusal.key, refusal.reason))
        }
        other => LinkError::Protocol(format!("{other:?}")),
    }
}

impl Device {
    /// One section.
    pub fn config_section(&mut self, section: ConfigSection) -> Result<ConfigValue, LinkError> {
        match self.request(Request::ConfigGet(section))? {
            DeviceMsg::Config { value, .. } => Ok(value),
            other => Err(refused(other)),
        }
    }

    /// Every section.
    pub fn config(&mut self) -> Result<DeviceConfig, LinkError> {
        let mut s = Settings::default();
        let ConfigValue::Status {
            store,
            schema_version,
            may_arm,
            unsaved,
        } = self.config_section(ConfigSection::Status)?
        else {
            return Err(LinkError::Protocol(
                "config status: unexpected section".into(),
            ));
        };
        let wrong = || LinkError::Protocol("config: a section answered with another".into());
        match self.config_section(ConfigSection::Identity)? {
            ConfigValue::Identity(v) => s.identity = v,
            _ => return Err(wrong()),
        }
        match self.config_section(ConfigSection::Calibration)? {
            ConfigValue::Calibration(v) => s.calibration = v,
            _ => return Err(wrong()),
        }
        for i in 0..PRESETS {
            match self.config_section(ConfigSection::Preset(i as u8))? {
                ConfigValue::Preset { preset, .. } => s.presets[i] = preset,
                _ => return Err(wrong()),
            }
        }
        match self.config_section(ConfigSection::Stream)? {
            ConfigValue::Stream(v) => s.stream = v,
            _ => return Err(wrong()),
        }
        match self.config_section(ConfigSection::Watchdog)? {
            ConfigValue::Watchdog(v) => s.watchdog = v,
            _ => return Err(wrong()),
        }
        Ok(DeviceConfig {
            settings: s,
            store,
            schema_version,
            may_arm,
            unsaved,
        })
    }

    /// Put `next` in force on the device, sending only the sections that differ from `current`.
    pub fn config_apply(&mut self, current: &Settings, next: &Settings) -> Result<(), LinkError> {
        next.validate()
            .map_err(|e| LinkError::Context(e.to_string()))?;
        let mut values = Vec::new();
        if next.identity != current.identity {
            values.push(ConfigValue::Identity(next.identity.clone()));
        }
        if next.calibration != current.calibration {
            values.push(ConfigValue::Calibration(next.calibration.clone()));
        }
        for i in 0..PRESETS {
            if next.presets[i] != current.presets[i] {
                values.push(ConfigValue::Preset {
                    index: i as u8,
                    preset: next.presets[i].clone(),
                });
            }
        }
        if next.stream != current.stream {
            values.push(ConfigValue::Stream(next.stream));
        }
        if next.watchdog != current.watchdog {
            values.push(ConfigValue::Watchdog(next.watchdog));
        }
        for v in values {
            match self.request(Request::ConfigSet(v))? {
                DeviceMsg::Ack { .. } => {}
                other => return Err(refused(other)),
            }
        }
        Ok(())
    }

    /// Write the settings in force to the device's flash.
    pub fn config_save(&mut self) -> Result<(), LinkError> {
        match self.request(Request::ConfigSave)? {
            DeviceMsg::Ack { .. } => Ok(()),
            other => Err(refused(other)),
        }
    }

    /// Erase the device's store; the defaults are in force.
    pub fn config_reset(&mut self) -> Result<(), LinkError> {
        match self.request(Request::ConfigReset)? {
            DeviceMsg::Ack { .. } => Ok(()),
            other => Err(refused(other)),
        }
    }
}

/// The settings as JSON (the dotted paths of `config set` are its keys, array indices included).
pub fn to_json(s: &Settings) -> Value {
    serde_json::to_value(s).unwrap_or(Value::Null)
}

/// Every leaf as `(dotted path, value)`, in order.
pub fn flatten(v: &Value) -> Vec<(String, Value)> {
    fn walk(prefix: &str, v: &Value, out: &mut Vec<(String, Value)>) {
        let key = |k: &str| {
            if prefix.is_empty() {
                k.to_string()
            } else {
                format!("{prefix}.{k}")
            }
        };
        match v {
            Value::Object(m) => m.iter().for_each(|(k, x)| walk(&key(k), x, out)),
            Value::Array(a) => a
                .iter()
                .enumerate()
                .for_each(|(i, x)| walk(&key(&i.to_string()), x, out)),
            leaf => out.push((prefix.to_string(), leaf.clone())),
        }
    }
    let mut out = Vec::new();
    walk("", v, &mut out);
    out
}

/// `settings` with `key` (a dotted path) set to `value` (a JSON literal, or else a string).
/// Errors name the key and why: unknown, wrong type, out of range.
pub fn set_dotted(settings: &Settings, key: &str, value: &str) -> Result<Settings, String> {
    let mut json = to_json(settings);
    let mut node = &mut json;
    for part in key.split('.') {
        node = match node {
            Value::Object(m) => m.get_mut(part),
            Value::Array(a) => part.parse::<usize>().ok().and_then(|i| a.get_mut(i)),
            Value::Null if !part.is_empty() => {
                return Err(format!(
                    "{key}: unknown key (its section is empty: set the whole section)"
                ));
            }
            _ => None,
        }
        .ok_or_else(|| format!("{key}: unknown key (`config get --json` lists the keys)"))?;
    }
    if node.is_object() || node.is_array() {
        return Err(format!(
            "{key}: not a field but a section; name one of its fields"
        ));
    }
    let parsed: Value =
        serde_json::from_str(value).unwrap_or_else(|_| Value::String(value.to_string()));
    *node = parsed;
    let next: Settings = serde_json::from_value(json)
        .map_err(|e| format!("{key}: {value:?} is not a valid value ({e})"))?;
    next.validate().map_err(|e| e.to_string())?;
    Ok(next)
}

/// The fields that differ, as `(key, before, after)`.
pub fn diff(before: &Settings, after: &Settings) -> Vec<(String, String, String)> {
    let a = flatten(&to_json(before));
    let b = flatten(&to_json(after));
    let mut out = Vec::new();
    for (k, vb) in &b {
        let va = a
            .iter()
            .find(|(ka, _)| ka == k)
            .map(|(_, v)| v.to_string())
            .unwrap_or_else(|| "-".into());
        let vb = vb.to_string();
        if va != vb {
            out.push((k.clone(), va, vb));
        }
    }
    for (k, va) in &a {
        if !b.iter().any(|(kb, _)| kb == k) {
            out.push((k.clone(), va.to_string(), "-".into()));
        }
    }
    out
}

/// The settings as TOML (what `config export` writes).
pub fn to_toml(s: &Settings) -> Result<String, String> {
    toml::to_string(s).map_err(|e| format!("cannot write TOML: {e}"))
}

/// Settings from TOML (what `config import` reads), validated.
pub fn from_toml(text: &str) -> Result<Settings, String> {
    let s: Settings = toml::from_str(text).map_err(|e| e.to_string())?;
    s.validate().map_err(|e| e.to_string())?;
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dotted_paths_set_fields_and_name_bad_keys() {
        let s = Settings::default();
        let t = set_dotted(&s, "presets.2.friction", "0.3").unwrap();
        assert_eq!(t.presets[2].friction, 0.3);
        assert_eq!(diff(&s, &t).len(), 1);
        let t = set_dotted(&s, "identity.name", "bench-a").unwrap();
        assert_eq!(t.identity.name.as_str(), "bench-a");
        assert!(set_dotted(&s, "presets.9.friction", "0.3")
            .unwrap_err()
            .contains("unknown key"));
        assert!(set_dotted(&s, "nope", "1")
            .unwrap_err()
            .starts_with("nope: unknown key"));
        assert!(set_dotted(&s, "presets", "1")
            .unwrap_err()
            .contains("section"));
        assert_eq!(
            set_dotted(&s, "presets.2.friction", "2.5").unwrap_err(),
            "presets.2.friction: out of range"
        );
        assert!(set_dotted(&s, "watchdog.timeout_ms", "x")
            .unwrap_err()
            .starts_with("watchdog.timeout_ms:"));
    }

    #[test]
    fn toml_round_trips_and_refuses_out_of_range() {
        let mut s = Settings::default();
        s.identity.serial = 7;
        let text = to_toml(&s).unwrap();
        assert_eq!(from_toml(&text).unwrap(), s);
        let bad = text.replace("timeout_ms = 200", "timeout_ms = 5");
        assert!(from_toml(&bad)
            .unwrap_err()
            .starts_with("watchdog.timeout_ms"));
    }
}
