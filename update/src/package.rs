//! The update file (`.sfu`) and the version trailer at the end of every image.
//!
//! ```text
//! .sfu  = "SFU1" | image_len:u32 LE | signature:[u8; 64] | image
//! image = payload | trailer
//! trailer (32 bytes) = "SFVERSN\0" | version: 23 bytes UTF-8, NUL-padded | flags:u8
//! ```
//!
//! The signature is ed25519 over the SHA-512 of the whole image (trailer included), the message
//! embassy-boot's `verify_and_mark_updated` checks. The trailer tells the device's version before
//! and after an update, read from the active slot. Flag [`FLAG_SIMULATE_SELF_TEST_FAILURE`] is
//! for the virtual device only (which does not execute the image): its self-test fails on such an
//! image, so a rollback can be shown; the firmware ignores it.

/// The file's magic.
pub const MAGIC: &[u8; 4] = b"SFU1";
/// The trailer's magic.
pub const TRAILER_MAGIC: &[u8; 8] = b"SFVERSN\0";
/// The trailer's length, bytes.
pub const TRAILER_LEN: usize = 32;
/// The longest version string, bytes.
pub const VERSION_LEN: usize = 23;
/// The file header's length, bytes.
pub const HEADER_LEN: usize = 4 + 4 + 64;
/// Trailer flag: the virtual device's self-test fails on this image.
pub const FLAG_SIMULATE_SELF_TEST_FAILURE: u8 = 1;

/// Why a file or image was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PackageError {
    /// Not an update file (its first 4 bytes are not "SFU1").
    BadMagic,
    /// Shorter than its header, or than the image length its header states.
    Truncated {
        /// Bytes the header says the image has.
        expected: u32,
        /// Bytes there are.
        got: u32,
    },
    /// Longer than the header says (a file with something appended).
    TrailingBytes,
    /// The image has no version trailer.
    NoTrailer,
    /// The version does not fit the trailer or is not UTF-8.
    BadVersion,
}

impl core::fmt::Display for PackageError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            PackageError::BadMagic => write!(f, "not a softfinger update file (no SFU1 header)"),
            PackageError::Truncated { expected, got } => {
                write!(
                    f,
                    "truncated: the header says {expected} image bytes, the file has {got}"
                )
            }
            PackageError::TrailingBytes => write!(f, "bytes after the image the header describes"),
            PackageError::NoTrailer => write!(
                f,
                "the image has no version trailer (not made by softfinger-sign)"
            ),
            PackageError::BadVersion => write!(f, "the version is not UTF-8 of at most 23 bytes"),
        }
    }
}

/// An image's version trailer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageTrailer {
    version: [u8; VERSION_LEN],
    /// Flags (see the module doc).
    pub flags: u8,
}

impl ImageTrailer {
    /// A trailer for `version`.
    pub fn new(version: &str, flags: u8) -> Result<Self, PackageError> {
        let b = version.as_bytes();
        if b.len() > VERSION_LEN || b.contains(&0) || b.is_empty() {
            return Err(PackageError::BadVersion);
        }
        let mut v = [0u8; VERSION_LEN];
        v[..b.len()].copy_from_slice(b);
        Ok(Self { version: v, flags })
    }

    /// The version string.
    pub fn version(&self) -> &str {
        let n = self
            .version
            .iter()
            .position(|b| *b == 0)
            .unwrap_or(VERSION_LEN);
        core::str::from_utf8(&self.version[..n]).unwrap_or("?")
    }

    /// The 32 trailer bytes.
    pub fn to_bytes(&self) -> [u8; TRAILER_LEN] {
        let mut t = [0u8; TRAILER_LEN];
        t[..8].copy_from_slice(TRAILER_MAGIC);
        t[8..8 + VERSION_LEN].copy_from_slice(&self.version);
        t[TRAILER_LEN - 1] = self.flags;
        t
    }

    /// The trailer at the end of `image`.
    pub fn read(image: &[u8]) -> Result<Self, PackageError> {
        if image.len() < TRAILER_LEN {
            return Err(PackageError::NoTrailer);
        }
        let t = &image[image.len() - TRAILER_LEN..];
        if &t[..8] != TRAILER_MAGIC {
            return Err(PackageError::NoTrailer);
        }
        let mut version = [0u8; VERSION_LEN];
        version.copy_from_slice(&t[8..8 + VERSION_LEN]);
        let n = version.iter().position(|b| *b == 0).unwrap_or(VERSION_LEN);
        if n == 0
            || core::str::from_utf8(&version[..n]).is_err()
            || version[n..].iter().any(|b| *b != 0)
        {
            return Err(PackageError::BadVersion);
        }
        Ok(Self {
            version,
            flags: t[TRAILER_LEN - 1],
        })
    }
}

/// A parsed update file, borrowing its bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Package<'a> {
    /// The ed25519 signature over the image's SHA-512.
    pub signature: [u8; 64],
    /// The image (what goes into the active slot).
    pub image: &'a [u8],
    /// The image's trailer.
    pub trailer: ImageTrailer,
}

impl<'a> Package<'a> {
    /// Parse an update file.
    pub fn parse(file: &'a [u8]) -> Result<Self, PackageError> {
        if file.len() < 4 || &file[..4] != MAGIC {
            return Err(PackageError::BadMagic);
        }
        if file.len() < HEADER_LEN {
            return Err(PackageError::Truncated {
                expected: 0,
                got: file.len() as u32,
            });
        }
        let len = u32::from_le_bytes([file[4], file[5], file[6], file[7]]);
        let mut signature = [0u8; 64];
        signature.copy_from_slice(&file[8..HEADER_LEN]);
        let image = &file[HEADER_LEN..];
        let got = image.len() as u32;
        if got < len {
            return Err(PackageError::Truncated { expected: len, got });
        }
        if got > len {
            return Err(PackageError::TrailingBytes);
        }
        let trailer = ImageTrailer::read(image)?;
        Ok(Self {
            signature,
            image,
            trailer,
        })
    }

    /// The file's header for `image` and `signature` (the image follows it).
    pub fn header(image_len: u32, signature: &[u8; 64]) -> [u8; HEADER_LEN] {
        let mut h = [0u8; HEADER_LEN];
        h[..4].copy_from_slice(MAGIC);
        h[4..8].copy_from_slice(&image_len.to_le_bytes());
        h[8..].copy_from_slice(signature);
        h
    }
}

/// The message the signature covers: the image's SHA-512.
pub fn digest(image: &[u8]) -> [u8; 64] {
    use sha2::{Digest, Sha512};
    let mut out = [0u8; 64];
    out.copy_from_slice(&Sha512::digest(image));
    out
}

/// Sign `image` with the 32-byte ed25519 secret `seed` (what `softfinger-sign` does).
pub fn sign(image: &[u8], seed: &[u8; 32]) -> [u8; 64] {
    use ed25519_dalek::Signer;
    let key = ed25519_dalek::SigningKey::from_bytes(seed);
    key.sign(&digest(image)).to_bytes()
}

/// The public key of the secret `seed`.
pub fn public_key(seed: &[u8; 32]) -> [u8; 32] {
    ed25519_dalek::SigningKey::from_bytes(seed)
        .verifying_key()
        .to_bytes()
}

/// Check `signature` over `image` with `public_key` (what the host does before sending; the
/// device checks again over what it received).
pub fn verify(image: &[u8], signature: &[u8; 64], public_key: &[u8; 32]) -> bool {
    use ed25519_dalek::Verifier;
    let Ok(key) = ed25519_dalek::VerifyingKey::from_bytes(public_key) else {
        return false;
    };
    key.verify(
        &digest(image),
        &ed25519_dalek::Signature::from_bytes(signature),
    )
    .is_ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::keys::DEV_PUBLIC_KEY;

    const DEV_SEED: &str = include_str!("../keys/dev-signing-key.hex");

    fn seed() -> [u8; 32] {
        crate::keys::parse_hex_key(DEV_SEED.trim())
    }

    #[test]
    fn the_dev_key_files_agree() {
        assert_eq!(public_key(&seed()), DEV_PUBLIC_KEY);
        let pubhex = include_str!("../keys/dev-public-key.hex");
        assert_eq!(crate::keys::parse_hex_key(pubhex.trim()), DEV_PUBLIC_KEY);
    }

    #[test]
    fn a_file_round_trips_and_verifies() {
        let mut image = std::vec![0x5Au8; 1000];
        image.extend_from_slice(&ImageTrailer::new("0.2.0", 0).unwrap().to_bytes());
        let sig = sign(&image, &seed());
        let mut file = Package::header(image.len() as u32, &sig).to_vec();
        file.extend_from_slice(&image);
        let p = Package::parse(&file).unwrap();
        assert_eq!(p.trailer.version(), "0.2.0");
        assert!(verify(p.image, &p.signature, &DEV_PUBLIC_KEY));
        let mut bad = sig;
        bad[5] ^= 1;
        assert!(!verify(p.image, &bad, &DEV_PUBLIC_KEY));
        assert_eq!(
            Package::parse(&file[..file.len() - 1]),
            Err(PackageError::Truncated {
                expected: 1032,
                got: 1031
            })
        );
        file.push(0);
        assert_eq!(Package::parse(&file), Err(PackageError::TrailingBytes));
        assert_eq!(Package::parse(b"SFU0aaaa"), Err(PackageError::BadMagic));
    }

    #[test]
    fn versions_of_23_bytes_fit_24_do_not() {
        assert!(ImageTrailer::new(&"v".repeat(23), 0).is_ok());
        assert_eq!(
            ImageTrailer::new(&"v".repeat(24), 0),
            Err(PackageError::BadVersion)
        );
        assert_eq!(ImageTrailer::new("", 0), Err(PackageError::BadVersion));
    }
}
