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
        ..Default::default()
    };
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
