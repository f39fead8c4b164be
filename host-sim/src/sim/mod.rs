//! The simulated world the core runs against: the device and the user's hand ([`plant`]), the
//! closed loop that couples them to the one control pipeline ([`closed_loop`]), the independent
//! rolling references ([`reference`]), the scene files ([`scene`]), the math backends as a run-time
//! value ([`backend`]) and the seeded generator of the noisy experiments ([`rng`]).
//!
//! Nothing here is a command: the experiments, the virtual device and the processor-in-the-loop
//! host side build on these.

pub mod backend;
pub mod closed_loop;
pub mod plant;
pub mod reference;
pub mod rng;
pub mod scene;
