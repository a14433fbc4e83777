//! `phase.csv` and `refine.csv`: the row format of a cell, reading for resume (a torn last
//! row is cut off), appending.
//!
//! A study's rows have one of four [`Format`]s: [`HEADER`]'s columns, then the
//! [`VERIFY_COLUMNS`] for a verified study, then the [`PERIODIC_COLUMNS`] for a study whose base
//! gait has a launch period. A file is read by its header and appended to only by a study of
//! the same format.
use super::cell::Cell;
use super::PhaseError;
use crate::observe::Regime;
use crate::studies::{optimize::PeriodicColumns, optimize::Status};
use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

pub use crate::studies::optimize::PERIODIC_COLUMNS;

/// Header of `phase.csv` (the column order is fixed; units in the README).
pub const HEADER: &str = "weight,torque,W_over_G,status,regime,v_s_over_v_m,displacement_angle_deg,max_elevation_over_a,lifted_arcs_max,writhe_max,lambda_pulse_r2,regime_detail,max_elevation_over_length,two_arc_lift_over_a,lambda_pulse_speed_over_v_m,writhe_snapshot,wall_time_s,base_hash,reason";

/// Number of columns of [`HEADER`].
const COLUMNS: usize = 19;

/// The columns a verified study (`verify = { ... }`) adds after [`HEADER`]'s.
pub const VERIFY_COLUMNS: &str = "label_agreement,v_s_over_v_m_min,v_s_over_v_m_max,regime_base,regime_finer,verify_runs,verify_seed";

/// Number of [`VERIFY_COLUMNS`].
const VERIFY_COUNT: usize = 7;

/// Number of [`PERIODIC_COLUMNS`].
const PERIODIC_COUNT: usize = 6;

/// Header of a verified study's `phase.csv` and `refine.csv` of a gait without a launch
/// period: [`HEADER`], then [`VERIFY_COLUMNS`].
pub fn verify_header() -> String {
    Format {
        verified: true,
        periodic: false,
    }
    .header()
}

/// The columns of a study's rows (`phase.csv`, `refine.csv`, `growth.csv`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Format {
    /// The [`VERIFY_COLUMNS`] follow [`HEADER`]'s (`verify = { ... }`).
    pub verified: bool,
    /// The [`PERIODIC_COLUMNS`] come last: the base gait has a launch period
    /// ([`crate::problem::Kind::has_launch_period`]).
    pub periodic: bool,
}

impl Format {
    /// The format of the rows of a study of `base` (verified with `verify`).
    pub fn of(base: &crate::problem::Problem, verify: Option<&super::Verify>) -> Format {
        Format {
            verified: verify.is_some(),
            periodic: base.gait.kind.has_launch_period(),
        }
    }

    /// The header line (no newline).
    pub fn header(self) -> String {
        let mut h = HEADER.to_string();
        if self.verified {
            h = format!("{h},{VERIFY_COLUMNS}");
        }
        if self.periodic {
            h = format!("{h},{PERIODIC_COLUMNS}");
        }
        h
    }

    /// The format whose header is `line`, if any.
    pub fn of_header(line: &str) -> Option<Format> {
        [false, true]
            .into_iter()
            .flat_map(|verified| [false, true].map(|periodic| Format { verified, periodic }))
            .find(|f| f.header() == line)
    }

    fn width(self) -> usize {
        COLUMNS
            + if self.verified { VERIFY_COUNT } else { 0 }
            + if self.periodic { PERIODIC_COUNT } else { 0 }
    }

    /// Why rows of `self` (a file's) cannot be mixed with rows of `want` (a study's), or
    /// `None` when they can (the same format).
    fn mismatch(self, want: Format) -> Option<String> {
        let mut why = Vec::new();
        if self.verified != want.verified {
            why.push(if want.verified {
                "it was written without verification and this study verifies its cells"
            } else {
                "it was written with verification (verify = { ... }) and this study has none"
            });
        }
        if self.periodic != want.periodic {
            why.push(if want.periodic {
                "it has no periodic columns and this study's gait has a launch period (a file of another base, or written before phase rows carried them)"
            } else {
                "it has the periodic columns of a gait with a launch period and this study's gait has none"
            });
        }
        (!why.is_empty()).then(|| why.join("; "))
    }

    /// [`PhaseError::Header`] on `file` unless a file of format `self` holds rows of `want`;
    /// `doing` says what was refused ("cannot append to it").
    pub(crate) fn check(self, want: Format, file: &Path, doing: &str) -> Result<(), PhaseError> {
        match self.mismatch(want) {
            None => Ok(()),
            Some(why) => Err(PhaseError::Header {
                file: file.to_path_buf(),
                why: format!("{doing}: {why}"),
                found: self.header(),
                expected: want.header(),
            }),
        }
    }
}

impl Cell {
    /// The cell as a row (no newline) for the base file with hash `hash`: a verified cell adds
    /// the [`VERIFY_COLUMNS`], and a row of a `periodic` study the [`PERIODIC_COLUMNS`] (empty
    /// when the cell has no periodic observables).
    pub(crate) fn row(&self, hash: u64, periodic: bool) -> String {
        let mut row = self.plain_row(hash);
        if let Some(v) = &self.verify {
            let label = |r: Option<Regime>| r.map_or("-", Regime::as_str);
            row += &format!(
                ",{},{:e},{:e},{},{},{},{:016x}",
                v.label_agreement,
                v.v_s_over_v_m_min,
                v.v_s_over_v_m_max,
                label(v.regime_base),
                label(v.regime_finer),
                v.runs,
                v.seed
            );
        }
        if periodic {
            row.push(',');
            row += &PeriodicColumns::csv_fields(self.periodic.as_ref());
        }
        row
    }

    fn plain_row(&self, hash: u64) -> String {
        let clean = crate::studies::csv_field(&self.reason);
        format!(
            "{:e},{:e},{:e},{},{},{:e},{:e},{:e},{},{:e},{:e},{},{:e},{:e},{:e},{:e},{:.3},{:016x},{}",
            self.weight,
            self.torque,
            self.weight / self.torque,
            self.status.as_str(),
            self.regime.map_or("-", Regime::as_str),
            self.v_s_over_v_m,
            self.displacement_angle_deg,
            self.max_elevation_over_a,
            self.lifted_arcs_max,
            self.writhe_max,
            self.lambda_pulse_r2,
            self.regime_detail,
            self.max_elevation_over_length,
            self.two_arc_lift_over_a,
            self.lambda_pulse_speed_over_v_m,
            self.writhe_snapshot,
            self.wall_time_s,
            hash,
            clean
        )
    }

    /// A row of a file of format `format`.
    fn parse(line: &str, format: Format) -> Option<(Cell, u64)> {
        // The free-text reason never holds a comma (`csv_field`): split on every comma.
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != format.width() {
            return None;
        }
        let num = |i: usize| f[i].parse::<f64>().ok();
        let label = |s: &str| match s {
            "-" => Some(None),
            r => r.parse().ok().map(Some),
        };
        let verify = if format.verified {
            Some(super::cell::Verification {
                label_agreement: num(19)?,
                v_s_over_v_m_min: num(20)?,
                v_s_over_v_m_max: num(21)?,
                regime_base: label(f[22])?,
                regime_finer: label(f[23])?,
                runs: f[24].parse().ok()?,
                seed: u64::from_str_radix(f[25], 16).ok()?,
            })
        } else {
            None
        };
        let periodic = if format.periodic {
            let at = format.width() - PERIODIC_COUNT;
            let names: Vec<&str> = PERIODIC_COLUMNS.split(',').collect();
            let field = |name: &str| {
                names
                    .iter()
                    .position(|n| *n == name)
                    .map_or("", |i| f[at + i])
            };
            PeriodicColumns::parse_fields(&field).ok()?
        } else {
            None
        };
        Some((
            Cell {
                weight: num(0)?,
                torque: num(1)?,
                status: Status::parse(f[3])?,
                regime: match f[4] {
                    "-" => None,
                    r => Some(r.parse().ok()?),
                },
                regime_detail: f[11].into(),
                v_s_over_v_m: num(5)?,
                displacement_angle_deg: num(6)?,
                max_elevation_over_a: num(7)?,
                lifted_arcs_max: f[8].parse().ok()?,
                writhe_max: num(9)?,
                lambda_pulse_r2: num(10)?,
                max_elevation_over_length: num(12)?,
                two_arc_lift_over_a: num(13)?,
                lambda_pulse_speed_over_v_m: num(14)?,
                writhe_snapshot: num(15)?,
                wall_time_s: num(16)?,
                reason: f[18].into(),
                verify,
                periodic,
            },
            u64::from_str_radix(f[17], 16).ok()?,
        ))
    }
}

/// Finished cells of an existing `phase.csv`, keyed by the bits of `(W, G)`.
#[derive(Debug, Default)]
pub struct PhaseCsv {
    /// Rows written for the base file with hash `base_hash`.
    pub cells: HashMap<(u64, u64), Cell>,
    /// The file did not exist or held nothing (not even a complete header).
    pub fresh: bool,
    /// An incomplete last line (no newline: a write cut short) was cut off the file.
    pub dropped_partial_row: bool,
    /// The file's columns (the default, [`HEADER`]'s, when the file is fresh).
    pub format: Format,
}

/// Read `phase.csv` for resuming: rows of other base files are skipped; a last line without
/// its newline (a row cut short by a crash) is removed from the file, so the next row is not
/// glued onto it; any other line that is not a row is [`PhaseError::Csv`] naming it.
pub fn read_phase_csv(csv: &Path, base_hash: u64) -> Result<PhaseCsv, PhaseError> {
    let r = read_rows(csv)?;
    Ok(PhaseCsv {
        cells: r
            .rows
            .into_iter()
            .filter(|(_, h)| *h == base_hash)
            .map(|(c, _)| ((c.weight.to_bits(), c.torque.to_bits()), c))
            .collect(),
        fresh: r.fresh,
        dropped_partial_row: r.dropped_partial_row,
        format: r.format,
    })
}

/// Every row of a `phase.csv` or `refine.csv` (the same columns), in file order.
#[derive(Debug, Default)]
pub struct Rows {
    /// The rows, each with the hash of the base file it was simulated for.
    pub rows: Vec<(Cell, u64)>,
    /// The file did not exist or held nothing (not even a complete header).
    pub fresh: bool,
    /// An incomplete last line (no newline: a write cut short) was cut off the file.
    pub dropped_partial_row: bool,
    /// The file's columns (the default, [`HEADER`]'s, when the file is fresh).
    pub format: Format,
}

/// Open a study's CSV of rows (`phase.csv`, `refine.csv`) for appending, writing the header
/// first when the file is `fresh` ([`Format::header`] of `want`). Rows are then written one per
/// `write_all` and flushed, so a crash leaves whole lines or a torn last one ([`read_rows`]
/// drops it). An existing file of another format (`had`, from its header) is
/// [`PhaseError::Header`]: its rows cannot be mixed.
pub(crate) fn append_rows(
    csv: &Path,
    fresh: bool,
    had: Format,
    want: Format,
) -> Result<std::fs::File, PhaseError> {
    let io = |source| PhaseError::Io {
        file: csv.to_path_buf(),
        source,
    };
    if !fresh {
        had.check(want, csv, "cannot append to it")?;
    }
    let mut file = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(csv)
        .map_err(io)?;
    if fresh {
        file.write_all(format!("{}\n", want.header()).as_bytes())
            .and_then(|_| file.flush())
            .map_err(io)?;
    }
    Ok(file)
}

/// Simulate the cells `todo` (`(W, G)` pairs) in parallel with `simulate`, appending each
/// cell's row (under the rows' hash `hash`) to `file` as soon as it is done, and calling
/// `report(done, cell)` after each (with the periodic columns when `periodic`). Returns the cells in `todo`'s order; the first write error
/// is [`PhaseError::Io`] on `csv`, after every simulation has finished.
pub(crate) fn simulate_appending(
    todo: &[(f64, f64)],
    simulate: &(dyn Fn(f64, f64) -> Cell + Sync),
    file: std::fs::File,
    csv: &Path,
    hash: u64,
    periodic: bool,
    report: &(dyn Fn(usize, &Cell) + Sync),
) -> Result<Vec<Cell>, PhaseError> {
    use rayon::prelude::*;
    let sink = std::sync::Mutex::new((file, 0usize, None::<std::io::Error>));
    let cells: Vec<Cell> = todo
        .par_iter()
        .map(|&(w, g)| {
            let c = simulate(w, g);
            let mut s = sink.lock().unwrap_or_else(|e| e.into_inner());
            let line = c.row(hash, periodic) + "\n";
            let r = s.0.write_all(line.as_bytes()).and_then(|_| s.0.flush());
            if let Err(e) = r {
                s.2.get_or_insert(e);
            }
            s.1 += 1;
            report(s.1, &c);
            c
        })
        .collect();
    match sink.into_inner().unwrap_or_else(|e| e.into_inner()).2 {
        Some(source) => Err(PhaseError::Io {
            file: csv.to_path_buf(),
            source,
        }),
        None => Ok(cells),
    }
}

/// Read every row of a `phase.csv` or `refine.csv` (of any base file), cutting a torn last line
/// off the file as [`read_phase_csv`] does.
pub fn read_rows(csv: &Path) -> Result<Rows, PhaseError> {
    let io = |source| PhaseError::Io {
        file: csv.to_path_buf(),
        source,
    };
    let mut out = Rows::default();
    let bytes = match std::fs::read(csv) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            out.fresh = true;
            return Ok(out);
        }
        Err(e) => return Err(io(e)),
    };
    let mut keep = bytes.len();
    if !bytes.is_empty() && !bytes.ends_with(b"\n") {
        keep = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        std::fs::OpenOptions::new()
            .write(true)
            .open(csv)
            .and_then(|f| f.set_len(keep as u64))
            .map_err(io)?;
        out.dropped_partial_row = true;
    }
    let text = match std::str::from_utf8(&bytes[..keep]) {
        Ok(t) => t,
        Err(e) => {
            let at = e.valid_up_to();
            return Err(PhaseError::Csv {
                file: csv.to_path_buf(),
                line: 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count(),
            });
        }
    };
    out.fresh = text.is_empty();
    for (n, line) in text.lines().enumerate() {
        if n == 0 {
            out.format = Format::of_header(line).ok_or(PhaseError::Csv {
                file: csv.to_path_buf(),
                line: 1,
            })?;
            continue;
        }
        if line.trim().is_empty() {
            continue;
        }
        let row = Cell::parse(line, out.format).ok_or(PhaseError::Csv {
            file: csv.to_path_buf(),
            line: n + 1,
        })?;
        out.rows.push(row);
    }
    Ok(out)
}

/// A cell's row without its wall time (what must agree between two runs of one cell; a
/// verified cell's wall time is the sum of its runs'), with the periodic columns when the cell
/// has periodic observables.
pub fn comparable_row(c: &Cell, hash: u64) -> String {
    let row = c.row(hash, c.periodic.is_some());
    let mut f: Vec<&str> = row.split(',').collect();
    if f.len() > 16 {
        f[16] = "";
    }
    f.join(",")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::observe::RegimeInputs;

    const PLAIN: Format = Format {
        verified: false,
        periodic: false,
    };
    const VERIFIED: Format = Format {
        verified: true,
        periodic: false,
    };

    #[test]
    fn rows_round_trip() {
        let c = Cell {
            weight: 300.0,
            torque: 15.0,
            status: crate::studies::optimize::Status::Failed,
            regime: None,
            regime_detail: "-".into(),
            v_s_over_v_m: f64::NAN,
            displacement_angle_deg: 12.5,
            max_elevation_over_a: 0.25,
            lifted_arcs_max: 2,
            writhe_max: 0.1,
            lambda_pulse_r2: 0.9,
            max_elevation_over_length: 0.005,
            two_arc_lift_over_a: 0.125,
            lambda_pulse_speed_over_v_m: 1.32,
            writhe_snapshot: -0.375,
            wall_time_s: 1.5,
            reason: "step rejected, at t = 1\nagain".into(),
            verify: None,
            periodic: None,
        };
        let row = c.row(0xabc, false);
        assert_eq!(row.split(',').count(), HEADER.split(',').count(), "{row}");
        let (d, h) = Cell::parse(&row, PLAIN).unwrap();
        assert_eq!(h, 0xabc);
        assert_eq!((d.weight, d.torque, d.lifted_arcs_max), (300.0, 15.0, 2));
        assert!(d.v_s_over_v_m.is_nan());
        assert_eq!(d.regime, None);
        assert_eq!(d.displacement_angle_deg, 12.5);
        let (di, ci) = (d.regime_inputs(), c.regime_inputs());
        assert!(di.v_s_over_v_m.is_nan());
        assert_eq!(
            RegimeInputs {
                v_s_over_v_m: 0.0,
                ..di
            },
            RegimeInputs {
                v_s_over_v_m: 0.0,
                ..ci
            }
        );
        assert_eq!(d.writhe_snapshot, -0.375);
        assert_eq!(d.reason, "step rejected; at t = 1;again");
        // An M cell keeps its label and the criteria it missed.
        let m = Cell {
            status: crate::studies::optimize::Status::Ok,
            regime: Some(Regime::M),
            regime_detail: "heading;pulse_speed".into(),
            v_s_over_v_m: 0.29,
            reason: String::new(),
            ..c
        };
        let (d, _) = Cell::parse(&m.row(1, false), PLAIN).unwrap();
        assert_eq!(d.regime, Some(Regime::M));
        assert_eq!(d.regime_detail, "heading;pulse_speed");
        assert_eq!(d.v_s_over_v_m, 0.29);
        assert_eq!(d.regime_inputs(), m.regime_inputs());
        // A label that is not a regime is not a row.
        let bad = m.row(1, false).replacen(",M,", ",X,", 1);
        assert!(Cell::parse(&bad, PLAIN).is_none());
        // A verified cell round-trips its verification columns, and is not a plain row.
        let v = Cell {
            verify: Some(crate::studies::phase::cell::Verification {
                label_agreement: 0.75,
                v_s_over_v_m_min: 0.25,
                v_s_over_v_m_max: 0.3125,
                regime_base: Some(Regime::S),
                regime_finer: None,
                runs: 4,
                seed: 0xfeed,
            }),
            ..m.clone()
        };
        let row = v.row(1, false);
        assert_eq!(row.split(',').count(), verify_header().split(',').count());
        assert_eq!(Cell::parse(&row, VERIFIED).unwrap().0.verify, v.verify);
        assert!(Cell::parse(&row, PLAIN).is_none());
        assert!(Cell::parse(&m.row(1, false), VERIFIED).is_none());
    }

    #[test]
    fn periodic_rows_carry_the_history_columns_last() {
        let periodic = Some(PeriodicColumns {
            cycles: 5,
            displacement_over_length_min: 0.1125,
            broadside_deg_min: 77.25,
            turn_deg_max_abs: 3.3,
            stationary_contact_share_min: 0.8125,
            sidewinding: true,
        });
        let c = Cell {
            weight: 300.0,
            torque: 15.0,
            status: crate::studies::optimize::Status::Ok,
            regime: Some(Regime::F),
            regime_detail: "-".into(),
            v_s_over_v_m: 0.25,
            displacement_angle_deg: 80.0,
            max_elevation_over_a: 2.0,
            lifted_arcs_max: 1,
            writhe_max: 0.1,
            lambda_pulse_r2: 0.5,
            max_elevation_over_length: 0.04,
            two_arc_lift_over_a: 1.0,
            lambda_pulse_speed_over_v_m: 1.0,
            writhe_snapshot: 0.0,
            wall_time_s: 1.5,
            reason: String::new(),
            verify: None,
            periodic,
        };
        // The periodic study's header: HEADER, then the history file's periodic columns, the
        // same names in the same order.
        let both = Format {
            verified: true,
            periodic: true,
        };
        let fmt = Format {
            verified: false,
            periodic: true,
        };
        assert_eq!(fmt.header(), format!("{HEADER},{PERIODIC_COLUMNS}"));
        assert!(crate::studies::optimize::HISTORY_HEADER.contains(PERIODIC_COLUMNS));
        assert_eq!(
            both.header(),
            format!("{HEADER},{VERIFY_COLUMNS},{PERIODIC_COLUMNS}")
        );
        for f in [PLAIN, VERIFIED, fmt, both] {
            assert_eq!(Format::of_header(&f.header()), Some(f));
            assert_eq!(f.header().split(',').count(), f.width());
        }
        assert_eq!(Format::of_header("weight,torque"), None);
        let row = c.row(7, true);
        assert!(row.ends_with(",5,0.1125,77.25,3.3,0.8125,yes"), "{row}");
        let (d, h) = Cell::parse(&row, fmt).unwrap();
        assert_eq!((d.periodic, h), (periodic, 7));
        // Not measured (failed, or G = 0): empty fields, read back as none.
        let none = Cell {
            periodic: None,
            ..c.clone()
        };
        let row = none.row(7, true);
        assert!(row.ends_with(",,,,,,"), "{row}");
        assert_eq!(Cell::parse(&row, fmt).unwrap().0.periodic, None);
        // A plain row is not a periodic one and the reverse; a bad verdict is not a row.
        assert!(Cell::parse(&c.row(7, false), fmt).is_none());
        assert!(Cell::parse(&c.row(7, true), PLAIN).is_none());
        let bad = c.row(7, true).replacen(",yes", ",maybe", 1);
        assert!(Cell::parse(&bad, fmt).is_none());
        // After the verification columns in a verified periodic study.
        let v = Cell {
            verify: Some(crate::studies::phase::cell::Verification {
                label_agreement: 1.0,
                v_s_over_v_m_min: 0.25,
                v_s_over_v_m_max: 0.25,
                regime_base: Some(Regime::F),
                regime_finer: Some(Regime::F),
                runs: 2,
                seed: 0xfeed,
            }),
            ..c
        };
        let (d, _) = Cell::parse(&v.row(7, true), both).unwrap();
        assert_eq!((d.verify, d.periodic), (v.verify, periodic));
        // Mixing formats is refused naming the file, the reason and both headers.
        let e = PLAIN
            .check(fmt, Path::new("out/phase.csv"), "cannot append to it")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("out/phase.csv") && e.contains("launch period"),
            "{e}"
        );
        assert!(e.contains(&format!("`{HEADER}`")), "{e}");
        assert!(e.contains(&format!("`{}`", fmt.header())), "{e}");
        assert!(fmt.check(fmt, Path::new("x"), "").is_ok());
    }
}
