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
    /// Frames per second, in [0.1, 100] (a GIF frame lasts 1 to 1000 centiseconds); a run
    /// with more frames than 15 s hold is shown at a stride (about 12 s).
    #[arg(long, default_value_t = 10.0)]
    pub fps: f64,
    /// Output file; its extension sets the format: `.gif` for the movie (default DIR/movie.gif
    /// for the 3d contact movie, else DIR/movie_<view>_<colour>.gif), `.png` for a still (with
    /// --still). Never a run's data file nor an existing directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Picture size WxH in px (160x120 to 4000x4000; default 480x300).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Write one frame, the one nearest this time (s, within the run's recorded times), as a
    /// PNG still instead of the movie (default DIR/still_<T>.png).
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

/// Slowest and fastest `--fps`: a GIF frame's delay is a whole number of centiseconds, 1 to
/// 1000 here (100 fps to one frame in 10 s).
pub const FPS_RANGE: (f64, f64) = (0.1, 100.0);

/// Refuse an `--out` that is not a file of the format asked for (`.gif` for a movie, `.png`
/// for a still), which covers a run's data files (`trajectory.npz`, `summary.json`,
/// `final.csv`), or that is a directory.
fn check_out(out: &std::path::Path, still: bool) -> Result<(), String> {
    let ext = out
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let shown = out.display();
    if out.is_dir() {
        return Err(format!(
            "--out {shown}: is a directory; name a file (.gif for the movie, .png for a still)"
        ));
    }
    match (ext.as_str(), still) {
        ("gif", false) | ("png", true) => Ok(()),
        ("png", false) => Err(format!(
            "--out {shown}: a .png holds one frame: add --still T (s) for a still, or name a .gif for the movie"
        )),
        ("gif", true) => Err(format!(
            "--out {shown}: --still writes a PNG: name a .png, or drop --still for the movie"
        )),
        _ => Err(format!(
            "--out {shown}: the format is taken from the extension, which must be .gif (movie) or .png (still with --still); slither movie never writes over other files such as a run's trajectory.npz, summary.json or final.csv"
        )),
    }
}

pub fn movie(a: &Args) -> ExitCode {
    let (lo, hi) = FPS_RANGE;
    if !(a.fps.is_finite() && a.fps >= lo && a.fps <= hi) {
        eprintln!(
            "error: --fps {} is not allowed: must be in [{lo}, {hi}] frames per second (a GIF frame lasts 1 to 1000 centiseconds)",
            a.fps
        );
        return ExitCode::from(2);
    }
    if let Some(out) = &a.out {
        if let Err(e) = check_out(out, a.still.is_some()) {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
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
