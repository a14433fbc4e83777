//! Selecting one item of a study to rerun: a grid cell by its values (`--cell W,G`) or by its
//! indices (`--cell-index i,j`), a size of the growth line (`--growth-size D`).
//!
//! A value matches a grid point when it lies within [`MATCH_RELATIVE`] of it (relative to the
//! larger of the two magnitudes; zero matches only zero), so the values printed in logs and
//! figures (six significant digits) select their point; it must match exactly one point.
//! Errors name the nearest grid points, never the whole axis.

/// Relative distance within which a value given on the command line selects a grid point.
pub const MATCH_RELATIVE: f64 = 1e-3;

/// Grid points named in an error: the nearest ones.
const NEAREST_SHOWN: usize = 3;

/// Whether `v` selects the grid value `x` ([`MATCH_RELATIVE`]).
pub fn matches(v: f64, x: f64) -> bool {
    (x - v).abs() <= MATCH_RELATIVE * x.abs().max(v.abs())
}

/// The nearest points of `grid` to `v`, as "value (index k)", nearest first.
fn nearest(v: f64, grid: &[f64]) -> String {
    let mut by: Vec<(usize, f64)> = grid.iter().copied().enumerate().collect();
    by.sort_by(|a, b| (a.1 - v).abs().total_cmp(&(b.1 - v).abs()));
    by.iter()
        .take(NEAREST_SHOWN)
        .map(|(k, x)| format!("{x} (index {k})"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The index of the one point of `grid` that `v` selects; the error names `name` (e.g.
/// "W", "phase.weight"), the nearest points and the grid's size.
pub fn on_axis(v: f64, grid: &[f64], name: &str, key: &str) -> Result<usize, String> {
    if !v.is_finite() {
        return Err(format!("{name} = {v} is not a finite number"));
    }
    let hits: Vec<usize> = (0..grid.len()).filter(|&k| matches(v, grid[k])).collect();
    match hits.as_slice() {
        [k] => Ok(*k),
        [] => Err(format!(
            "{name} = {v} is not within {MATCH_RELATIVE} (relative) of a value of {key}; nearest of its {}: {}",
            grid.len(),
            nearest(v, grid)
        )),
        many => Err(format!(
            "{name} = {v} is within {MATCH_RELATIVE} of {} values of {key}: {}; give more digits or select by index",
            many.len(),
            many.iter()
                .map(|&k| format!("{} (index {k})", grid[k]))
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// Two comma-separated values `A,B` parsed by `parse`.
fn pair<T: std::str::FromStr>(text: &str) -> Option<(T, T)> {
    let (a, b) = text.split_once(',')?;
    Some((a.trim().parse().ok()?, b.trim().parse().ok()?))
}

/// `--cell W,G`: the indices of the cell of the grid `weight x torque` the values select.
pub fn cell(weight: &[f64], torque: &[f64], text: &str) -> Result<(usize, usize), String> {
    let (w, g) = pair::<f64>(text)
        .ok_or_else(|| format!("--cell {text:?}: not W,G (two numbers, e.g. --cell 0.5,2)"))?;
    let i = on_axis(w, weight, "W", "phase.weight").map_err(|e| format!("--cell {text}: {e}"))?;
    let j = on_axis(g, torque, "G", "phase.torque").map_err(|e| format!("--cell {text}: {e}"))?;
    Ok((i, j))
}

/// `--cell-index i,j`: `i` an index of `weight`, `j` of `torque` (from 0).
pub fn cell_index(weight: &[f64], torque: &[f64], text: &str) -> Result<(usize, usize), String> {
    let (i, j) = pair::<usize>(text).ok_or_else(|| {
        format!("--cell-index {text:?}: not i,j (two indices from 0, e.g. --cell-index 0,2)")
    })?;
    for (k, axis, key) in [(i, weight, "phase.weight"), (j, torque, "phase.torque")] {
        if k >= axis.len() {
            return Err(format!(
                "--cell-index {text}: index {k} is beyond {key}, whose {} values have indices 0 to {}",
                axis.len(),
                axis.len() - 1
            ));
        }
    }
    Ok((i, j))
}

/// `--growth-size D`: the index of the growth line's diameter `D` (m) selects.
pub fn growth_size(diameters: &[f64], text: &str) -> Result<usize, String> {
    let d = text
        .trim()
        .parse::<f64>()
        .map_err(|_| format!("--growth-size {text:?}: not a diameter in metres (e.g. 0.03)"))?;
    on_axis(d, diameters, "D", "phase.growth diameters (m)")
        .map_err(|e| format!("--growth-size {text}: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn log_axis(from: f64, to: f64, count: usize) -> Vec<f64> {
        (0..count)
            .map(|k| from * (to / from).powf(k as f64 / (count - 1) as f64))
            .collect()
    }

    #[test]
    fn printed_values_select_their_point_and_errors_name_the_nearest() {
        // The audit's grid: 316.22776601683796 is selected by its six printed digits.
        let w = log_axis(10.0, 1e4, 7);
        let g = vec![10.0, 15.0];
        assert!((w[3] - 316.22776601683796).abs() < 1e-12);
        assert_eq!(cell(&w, &g, "316.228,10"), Ok((3, 0)));
        assert_eq!(cell(&w, &g, " 1e4 , 15.01 "), Ok((6, 1)));
        // Off by more than 1e-3: refused, naming the nearest three points, not the axis.
        let e = cell(&w, &g, "330,10").unwrap_err();
        assert!(
            e.contains("W = 330") && e.contains("nearest of its 7"),
            "{e}"
        );
        assert!(e.contains(&format!("{} (index 3)", w[3])), "{e}");
        assert_eq!(e.matches("(index").count(), 3, "{e}");
        // A 201-value axis: still three points named.
        let long = log_axis(1.0, 1e3, 201);
        let e = on_axis(0.5, &long, "W", "phase.weight").unwrap_err();
        assert_eq!(e.matches("(index").count(), 3, "{e}");
        assert!(e.len() < 300, "{e}");
        // Two points within 1e-3 of the value: ambiguous, both named.
        let close = [1.0, 1.0005, 2.0];
        let e = on_axis(1.0002, &close, "G", "phase.torque").unwrap_err();
        assert!(e.contains("2 values") && e.contains("(index 1)"), "{e}");
        // Zero selects zero only.
        assert_eq!(on_axis(0.0, &[0.0, 1.0], "G", "phase.torque"), Ok(0));
        assert!(on_axis(1e-9, &[0.0, 1.0], "G", "phase.torque").is_err());
        assert!(cell(&w, &g, "abc").unwrap_err().contains("not W,G"));
    }

    #[test]
    fn indices_select_by_position_and_growth_sizes_by_diameter() {
        let (w, g) = (vec![1.0, 2.0, 3.0], vec![5.0]);
        assert_eq!(cell_index(&w, &g, "2,0"), Ok((2, 0)));
        let e = cell_index(&w, &g, "0,1").unwrap_err();
        assert!(
            e.contains("phase.torque") && e.contains("indices 0 to 0"),
            "{e}"
        );
        assert!(cell_index(&w, &g, "-1,0").is_err());
        let d = [0.01, 0.0316227766, 0.1];
        assert_eq!(growth_size(&d, "0.0316"), Ok(1));
        let e = growth_size(&d, "0.05").unwrap_err();
        assert!(
            e.contains("--growth-size 0.05") && e.contains("0.0316227766 (index 1)"),
            "{e}"
        );
    }
}
