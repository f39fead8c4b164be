//! `host-sim serve`: the virtual device. The device core runs against the plant in real time and
//! speaks the softfinger protocol over TCP to any number of clients at once, so applications are
//! written and tested without hardware.
//!
//! Threads: one device loop ([`device::DeviceLoop`]), one acceptor, and a reader and a writer per
//! connection ([`link`]). Connections hand their bytes to the device loop through one event
//! channel; the device loop holds the protocol's device side of each connection
//! (`softfinger_protocol::DeviceEndpoint`, as the firmware's link does: it decodes the frames,
//! counts them and their errors, answers hello and the stream divisor) and answers through each
//! connection's bounded queue. A client that sends garbage gets its bad frames counted and
//! answered; a client that stops reading loses state samples (counted); neither affects the other
//! clients or the tick.

pub mod core;
pub mod device;
pub mod hand;
pub mod link;
pub mod log;
pub mod persist;

use crate::sim::scene::Scene;
use clap::Parser;
use softfinger_core::contact::{ModelChoice, Parts};
use std::net::{Shutdown, TcpStream};
use std::net::{SocketAddr, TcpListener};
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::mpsc::channel;
use std::sync::{Arc, Mutex};
use std::thread::{self, JoinHandle};
use std::time::Duration;

/// `host-sim serve` arguments.
#[derive(Clone, Debug, Parser)]
pub struct Args {
    /// Address to listen on (port 0: any free port, printed).
    #[arg(long, default_value = "127.0.0.1:7700")]
    pub listen: String,
    /// Scene (built-in name or TOML file): the initial surface, contact parameters, control rate
    /// and the hand's script.
    #[arg(long, default_value = "finger-on-plane")]
    pub scene: String,
    /// Blend time of local model switches, ms.
    #[arg(long, default_value_t = 2.0)]
    pub blend_ms: f32,
    /// Communication watchdog timeout, ms (0: off). Clients keep it fed with a heartbeat.
    #[arg(long, default_value_t = 200.0)]
    pub watchdog_ms: f32,
    /// Home and arm at start, watchdog off (bench mode: force without a client).
    #[arg(long)]
    pub auto_arm: bool,
    /// Keep the device's flash (settings store, firmware slots) in FILE, the G474's 512 KiB with
    /// its page size and write granularity: settings and updates survive a restart. Without it,
    /// RAM. A store it cannot read (corrupt, unknown schema) refuses arming until saved over or
    /// reset, as on the firmware.
    #[arg(long, value_name = "FILE")]
    pub flash: Option<std::path::PathBuf>,
    /// Stop after this many seconds (default: run until killed).
    #[arg(long)]
    pub duration_s: Option<f64>,
    /// Serve this many independent virtual devices (1 or 2), each with its own plant, pipeline
    /// and hand: device i listens on the port of `--listen` plus i (targets
    /// `tcp:127.0.0.1:7700` and `tcp:127.0.0.1:7701` by default; with port 0, each on any free
    /// port, all printed). With `--flash`, device i > 0 keeps its flash in FILE.i.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=2))]
    pub devices: u8,
    /// Do not log connections, mode changes, model changes and faults (one line each on
    /// stdout, with the device time).
    #[arg(long)]
    pub quiet: bool,
}

/// A running virtual device.
#[derive(Debug)]
pub struct Server {
    addr: SocketAddr,
    stop: Arc<AtomicBool>,
    threads: Vec<JoinHandle<()>>,
    connections: Arc<Mutex<Vec<TcpStream>>>,
}

/// Why the virtual device could not start.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The scene could not be loaded.
    #[error(transparent)]
    Scene(#[from] crate::sim::scene::SceneError),
    /// The scene's configuration, or the operator's session before serving, failed.
    #[error(transparent)]
    Setup(#[from] crate::sim::closed_loop::ClosedLoopError),
    /// The plant rejected the scene.
    #[error("plant: {0}")]
    Plant(crate::sim::plant::PlantError),
    /// The pipeline rejected its configuration.
    #[error("pipeline: {0}")]
    Pipeline(#[from] softfinger_core::control::pipeline::PipelineError),
    /// The pipeline refused to turn its watchdog off for bench mode.
    #[error("watchdog: {0}")]
    Watchdog(softfinger_core::control::pipeline::CommandError),
    /// The listening socket could not be set up.
    #[error("{0}: cannot listen: {1}")]
    Listen(String, std::io::Error),
    /// The `--flash` file could not be opened or booted from.
    #[error("{0}")]
    Flash(String),
    /// `--duration-s` was not a positive number.
    #[error("--duration-s must be positive, got {0}")]
    Duration(f64),
}

/// The contact model `scene` names ([`softfinger_core::contact::parts`]; the full model when it
/// names none): the device's type parameter, picked once at start.
pub fn scene_parts(scene: &Scene) -> Result<ModelChoice, ServeError> {
    Ok(scene
        .model()
        .map_err(crate::sim::closed_loop::ClosedLoopError::from)?)
}

/// The device's core for `scene`, rendering with the contact model of parts `P`, blending model
/// switches over `blend_s`, the watchdog at `watchdog_s`. With `auto_arm` the operator's session
/// in simulated time first: home against the plant, the hand takes the handle, arm (bench mode:
/// no client feeds the watchdog, so it is off).
pub fn device_core<P: Parts>(
    scene: &Scene,
    blend_s: f32,
    watchdog_s: f32,
    auto_arm: bool,
    plant: &mut crate::sim::plant::Plant,
) -> Result<core::PipelineCore<P>, ServeError> {
    let mut core = core::PipelineCore::<P>::new(scene, blend_s, watchdog_s)?;
    if auto_arm {
        let pipe = core.pipeline_mut();
        pipe.command(softfinger_core::control::pipeline::Command::SetWatchdog { timeout_s: 0.0 })
            .map_err(ServeError::Watchdog)?;
        crate::sim::closed_loop::prepare(pipe, plant)?;
    }
    Ok(core)
}

impl Server {
    /// Bind, build the device from the scene, and start the threads; the event log on stdout
    /// unless `--quiet`.
    pub fn start(args: &Args) -> Result<Server, ServeError> {
        let out: Option<log::LogSink> = if args.quiet {
            None
        } else {
            Some(Arc::new(Mutex::new(std::io::stdout())))
        };
        Server::start_logging(args, out)
    }

    /// [`Server::start`] with the event log into `log` (`None`: silent, whatever `--quiet`).
    pub fn start_logging(args: &Args, log: Option<log::LogSink>) -> Result<Server, ServeError> {
        let scene = Scene::load(&args.scene)?;
        let (contact, _) = core::scene_model(&scene)?;
        let script = crate::sim::closed_loop::touch_script(&scene, &contact);
        let plant = crate::sim::closed_loop::plant(&scene, &contact).map_err(ServeError::Plant)?;
        let parts = scene_parts(&scene)?;
        softfinger_core::with_parts!(parts, P => Server::start_with::<P>(args, log, &scene, plant, script))
    }

    /// [`Server::start_logging`] with the scene loaded, its plant and hand script made, rendering
    /// with the contact model of parts `P`.
    fn start_with<P: Parts>(
        args: &Args,
        log: Option<log::LogSink>,
        scene: &Scene,
        mut plant: crate::sim::plant::Plant,
        script: crate::sim::plant::HandScript,
    ) -> Result<Server, ServeError> {
        let device = softfinger_core::omega_like::OMEGA_LIKE.params;
        let watchdog_s = args.watchdog_ms * 1e-3;
        let core = device_core::<P>(
            scene,
            args.blend_ms * 1e-3,
            watchdog_s,
            args.auto_arm,
            &mut plant,
        )?;
        let listener = TcpListener::bind(&args.listen)
            .map_err(|e| ServeError::Listen(args.listen.clone(), e))?;
        let addr = listener
            .local_addr()
            .map_err(|e| ServeError::Listen(args.listen.clone(), e))?;
        listener
            .set_nonblocking(true)
            .map_err(|e| ServeError::Listen(args.listen.clone(), e))?;
        let stop = Arc::new(AtomicBool::new(false));
        let (events_tx, events_rx) = channel();
        let persist = match &args.flash {
            Some(path) => persist::Persist::open(path).map_err(ServeError::Flash)?,
            None => persist::Persist::in_ram(),
        };
        let dev = device::DeviceLoop::new(core, device, plant, script)
            .with_log(log)
            .with_persist(persist);
        let stop_dev = stop.clone();
        let device_thread = thread::spawn(move || dev.run(events_rx, stop_dev));
        let stop_acc = stop.clone();
        let connections = Arc::new(Mutex::new(Vec::new()));
        let conns = connections.clone();
        let acceptor = thread::spawn(move || {
            let next_id = AtomicU32::new(1);
            while !stop_acc.load(Ordering::Relaxed) {
                match listener.accept() {
                    Ok((stream, _)) => {
                        let _ = stream.set_nonblocking(false);
                        if let (Ok(c), Ok(mut list)) = (stream.try_clone(), conns.lock()) {
                            list.push(c);
                        }
                        let id = next_id.fetch_add(1, Ordering::Relaxed);
                        let ev = events_tx.clone();
                        thread::spawn(move || link::serve_connection(stream, id, ev));
                    }
                    Err(_) => thread::sleep(Duration::from_millis(5)),
                }
            }
        });
        Ok(Server {
            addr,
            stop,
            threads: vec![device_thread, acceptor],
            connections,
        })
    }

    /// The address it listens on.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// Stop the device and the acceptor, and close every connection (clients see the device go
    /// away).
    pub fn stop(self) {
        self.stop.store(true, Ordering::Relaxed);
        for t in self.threads {
            let _ = t.join();
        }
        if let Ok(list) = self.connections.lock() {
            for c in list.iter() {
                let _ = c.shutdown(Shutdown::Both);
            }
        }
    }
}

/// The arguments of device `index` of `--devices`: its own port (the base port plus the index;
/// port 0 stays 0, any free port) and, with `--flash`, its own flash file (FILE.index for
/// index > 0).
pub fn device_args(args: &Args, index: u8) -> Result<Args, ServeError> {
    let mut a = args.clone();
    if index == 0 {
        return Ok(a);
    }
    let base: SocketAddr = args.listen.parse().map_err(|_| {
        ServeError::Listen(
            args.listen.clone(),
            std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "--devices 2 needs --listen as IP:PORT",
            ),
        )
    })?;
    let mut addr = base;
    if base.port() != 0 {
        let port = base.port().checked_add(u16::from(index)).ok_or_else(|| {
            ServeError::Listen(
                args.listen.clone(),
                std::io::Error::new(
                    std::io::ErrorKind::InvalidInput,
                    "no port above it for the next device",
                ),
            )
        })?;
        addr.set_port(port);
    }
    a.listen = addr.to_string();
    a.flash = args.flash.as_ref().map(|f| {
        let mut name = f.clone().into_os_string();
        name.push(format!(".{index}"));
        std::path::PathBuf::from(name)
    });
    Ok(a)
}

/// Start every device of `--devices` (device i on the base port plus i), in order; on an error
/// the ones already started are stopped.
pub fn start_all(args: &Args, log: Option<log::LogSink>) -> Result<Vec<Server>, ServeError> {
    let mut servers: Vec<Server> = Vec::new();
    for i in 0..args.devices {
        let started = device_args(args, i).and_then(|a| Server::start_logging(&a, log.clone()));
        match started {
            Ok(s) => servers.push(s),
            Err(e) => {
                for s in servers {
                    s.stop();
                }
                return Err(e);
            }
        }
    }
    Ok(servers)
}

/// Run `host-sim serve`.
pub fn main(args: &Args) -> Result<(), ServeError> {
    if let Some(s) = args.duration_s {
        if !(s.is_finite() && s > 0.0) {
            return Err(ServeError::Duration(s));
        }
    }
    let log: Option<log::LogSink> = if args.quiet {
        None
    } else {
        Some(Arc::new(Mutex::new(std::io::stdout())))
    };
    let servers = start_all(args, log)?;
    let armed = if args.auto_arm { ", armed" } else { "" };
    for (i, server) in servers.iter().enumerate() {
        if servers.len() == 1 {
            println!(
                "virtual device listening on {} (scene '{}'{armed}); Ctrl-C to stop",
                server.addr(),
                args.scene,
            );
        } else {
            println!(
                "virtual device {i} listening on {} (target tcp:{}; scene '{}'{armed}); Ctrl-C to stop",
                server.addr(),
                server.addr(),
                args.scene,
            );
        }
    }
    match args.duration_s {
        Some(s) => thread::sleep(Duration::from_secs_f64(s)),
        None => loop {
            thread::sleep(Duration::from_secs(3600));
        },
    }
    for server in servers {
        server.stop();
    }
    Ok(())
}
