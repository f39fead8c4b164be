//! `softfinger update FILE`: a signed firmware update (made by `softfinger-sign sign`).

use super::connect;
use indicatif::{ProgressBar, ProgressStyle};
use softfinger_protocol::update::BootStateWire;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// The update file (.sfu).
    pub file: PathBuf,
    /// Testing: send the chunk at this offset once with a bad CRC (the device refuses it; it is
    /// sent again).
    #[arg(long, hide = true)]
    pub corrupt_chunk_at: Option<u32>,
}

pub fn main(spec: &str, a: &Args) -> Result<(), String> {
    let file = std::fs::read(&a.file).map_err(|e| format!("{}: {e}", a.file.display()))?;
    let mut d = connect(spec).map_err(|e| e.to_string())?;
    let bar = ProgressBar::new(0);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {bytes}/{total_bytes} {bytes_per_sec}")
            .map_err(|e| e.to_string())?,
    );
    let out = d
        .update(
            &file,
            |sent, total| {
                bar.set_length(u64::from(total));
                bar.set_position(u64::from(sent));
            },
            a.corrupt_chunk_at,
        )
        .map_err(|e| format!("{}: {e}", a.file.display()))?;
    bar.finish_and_clear();
    println!("before: {} ({:?})", out.before.version, out.before.boot);
    println!(
        "sent: {} ({} bytes, signature verified by the device){}",
        out.offered,
        file.len(),
        if out.resumed > 0 {
            format!(", resumed {} times", out.resumed)
        } else {
            String::new()
        }
    );
    println!("after: {} ({:?})", out.after.version, out.after.boot);
    if out.after.boot == BootStateWire::RolledBack || out.after.version.as_str() != out.offered {
        return Err(format!(
            "the new image failed its self-test and was rolled back; running {}",
            out.after.version
        ));
    }
    Ok(())
}
