//! The pictures of a run directory: the figures, the ParaView series, the ground tracks and
//! `movie.gif` ([`write_plots`]). The run pipeline ([`crate::pipeline`]) simulates and calls it
//! beside the data files of [`super`]; this module only writes.

use crate::model::Model;
use crate::observe::Fields;
use crate::plot::movie::MovieStats;
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
