//! A run's movie and ground tracks: the [`Clip`] a movie shows, built from a run in memory
//! ([`clip_from_run`]) or from a run directory's `trajectory.npz` and `summary.json`
//! ([`clip_from_dir`]), and the files `movie.gif` ([`write_movie`]) and `tracks.png` /
//! `tracks.svg` ([`write_tracks`]).
//!
//! Contact state of a node: in the air when it is not in contact ([`Model::in_contact`]; the
//! npz's `slip_speed` is NaN there), stuck when in contact and slower than
//! [`stuck_speed`], sliding otherwise.

use crate::model::Model;
use crate::observe::Fields;
use crate::plot::movie::{Clip, ContactState, MovieOptions, MovieStats};
use crate::sim::Frame;
use std::path::Path;

/// The speed (m/s) below which a node in contact counts as stuck: a tenth of the gait speed
/// `v_m` (the threshold of the regime rules' static middle segment), or, without a gait, a
/// thousandth of a body length per second.
pub fn stuck_speed(m: &Model) -> f64 {
    match gait_speed(m) {
        Some(vm) => 0.1 * vm,
        None => 1e-3 * m.length,
    }
}

/// The gait speed `v_m` (m/s), if the run has a gait.
fn gait_speed(m: &Model) -> Option<f64> {
    let g = &m.gait;
    (g.kind != crate::gait::Kind::None && g.speed > 0.0 && g.speed.is_finite()).then_some(g.speed)
}

/// Contact state from a slip speed (NaN in the air) and the stuck speed.
fn state(slip: f64, stuck: f64) -> ContactState {
    if slip.is_nan() {
        ContactState::Air
    } else if slip < stuck {
        ContactState::Stuck
    } else {
        ContactState::Sliding
    }
}

/// `lambda` (frames x windows, window `j` centred at `s_window[j]`) at the nodes `s`: the value
/// of the nearest window centre.
pub fn lambda_at_nodes(s: &[f64], s_window: &[f64], lambda: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let nearest: Vec<usize> = s
        .iter()
        .map(|&si| {
            s_window
                .iter()
                .enumerate()
                .min_by(|x, y| (x.1 - si).abs().total_cmp(&(y.1 - si).abs()))
                .map_or(0, |(j, _)| j)
        })
        .collect();
    lambda
        .iter()
        .map(|row| {
            nearest
                .iter()
                .map(|&j| row.get(j).copied().unwrap_or(f64::NAN))
                .collect()
        })
        .collect()
}

/// The label a movie shows for a run: its regime and, for a periodic gait, whether it
/// sidewinds and its lateral speed over `v_m` (`periodic`: `(sidewinding, lateral)`), e.g.
/// `U; sidewinding no, lateral 0.27 v_m`.
pub fn movie_label(regime: Option<String>, periodic: Option<(bool, f64)>) -> Option<String> {
    regime.map(|r| match periodic {
        Some((sw, lateral)) => format!(
            "{r}; sidewinding {}, lateral {lateral:.2} v_m",
            if sw { "yes" } else { "no" }
        ),
        None => r,
    })
}

/// The clip of a run in memory: its frames, their fields, and the regime when known.
pub fn clip_from_run(
    m: &Model,
    frames: &[Frame],
    fl: &Fields,
    title: &str,
    regime: Option<String>,
) -> Clip {
    let stuck = stuck_speed(m);
    Clip {
        title: title.to_string(),
        t: frames.iter().map(|f| f.t).collect(),
        x: frames.iter().map(|f| f.x.clone()).collect(),
        contact: fl
            .slip
            .iter()
            .map(|row| row.iter().map(|&v| state(v, stuck)).collect())
            .collect(),
        self_contact: {
            let sc = crate::energy::self_contact::SelfContact::geometry(m);
            frames
                .iter()
                .map(|f| crate::energy::self_contact::touching_of_frame(&sc, m, &f.x))
                .collect()
        },
        lambda: lambda_at_nodes(&fl.s, &fl.s_window, &fl.lambda),
        diameter: m.diameter,
        length: m.length,
        period: gait_speed(m).map(|_| m.gait.pulse_time(m.length)),
        gait_speed: gait_speed(m),
        stuck_speed: stuck,
        regime,
    }
}

/// The scalars a movie needs beyond the frames, stored in `trajectory.npz` as one-element
/// arrays: `diameter` (m), `gait_period` (s, NaN without a gait), `gait_speed` (m/s, NaN
/// without a gait) and `stuck_speed` (m/s).
pub fn movie_scalars(m: &Model) -> [(&'static str, f64); 4] {
    [
        ("diameter", m.diameter),
        (
            "gait_period",
            gait_speed(m).map_or(f64::NAN, |_| m.gait.pulse_time(m.length)),
        ),
        ("gait_speed", gait_speed(m).unwrap_or(f64::NAN)),
        ("stuck_speed", stuck_speed(m)),
    ]
}

/// An npz array: shape and values.
type Array = (Vec<u64>, Vec<f64>);

/// The clip of a run directory: `trajectory.npz` (times, positions, slip speeds, lambda and the
/// [`movie_scalars`]) and, when present, `summary.json` (the regime and the problem's name).
/// Errors name the file and the missing or malformed array.
pub fn clip_from_dir(dir: &Path) -> Result<Clip, String> {
    let path = dir.join("trajectory.npz");
    let mut npz = npyz::npz::NpzArchive::open(&path)
        .map_err(|e| format!("{}: cannot open: {e}", path.display()))?;
    let mut get = |name: &str| -> Result<Option<Array>, String> {
        match npz.by_name(name) {
            Ok(Some(a)) => {
                let shape = a.shape().to_vec();
                let v = a
                    .into_vec::<f64>()
                    .map_err(|e| format!("{}: array {name:?}: {e}", path.display()))?;
                Ok(Some((shape, v)))
            }
            Ok(None) => Ok(None),
            Err(e) => Err(format!("{}: array {name:?}: {e}", path.display())),
        }
    };
    let need = |a: Option<Array>, name: &str| {
        a.ok_or_else(|| {
            format!(
                "{}: no array {name:?} (written by an older slither? re-run the problem)",
                path.display()
            )
        })
    };
    let (_, t) = need(get("t")?, "t")?;
    let (xs, x) = need(get("x")?, "x")?;
    let (_, s) = need(get("s")?, "s")?;
    let (ss, slip) = need(get("slip_speed")?, "slip_speed")?;
    let nf = t.len();
    let nn = s.len();
    if xs != [nf as u64, nn as u64, 3] || ss != [nf as u64, nn as u64] {
        return Err(format!(
            "{}: shapes do not agree: t {nf}, s {nn}, x {xs:?}, slip_speed {ss:?}",
            path.display()
        ));
    }
    let scalar = |a: Option<Array>| a.and_then(|(_, v)| v.first().copied());
    let diameter = scalar(get("diameter")?);
    let period = scalar(get("gait_period")?).filter(|v| v.is_finite());
    let gait_speed = scalar(get("gait_speed")?).filter(|v| v.is_finite());
    let stuck = scalar(get("stuck_speed")?);
    let lambda = get("lambda")?;
    let length = s.last().copied().unwrap_or(0.0) - s.first().copied().unwrap_or(0.0);
    let summary: Option<serde_json::Value> = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|text| serde_json::from_str(&text).ok());
    let diameter = match diameter {
        Some(a) => a,
        None => {
            // Older runs: a = L / (L/a) from the summary's dimensionless groups.
            let ar = summary
                .as_ref()
                .and_then(|s| s["dimensionless"]["aspect_ratio"].as_f64())
                .ok_or_else(|| {
                    format!(
                        "{}: no array \"diameter\" and no summary.json aspect ratio beside it",
                        path.display()
                    )
                })?;
            length / ar
        }
    };
    let stuck = stuck.unwrap_or(match gait_speed {
        Some(vm) => 0.1 * vm,
        None => 1e-3 * length,
    });
    let regime = summary.as_ref().and_then(|s| {
        // The observables sit at the summary's top level (older runs: under
        // "observables").
        let regime = s["regime"]
            .as_str()
            .or_else(|| s["observables"]["regime"].as_str())
            .map(str::to_string);
        let p = &s["periodic"];
        let periodic = p["sidewinding"]
            .as_bool()
            .zip(p["lateral_speed_over_v_m"].as_f64());
        movie_label(regime, periodic)
    });
    let title = summary
        .as_ref()
        .and_then(|s| s["problem"].as_str())
        .map(|p| {
            Path::new(p)
                .file_stem()
                .map_or(p.to_string(), |n| n.to_string_lossy().into_owned())
        })
        .unwrap_or_else(|| dir.display().to_string());
    let lambda = match lambda {
        Some((shape, v)) if shape.len() == 2 && shape[0] == nf as u64 && shape[1] > 0 => {
            let nw = shape[1] as usize;
            let rows: Vec<Vec<f64>> = v.chunks(nw).map(|r| r.to_vec()).collect();
            // Windows of L/10 start at the first nodes (observe::fields).
            let s_window: Vec<f64> = s[..nw.min(nn)]
                .iter()
                .map(|si| si + 0.05 * length)
                .collect();
            lambda_at_nodes(&s, &s_window, &rows)
        }
        _ => Vec::new(),
    };
    Ok(Clip {
        title,
        x: x.chunks(3 * nn)
            .map(|fr| fr.chunks(3).map(|p| [p[0], p[1], p[2]]).collect())
            .collect(),
        contact: slip
            .chunks(nn)
            .map(|row| row.iter().map(|&v| state(v, stuck)).collect())
            .collect(),
        // Older runs have no self-contact flags.
        self_contact: match get("self_contact")? {
            Some((shape, v)) if shape == [nf as u64, nn as u64] => v
                .chunks(nn)
                .map(|r| r.iter().map(|&b| b > 0.5).collect())
                .collect(),
            _ => Vec::new(),
        },
        t,
        lambda,
        diameter,
        length,
        period,
        gait_speed,
        stuck_speed: stuck,
        regime,
    })
}

/// Write `movie.gif` (or `name`) into `dir`, atomically.
pub fn write_movie(
    dir: &Path,
    name: &str,
    clip: &Clip,
    opts: &MovieOptions,
) -> Result<MovieStats, String> {
    write_gif_file(&dir.join(name), clip, opts)
}

/// Render `clip` and write the GIF to `path` atomically.
fn write_gif_file(path: &Path, clip: &Clip, opts: &MovieOptions) -> Result<MovieStats, String> {
    let start = std::time::Instant::now();
    let bytes = crate::plot::movie::movie_bytes(clip, opts)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    super::write_atomic(path, &bytes).map_err(|e| e.to_string())?;
    Ok(MovieStats {
        frames: crate::plot::movie::frame_picks(clip.t.len(), opts.fps, opts.max_seconds).len(),
        bytes: bytes.len(),
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// Write `tracks.png` and `tracks.svg` into `dir`: every node's stuck contact over time and the
/// body at six instants, seen from above.
pub fn write_tracks(dir: &Path, clip: &Clip) -> Result<(), String> {
    for name in ["tracks.png", "tracks.svg"] {
        super::figure(&dir.join(name), |p| crate::plot::tracks(p, clip))?;
    }
    Ok(())
}

/// `slither movie DIR`: render the movie of the run in `dir` from its `trajectory.npz` (and
/// `summary.json`) to `out` (default `DIR/movie_<view>_<colour>.gif`, or `DIR/movie.gif` for
/// the run's own view and colouring). Returns the file written and what it took.
pub fn movie_of_dir(
    dir: &Path,
    opts: &MovieOptions,
    out: Option<&Path>,
) -> Result<(std::path::PathBuf, MovieStats), String> {
    use crate::plot::movie::{Colouring, View};
    let clip = clip_from_dir(dir)?;
    let path = match out {
        Some(p) => p.to_path_buf(),
        None => {
            let view = match opts.view {
                View::ThreeD => "3d",
                View::Top => "top",
                View::Side => "side",
            };
            let colour = match opts.colour {
                Colouring::Contact => "contact",
                Colouring::Elevation => "elevation",
                Colouring::Lambda => "lambda",
            };
            if opts.view == View::ThreeD && opts.colour == Colouring::Contact {
                dir.join("movie.gif")
            } else {
                dir.join(format!("movie_{view}_{colour}.gif"))
            }
        }
    };
    let stats = write_gif_file(&path, &clip, opts)?;
    Ok((path, stats))
}

/// `slither movie DIR --still T`: the movie frame nearest time `t` (s) of the run in `dir` as
/// a PNG at `out` (default `DIR/still_<t>.png`). Returns the file written.
pub fn still_of_dir(
    dir: &Path,
    opts: &MovieOptions,
    t: f64,
    out: Option<&Path>,
) -> Result<std::path::PathBuf, String> {
    let clip = clip_from_dir(dir)?;
    let (first, last) = (
        clip.t.first().copied().unwrap_or(0.0),
        clip.t.last().copied().unwrap_or(0.0),
    );
    // Half a frame's spacing of slack at either end (the nearest frame is shown).
    let slack = if clip.t.len() > 1 {
        0.5 * (last - first) / (clip.t.len() - 1) as f64
    } else {
        0.0
    };
    if !(t >= first - slack && t <= last + slack) {
        return Err(format!(
            "--still {t} is not allowed: the run in {} recorded t in [{first}, {last}] s",
            dir.display()
        ));
    }
    let path = match out {
        Some(p) => p.to_path_buf(),
        None => dir.join(format!("still_{t}.png")),
    };
    crate::plot::movie::still(&path, &clip, opts, t)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::movie_label;

    #[test]
    fn the_label_adds_the_periodic_verdict_to_the_regime() {
        assert_eq!(movie_label(Some("S".into()), None).as_deref(), Some("S"));
        assert_eq!(
            movie_label(Some("U".into()), Some((false, 0.2661))).as_deref(),
            Some("U; sidewinding no, lateral 0.27 v_m")
        );
        assert_eq!(
            movie_label(Some("M".into()), Some((true, 0.3))).as_deref(),
            Some("M; sidewinding yes, lateral 0.30 v_m")
        );
        assert_eq!(movie_label(None, Some((true, 0.3))), None);
    }
}
