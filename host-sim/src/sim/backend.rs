//! The core's math backends as one run-time value: parsed on the command line (clap), written in
//! JSON and tables by the core's own names (`libm`, `fast`, `micromath`), and dispatched to the
//! core's static types ([`Libm`], [`Fast`], [`Micromath`]) with [`dispatch!`](crate::sim::backend::dispatch).

use softfinger_core::{Fast, Libm, Math, Micromath};

/// A math backend of the core, chosen at run time here (the core itself dispatches statically).
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    clap::ValueEnum,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
#[value(rename_all = "lowercase")]
pub enum Backend {
    /// [`Libm`].
    Libm,
    /// [`Fast`].
    Fast,
    /// [`Micromath`].
    Micromath,
}

impl Backend {
    /// All backends, in table order.
    pub const ALL: [Backend; 3] = [Backend::Libm, Backend::Fast, Backend::Micromath];

    /// The backend's own name ([`Math::NAME`]): `libm`, `fast`, `micromath`.
    pub const fn name(self) -> &'static str {
        match self {
            Backend::Libm => Libm::NAME,
            Backend::Fast => Fast::NAME,
            Backend::Micromath => Micromath::NAME,
        }
    }
}

impl std::fmt::Display for Backend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

/// A core math type with its [`Backend`] value, so generic code can label its results.
pub trait MathBackend: Math {
    /// This type's backend.
    const BACKEND: Backend;
}

impl MathBackend for Libm {
    const BACKEND: Backend = Backend::Libm;
}
impl MathBackend for Fast {
    const BACKEND: Backend = Backend::Fast;
}
impl MathBackend for Micromath {
    const BACKEND: Backend = Backend::Micromath;
}

/// Evaluate `$body` with the type alias `$m` set to the core type of backend `$b`:
/// `dispatch!(b, M => run::<M>(x))`.
macro_rules! dispatch {
    ($b:expr, $m:ident => $body:expr) => {
        match $b {
            $crate::sim::backend::Backend::Libm => {
                type $m = softfinger_core::Libm;
                $body
            }
            $crate::sim::backend::Backend::Fast => {
                type $m = softfinger_core::Fast;
                $body
            }
            $crate::sim::backend::Backend::Micromath => {
                type $m = softfinger_core::Micromath;
                $body
            }
        }
    };
}
pub(crate) use dispatch;

#[cfg(test)]
mod tests {
    use super::*;

    /// The names are the core's, in JSON and on the command line, and each type maps back to its
    /// value.
    #[test]
    fn names_match_the_core_in_json_and_on_the_command_line() {
        use clap::ValueEnum;
        for b in Backend::ALL {
            assert_eq!(
                serde_json::to_string(&b).unwrap(),
                format!("\"{}\"", b.name())
            );
            assert_eq!(Backend::from_str(b.name(), false), Ok(b));
            assert_eq!(dispatch!(b, M => <M as MathBackend>::BACKEND), b);
            assert_eq!(dispatch!(b, M => M::NAME), b.name());
        }
        assert!(Backend::from_str("sse", false).is_err());
    }
}
