//! Evaluations and `history.csv`: one row per simulation, written whole and flushed; read
//! back on resume.

use super::*;

/// Name of the history file in the output directory.
pub const HISTORY_FILE: &str = "history.csv";

/// Header of `history.csv` (the column order is fixed; units and meanings in
/// [`crate::output::schema::HISTORY_CSV`], which `tests/docs.rs` keeps equal to it). The
/// periodic columns are empty for a gait without a launch period.
pub const HISTORY_HEADER: &str = "eval,stress,sigma,speed,period,spacing,lift,duration,G,W,v_s,v_s_over_v_m,writhe_max,writhe_mean,displacement_angle_deg,regime,periodic_cycles,displacement_over_length_min,broadside_deg_min,turn_deg_max_abs,stationary_contact_share_min,sidewinding,status,wall_time_s,objective,base_hash,reason";

/// The periodic columns, in order: in [`HISTORY_HEADER`] after `regime`, and last in the rows
/// of a phase study of a gait with a launch period ([`crate::studies::phase::Format`]). Written
/// and read by [`PeriodicColumns::csv_fields`] and [`PeriodicColumns::parse_fields`].
pub const PERIODIC_COLUMNS: &str = "periodic_cycles,displacement_over_length_min,broadside_deg_min,turn_deg_max_abs,stationary_contact_share_min,sidewinding";

/// Header of the `history.csv` files written before the study could vary the period, the
/// spacing and the lift (and before the periodic columns): still read, their rows taking the
/// base file's period, spacing and lift, and rewritten with [`HISTORY_HEADER`] when a study
/// resumes from them.
pub const LEGACY_HISTORY_HEADER: &str = "eval,stress,sigma,speed,duration,G,W,v_s,v_s_over_v_m,writhe_max,writhe_mean,displacement_angle_deg,regime,status,wall_time_s,objective,base_hash,reason";

/// The periodic observables of an evaluation ([`crate::observe::periodic`]), for a gait with
/// a launch period.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PeriodicColumns {
    /// Measured cycles (after the settling one).
    #[serde(rename = "periodic_cycles")]
    pub cycles: usize,
    /// Smallest centroid displacement per cycle (over L).
    pub displacement_over_length_min: f64,
    /// Smallest broadside angle over the cycles (degrees).
    pub broadside_deg_min: f64,
    /// Largest |turn| per cycle (degrees).
    pub turn_deg_max_abs: f64,
    /// Smallest stationary share of the contact time over the cycles.
    pub stationary_contact_share_min: f64,
    /// Whether every sidewinding criterion holds.
    pub sidewinding: bool,
}

impl PeriodicColumns {
    /// As written in log lines ("5 cycles, sidewinding no: broadside >= 85.4 deg, |turn| <=
    /// 3.8 deg, >= 0.113 L, stationary share >= 0.682").
    pub fn describe(&self) -> String {
        format!(
            "{} cycles, sidewinding {}: broadside >= {:.1} deg, |turn| <= {:.1} deg, >= {:.3} L, stationary share >= {:.3}",
            self.cycles,
            if self.sidewinding { "yes" } else { "no" },
            self.broadside_deg_min,
            self.turn_deg_max_abs,
            self.displacement_over_length_min,
            self.stationary_contact_share_min
        )
    }

    /// The [`PERIODIC_COLUMNS`] fields of `c` as written (comma-joined, numbers in their
    /// shortest round-trip form); empty fields for `None` (not measured).
    pub fn csv_fields(c: Option<&PeriodicColumns>) -> String {
        let num = crate::problem::num;
        match c {
            Some(c) => format!(
                "{},{},{},{},{},{}",
                c.cycles,
                num(c.displacement_over_length_min),
                num(c.broadside_deg_min),
                num(c.turn_deg_max_abs),
                num(c.stationary_contact_share_min),
                if c.sidewinding { "yes" } else { "no" }
            ),
            None => ",,,,,".into(),
        }
    }

    /// Read back what [`PeriodicColumns::csv_fields`] wrote, `field(name)` giving the trimmed
    /// field of each of the [`PERIODIC_COLUMNS`] (`""` when empty or absent): `None` when
    /// `periodic_cycles` is empty, else the columns or a message naming the bad one.
    pub fn parse_fields<'a>(
        field: &dyn Fn(&str) -> &'a str,
    ) -> Result<Option<PeriodicColumns>, String> {
        let num = |name: &str| -> Result<f64, String> {
            let v = field(name);
            v.parse::<f64>()
                .map_err(|_| format!("column `{name}` = {v:?} is not a number"))
        };
        let cycles = match field("periodic_cycles") {
            "" => return Ok(None),
            c => c
                .parse::<usize>()
                .map_err(|_| format!("column `periodic_cycles` = {c:?} is not an integer"))?,
        };
        Ok(Some(PeriodicColumns {
            cycles,
            displacement_over_length_min: num("displacement_over_length_min")?,
            broadside_deg_min: num("broadside_deg_min")?,
            turn_deg_max_abs: num("turn_deg_max_abs")?,
            stationary_contact_share_min: num("stationary_contact_share_min")?,
            sidewinding: match field("sidewinding") {
                "yes" => true,
                "no" => false,
                other => {
                    return Err(format!(
                        "column `sidewinding` = {other:?} must be \"yes\" or \"no\" (or empty with periodic_cycles)"
                    ))
                }
            },
        }))
    }

    /// The columns of measured periodic observables.
    pub fn of(p: &crate::observe::periodic::Periodic) -> PeriodicColumns {
        PeriodicColumns {
            cycles: p.cycles.len(),
            displacement_over_length_min: p.displacement_over_length_min,
            broadside_deg_min: p.broadside_deg_min,
            turn_deg_max_abs: p.turn_deg_max_abs,
            stationary_contact_share_min: p.stationary_contact_share_min,
            sidewinding: p.sidewinding,
        }
    }
}

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
    /// The periodic observables of a finished run of a gait with a launch period.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub periodic: Option<PeriodicColumns>,
    /// Finished or failed.
    pub status: Status,
    /// Wall time of the simulation (s).
    pub wall_time_s: f64,
    /// Why a failed run failed (empty when it finished).
    pub reason: String,
    /// The objective of a finished run without penalties (m/s): `-v_s`, or for
    /// `objective = "broadside"` minus the mean lateral speed per cycle plus `turn_penalty`
    /// times the mean |turn| per cycle and `stationary_penalty` times the smallest stationary
    /// share's shortfall below 0.8 (the `objective` column).
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
        let reason = crate::studies::csv_field(&self.reason);
        // Numbers in their shortest round-trip form, with an exponent outside [1e-4, 1e7)
        // (the failed-run objective is not written as 300 digits); an unrecorded value
        // (NaN period, spacing or lift of a legacy row) is an empty field.
        let num = crate::problem::num;
        let known = |x: f64| if x.is_nan() { String::new() } else { num(x) };
        let periodic = PeriodicColumns::csv_fields(self.periodic.as_ref());
        let p = &self.point;
        [
            self.eval.to_string(),
            num(p.stress),
            num(p.sigma),
            num(p.speed),
            known(p.period),
            known(p.spacing),
            known(p.lift),
            num(self.duration),
            num(self.g),
            num(self.w),
            num(self.v_s),
            num(self.v_s_over_v_m),
            num(self.writhe_max),
            num(self.writhe_mean),
            num(self.displacement_angle_deg),
            self.regime.clone(),
            periodic,
            self.status.as_str().into(),
            num(self.wall_time_s),
            num(self.objective()),
            base_hash.into(),
            reason,
        ]
        .join(",")
    }
}

/// Cache key: exact bits of every gait parameter and the duration.
pub(super) type Key = [u64; 7];

pub(super) fn key(p: &GaitParams, duration: f64) -> Key {
    [
        p.stress.to_bits(),
        p.sigma.to_bits(),
        p.speed.to_bits(),
        p.period.to_bits(),
        p.spacing.to_bits(),
        p.lift.to_bits(),
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
    /// The file has the [`LEGACY_HISTORY_HEADER`]: its rows' period, spacing and lift are NaN
    /// (the base file's, unrecorded) and it holds no periodic columns.
    pub legacy: bool,
}

/// Write `rows` as a whole `history.csv` in the current format (through a temporary file).
pub(super) fn rewrite_history(path: &Path, rows: &[(Evaluation, String)]) -> std::io::Result<()> {
    let mut text = format!("{HISTORY_HEADER}\n");
    for (e, hash) in rows {
        text += &e.csv_row(hash);
        text.push('\n');
    }
    crate::output::write_atomic(path, text.as_bytes())
}

/// Read `path` if it exists (a missing file is an empty history). A last line without its
/// newline (a write cut short) is removed from the file; any other malformed line is an error
/// naming its line.
pub fn read_history(path: &Path) -> Result<History, OptimizeError> {
    let mut h = History::default();
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(h),
        Err(source) => {
            return Err(OptimizeError::Io {
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
        f.map_err(|source| OptimizeError::Io {
            path: path.into(),
            source,
        })?;
        h.dropped_partial = true;
    }
    let bad = |line: usize, message: String| OptimizeError::History {
        file: path.into(),
        line,
        message,
    };
    let mut columns: Vec<&str> = HISTORY_HEADER.split(',').collect();
    for (n, line) in complete.lines().enumerate() {
        let line_no = n + 1;
        if n == 0 {
            let header = line.trim_end();
            if header == LEGACY_HISTORY_HEADER {
                h.legacy = true;
                columns = header.split(',').collect();
            } else if header != HISTORY_HEADER {
                return Err(bad(
                    1,
                    format!("the header must be `{HISTORY_HEADER}` (written by this version of slither) or the older `{LEGACY_HISTORY_HEADER}`; move the file away to start afresh"),
                ));
            }
            continue;
        }
        if line.trim().is_empty() {
            continue;
        }
        h.rows
            .push(parse_row(line, &columns, &|m| bad(line_no, m))?);
    }
    Ok(h)
}

/// One row of `history.csv` under `columns` (the file's header), with its base hash.
fn parse_row(
    line: &str,
    columns: &[&str],
    bad: &dyn Fn(String) -> OptimizeError,
) -> Result<(Evaluation, String), OptimizeError> {
    let width = columns.len();
    let f: Vec<&str> = line.splitn(width, ',').collect();
    if f.len() != width {
        return Err(bad(format!(
            "expected {width} comma-separated fields, found {}",
            f.len()
        )));
    }
    // The field of a column (absent from a legacy file: None).
    let field = |name: &str| columns.iter().position(|c| *c == name).map(|i| f[i].trim());
    let text = |name: &str| field(name).unwrap_or("");
    let num = |name: &str| -> Result<f64, OptimizeError> {
        let v = text(name);
        v.parse::<f64>()
            .map_err(|_| bad(format!("column `{name}` = {v:?} is not a number")))
    };
    // The gait parameters and the duration are inputs of a re-run: finite and positive (the
    // spacing and the lift finite); an empty or absent period, spacing or lift is the base
    // file's (NaN here).
    let input = |name: &str, positive: bool| -> Result<f64, OptimizeError> {
        if matches!(name, "period" | "spacing" | "lift") && text(name).is_empty() {
            return Ok(f64::NAN);
        }
        let x = num(name)?;
        if x.is_finite() && (!positive || x > 0.0) {
            Ok(x)
        } else {
            let allowed = if positive { "finite and > 0" } else { "finite" };
            Err(bad(format!(
                "column `{name}` = {:?} is out of range: allowed {allowed}",
                text(name)
            )))
        }
    };
    let eval = text("eval").parse::<usize>().map_err(|_| {
        bad(format!(
            "column `eval` = {:?} is not an integer",
            text("eval")
        ))
    })?;
    let status = Status::parse(text("status")).ok_or_else(|| {
        bad(format!(
            "column `status` = {:?} must be \"ok\" or \"failed\"",
            text("status")
        ))
    })?;
    let periodic = PeriodicColumns::parse_fields(&text).map_err(bad)?;
    let e = Evaluation {
        eval,
        point: GaitParams {
            stress: input("stress", true)?,
            sigma: input("sigma", true)?,
            speed: input("speed", true)?,
            period: input("period", true)?,
            spacing: input("spacing", false)?,
            lift: input("lift", false)?,
        },
        duration: input("duration", true)?,
        g: num("G")?,
        w: num("W")?,
        v_s: num("v_s")?,
        v_s_over_v_m: num("v_s_over_v_m")?,
        writhe_max: num("writhe_max")?,
        writhe_mean: num("writhe_mean")?,
        displacement_angle_deg: num("displacement_angle_deg")?,
        regime: text("regime").to_string(),
        periodic,
        status,
        wall_time_s: num("wall_time_s")?,
        reason: field("reason").map_or(String::new(), |r| r.to_string()),
        objective_value: num("objective")?,
    };
    Ok((e, text("base_hash").to_string()))
}
