//! Files a run writes into its output directory: `summary.json` (statistics, observables and
//! dimensionless groups), `final.csv` (the final centreline and directors) and
//! `trajectory.npz` (times, positions and twist angles at the output times, loadable by
//! `numpy.load`).
//!
//! Every file is written under a temporary name in the same directory (`.NAME.tmp`, synced)
//! and renamed over its final name only when complete, so a full disk or a crash never leaves
//! a truncated file under a result's name; an I/O error names the file. [`lock`] keeps two
//! runs out of one output directory. A run writes into a [`staging`] folder and swaps its
//! outputs in when they are complete ([`staging::Staging::commit`], which replaces the previous
//! run's [`RUN_OUTPUTS`] all at once or not at all), so an interrupted or failed rerun never
//! destroys the previous results. [`schema`] lists every key of `summary.json` and every column of the
//! studies' CSV files with its unit and meaning.

pub mod ensemble;
pub mod lock;
pub mod movie;
pub mod rundir;
pub mod schema;
pub mod self_contact;
pub mod staging;
pub mod vtk;

pub use self_contact::{self_contact_arrays, SelfContactSummary};

use crate::model::Model;
use crate::rod::vec3::f;
use crate::sim::{Frame, Outcome};
use npyz::WriterBuilder;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::Path;

/// The `summary.json` record.
#[derive(Serialize)]
pub struct Summary {
    /// "completed", "failed" or "interrupted".
    pub status: crate::sim::RunStatus,
    /// Failure message, if the run stopped early.
    pub error: Option<String>,
    /// Problem file.
    pub problem: String,
    /// "dynamic" or "static" (`[time] mode`).
    pub mode: crate::problem::Mode,
    /// Simulated time reached (s).
    pub t_final: f64,
    /// Accepted steps (static: load increments).
    pub steps: usize,
    /// Wall-clock time of the integration (s).
    pub wall_time_s: f64,
    /// Largest |edge strain| over the run.
    pub max_strain: f64,
    /// Total energy at the end (J): kinetic + elastic + gravitational.
    pub energy_final: f64,
    /// Energy split at the end (J).
    pub energies_final: crate::integrator::Energies,
    /// Mean Newton iterations per accepted step.
    pub newton_iterations_mean: f64,
    /// Step halvings.
    pub step_halvings: usize,
    /// Time steps: `adaptive` (error-controlled or fixed), `accepted`, `rejected` (error test
    /// and failed solves; fixed steps: halvings), `rejected_error`, `rejected_solve`,
    /// `dt_min` and `dt_max` (s, smallest and largest accepted step), `error_max` (largest
    /// scaled error estimate of an accepted step, adaptive only).
    pub time_steps: crate::integrator::adaptive::StepStats,
    /// Dimensionless groups.
    pub dimensionless: crate::model::Dimensionless,
    /// Full solver statistics.
    pub stats: crate::integrator::RunStats,
    /// Largest penetration below `z = a/2` (m).
    pub max_penetration: f64,
    /// Self-contact: how close parts of the body came and what the barrier carried.
    pub self_contact: SelfContactSummary,
    /// Displacement of the centroid from the first to the last frame (m).
    pub centroid_displacement: [f64; 3],
    /// Largest slip speed of a node in contact over every accepted step (m/s): contact as in
    /// [`crate::model::Model::in_contact`]; 0 when no node touches.
    pub slip_speed_max: f64,
    /// Summed normal force at the end (N).
    pub normal_force_final: f64,
    /// Mean Clarabel iterations per conic solve.
    pub conic_iterations_mean: f64,
    /// Conic solves per accepted step.
    pub conic_solves_per_step: f64,
    /// Gait observables and regime (present when the run has frames).
    #[serde(flatten)]
    pub observables: Option<crate::observe::Observables>,
    /// Periodic-gait observables, cycle by cycle, and the sidewinding label
    /// ([`crate::observe::periodic`]); absent for a gait without a launch period and for a
    /// failed run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub periodic: Option<crate::observe::periodic::Periodic>,
    /// Tip (head) position at the end (m).
    pub head_final: [f64; 3],
    /// Tail position at the end (m).
    pub tail_final: [f64; 3],
    /// The model chosen for an accuracy target (`--accuracy`, `[accuracy] target`), with the
    /// error estimates and every run of the selection; absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accuracy: Option<AccuracyReport>,
    /// `slither run --ensemble K`: the perturbed runs and the spread of every scalar
    /// observable over them ([`ensemble`], run by `crate::studies::ensemble`); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ensemble: Option<ensemble::Ensemble>,
}

/// How `slither run --accuracy` chose its model (see `crate::studies::accuracy::selection`).
#[derive(Clone, Debug, Serialize)]
pub struct AccuracyReport {
    /// Allowed relative error of `v_s/v_m`.
    pub target: f64,
    /// How time was refined: `"implicit"` (fixed implicit Euler steps, halved) or
    /// `"bdf2-adaptive"` (adaptive BDF2, tolerance divided by ten), from the file's
    /// `[solver] integrator`.
    pub integrator: String,
    /// Chosen mesh (elements).
    pub elements: usize,
    /// Chosen fixed step (s), implicit Euler; absent for adaptive BDF2.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Chosen error tolerance (adaptive BDF2, fraction of L per step); absent for implicit
    /// Euler.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error_tolerance: Option<f64>,
    /// Estimated relative error of `v_s/v_m` from the time stepping at the chosen model (a
    /// bound under the assumptions of [`crate::studies::accuracy::selection::PairEstimate`]).
    pub time_error: f64,
    /// The mesh the time error was measured on (always the chosen one: its time pair is run).
    pub time_error_elements: usize,
    /// Estimated relative error of `v_s/v_m` from the mesh at the chosen model.
    pub mesh_error: f64,
    /// `time_error + mesh_error`.
    pub estimated_error: f64,
    /// Whether the estimate is below the target and both estimates come from converging
    /// runs (false: the refinement hit its limits, or its last differences did not shrink).
    pub met: bool,
    /// Observed order of the time estimate's runs (in the step, or in the tolerance for
    /// adaptive BDF2), from three successive resolutions; absent with two, or when the
    /// differences did not shrink.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_order_observed: Option<f64>,
    /// Observed order in the element length of the mesh estimate's runs, from three meshes;
    /// absent with two, or when the differences did not shrink.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh_order_observed: Option<f64>,
    /// Richardson extrapolation of `v_s/v_m` to the limits of time and mesh refinement: the
    /// chosen value plus the middle of each interval of limits the estimates allow
    /// ([`crate::studies::accuracy::selection::PairEstimate`]).
    pub v_s_over_v_m_extrapolated: f64,
    /// Uncertainty of the extrapolation (absolute): the estimated error of the answer plus
    /// the extrapolation's correction, so its interval contains the answer's. The answer of
    /// the run is the chosen model's `v_s/v_m` (a simulated motion, which every other output
    /// describes, with the error estimate `estimated_error`); the extrapolation is reported
    /// beside it.
    pub v_s_over_v_m_extrapolated_uncertainty: f64,
    /// Every run of the selection, in order.
    pub runs: Vec<AccuracyRun>,
    /// Wall time of the probes (s): every run of the selection except the chosen one, the
    /// price of the estimate.
    pub probes_wall_time_s: f64,
    /// Wall time of all runs of the selection, the chosen one included (s).
    pub wall_time_total_s: f64,
    /// Elapsed time of the whole selection (s): its runs go in parallel, one per core, so
    /// this is less than `wall_time_total_s` on several cores.
    #[serde(default)]
    pub elapsed_s: f64,
}

/// One run of the accuracy selection (also a line of the selection's journal, which reads it
/// back).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct AccuracyRun {
    /// Elements.
    pub elements: usize,
    /// Fixed step (s), implicit Euler.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Error tolerance, adaptive BDF2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_tolerance: Option<f64>,
    /// `v_s/v_m` (NaN when the run failed; JSON writes it as `null`).
    #[serde(deserialize_with = "null_as_nan")]
    pub v_s_over_v_m: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Wall time (s).
    pub wall_time_s: f64,
    /// "ok" or the failure.
    pub status: String,
}

/// A number that JSON wrote as `null` (serde_json writes NaN so) read back as NaN.
fn null_as_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

impl Summary {
    /// Build from a run.
    pub fn new(problem: &Path, m: &Model, o: &Outcome) -> Self {
        let s = &o.state;
        Summary {
            status: o.status(),
            error: o.error.as_ref().map(|e| e.to_string()),
            problem: problem.display().to_string(),
            mode: m.mode,
            t_final: s.t,
            steps: o.stats.steps,
            wall_time_s: o.wall_time_s,
            max_strain: o.max_strain,
            energy_final: o.energies.total,
            energies_final: o.energies,
            newton_iterations_mean: o.stats.newton_iterations as f64 / o.stats.steps.max(1) as f64,
            step_halvings: o.stats.step_halvings,
            time_steps: o.steps,
            dimensionless: m.dimensionless(),
            stats: o.stats.clone(),
            max_penetration: o.max_penetration,
            self_contact: SelfContactSummary::new(m, o),
            centroid_displacement: centroid_displacement(&o.frames),
            slip_speed_max: o.slip_speed_max,
            normal_force_final: o.frames.last().map_or(0.0, |f| f.normal.iter().sum()),
            conic_iterations_mean: o.stats.contact.conic_iterations as f64
                / o.stats.contact.conic_solves.max(1) as f64,
            conic_solves_per_step: o.stats.contact.conic_solves as f64
                / o.stats.steps.max(1) as f64,
            observables: None,
            periodic: None,
            head_final: s.node(m.real.start),
            tail_final: s.node(m.real.end - 1),
            accuracy: None,
            ensemble: None,
        }
    }
}

/// Files and folders a `slither run` writes into its output directory (a rerun's commit,
/// [`staging::Staging::commit`], replaces or removes them, with `slither movie`'s renderings:
/// [`staging::is_run_output`]; in `vtk/` only its `frame_*.vtp` files and `frames.pvd`).
pub const RUN_OUTPUTS: &[&str] = &[
    "summary.json",
    "final.csv",
    "trajectory.npz",
    "kymograph_elevation.png",
    "kymograph_slip.png",
    "kymograph_lambda.png",
    "snapshots.png",
    "topology.png",
    "movie.gif",
    "tracks.png",
    "tracks.svg",
    "vtk",
];

/// The error `e` with the file's path in front.
fn context(path: &Path, e: std::io::Error) -> std::io::Error {
    std::io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

/// The temporary name of `path`: `.NAME.tmp` beside it (`.NAME.tmp.png` for a PNG and
/// `.NAME.tmp.svg` for an SVG, whose backend or encoder is chosen by the extension).
fn tmp_path(path: &Path) -> std::path::PathBuf {
    let name = path
        .file_name()
        .map_or("out".into(), |n| n.to_string_lossy().into_owned());
    if let Some(stem) = name.strip_suffix(".png") {
        path.with_file_name(format!(".{stem}.tmp.png"))
    } else if let Some(stem) = name.strip_suffix(".svg") {
        path.with_file_name(format!(".{stem}.tmp.svg"))
    } else {
        path.with_file_name(format!(".{name}.tmp"))
    }
}

/// Write `bytes` to `path` through its temporary name: written in one call, synced, then
/// renamed over `path`. On an error the temporary file is removed and `path` is untouched;
/// the error names the file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = tmp_path(path);
    let written = std::fs::File::create(&tmp).and_then(|mut f| {
        f.write_all(bytes)?;
        f.sync_all()
    });
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        return Err(context(path, e));
    }
    std::fs::rename(&tmp, path).map_err(|e| context(path, e))
}

/// Draw a figure into `path`'s temporary name with `draw`, then rename it over `path`.
pub(crate) fn figure<E: std::fmt::Display>(
    path: &Path,
    draw: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<(), String> {
    let tmp = tmp_path(path);
    if let Err(e) = draw(&tmp) {
        let _ = std::fs::remove_file(&tmp);
        return Err(format!("{}: {e}", path.display()));
    }
    std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
}

/// The `summary.json` text. A failed run reports its observables (gait and regime) as `null`:
/// they describe a whole run, and one cut short has not measured them.
pub fn summary_json(s: &Summary) -> String {
    let mut v = serde_json::to_value(s).expect("summary serialises");
    if s.error.is_some() {
        if let (Some(obj), serde_json::Value::Object(keys)) = (
            v.as_object_mut(),
            serde_json::to_value(crate::observe::Observables::default())
                .expect("observables serialise"),
        ) {
            for key in keys.keys() {
                obj.insert(key.clone(), serde_json::Value::Null);
            }
        }
    }
    serde_json::to_string_pretty(&v).expect("summary serialises") + "\n"
}

/// Write `summary.json` (see [`summary_json`]).
pub fn write_summary(dir: &Path, s: &Summary) -> std::io::Result<()> {
    write_atomic(&dir.join("summary.json"), summary_json(s).as_bytes())
}

/// Write `final.csv`: header `s,x,y,z,d1x,d1y,d1z`, one row per real node; row i's d1 is the
/// director of the edge starting at node i (the last row repeats the last edge's).
pub fn write_final_csv(dir: &Path, m: &Model, o: &Outcome) -> std::io::Result<()> {
    let mut w = Vec::new();
    writeln!(w, "s,x,y,z,d1x,d1y,d1z")?;
    let s = &o.state;
    let last_edge = m.real.end - 2;
    for i in m.real.clone() {
        let x = s.node(i);
        let (d1, _) = s.directors(i.min(last_edge));
        writeln!(
            w,
            "{:.17e},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e},{:.17e}",
            m.arc_length(i),
            x[0],
            x[1],
            x[2],
            d1[0],
            d1[1],
            d1[2]
        )?;
    }
    write_atomic(&dir.join("final.csv"), &w)
}

type Npz = npyz::npz::NpzWriter<std::io::Cursor<Vec<u8>>>;

fn put(
    npz: &mut Npz,
    name: &str,
    shape: &[u64],
    data: impl IntoIterator<Item = f64>,
) -> std::io::Result<()> {
    // A fixed timestamp (1980-01-01, zip's epoch): the same run writes the same bytes, whenever
    // it ran (the archive's default is the time of writing).
    let opts = npyz::zip::write::FileOptions::default()
        .compression_method(npyz::zip::CompressionMethod::Stored)
        .last_modified_time(npyz::zip::DateTime::default());
    let mut w = npz
        .array::<f64>(name, opts)?
        .default_dtype()
        .shape(shape)
        .begin_nd()?;
    w.extend(data)?;
    w.finish()
}

/// Write `trajectory.npz` with `t` (F), `x` (F x nodes x 3), `theta` (F x edges),
/// `v` (F x nodes x 3), `s` (nodes), `closest_distance` (F: the closest centreline distance
/// between parts of the body more than `2a` apart along it, m), `self_contact` (F x nodes: 1
/// where a node touches another part of the body, within the activation gap), the one-element arrays of [`movie::movie_scalars`]
/// (`diameter`, `gait_period`, `gait_speed`, `stuck_speed`) and any extra per-frame arrays
/// `(name, per-node values)`.
pub fn write_trajectory(
    dir: &Path,
    m: &Model,
    frames: &[Frame],
    extra: &[(&str, Vec<Vec<f64>>)],
) -> std::io::Result<()> {
    // Assembled in memory (an in-memory zip cannot fail half-way), then written atomically.
    let mut npz = npyz::npz::NpzWriter::new(std::io::Cursor::new(Vec::new()));
    let nf = frames.len() as u64;
    let nn = m.real.len() as u64;
    let ne = nn - 1;
    put(&mut npz, "t", &[nf], frames.iter().map(|fr| fr.t))?;
    put(
        &mut npz,
        "s",
        &[nn],
        m.real.clone().map(|i| m.arc_length(i)),
    )?;
    put(
        &mut npz,
        "x",
        &[nf, nn, 3],
        frames.iter().flat_map(|fr| fr.x.iter().flatten().copied()),
    )?;
    put(
        &mut npz,
        "v",
        &[nf, nn, 3],
        frames.iter().flat_map(|fr| fr.v.iter().flatten().copied()),
    )?;
    put(
        &mut npz,
        "theta",
        &[nf, ne],
        frames.iter().flat_map(|fr| fr.theta.iter().copied()),
    )?;
    put(
        &mut npz,
        "normal_force",
        &[nf, nn],
        frames.iter().flat_map(|fr| fr.normal.iter().copied()),
    )?;
    // Slip velocity: the horizontal velocity of nodes in contact (zero elsewhere).
    put(
        &mut npz,
        "slip_velocity",
        &[nf, nn, 3],
        frames.iter().flat_map(|fr| {
            fr.v.iter().zip(&fr.normal).flat_map(|(v, n)| {
                if m.in_contact(*n) {
                    [v[0], v[1], 0.0]
                } else {
                    [0.0; 3]
                }
            })
        }),
    )?;
    // Self-contact per frame: the closest distance (m) and the touching nodes.
    let (closest, touching) = self_contact_arrays(m, frames);
    put(&mut npz, "closest_distance", &[nf], closest)?;
    put(&mut npz, "self_contact", &[nf, nn], touching)?;
    for (name, v) in movie::movie_scalars(m) {
        put(&mut npz, name, &[1], [v])?;
    }
    for (name, data) in extra {
        let k = data.first().map_or(0, |r| r.len()) as u64;
        put(
            &mut npz,
            name,
            &[data.len() as u64, k],
            data.iter().flatten().copied(),
        )?;
    }
    let bytes = npz
        .zip_writer()
        .finish()
        .map_err(std::io::Error::other)?
        .into_inner();
    write_atomic(&dir.join("trajectory.npz"), &bytes)
}

/// Centroid displacement between the first and last frame (m).
pub fn centroid_displacement(frames: &[Frame]) -> [f64; 3] {
    let c = |fr: &Frame| {
        let mut c = [0.0; 3];
        for x in &fr.x {
            c = f::add(c, *x);
        }
        f::scale(c, 1.0 / fr.x.len() as f64)
    };
    match (frames.first(), frames.last()) {
        (Some(a), Some(b)) => f::sub(c(b), c(a)),
        _ => [0.0; 3],
    }
}

/// Horizontal axis of the kymographs: which end is the head.
const S_DESC: &str = "arc length s (m), head at s = 0";

/// The slip kymograph's colours end at this quantile of the slip speeds (one fast node at the
/// body's end does not set the scale); the colour bar notes the clip.
pub const SLIP_CLIP_QUANTILE: f64 = 0.99;

/// Slip speed below which a contact counts as stuck in the slip kymograph (m/s): the
/// solver's own sticking test, a slip over one step below `contact_tolerance * a`.
pub fn stuck_speed(m: &Model) -> f64 {
    m.solver.contact_tolerance * m.diameter / m.dt.max(f64::MIN_POSITIVE)
}

/// Figures and ParaView files of a run: kymographs of elevation, slip speed and local link
/// density over s and t/T, top and side snapshots, Tw/Wr/Lk over time (PNG), and `vtk/`.
pub fn write_figures(
    dir: &Path,
    m: &Model,
    frames: &[Frame],
    fl: &crate::observe::Fields,
) -> Result<(), String> {
    use crate::plot;
    if frames.len() < 2 {
        return Ok(());
    }
    let has_gait = m.gait.kind != crate::gait::Kind::None;
    let period = if has_gait {
        m.gait.pulse_time(m.length)
    } else {
        fl.t.last().copied().unwrap_or(1.0).max(1e-300)
    };
    // Every kymograph says which end is the head and what T is.
    let t_desc = if has_gait {
        format!(
            "t/T (T = L/v_m = {} s, the pulse time)",
            crate::problem::num(period)
        )
    } else {
        format!("t/T (T = {} s, the duration)", crate::problem::num(period))
    };
    let style = |diverging: bool| plot::KymographStyle {
        diverging,
        s_desc: Some(S_DESC),
        t_desc: Some(&t_desc),
        ..Default::default()
    };
    let t_over: Vec<f64> = fl.t.iter().map(|t| t / period).collect();
    let a = m.diameter;
    let elev_a: Vec<Vec<f64>> = fl
        .elevation
        .iter()
        .map(|r| r.iter().map(|e| e / a).collect())
        .collect();
    figure(&dir.join("kymograph_elevation.png"), |p| {
        plot::kymograph_styled(
            p,
            "Elevation",
            "(z - a/2) / a",
            &fl.s,
            &t_over,
            &elev_a,
            &style(false),
        )
        .map(|_| ())
    })?;
    let stuck = stuck_speed(m);
    let stuck_label = format!("stuck (< {} m/s)", crate::problem::num(stuck));
    figure(&dir.join("kymograph_slip.png"), |p| {
        plot::kymograph_styled(
            p,
            "Slip speed of the nodes in contact",
            "|v| (m/s)",
            &fl.s,
            &t_over,
            &fl.slip,
            &plot::KymographStyle {
                from_zero: true,
                clip_quantile: Some(SLIP_CLIP_QUANTILE),
                nan_label: Some("in the air"),
                floor: Some((stuck, &stuck_label)),
                ..style(false)
            },
        )
        .map(|_| ())
    })?;
    if !fl.s_window.is_empty() {
        figure(&dir.join("kymograph_lambda.png"), |p| {
            plot::kymograph_styled(
                p,
                "Local link density (window L/10)",
                "lambda (turns/m)",
                &fl.s_window,
                &t_over,
                &fl.lambda,
                &style(true),
            )
            .map(|_| ())
        })?;
    }
    let picks: Vec<usize> = {
        let n = frames.len();
        let k = 6.min(n);
        (0..k).map(|j| j * (n - 1) / (k - 1).max(1)).collect()
    };
    let snaps: Vec<(f64, Vec<[f64; 3]>)> = picks
        .iter()
        .map(|&j| (frames[j].t, frames[j].x.clone()))
        .collect();
    figure(&dir.join("snapshots.png"), |p| {
        plot::snapshots(p, "Body: top and side views", &snaps)
    })?;
    figure(&dir.join("topology.png"), |p| {
        plot::series(
            p,
            "Twist, writhe and link of the ribbon (r, d1)",
            "turns",
            &fl.t,
            &[
                ("Tw", fl.tw.clone()),
                ("Wr", fl.wr.clone()),
                ("Lk = Tw + Wr", fl.lk.clone()),
            ],
        )
    })?;
    // ParaView: elevation, slip speed and lambda interpolated to the nodes.
    let lambda_nodes = movie::lambda_at_nodes(&fl.s, &fl.s_window, &fl.lambda);
    let positions: Vec<Vec<[f64; 3]>> = frames.iter().map(|f| f.x.clone()).collect();
    // Written into `.vtk.tmp/vtk/` and moved to `vtk/` when complete.
    let staging = dir.join(".vtk.tmp");
    let _ = std::fs::remove_dir_all(&staging);
    let vtk_dir = dir.join("vtk");
    vtk::write_vtk(
        &staging,
        &fl.t,
        &positions,
        &[
            ("elevation", fl.elevation.clone()),
            ("slip_speed", fl.slip.clone()),
            ("lambda", lambda_nodes),
        ],
    )
    .and_then(|_| {
        let _ = std::fs::remove_dir(&vtk_dir);
        std::fs::rename(staging.join("vtk"), &vtk_dir)
    })
    .map_err(|e| {
        let _ = std::fs::remove_dir_all(&staging);
        format!("{}: {e}", vtk_dir.display())
    })?;
    let _ = std::fs::remove_dir_all(&staging);
    Ok(())
}
