//! The commands that run the simulated world and report on it: each module is one `host-sim`
//! command (its `Args`, its `main` and what it prints or writes), built on [`crate::sim`] and
//! drawing with [`crate::chart`].

pub mod creep;
pub mod faults;
pub mod grasp;
pub mod limit_surface;
pub mod model;
pub mod replay;
pub mod run;
pub mod speed_accuracy;
pub mod stability;
pub mod validate;
