//! Independent high-accuracy reference for sphere rolling contact (the paper's §3.1 validation).

pub mod rk45;
