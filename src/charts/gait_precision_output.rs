//! The work-precision chart's files: its CSV, JSON and figures.

use super::*;

/// Write `gait_precision.csv`, `gait_precision.json`, `gait_precision.png` (error of
/// `v_s/v_m` against wall time) and `gait_precision_centreline.png` into `dir`, and with
/// external runs `gait_precision_external.csv` (they are drawn on `gait_precision.png` only).
pub fn write_gait_precision(dir: &Path, g: &GaitPrecision) -> Result<(), ChartError> {
    std::fs::create_dir_all(dir).map_err(|source| ChartError::Io {
        path: dir.into(),
        source,
    })?;
    let csv = points_csv(g);
    write(&dir.join("gait_precision.csv"), &csv)?;
    if !g.external.is_empty() {
        write(
            &dir.join("gait_precision_external.csv"),
            &super::external::external_csv(&g.external),
        )?;
    }
    let json = serde_json::to_string_pretty(g).expect("serialisable");
    write(&dir.join("gait_precision.json"), &json)?;
    // One line per method and mesh, its points in order of cost (wall time).
    let series = |method: GaitMethod, n: usize, y: &dyn Fn(&GaitPoint) -> f64| -> Vec<(f64, f64)> {
        let mut v: Vec<(f64, f64)> = g
            .points
            .iter()
            .filter(|p| p.run.method == method && p.run.elements == n)
            .map(|p| (p.run.wall_s, y(p)))
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v
    };
    let mut meshes: Vec<usize> = g.points.iter().map(|p| p.run.elements).collect();
    meshes.sort_unstable();
    meshes.dedup();
    let walls: Vec<f64> = g
        .points
        .iter()
        .map(|p| p.run.wall_s)
        .chain(g.external.iter().map(|p| p.wall_s))
        .collect();
    let wmin = walls.iter().copied().fold(f64::INFINITY, f64::min);
    let wmax = walls.iter().copied().fold(0.0, f64::max);
    let names = [
        (
            GaitMethod::Fixed(IntegratorKind::ImplicitEuler),
            "implicit Euler",
        ),
        (GaitMethod::Fixed(IntegratorKind::Bdf2), "BDF2"),
        (GaitMethod::Adaptive(IntegratorKind::Bdf2), "adaptive BDF2"),
    ];
    for (file, label, y) in [
        (
            "gait_precision.png",
            "relative error of v_s/v_m against the converged value",
            &(|p: &GaitPoint| p.v_error) as &dyn Fn(&GaitPoint) -> f64,
        ),
        (
            "gait_precision_centreline.png",
            "final centreline error / L (max node distance)",
            &(|p: &GaitPoint| p.x_error) as &dyn Fn(&GaitPoint) -> f64,
        ),
    ] {
        let mut lines: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
        for (method, name) in names {
            for &n in &meshes {
                let v = series(method, n, y);
                if !v.is_empty() {
                    lines.push((format!("{name}, {n} el."), v));
                }
            }
        }
        let acc: Vec<(f64, f64)> = g
            .points
            .iter()
            .filter(|p| p.run.method == GaitMethod::Accuracy)
            .map(|p| (p.run.wall_s, y(p)))
            .collect();
        if let Some(a) = g
            .points
            .iter()
            .find(|p| p.run.method == GaitMethod::Accuracy)
        {
            lines.push((
                format!(
                    "--accuracy {} (chose {} el., all probes)",
                    g.options.accuracy_target.unwrap_or(f64::NAN),
                    a.run.elements
                ),
                acc,
            ));
        }
        // Another code's runs: one line per code and mesh, triangles, against its own
        // converged value (the centreline chart has no external data).
        let circles = lines.len();
        if file == "gait_precision.png" {
            for (code, n) in g.external_lines() {
                let mut v: Vec<(f64, f64)> = g
                    .external
                    .iter()
                    .filter(|p| p.run.code == code && p.run.elements == n)
                    .map(|p| (p.wall_s, p.v_error))
                    .collect();
                v.sort_by(|a, b| a.0.total_cmp(&b.0));
                lines.push((format!("{code}, {n} el. (vs its own converged value)"), v));
            }
        }
        let triangles = lines.len() - circles;
        if file == "gait_precision.png" {
            lines.push(("1 % error".into(), vec![(wmin, 0.01), (wmax, 0.01)]));
            lines.push((
                "reference scatter".into(),
                vec![(wmin, g.reference.scatter), (wmax, g.reference.scatter)],
            ));
        }
        // Circles for slither's lines, triangles for another code's.
        let lines: Vec<plot::MarkedSeries> = lines
            .iter()
            .enumerate()
            .map(|(k, (n, v))| {
                let m = if (circles..circles + triangles).contains(&k) {
                    plot::Marker::Triangle
                } else {
                    plot::Marker::Circle
                };
                (n.as_str(), v.clone(), m)
            })
            .collect();
        let (title, wall_label) = titles(g);
        plot::xy_marked(
            &dir.join(file),
            &title,
            &wall_label,
            label,
            &lines,
            true,
            true,
        )?;
    }
    Ok(())
}

/// `gait_precision.csv`: one row per run with its errors.
fn points_csv(g: &GaitPrecision) -> String {
    let mut csv = String::from(
        "method,elements,dt_s,tolerance,steps,rejected,dt_min_s,dt_max_s,wall_s,v_s_over_v_m,v_error,x_error_over_L,status\n",
    );
    for p in &g.points {
        let q = &p.run;
        let _ = writeln!(
            csv,
            "{},{},{:e},{:e},{},{},{:e},{:e},{:e},{:e},{:e},{:e},\"{}\"",
            q.method,
            q.elements,
            q.dt,
            q.tolerance.unwrap_or(f64::NAN),
            q.steps,
            q.rejected,
            q.dt_range.0,
            q.dt_range.1,
            q.wall_s,
            q.v_ratio,
            p.v_error,
            p.x_error,
            q.status.replace('"', "'")
        );
    }
    csv
}

/// The figures' title and wall-time axis label: with another code's points the title names
/// whose converged value the lines use (and drops "Work-precision" to stay within the
/// figure's width).
fn titles(g: &GaitPrecision) -> (String, String) {
    let ref_dt = g.reference.runs.last().map_or(f64::NAN, |r| r.dt);
    let title = if g.external.is_empty() {
        format!(
            "Work-precision: {} (T = {} s; converged: {} el., dt {ref_dt:.1e} s)",
            g.scene, g.duration, g.elements
        )
    } else {
        format!(
            "{}, T = {} s (slither converged: {} el., dt {ref_dt:.1e} s)",
            g.scene, g.duration, g.elements
        )
    };
    let wall_label = if g.external.is_empty() {
        "wall time (s)".to_string()
    } else {
        format!(
            "wall time for the scene's {} s (s; external: wall s per simulated s x {})",
            g.duration, g.duration
        )
    };
    (title, wall_label)
}
