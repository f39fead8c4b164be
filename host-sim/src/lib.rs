//! host-sim as a library: the simulated device and hand, the commands that run them, the virtual
//! device and the processor-in-the-loop host side, so the cross-crate tests in `tests/` and the
//! host command line run them in-process. `main.rs` only calls [`cli::run`].
//!
//! | module | what it holds |
//! | --- | --- |
//! | [`sim`] | the model and plant: the delta device, motors, bridges, 16-bit counters and the scripted hand ([`sim::plant`]); the closed loop of the core's pipeline against it ([`sim::closed_loop`]); the RK45 / Montana rolling references ([`sim::reference`]); scene files, math backends, the seeded generator |
//! | [`experiments`] | one module per command that runs the simulated world: [`run`](experiments::run) (the default, with its charts and limit-surface path), [`replay`](experiments::replay), [`validate`](experiments::validate), [`speed_accuracy`](experiments::speed_accuracy) (`chart`), [`stability`](experiments::stability), [`creep`](experiments::creep), [`faults`](experiments::faults) (and `soak`), [`model`](experiments::model) (the model ablation), [`grasp`](experiments::grasp), [`limit_surface`](experiments::limit_surface) |
//! | [`serve`] | the virtual device (`host-sim serve`): the pipeline against the plant in real time, speaking the host protocol over TCP |
//! | [`pil`] | the processor-in-the-loop host side (`host-sim pil`, `pil-decode`): the firmware on the emulated Cortex-M4F in lock step with the plant |
//! | [`chart`] | the one chart style, its line, bar and heat-map charts, and the `index.html` page the commands write |
//! | [`cli`] | the command line: parsing and dispatch to the modules above |
//! | [`error`], [`atomic_file`] | the error types every command shares; files written whole or not at all |
//!
//! Imports point one way, down this order: `cli` -> `pil`, `serve`, `experiments` -> `chart` ->
//! `sim` (`pil` reads `experiments::replay`'s CSV header, `serve` only `sim`); no file imports
//! one that imports it back (`scripts/import-loops host-sim/src`).

pub mod atomic_file;
pub mod chart;
pub mod cli;
pub mod error;
pub mod experiments;
pub mod pil;
pub mod serve;
pub mod sim;
