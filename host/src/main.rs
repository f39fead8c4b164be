//! `softfinger`: talk to a softfinger device or the virtual device. `softfinger --help`.

fn main() -> std::process::ExitCode {
    std::process::ExitCode::from(softfinger_host_cli::run(std::env::args_os()))
}

#[path = "cli/mod.rs"]
mod softfinger_host_cli;
