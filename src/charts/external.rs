//! Another code's runs on the gait work-precision chart ([`super::gait`]): points read from a
//! CSV file and drawn as their own series, each run's error of `v_s/v_m` against that code's
//! own converged value. Two codes whose models differ (PyElastica's rod is damped and its
//! ground is a penalty spring; slither's contact is exact) converge to different values, so
//! each is judged against itself, and the chart compares what an answer within a given error
//! of one's own converged value costs.
//!
//! **File** (`slither chart work-precision PROBLEM --external FILE`): comma-separated, a
//! header line naming the columns (any order, each once, no others), one run per line; empty
//! lines are skipped; no quoting (a field holds no comma):
//!
//! | column | meaning |
//! |---|---|
//! | `scene` | the problem file's name the runs reproduce (e.g. `pyelastica_s_start.toml`); must be the chart's |
//! | `code` | the code and version, e.g. `PyElastica 1.0.0` (the series' label) |
//! | `elements` | elements of the run (positive integer) |
//! | `dt_s` | step (s, positive) |
//! | `v_s_over_v_m` | the run's `v_s/v_m` (finite) |
//! | `reference_v_s_over_v_m` | that code's converged `v_s/v_m` (finite, not zero) |
//! | `wall_s_per_simulated_s` | wall seconds per simulated second (positive) |
//!
//! The chart's wall axis is the wall time of the whole scene; an external run's is its wall
//! seconds per simulated second times the scene's duration.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The columns of an external points file, in the order they are written.
pub const EXTERNAL_COLUMNS: [&str; 7] = [
    "scene",
    "code",
    "elements",
    "dt_s",
    "v_s_over_v_m",
    "reference_v_s_over_v_m",
    "wall_s_per_simulated_s",
];

/// One run of another code, as read from the file.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ExternalRun {
    /// Problem file name the run reproduces.
    pub scene: String,
    /// Code and version.
    pub code: String,
    /// Elements.
    pub elements: usize,
    /// Step (s).
    pub dt: f64,
    /// `v_s/v_m` of the run.
    pub v_ratio: f64,
    /// The code's own converged `v_s/v_m`.
    pub reference: f64,
    /// Wall seconds per simulated second.
    pub wall_per_simulated_s: f64,
}

/// An external run placed on a chart of a scene of duration `T`.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ExternalPoint {
    /// The run.
    #[serde(flatten)]
    pub run: ExternalRun,
    /// `|v_s/v_m / reference - 1|`.
    pub v_error: f64,
    /// Wall time for the scene's duration: `wall_per_simulated_s * T` (s).
    pub wall_s: f64,
}

impl ExternalPoint {
    /// `run` on a chart of a scene lasting `duration` (s).
    pub fn new(run: ExternalRun, duration: f64) -> ExternalPoint {
        ExternalPoint {
            v_error: (run.v_ratio / run.reference - 1.0).abs(),
            wall_s: run.wall_per_simulated_s * duration,
            run,
        }
    }
}

/// A bad external points file: the file, the line (1-based; 0 when the file cannot be
/// read) and the column concerned.
#[derive(Debug, thiserror::Error)]
#[error("{}{}{}: {message}", path.display(), if *line > 0 { format!(":{line}") } else { String::new() }, column.as_ref().map_or(String::new(), |c| format!(": column '{c}'")))]
pub struct ExternalError {
    /// The file.
    pub path: PathBuf,
    /// Line (1-based), 0 for the whole file.
    pub line: usize,
    /// Column name, when one is concerned.
    pub column: Option<String>,
    /// What is wrong.
    pub message: String,
}

/// Read an external points file (format in the module doc) for the chart of `scene` (the
/// problem file's name).
pub fn read_external(path: &Path, scene: &str) -> Result<Vec<ExternalRun>, ExternalError> {
    let text = std::fs::read_to_string(path).map_err(|e| ExternalError {
        path: path.into(),
        line: 0,
        column: None,
        message: format!("cannot read: {e}"),
    })?;
    parse_external(&text, path, scene)
}

/// Parse the text of an external points file named `path` (for the messages) for the chart
/// of `scene`.
pub fn parse_external(
    text: &str,
    path: &Path,
    scene: &str,
) -> Result<Vec<ExternalRun>, ExternalError> {
    let err = |line: usize, column: Option<&str>, message: String| ExternalError {
        path: path.into(),
        line,
        column: column.map(str::to_string),
        message,
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty());
    let (hline, header) = lines.next().ok_or_else(|| {
        err(
            0,
            None,
            format!(
                "empty: expected a header line with the columns {}",
                EXTERNAL_COLUMNS.join(",")
            ),
        )
    })?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    for (k, n) in names.iter().enumerate() {
        if !EXTERNAL_COLUMNS.contains(n) {
            return Err(err(
                hline,
                Some(n),
                format!("unknown column (expected {})", EXTERNAL_COLUMNS.join(",")),
            ));
        }
        if names[..k].contains(n) {
            return Err(err(hline, Some(n), "named twice".into()));
        }
    }
    let index = |c: &str| names.iter().position(|n| *n == c);
    let mut idx = [0usize; 7];
    for (k, c) in EXTERNAL_COLUMNS.iter().enumerate() {
        idx[k] = index(c).ok_or_else(|| err(hline, Some(c), "missing from the header".into()))?;
    }
    let mut runs = Vec::new();
    for (ln, line) in lines {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            return Err(err(
                ln,
                None,
                format!(
                    "{} fields, the header has {} columns",
                    fields.len(),
                    names.len()
                ),
            ));
        }
        let field = |k: usize| fields[idx[k]];
        let number = |k: usize, ok: fn(f64) -> bool, what: &str| -> Result<f64, ExternalError> {
            let c = EXTERNAL_COLUMNS[k];
            match field(k).parse::<f64>() {
                Ok(v) if ok(v) => Ok(v),
                Ok(_) => Err(err(ln, Some(c), format!("'{}' is not {what}", field(k)))),
                Err(_) => Err(err(ln, Some(c), format!("'{}' is not a number", field(k)))),
            }
        };
        let text_field = |k: usize| -> Result<String, ExternalError> {
            if field(k).is_empty() {
                Err(err(ln, Some(EXTERNAL_COLUMNS[k]), "empty".into()))
            } else {
                Ok(field(k).to_string())
            }
        };
        let run_scene = text_field(0)?;
        if run_scene != scene {
            return Err(err(
                ln,
                Some("scene"),
                format!(
                    "'{run_scene}' is not this chart's scene '{scene}' (points of another scene do not belong on its chart)"
                ),
            ));
        }
        let elements = match field(2).parse::<usize>() {
            Ok(n) if n > 0 => n,
            _ => {
                return Err(err(
                    ln,
                    Some("elements"),
                    format!("'{}' is not a positive integer", field(2)),
                ))
            }
        };
        runs.push(ExternalRun {
            scene: run_scene,
            code: text_field(1)?,
            elements,
            dt: number(3, |v| v.is_finite() && v > 0.0, "a positive step")?,
            v_ratio: number(4, f64::is_finite, "finite")?,
            reference: number(5, |v| v.is_finite() && v != 0.0, "finite and not zero")?,
            wall_per_simulated_s: number(6, |v| v.is_finite() && v > 0.0, "positive")?,
        });
    }
    if runs.is_empty() {
        return Err(err(hline, None, "a header and no runs".into()));
    }
    Ok(runs)
}

/// The external points as CSV: the file's columns, then the chart's `wall_s` and `v_error`.
pub fn external_csv(points: &[ExternalPoint]) -> String {
    let mut csv = format!("{},wall_s,v_error\n", EXTERNAL_COLUMNS.join(","));
    for p in points {
        let r = &p.run;
        let _ = writeln!(
            csv,
            "{},{},{},{:e},{:e},{:e},{:e},{:e},{:e}",
            r.scene,
            r.code,
            r.elements,
            r.dt,
            r.v_ratio,
            r.reference,
            r.wall_per_simulated_s,
            p.wall_s,
            p.v_error
        );
    }
    csv
}
