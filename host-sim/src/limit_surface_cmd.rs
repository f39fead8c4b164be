//! `host-sim limit-surface`: the ellipsoidal limit surface against the true limit surface of a
//! Hertzian patch (numerical integration in f64, [`crate::reference::limit_surface`]): the curve,
//! the ellipse's radial error at each point, and the worst error.

use crate::reference::limit_surface::{curve, ellipse_error_range, LimitPoint};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Points on the curve (instantaneous centres between 0.01 a and 100 a).
    #[arg(long, default_value_t = 60)]
    pub points: usize,
    /// Radial cells of the integration (the angular ones are twice as many).
    #[arg(long, default_value_t = 200)]
    pub cells: usize,
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// The curve and the worst errors, rendered as the command prints them.
pub fn render(args: &Args) -> Result<String, String> {
    if args.points < 2 || args.cells < 10 || args.cells > 5000 {
        return Err("--points must be >= 2 and --cells between 10 and 5000".into());
    }
    let c = curve(args.points, args.cells, 2 * args.cells);
    let (lo, hi) = ellipse_error_range(&c);
    if args.json {
        let doc =
            serde_json::json!({ "curve": c, "ellipse_error_min": lo, "ellipse_error_max": hi });
        return serde_json::to_string_pretty(&doc).map_err(|e| format!("JSON output: {e}"));
    }
    let mut out = String::from(
        "Hertzian limit surface (f64 integration) vs the ellipse (|f|/(mu fN))^2 + (tau/tau_max)^2 = 1\n\
         centre/a          |f|/(mu fN)   tau/tau_max   ellipse radial error\n",
    );
    for p in &c {
        out += &format!(
            "{:<16.4e} {:>12.6} {:>13.6} {:>14.4e}\n",
            p.centre_a,
            p.x,
            p.y,
            p.ellipse_error()
        );
    }
    out += &format!(
        "worst radial error of the ellipse: {lo:.4e} (over-estimate), {hi:.4e} (under-estimate)\n"
    );
    Ok(out)
}

/// The normalised true curve, for charts.
pub fn true_curve() -> Vec<LimitPoint> {
    curve(60, 200, 400)
}

pub fn main(args: &Args) -> Result<(), String> {
    println!("{}", render(args)?);
    Ok(())
}
