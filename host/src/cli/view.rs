//! `view`: a live panel of the device (ratatui), redrawn 10 times a second: mode and contact,
//! the local model, |F| and the spin torque as bars with their scales and as plots over the last
//! [`HISTORY_S`] seconds, the raised flags with their meaning (those that hold the force at zero
//! and the latched faults highlighted), tick and link statistics, and the keys that quit (`q`,
//! Esc, Ctrl-C). Fits 80 × 24. When stdout is not a terminal it prints one line per refresh.

use super::connect;
use ratatui::crossterm::event::{self, Event, KeyCode, KeyEventKind, KeyModifiers};
use ratatui::layout::{Constraint, Layout};
use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Block, Chart, Dataset, GraphType, Paragraph};
use ratatui::Frame;
use softfinger_host::protocol::{DeviceStatus, LinkCounters, Mode, StateSample};
use softfinger_host::{flags, LinkError};
use std::collections::VecDeque;
use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Seconds of history plotted.
pub const HISTORY_S: f64 = 10.0;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Stop after this many seconds (default: until q, Esc or Ctrl-C).
    #[arg(long)]
    pub seconds: Option<f64>,
}

/// What the panel shows.
#[derive(Debug, Default)]
pub struct ViewState {
    /// Control rate, Hz.
    pub rate_hz: f64,
    /// The device's force limit, N (the |F| bar's full scale).
    pub max_force_n: f32,
    /// The newest sample.
    pub latest: Option<StateSample>,
    /// The newest status (model, latched faults).
    pub status: Option<DeviceStatus>,
    /// Link counters.
    pub counters: LinkCounters,
    /// Samples per second arriving.
    pub stream_hz: f64,
    /// (device time s, |F| N, spin torque mN·m), oldest first, the last [`HISTORY_S`].
    pub history: VecDeque<(f64, f64, f64)>,
    /// A line about the link (e.g. reconnecting), shown in place of the header's time.
    pub note: Option<String>,
}

impl ViewState {
    /// Take sample `s`.
    pub fn push(&mut self, s: StateSample) {
        let t = s.tick as f64 / self.rate_hz.max(1.0);
        if self.history.back().is_some_and(|b| b.0 > t) {
            // The device restarted: its time went back.
            self.history.clear();
        }
        let f = s.force_n;
        let fmag = ((f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) as f64).sqrt();
        self.history
            .push_back((t, fmag, f64::from(s.spin_torque_nm) * 1e3));
        while self.history.front().is_some_and(|h| h.0 < t - HISTORY_S) {
            self.history.pop_front();
        }
        self.latest = Some(s);
    }
}

/// A bar of `v` on `0 ..= full`, `width` cells, with the scale's ends as labels.
fn bar(label: &str, v: f64, full: f64, unit: &str, width: usize) -> Line<'static> {
    let x = if v.is_finite() && full > 0.0 {
        (v.abs() / full).min(1.0)
    } else {
        0.0
    };
    let n = (x * width as f64).round() as usize;
    Line::from(vec![
        Span::raw(format!(" {label:<5}{v:>7.2} {unit:<5} 0 ")),
        Span::styled("█".repeat(n), Style::default().fg(Color::Cyan)),
        Span::raw(" ".repeat(width - n)),
        Span::raw(format!(" {full} {unit}")),
    ])
}

/// The style of a mode's name.
fn mode_style(m: Mode) -> Style {
    let c = match m {
        Mode::Armed => Color::Green,
        Mode::Faulted => Color::Red,
        Mode::Homing => Color::Yellow,
        Mode::Unhomed | Mode::Disarmed => Color::Gray,
    };
    Style::default().fg(c).add_modifier(Modifier::BOLD)
}

fn chart<'a>(title: &'a str, data: &'a [(f64, f64)], y: [f64; 2], unit: &str, t: f64) -> Chart<'a> {
    let ds = Dataset::default()
        .marker(Marker::Braille)
        .graph_type(GraphType::Line)
        .style(Style::default().fg(Color::Cyan))
        .data(data);
    Chart::new(vec![ds])
        .block(Block::bordered().title(title))
        .x_axis(
            Axis::default()
                .bounds([t - HISTORY_S, t])
                .labels([format!("-{HISTORY_S:.0} s"), "now".into()]),
        )
        .y_axis(
            Axis::default()
                .bounds(y)
                .labels([format!("{:.1}", y[0]), format!("{:.1} {unit}", y[1])]),
        )
}

/// Draw the panel.
pub fn draw(f: &mut Frame, v: &ViewState) {
    let area = f.area();
    let rows = Layout::vertical([
        Constraint::Length(1), // header
        Constraint::Length(1), // model
        Constraint::Length(2), // bars
        Constraint::Min(6),    // plots
        Constraint::Length(4), // flags
        Constraint::Length(1), // stats
        Constraint::Length(1), // keys
    ])
    .split(area);
    let Some(s) = v.latest else {
        f.render_widget(
            Paragraph::new(vec![
                Line::from(v.note.clone().unwrap_or("waiting for the device...".into())),
                Line::from("q or Esc quits"),
            ]),
            area,
        );
        return;
    };
    let held = s.flags & flags::HOLD_FORCE_DOWN.0;
    let rendering = s.mode == Mode::Armed && held == 0;
    let mut head = vec![
        Span::styled(
            " softfinger ",
            Style::default().add_modifier(Modifier::BOLD),
        ),
        Span::raw(match &v.note {
            Some(n) => format!(" {n} "),
            None => format!(" t {:.3} s ", s.tick as f64 / v.rate_hz.max(1.0)),
        }),
        Span::raw(" mode "),
        Span::styled(s.mode.name(), mode_style(s.mode)),
        Span::raw(format!("  contact {}  ", s.contact.name())),
    ];
    if !rendering {
        head.push(Span::styled(
            " NO FORCE ",
            Style::default().fg(Color::White).bg(Color::Red),
        ));
    }
    f.render_widget(Paragraph::new(Line::from(head)), rows[0]);
    let model = match &v.status {
        Some(st) => short_model_line(&st.model),
        None => format!("model {}", s.model_seq),
    };
    f.render_widget(Paragraph::new(format!(" {model}")), rows[1]);
    let fmag = v.history.back().map_or(0.0, |h| h.1);
    let tau = f64::from(s.spin_torque_nm) * 1e3;
    let tau_full = v
        .history
        .iter()
        .fold(1.0f64, |m, h| m.max(h.2.abs()))
        .ceil();
    f.render_widget(
        Paragraph::new(vec![
            bar("|F|", fmag, f64::from(v.max_force_n), "N", 40),
            bar("spin", tau, tau_full, "mN·m", 40),
        ]),
        rows[2],
    );
    let cols =
        Layout::horizontal([Constraint::Percentage(50), Constraint::Percentage(50)]).split(rows[3]);
    let t = v.history.back().map_or(0.0, |h| h.0);
    let force: Vec<(f64, f64)> = v.history.iter().map(|h| (h.0, h.1)).collect();
    let spin: Vec<(f64, f64)> = v.history.iter().map(|h| (h.0, h.2)).collect();
    let f_top = force.iter().fold(1.0f64, |m, p| m.max(p.1)).ceil();
    f.render_widget(chart("|F|, N", &force, [0.0, f_top], "N", t), cols[0]);
    f.render_widget(
        chart("spin torque, mN·m", &spin, [-tau_full, tau_full], "", t),
        cols[1],
    );
    f.render_widget(Paragraph::new(flag_lines(&s, v.status.as_ref())), rows[4]);
    f.render_widget(
        Paragraph::new(format!(
            " tick max {} ns mean {} ns, overruns {}; stream {:.0} Hz, dropped {}; {} conn.",
            s.tick_stats.max_duration_ns,
            s.tick_stats.mean_duration_ns,
            s.tick_stats.overruns,
            v.stream_hz,
            s.dropped,
            v.counters.connections
        )),
        rows[5],
    );
    f.render_widget(
        Paragraph::new(Line::from(vec![
            Span::styled(" q", Style::default().add_modifier(Modifier::BOLD)),
            Span::raw(" or "),
            Span::styled("Esc", Style::default().add_modifier(Modifier::BOLD)),
            Span::raw(" quits"),
        ])),
        rows[6],
    );
}

/// The model within 79 columns: kind and size, position (whole mm), stiffness, friction.
fn short_model_line(m: &softfinger_host::protocol::LocalModel) -> String {
    let [x, y, z] = m.position_m;
    format!(
        "model {} {} ({:.0},{:.0},{:.0}) mm {} N/m mu {}/{}",
        m.seq,
        host_sim::serve::log::shape(&m.shape),
        x * 1e3,
        y * 1e3,
        z * 1e3,
        m.stiffness_n_per_m,
        m.mu_s,
        m.mu_k
    )
}

/// The raised flags, one line each with its meaning; those that hold the force at zero and
/// the latched faults first and highlighted.
fn flag_lines(s: &StateSample, st: Option<&DeviceStatus>) -> Vec<Line<'static>> {
    let latched = st.map_or(0, |st| st.latched);
    let loud = (s.flags & flags::HOLD_FORCE_DOWN.0) | latched;
    let alarm = Style::default()
        .fg(Color::White)
        .bg(Color::Red)
        .add_modifier(Modifier::BOLD);
    let mut lines: Vec<Line> = flags::raised(loud)
        .map(|(n, m)| {
            // The guard's faults and the watchdog's timeout stay until cleared or re-armed; a
            // stale model's fade lasts while the model is old.
            let bit = bit_of(n);
            let tag = if (latched | softfinger_core::Flags::COMM_TIMEOUT.0) & bit != 0 {
                "latched"
            } else {
                "active"
            };
            Line::from(vec![
                Span::styled(format!(" {n} "), alarm),
                Span::raw(format!(" {tag}: {m}")),
            ])
        })
        .collect();
    lines.extend(flags::raised(s.flags & !loud).map(|(n, m)| {
        Line::from(vec![
            Span::styled(format!(" {n}"), Style::default().fg(Color::Yellow)),
            Span::raw(format!(": {m}")),
        ])
    }));
    if lines.is_empty() {
        lines.push(Line::from(" flags: none"));
    }
    lines
}

fn bit_of(name: &str) -> u32 {
    flags::FLAGS
        .iter()
        .find(|(_, n, _)| *n == name)
        .map_or(0, |(f, _, _)| f.0)
}

/// True when a key that quits was pressed (within `wait`).
fn quit_pressed(wait: Duration) -> bool {
    let Ok(true) = event::poll(wait) else {
        return false;
    };
    match event::read() {
        Ok(Event::Key(k)) if k.kind == KeyEventKind::Press => {
            matches!(k.code, KeyCode::Char('q') | KeyCode::Esc)
                || (k.code == KeyCode::Char('c') && k.modifiers.contains(KeyModifiers::CONTROL))
        }
        _ => false,
    }
}

pub fn main(spec: &str, a: &Args) -> Result<(), String> {
    let mut dev = connect(spec).map_err(|e| e.to_string())?;
    let info = dev.info().map_err(|e| e.to_string())?;
    let divisor = super::stream::divisor_for(info.control_rate_hz, 100.0, info.min_stream_divisor)?;
    dev.set_stream(divisor).map_err(|e| e.to_string())?;
    let tty = std::io::stdout().is_terminal();
    let mut v = ViewState {
        rate_hz: info.control_rate_hz as f64,
        max_force_n: info.max_force_n,
        ..ViewState::default()
    };
    let mut term = if tty {
        Some(ratatui::try_init().map_err(|e| format!("terminal: {e}"))?)
    } else {
        super::interrupt::install();
        None
    };
    let t0 = Instant::now();
    let mut last_poll: Option<Instant> = None;
    let (mut n, mut window) = (0u32, Instant::now());
    let result = loop {
        if a.seconds.is_some_and(|s| t0.elapsed().as_secs_f64() >= s)
            || super::interrupt::requested()
        {
            break Ok(());
        }
        let frame_end = Instant::now() + Duration::from_millis(100);
        let mut failed = None;
        let mut quit = false;
        while let Some(left) = frame_end.checked_duration_since(Instant::now()) {
            match dev.next_state(left.min(Duration::from_millis(20))) {
                Ok(Some(s)) => {
                    v.push(s);
                    v.note = None;
                    n += 1;
                }
                Ok(None) => {
                    if term.is_some() && quit_pressed(Duration::ZERO) {
                        quit = true;
                        break;
                    }
                }
                Err(LinkError::Disconnected) => {
                    v.note = Some("device gone: reconnecting".into());
                    std::thread::sleep(Duration::from_millis(300));
                    let _ = dev.reconnect();
                    break;
                }
                Err(e) => {
                    failed = Some(e.to_string());
                    break;
                }
            }
        }
        if let Some(e) = failed {
            break Err(e);
        }
        if quit || (term.is_some() && quit_pressed(Duration::ZERO)) {
            break Ok(());
        }
        if window.elapsed() >= Duration::from_secs(1) {
            v.stream_hz = n as f64 / window.elapsed().as_secs_f64();
            (n, window) = (0, Instant::now());
        }
        if last_poll.is_none_or(|t| t.elapsed() >= Duration::from_secs(1)) {
            if let Ok(c) = dev.counters() {
                v.counters = c;
            }
            if let Ok(st) = dev.status() {
                v.status = Some(st);
            }
            last_poll = Some(Instant::now());
        }
        match &mut term {
            Some(t) => {
                if let Err(e) = t.draw(|f| draw(f, &v)) {
                    break Err(format!("terminal: {e}"));
                }
            }
            None => {
                if let Some(s) = v.latest {
                    let mut out = std::io::stdout().lock();
                    let _ = writeln!(
                        out,
                        "t {:.3} s mode {} contact {} |F| {:.3} N spin {:.3} mN·m flags {}",
                        s.tick as f64 / v.rate_hz,
                        s.mode.name(),
                        s.contact.name(),
                        v.history.back().map_or(0.0, |h| h.1),
                        s.spin_torque_nm * 1e3,
                        flags::describe(s.flags)
                    );
                    let _ = out.flush();
                }
            }
        }
    };
    if term.is_some() {
        ratatui::restore();
    }
    let _ = dev.set_stream(0);
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use ratatui::backend::TestBackend;
    use ratatui::Terminal;
    use softfinger_core::Flags;

    fn screen(v: &ViewState) -> Vec<String> {
        let mut t = Terminal::new(TestBackend::new(80, 24)).unwrap();
        t.draw(|f| draw(f, v)).unwrap();
        let buf = t.backend().buffer().clone();
        (0..24)
            .map(|y| (0..80).map(|x| buf[(x, y)].symbol().to_string()).collect())
            .collect()
    }

    /// After a watchdog timeout: mode armed, no force, the flag highlighted with its meaning;
    /// the plots, the bar scales and the quit keys on an 80 × 24 screen, nothing cut off.
    #[test]
    fn the_panel_fits_80_columns_and_says_why_there_is_no_force() {
        let mut v = ViewState {
            rate_hz: 10_000.0,
            max_force_n: 12.0,
            ..ViewState::default()
        };
        for k in 0..1200u64 {
            let t = k as f32 / 100.0;
            let timed_out = k >= 1100;
            v.push(StateSample {
                tick: k * 100,
                mode: Mode::Armed,
                force_n: [0.0, 0.0, if timed_out { 0.0 } else { 2.0 + t.sin() }],
                spin_torque_nm: 2e-3 * (t * 0.5).cos(),
                flags: if timed_out {
                    (Flags::COMM_TIMEOUT | Flags::OUTPUT_LIMITED).0
                } else {
                    0
                },
                ..StateSample::default()
            });
        }
        let kept = v.history.back().unwrap().0 - v.history.front().unwrap().0;
        assert!((kept - HISTORY_S).abs() <= 0.01, "{kept} s kept");
        v.status = Some(DeviceStatus {
            tick: 0,
            mode: Mode::Armed,
            flags: 0,
            latched: 0,
            model: softfinger_host::protocol::LocalModel {
                seq: 65_535,
                shape: softfinger_host::protocol::SurfaceShape::Cylinder { radius_m: 0.125 },
                position_m: [-0.1234, -0.1234, -0.2255],
                orientation: [1.0, 0.0, 0.0, 0.0],
                stiffness_n_per_m: 12_345.0,
                damping_n_s_per_m: 2.0,
                mu_s: 0.85,
                mu_k: 0.65,
                spin_stiffness_nm_per_rad: 0.01,
                max_age_ms: 0,
            },
        });
        let s = screen(&v);
        let all = s.join("\n");
        println!("{all}");
        assert!(
            s[0].contains("mode armed") && s[0].contains("NO FORCE"),
            "{}",
            s[0]
        );
        assert!(
            all.contains("|F|, N") && all.contains("spin torque, mN·m"),
            "{all}"
        );
        assert!(all.contains("-10 s") && all.contains("now"), "{all}");
        assert!(
            all.contains(" 0 ") && all.contains("12 N"),
            "bar scale: {all}"
        );
        assert!(
            all.contains("comm-timeout") && all.contains("force 0 until armed"),
            "{all}"
        );
        assert!(all.contains("output-limited"), "{all}");
        assert!(s[23].contains("q or Esc quits"), "{}", s[23]);
        assert!(
            s[1].trim_end().ends_with("12345 N/m mu 0.85/0.65"),
            "{}",
            s[1]
        );
        // Nothing wraps: every line that reaches the last column is a frame or a plot.
        for l in &s[..3] {
            assert!(l.trim_end().chars().count() < 80, "{l}");
        }
    }

    #[test]
    fn a_restart_clears_the_history() {
        let mut v = ViewState {
            rate_hz: 100.0,
            ..ViewState::default()
        };
        v.push(StateSample {
            tick: 500,
            ..StateSample::default()
        });
        v.push(StateSample {
            tick: 3,
            ..StateSample::default()
        });
        assert_eq!(v.history.len(), 1);
    }
}
