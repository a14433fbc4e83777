//! The growth line of a phase study (`[phase] growth = { ... }`): the base snake grown
//! geometrically similar, from one diameter to another, at fixed Young's modulus, density,
//! aspect ratio `L/a`, friction and pulse speed `v_m`, with the muscle stress of an allometric
//! law (by default Moon 2007 for snakes, `Gamma = 7.72 kPa (a / 1 cm)^1.39`).
//!
//! Growing the snake by `s = a / a0` keeps `L/a`; `B` grows like `s^4`, so
//! `W = rho g a^2 L^3 / B` grows like `s` and `G = Gamma a^3 L / B` like `Gamma(a) / Gamma0`.
//! The ratio of the pulse time `L / v_m` to the elastic time `L^2 sqrt(rho A / B)` is
//! `v_m (L/a) 4 sqrt(rho / E)`: unchanged, since `v_m` and `E` are. So the snake of diameter
//! `a` is, in every dimensionless group, the base's cell `(W(a), G(a))` under the protocol
//! `similar = true` with `W` set through `B` ([`PROTOCOL`]), and that is how it is simulated:
//! on the same mesh and at the same step per pulse as the grid's cells. [`grown_problem`] is
//! the snake itself in SI units; a test runs both and compares.
//!
//! The line's simulations are kept in `growth.csv` (rows as `phase.csv`'s, resumable), its
//! values and the size at which the S-start stops in `growth.json`, and its figure in
//! `growth.png` / `growth.svg` ([`crate::plot::growth`]).
pub use super::allometry::{
    grown_problem, scale_times, Growth, GrowthPoint, MAX_SIZES, MOON_EXPONENT, MOON_REFERENCE,
    MOON_STRESS,
};
use super::cell::{simulate_verified, Cell};
use super::csv::{append_rows, read_phase_csv, simulate_appending, Format};
use super::file::{Protocol, Verify, WeightVia};
use super::PhaseError;
use crate::observe::Regime;
use crate::problem::Problem;
use crate::studies::optimize::Status;
use serde::Serialize;
use std::path::Path;

/// How the growth line's snakes are made from the base: `W` through `B`, dynamically similar.
pub const PROTOCOL: Protocol = Protocol {
    weight_via: WeightVia::Stiffness,
    similar: true,
};

/// Where the S-start stops along the line: between the last size with a confident S label
/// and the next size, which is not S.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stop {
    /// The largest diameter (m) that S-starts, below the first larger size that does not.
    pub last_s: f64,
    /// That next diameter (m), and its label (`-`: failed or not confident).
    pub next: f64,
    /// The next size's label.
    pub next_label: String,
}

/// What `growth.json` holds.
#[derive(Clone, Debug, Serialize)]
pub struct GrowthLine {
    /// The law and the sizes.
    pub growth: Growth,
    /// The base's Young's modulus (Pa), kept along the line.
    pub young_modulus: f64,
    /// The base's diameter (m).
    pub base_diameter: f64,
    /// Every size with its cell's values.
    pub points: Vec<GrowthRow>,
    /// Every place where the confident S label ends going to larger sizes (none: the line
    /// never S-starts, or S-starts up to its largest size).
    pub stops: Vec<Stop>,
    /// The diameters (m) with a confident S label.
    pub s_diameters: Vec<f64>,
    /// Sizes whose simulation failed (every one of them: no verdict, and `slither phase` and
    /// `merge` exit 3).
    pub failed_sizes: usize,
    /// The answer in one sentence.
    pub verdict: String,
    /// The cells' verification the line ran with (`null`: none), as the phase file's
    /// `verify`.
    pub verify: Option<Verify>,
    /// How the sizes' problems are made (always [`PROTOCOL`]: `W` through `B`, similar).
    pub protocol: Protocol,
}

impl GrowthLine {
    /// Whether every size failed: the line has no answer (exit 3 on the command line).
    pub fn all_failed(&self) -> bool {
        !self.points.is_empty() && self.failed_sizes == self.points.len()
    }
}

/// One size of `growth.json`.
#[derive(Clone, Debug, Serialize)]
pub struct GrowthRow {
    /// The size.
    #[serde(flatten)]
    pub point: GrowthPoint,
    /// `W / G`.
    pub w_over_g: f64,
    /// The cell's label (`-`: failed).
    pub regime: String,
    /// Every run of the cell agrees on the label (always true without verification).
    pub confident: bool,
    /// The fraction of the cell's runs giving its label (1 without verification).
    pub label_agreement: f64,
    /// `v_s / v_m`.
    pub v_s_over_v_m: f64,
    /// Smallest and largest `v_s/v_m` over the cell's runs (the value itself without
    /// verification).
    pub v_s_over_v_m_range: [f64; 2],
}

impl GrowthLine {
    /// The line's values from its points and cells (in diameter order).
    pub fn new(base: &Problem, growth: &Growth, cells: &[(GrowthPoint, Cell)]) -> Self {
        let points: Vec<GrowthRow> = cells
            .iter()
            .map(|(p, c)| {
                let v = c.v_s_over_v_m;
                let (agreement, range) = c.verify.as_ref().map_or((1.0, [v, v]), |x| {
                    (x.label_agreement, [x.v_s_over_v_m_min, x.v_s_over_v_m_max])
                });
                GrowthRow {
                    point: *p,
                    w_over_g: p.weight / p.torque,
                    regime: c.regime.map_or("-".into(), |r| r.to_string()),
                    confident: c.status == Status::Ok && c.unanimous(),
                    label_agreement: agreement,
                    v_s_over_v_m: v,
                    v_s_over_v_m_range: range,
                }
            })
            .collect();
        let is_s = |r: &GrowthRow| r.confident && r.regime == Regime::S.as_str();
        let stops: Vec<Stop> = points
            .windows(2)
            .filter(|w| is_s(&w[0]) && !is_s(&w[1]))
            .map(|w| Stop {
                last_s: w[0].point.diameter,
                next: w[1].point.diameter,
                next_label: if w[1].confident {
                    w[1].regime.clone()
                } else {
                    format!("{} (not confident)", w[1].regime)
                },
            })
            .collect();
        // Centimetres to 4 significant digits, without trailing zeros.
        let cm = |a: f64| {
            let s = format!("{:.4}", a * 100.0);
            format!("{} cm", s.trim_end_matches('0').trim_end_matches('.'))
        };
        let (first, last) = (
            growth.diameters[0],
            growth.diameters[growth.diameters.len() - 1],
        );
        let s_diameters: Vec<f64> = points
            .iter()
            .filter(|r| is_s(r))
            .map(|r| r.point.diameter)
            .collect();
        let label = |r: &GrowthRow| {
            if r.confident {
                r.regime.clone()
            } else {
                format!("{} (not confident)", r.regime)
            }
        };
        let failed_sizes = cells.iter().filter(|(_, c)| c.status != Status::Ok).count();
        let verdict = if failed_sizes == points.len() && !points.is_empty() {
            format!(
                "every size between {} and {} failed (see growth.csv's reasons): no verdict",
                cm(first),
                cm(last)
            )
        } else if s_diameters.is_empty() {
            format!(
                "no size between {} and {} S-starts (confidently)",
                cm(first),
                cm(last)
            )
        } else {
            let list: Vec<String> = s_diameters.iter().map(|&a| cm(a)).collect();
            let mut v = format!(
                "confident S at {} of {} sizes ({})",
                s_diameters.len(),
                points.len(),
                list.join(", ")
            );
            match stops.first() {
                None => {
                    v += &format!(
                    "; no threshold between {} and {}: the S-start does not stop along the line",
                    cm(first),
                    cm(last)
                )
                }
                Some(s) => {
                    v += &format!(
                        "; the S-start stops between {} (S) and {} ({})",
                        cm(s.last_s),
                        cm(s.next),
                        s.next_label
                    );
                    if stops.len() > 1 {
                        v += &format!("; it stops {} times along the line", stops.len());
                    }
                }
            }
            // Below the smallest S-start: the size under it.
            if let Some(k) = points.iter().position(is_s).filter(|&k| k > 0) {
                let below = &points[k - 1];
                v += &format!(
                    "; below {}, {} is {}",
                    cm(points[k].point.diameter),
                    cm(below.point.diameter),
                    label(below)
                );
            }
            v
        };
        GrowthLine {
            growth: growth.clone(),
            young_modulus: Growth::young_modulus(base),
            base_diameter: base.rod.diameter,
            points,
            stops,
            s_diameters,
            failed_sizes,
            verdict,
            verify: None,
            protocol: PROTOCOL,
        }
    }
}

/// Simulate the growth line of `base` into `out/growth.csv` (reusing the rows of the hash
/// `hash`, as `phase.csv`'s: the base, the protocol [`PROTOCOL`] and the verification), each
/// size verified as a grid cell would be, in parallel; then write `growth.json`. Returns
/// the line and how many sizes were simulated now. `report(done, cell)` after each new one.
pub fn run(
    base: &Problem,
    base_hash: u64,
    growth: &Growth,
    verify: Option<&Verify>,
    out: &Path,
    report: &(dyn Fn(usize, &Cell) + Sync),
) -> Result<(GrowthLine, usize), PhaseError> {
    let io = |file: &Path| {
        let file = file.to_path_buf();
        move |source| PhaseError::Io {
            file: file.clone(),
            source,
        }
    };
    let hash = PROTOCOL.row_hash(base_hash);
    let hash = verify.map_or(hash, |v| v.row_hash(hash));
    let csv = out.join("growth.csv");
    let old = read_phase_csv(&csv, hash)?;
    let format = Format::of(base, verify);
    let file = append_rows(&csv, old.fresh, old.format, format)?;
    let points = growth.points(base);
    let key = |p: &GrowthPoint| (p.weight.to_bits(), p.torque.to_bits());
    let todo: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| !old.cells.contains_key(&key(p)))
        .map(|p| (p.weight, p.torque))
        .collect();
    let new = simulate_appending(
        &todo,
        &|w, g| simulate_verified(base, w, g, verify, PROTOCOL),
        file,
        &csv,
        hash,
        format.periodic,
        report,
    )?;
    let simulated = new.len();
    let mut done = old.cells;
    for c in new {
        done.insert((c.weight.to_bits(), c.torque.to_bits()), c);
    }
    let cells: Vec<(GrowthPoint, Cell)> =
        points.iter().map(|p| (*p, done[&key(p)].clone())).collect();
    let line = GrowthLine {
        verify: verify.copied(),
        ..GrowthLine::new(base, growth, &cells)
    };
    let json = out.join("growth.json");
    let text = serde_json::to_string_pretty(&line).expect("serialisable") + "\n";
    std::fs::write(&json, text).map_err(io(&json))?;
    Ok((line, simulated))
}
