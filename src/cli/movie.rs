//! `slither movie`: render a movie of a run directory from its `trajectory.npz`.
use slither::output;
use slither::plot::movie::{Colouring, MovieOptions, View};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// Run directory written by `slither run` (holds trajectory.npz and summary.json).
    pub dir: PathBuf,
    /// Camera: 3d (perspective, following the body), top or side (orthographic, fixed when
    /// the run fits in 3 body lengths).
    #[arg(long, default_value = "3d")]
    pub view: View,
    /// Body colour: contact (stuck, sliding, in the air), elevation or lambda.
    #[arg(long, default_value = "contact")]
    pub colour: Colouring,
    /// Frames per second, in (0, 100]; a run with more frames than 15 s hold is shown at a
    /// stride (about 12 s).
    #[arg(long, default_value_t = 10.0)]
    pub fps: f64,
    /// Output GIF (default DIR/movie.gif for the 3d contact movie, else
    /// DIR/movie_<view>_<colour>.gif).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Picture size WxH in px (160x120 to 4000x4000; default 480x300).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Write one frame, the one nearest this time (s), as a PNG still instead of the movie
    /// (default DIR/still_<T>.png).
    #[arg(long)]
    pub still: Option<f64>,
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("size {s:?} is not WxH in px, e.g. 640x400");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    Ok((
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    ))
}

pub fn movie(a: &Args) -> ExitCode {
    if !(a.fps.is_finite() && a.fps > 0.0 && a.fps <= 100.0) {
        eprintln!("error: --fps {} is not allowed: must be in (0, 100]", a.fps);
        return ExitCode::from(2);
    }
    let opts = MovieOptions {
        view: a.view,
        colour: a.colour,
        fps: a.fps,
        size: a.size.unwrap_or(MovieOptions::default().size),
        ..Default::default()
    };
    if let Some(t) = a.still {
        if !t.is_finite() {
            eprintln!("error: --still {t} is not allowed: must be a finite time (s)");
            return ExitCode::from(2);
        }
        return match output::movie::still_of_dir(&a.dir, &opts, t, a.out.as_deref()) {
            Ok(path) => {
                eprintln!("wrote {}", path.display());
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        };
    }
    match output::movie::movie_of_dir(&a.dir, &opts, a.out.as_deref()) {
        Ok((path, s)) => {
            eprintln!(
                "wrote {}: {} frames, {:.1} MB, {:.2} s",
                path.display(),
                s.frames,
                s.bytes as f64 / 1e6,
                s.seconds
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
