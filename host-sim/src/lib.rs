//! host-sim as a library: the commands, the plant model and the references, so the cross-crate
//! tests in `tests/` run them in-process.

pub mod atomic_file;
pub mod backend;
pub mod chart;
pub mod cli;
pub mod closed_loop;
pub mod creep;
pub mod error;
pub mod faults;
pub mod grasp;
pub mod hold_quantisation;
pub mod limit_path;
pub mod limit_surface_cmd;
pub mod model;
pub mod pil;
pub mod plant;
pub mod reference;
pub mod replay;
pub mod rng;
pub mod run;
pub mod scene;
pub mod serve;
pub mod stability;
pub mod validate;
