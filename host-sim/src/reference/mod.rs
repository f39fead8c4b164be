//! Independent high-accuracy reference for sphere rolling contact (the paper's §3.1 validation).

pub mod montana;
pub mod rk45;
pub mod surface;
