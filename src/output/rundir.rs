//! A run directory: what `slither run` writes (`final.csv`, `trajectory.npz`, `summary.json`,
//! the figures, the tracks and `movie.gif`), written by [`write_plots`] for `slither run` and
//! whole by [`write_run_dir`] for a problem built in memory: the best evaluation of
//! `slither optimize` (its `best/`) and one cell of a phase study (`slither phase --cell`).

use super::staging::Staging;
use crate::model::Model;
use crate::observe::{self, Fields, Measure, Observed};
use crate::plot::movie::MovieStats;
use crate::problem::Problem;
use crate::sim::Outcome;
use std::path::Path;

/// The figures (kymographs, snapshots, topology, ParaView series), the ground tracks and,
/// with `movie`, `movie.gif` of a run into `dir`; the movie is rendered while the figures
/// are drawn (both on the thread pool). `title` is shown on the movie, `regime` when known.
/// Returns what the movie took.
pub fn write_plots(
    dir: &Path,
    m: &Model,
    o: &Outcome,
    fields: &Fields,
    title: &str,
    regime: Option<String>,
    movie: bool,
) -> Result<Option<MovieStats>, String> {
    let clip = super::movie::clip_from_run(m, &o.frames, fields, title, regime);
    let (figures, made) = rayon::join(
        || {
            super::write_figures(dir, m, &o.frames, fields)
                .map_err(|e| format!("cannot write figures: {e}"))
                .and_then(|_| {
                    super::movie::write_tracks(dir, &clip)
                        .map_err(|e| format!("cannot write the tracks: {e}"))
                })
        },
        || {
            movie
                .then(|| {
                    super::movie::write_movie(dir, "movie.gif", &clip, &Default::default())
                        .map_err(|e| format!("cannot write the movie: {e}"))
                })
                .transpose()
        },
    );
    figures.and(made)
}

/// What [`write_run_dir`] ran and wrote.
pub struct RunDir {
    /// The run's summary (with its observables).
    pub summary: super::Summary,
    /// What the movie took, if one was written.
    pub movie: Option<MovieStats>,
}

/// Simulate `p` and write its run directory `dir`, as `slither run` would (the outputs are
/// staged in `dir` and swapped in when complete; hold `dir`'s lock and check its writer
/// first). `label` is the file named in `summary.json` as the problem and shown as the
/// movie's title (its stem). Figures, tracks and movie unless `plots` is false (the movie
/// also when `p.output.movie` is). A run that stops early (a failed step) is written up to
/// then, as `slither run` does; its summary says so.
pub fn write_run_dir(p: &Problem, label: &Path, dir: &Path, plots: bool) -> Result<RunDir, String> {
    let model = Model::new(p);
    let Observed {
        outcome: o,
        fields,
        observables,
    } = observe::evaluate(&model, Measure::Full, &mut |_| {}, &mut |_| {})
        .map_err(|e| format!("{}: {e}", label.display()))?;
    let staging = Staging::new(dir)
        .map_err(|e| format!("{}: cannot create the staging folder: {e}", dir.display()))?;
    let stage = staging.dir().to_path_buf();
    let mut summary = super::Summary::new(label, &model, &o);
    summary.periodic = o
        .error
        .is_none()
        .then(|| crate::observe::periodic::of_outcome(&model, &o))
        .flatten();
    let regime = super::movie::movie_label(
        o.error.is_none().then(|| observables.regime.to_string()),
        summary
            .periodic
            .as_ref()
            .map(|p| (p.sidewinding, p.lateral_speed_over_v_m)),
    );
    summary.observables = Some(observables);
    let extra = [
        ("elevation", fields.elevation.clone()),
        ("slip_speed", fields.slip.clone()),
        ("lambda", fields.lambda.clone()),
    ];
    super::write_final_csv(&stage, &model, &o)
        .and_then(|_| super::write_trajectory(&stage, &model, &o.frames, &extra))
        .and_then(|_| super::write_summary(&stage, &summary))
        .map_err(|e| format!("{}: cannot write results: {e}", dir.display()))?;
    let movie = if plots {
        let title = label
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        write_plots(&stage, &model, &o, &fields, &title, regime, p.output.movie)
            .map_err(|e| format!("{}: {e}", dir.display()))?
    } else {
        None
    };
    staging
        .commit()
        .map_err(|e| format!("{}: cannot move the results into place: {e}", dir.display()))?;
    Ok(RunDir { summary, movie })
}
