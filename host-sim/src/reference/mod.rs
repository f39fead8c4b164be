//! Independent high-accuracy reference for sphere rolling contact (the paper's §3.1 validation).

pub mod closed_form;
pub mod montana;
pub mod rk45;
pub mod scene;
pub mod surface;
