//! host-sim: runs the softfinger core on a PC. `cargo run --release -p host-sim` runs the default
//! scene in closed loop; `host-sim --help` lists the commands.

fn main() -> std::process::ExitCode {
    std::process::ExitCode::from(host_sim::cli::run(std::env::args_os()))
}
