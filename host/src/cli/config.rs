//! `softfinger config ...`: the device's persistent settings.

use super::connect;
use clap::Subcommand;
use softfinger_host::config::{diff, flatten, from_toml, set_dotted, to_json, to_toml};
use std::path::PathBuf;

#[derive(Debug, Subcommand)]
pub enum ConfigCmd {
    /// The settings in force and where they came from.
    Get {
        /// As JSON (its dotted paths are the keys of `config set`).
        #[arg(long)]
        json: bool,
    },
    /// Change fields of the settings in force (not saved): KEY=VALUE with KEY a dotted path.
    Set {
        /// `presets.2.friction=0.4 identity.name=bench-a ...`
        #[arg(required = true)]
        pairs: Vec<String>,
    },
    /// Write the settings in force to the device's flash (disarmed only).
    Save,
    /// Erase the device's store: the defaults are in force (and after a restart).
    Reset,
    /// Write the settings in force to a TOML file.
    Export {
        /// The file (written whole or not at all).
        file: PathBuf,
    },
    /// Read a TOML file, validate it, show what changes, and put it in force (then `config save`).
    Import {
        /// The file.
        file: PathBuf,
    },
}

pub fn main(spec: &str, cmd: &ConfigCmd) -> Result<(), String> {
    let mut d = connect(spec).map_err(|e| e.to_string())?;
    let err = |e: softfinger_host::LinkError| e.to_string();
    match cmd {
        ConfigCmd::Get { json } => {
            let c = d.config().map_err(err)?;
            if *json {
                let mut v = to_json(&c.settings);
                v["status"] = serde_json::json!({
                    "store": format!("{:?}", c.store),
                    "schema_version": c.schema_version,
                    "may_arm": c.may_arm,
                    "unsaved": c.unsaved,
                });
                println!(
                    "{}",
                    serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
                );
            } else {
                println!(
                    "store: {:?}, schema {}, may arm: {}, unsaved changes: {}",
                    c.store, c.schema_version, c.may_arm, c.unsaved
                );
                for (k, v) in flatten(&to_json(&c.settings)) {
                    println!("{k} = {v}");
                }
            }
            Ok(())
        }
        ConfigCmd::Set { pairs } => {
            let c = d.config().map_err(err)?;
            let mut next = c.settings.clone();
            for p in pairs {
                let (k, v) = p
                    .split_once('=')
                    .ok_or_else(|| format!("{p}: expected KEY=VALUE"))?;
                next = set_dotted(&next, k.trim(), v.trim())?;
            }
            d.config_apply(&c.settings, &next).map_err(err)?;
            for (k, a, b) in diff(&c.settings, &next) {
                println!("{k}: {a} -> {b}");
            }
            println!("in force, not saved (config save)");
            Ok(())
        }
        ConfigCmd::Save => {
            d.config_save().map_err(err)?;
            println!("saved");
            Ok(())
        }
        ConfigCmd::Reset => {
            d.config_reset().map_err(err)?;
            println!("store erased; defaults in force");
            Ok(())
        }
        ConfigCmd::Export { file } => {
            let c = d.config().map_err(err)?;
            let text = to_toml(&c.settings)?;
            let tmp = file.with_extension("toml.tmp");
            std::fs::write(&tmp, text).map_err(|e| format!("{}: {e}", tmp.display()))?;
            std::fs::rename(&tmp, file).map_err(|e| {
                let _ = std::fs::remove_file(&tmp);
                format!("{}: {e}", file.display())
            })?;
            println!("{}: settings written", file.display());
            Ok(())
        }
        ConfigCmd::Import { file } => {
            let text =
                std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
            let next = from_toml(&text).map_err(|e| format!("{}: {e}", file.display()))?;
            let c = d.config().map_err(err)?;
            let changes = diff(&c.settings, &next);
            for (k, a, b) in &changes {
                println!("{k}: {a} -> {b}");
            }
            d.config_apply(&c.settings, &next).map_err(err)?;
            println!(
                "{} fields changed, in force, not saved (config save)",
                changes.len()
            );
            Ok(())
        }
    }
}
