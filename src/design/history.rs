//! Evaluations and `history.csv`: one row per simulation, written whole and flushed; read
//! back on resume.

use super::*;

/// Name of the history file in the output directory.
pub const HISTORY_FILE: &str = "history.csv";

/// Header of `history.csv` (the column order is fixed; units and meanings in
/// [`crate::output::schema::HISTORY_CSV`], which `tests/docs.rs` keeps equal to it).
pub const HISTORY_HEADER: &str = "eval,stress,sigma,speed,duration,G,W,v_s,v_s_over_v_m,writhe_max,writhe_mean,displacement_angle_deg,regime,status,wall_time_s,objective,base_hash,reason";

/// Outcome of one simulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// The run finished and `v_s` is finite.
    Ok,
    /// The run stopped early (or `v_s` was not finite): cost [`FAILED_COST`].
    Failed,
}

impl Status {
    /// As written in `history.csv` and `phase.csv`.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Failed => "failed",
        }
    }

    /// From its written form.
    pub fn parse(s: &str) -> Option<Status> {
        match s {
            "ok" => Some(Status::Ok),
            "failed" => Some(Status::Failed),
            _ => None,
        }
    }
}

/// One simulated point: a row of `history.csv`.
#[derive(Clone, Debug, Serialize)]
pub struct Evaluation {
    /// Row number in `history.csv` (1-based, continues across resumed runs).
    pub eval: usize,
    /// Gait values.
    #[serde(flatten)]
    pub point: GaitParams,
    /// Simulated duration (s).
    pub duration: f64,
    /// Scaled torque `G = Gamma a^3 L / B`.
    #[serde(rename = "G")]
    pub g: f64,
    /// Scaled weight `W = rho g a^2 L^3 / B`.
    #[serde(rename = "W")]
    pub w: f64,
    /// Mean forward speed of the centroid (m/s); NaN for a failed run (its observables are
    /// not measured: NaN, regime "-").
    pub v_s: f64,
    /// `v_s / v_m`.
    pub v_s_over_v_m: f64,
    /// Largest |writhe| over the frames (turns).
    pub writhe_max: f64,
    /// Mean writhe over the frames (turns).
    pub writhe_mean: f64,
    /// Angle of the net displacement from the initial head direction (degrees).
    pub displacement_angle_deg: f64,
    /// Regime "S", "F", "N" or "U" ([`crate::observe`]).
    pub regime: String,
    /// Finished or failed.
    pub status: Status,
    /// Wall time of the simulation (s).
    pub wall_time_s: f64,
    /// Why a failed run failed (empty when it finished).
    pub reason: String,
    /// The objective of a finished run without penalties (m/s): `-v_s`, or for
    /// `objective = "broadside"` minus the mean lateral speed per cycle plus `turn_penalty`
    /// times the mean |turn| per cycle (the `objective` column).
    #[serde(skip)]
    pub objective_value: f64,
}

impl Evaluation {
    /// The objective at this point, without any out-of-bounds penalty (m/s):
    /// `objective_value` (`-v_s` by default), or [`FAILED_COST`] for a failed run.
    pub fn objective(&self) -> f64 {
        match self.status {
            Status::Ok => self.objective_value,
            Status::Failed => FAILED_COST,
        }
    }

    pub(super) fn csv_row(&self, base_hash: &str) -> String {
        let reason = super::csv_field(&self.reason);
        // Numbers in their shortest round-trip form, with an exponent outside [1e-4, 1e7)
        // (the failed-run objective is not written as 300 digits).
        let num = crate::problem::num;
        format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            self.eval,
            num(self.point.stress),
            num(self.point.sigma),
            num(self.point.speed),
            num(self.duration),
            num(self.g),
            num(self.w),
            num(self.v_s),
            num(self.v_s_over_v_m),
            num(self.writhe_max),
            num(self.writhe_mean),
            num(self.displacement_angle_deg),
            self.regime,
            self.status.as_str(),
            num(self.wall_time_s),
            num(self.objective()),
            base_hash,
            reason
        )
    }
}

/// Cache key: exact bits of stress, sigma, speed and duration.
pub(super) type Key = [u64; 4];

pub(super) fn key(p: &GaitParams, duration: f64) -> Key {
    [
        p.stress.to_bits(),
        p.sigma.to_bits(),
        p.speed.to_bits(),
        duration.to_bits(),
    ]
}

/// Rows of an existing `history.csv`.
#[derive(Debug, Default)]
pub struct History {
    /// Every row, in file order, with its base hash.
    pub rows: Vec<(Evaluation, String)>,
    /// An incomplete last line (an interrupted write) was dropped from the file.
    pub dropped_partial: bool,
}

/// Read `path` if it exists (a missing file is an empty history). A last line without its
/// newline (a write cut short) is removed from the file; any other malformed line is an error
/// naming its line.
pub fn read_history(path: &Path) -> Result<History, DesignError> {
    let mut h = History::default();
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(h),
        Err(source) => {
            return Err(DesignError::Io {
                path: path.into(),
                source,
            })
        }
    };
    let mut complete = text.as_str();
    if !text.is_empty() && !text.ends_with('\n') {
        let keep = text.rfind('\n').map_or(0, |i| i + 1);
        complete = &text[..keep];
        let f = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .and_then(|f| f.set_len(keep as u64));
        f.map_err(|source| DesignError::Io {
            path: path.into(),
            source,
        })?;
        h.dropped_partial = true;
    }
    let bad = |line: usize, message: String| DesignError::History {
        file: path.into(),
        line,
        message,
    };
    for (n, line) in complete.lines().enumerate() {
        let line_no = n + 1;
        if n == 0 {
            if line.trim_end() != HISTORY_HEADER {
                return Err(bad(
                    1,
                    format!("the header must be `{HISTORY_HEADER}` (written by this version of slither); move the file away to start afresh"),
                ));
            }
            continue;
        }
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.splitn(18, ',').collect();
        if f.len() != 18 {
            return Err(bad(
                line_no,
                format!("expected 18 comma-separated fields, found {}", f.len()),
            ));
        }
        let num = |i: usize| -> Result<f64, DesignError> {
            f[i].trim().parse::<f64>().map_err(|_| {
                bad(
                    line_no,
                    format!(
                        "column `{}` = {:?} is not a number",
                        HISTORY_HEADER.split(',').nth(i).unwrap_or("?"),
                        f[i]
                    ),
                )
            })
        };
        // The gait parameters and the duration are inputs of a re-run: finite and positive.
        let input = |i: usize| -> Result<f64, DesignError> {
            let x = num(i)?;
            if x.is_finite() && x > 0.0 {
                Ok(x)
            } else {
                Err(bad(
                    line_no,
                    format!(
                        "column `{}` = {:?} is out of range: allowed finite and > 0",
                        HISTORY_HEADER.split(',').nth(i).unwrap_or("?"),
                        f[i]
                    ),
                ))
            }
        };
        let eval = f[0].trim().parse::<usize>().map_err(|_| {
            bad(
                line_no,
                format!("column `eval` = {:?} is not an integer", f[0]),
            )
        })?;
        let status = match f[13].trim() {
            "ok" => Status::Ok,
            "failed" => Status::Failed,
            other => {
                return Err(bad(
                    line_no,
                    format!("column `status` = {other:?} must be \"ok\" or \"failed\""),
                ))
            }
        };
        let e = Evaluation {
            eval,
            point: GaitParams {
                stress: input(1)?,
                sigma: input(2)?,
                speed: input(3)?,
            },
            duration: input(4)?,
            g: num(5)?,
            w: num(6)?,
            v_s: num(7)?,
            v_s_over_v_m: num(8)?,
            writhe_max: num(9)?,
            writhe_mean: num(10)?,
            displacement_angle_deg: num(11)?,
            regime: f[12].trim().to_string(),
            status,
            wall_time_s: num(14)?,
            reason: f[17].to_string(),
            objective_value: num(15)?,
        };
        h.rows.push((e, f[16].trim().to_string()));
    }
    Ok(h)
}
