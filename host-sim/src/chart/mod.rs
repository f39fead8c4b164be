//! Charts: the one chart style of every SVG host-sim writes ([`style`], with the line charts of
//! [`lines`], [`bars`] and [`heatmap`] built on it) and the `index.html` every command with charts
//! writes ([`index_page`]). The commands draw their own charts with these
//! ([`crate::experiments`]; `host-sim chart`'s in [`crate::experiments::speed_accuracy`]).

pub mod bars;
pub mod heatmap;
pub mod index_page;
pub mod lines;
pub mod style;
