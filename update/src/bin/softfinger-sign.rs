//! `softfinger-sign`: make and check signed update files (`.sfu`) for `softfinger update FILE`.
//!
//! ```sh
//! # sign an image with the development key (anyone can: for development devices only)
//! cargo run -p softfinger-update --features sign --bin softfinger-sign -- \
//!     sign --key update/keys/dev-signing-key.hex --version 0.2.0 firmware.bin firmware.sfu
//! # a device maker's own key: generate once, keep the secret file private
//! softfinger-sign keygen --out maker-key.hex      # prints the public key
//! SOFTFINGER_UPDATE_PUBLIC_KEY=<that hex> cargo build ...   # firmware and bootloader trust it
//! ```

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use softfinger_update::package::{self, ImageTrailer, Package, FLAG_SIMULATE_SELF_TEST_FAILURE};

#[derive(Parser)]
#[command(
    name = "softfinger-sign",
    about = "Sign softfinger firmware images for an update over the host link"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Append the version trailer to IN (a raw binary image), sign it, write OUT (.sfu).
    Sign {
        /// The secret key: 64 hex digits (an ed25519 seed).
        #[arg(long)]
        key: PathBuf,
        /// The version the image reports (at most 23 bytes).
        #[arg(long)]
        version: String,
        /// Mark the image so the virtual device's self-test fails on it (to show a rollback).
        #[arg(long, hide = true)]
        fail_self_test: bool,
        /// The raw image (e.g. `arm-none-eabi-objcopy -O binary` of the firmware ELF).
        input: PathBuf,
        /// The update file to write.
        output: PathBuf,
    },
    /// Check FILE's signature against a public key (64 hex digits; default: the development key).
    Verify {
        /// The public key file; without it the development key.
        #[arg(long)]
        public_key: Option<PathBuf>,
        /// The update file.
        file: PathBuf,
    },
    /// Generate a key pair: the secret to OUT (refuses to overwrite), the public key printed.
    Keygen {
        /// Where to write the secret key.
        #[arg(long)]
        out: PathBuf,
    },
    /// Print the public key of a secret key.
    Pubkey {
        /// The secret key file.
        #[arg(long)]
        key: PathBuf,
    },
}

fn hex32(path: &Path) -> Result<[u8; 32], String> {
    let s = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let s = s.trim();
    if s.len() != 64 || !s.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(format!(
            "{}: expected 64 hex digits (a 32-byte key)",
            path.display()
        ));
    }
    Ok(softfinger_update::keys::parse_hex_key(s))
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|x| format!("{x:02x}")).collect()
}

/// Write `bytes` to `path` through a temporary file and a rename: never a half-written file.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let tmp = path.with_extension("sfu.tmp");
    std::fs::write(&tmp, bytes).map_err(|e| format!("{}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        format!("{}: {e}", path.display())
    })
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.cmd {
        Cmd::Sign {
            key,
            version,
            fail_self_test,
            input,
            output,
        } => {
            let seed = hex32(&key)?;
            let mut image =
                std::fs::read(&input).map_err(|e| format!("{}: {e}", input.display()))?;
            if image.is_empty() {
                return Err(format!("{}: empty image", input.display()));
            }
            let flags = if fail_self_test {
                FLAG_SIMULATE_SELF_TEST_FAILURE
            } else {
                0
            };
            let trailer = ImageTrailer::new(&version, flags)
                .map_err(|e| format!("--version {version:?}: {e}"))?;
            image.extend_from_slice(&trailer.to_bytes());
            let len = u32::try_from(image.len()).map_err(|_| "image over 4 GiB".to_string())?;
            let sig = package::sign(&image, &seed);
            let mut file = Package::header(len, &sig).to_vec();
            file.extend_from_slice(&image);
            write_atomic(&output, &file)?;
            println!(
                "{}: version {version}, image {len} bytes, signed by {}",
                output.display(),
                hex(&package::public_key(&seed))
            );
            Ok(())
        }
        Cmd::Verify { public_key, file } => {
            let pk = match public_key {
                Some(p) => hex32(&p)?,
                None => softfinger_update::keys::DEV_PUBLIC_KEY,
            };
            let bytes = std::fs::read(&file).map_err(|e| format!("{}: {e}", file.display()))?;
            let p = Package::parse(&bytes).map_err(|e| format!("{}: {e}", file.display()))?;
            if !package::verify(p.image, &p.signature, &pk) {
                return Err(format!(
                    "{}: the signature does not verify against {}",
                    file.display(),
                    hex(&pk)
                ));
            }
            println!(
                "{}: version {}, {} bytes, signature good",
                file.display(),
                p.trailer.version(),
                p.image.len()
            );
            Ok(())
        }
        Cmd::Keygen { out } => {
            if out.exists() {
                return Err(format!("{}: exists; not overwritten", out.display()));
            }
            let mut seed = [0u8; 32];
            let mut f =
                std::fs::File::open("/dev/urandom").map_err(|e| format!("/dev/urandom: {e}"))?;
            std::io::Read::read_exact(&mut f, &mut seed)
                .map_err(|e| format!("/dev/urandom: {e}"))?;
            std::fs::write(&out, format!("{}\n", hex(&seed)))
                .map_err(|e| format!("{}: {e}", out.display()))?;
            println!("{}", hex(&package::public_key(&seed)));
            Ok(())
        }
        Cmd::Pubkey { key } => {
            println!("{}", hex(&package::public_key(&hex32(&key)?)));
            Ok(())
        }
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("softfinger-sign: {e}");
            ExitCode::from(2)
        }
    }
}
