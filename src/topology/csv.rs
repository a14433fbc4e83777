//! The framed-curve CSV reader of `slither topology`.

use super::*;

/// A closed curve's last row repeats its first node when they are closer than this fraction of
/// the mean edge length (such a row is dropped by [`parse_curve_csv`]).
pub const REPEAT_TOL: f64 = 1e-9;

/// [`parse_curve_csv`] rejects a director whose component perpendicular to its edge is at most
/// this fraction of its length (within about 1e-6 rad of the tangent): twist is measured from
/// that component, so it would be round-off.
pub const ALONG_TANGENT_TOL: f64 = 1e-6;

/// [`parse_curve_csv`] rejects a curve that doubles back on itself: two consecutive edges
/// whose unit tangents satisfy `1 + t_prev . t_next` at most this (a turn within about
/// 1.4e-3 rad of a full reversal). Parallel transport from an edge to its antiparallel
/// successor is undefined (the curvature binormal `2 e x f / (|e||f| + e.f)` divides by zero),
/// so twist and writhe would be arbitrary there.
pub const ANTIPARALLEL_TOL: f64 = 1e-6;

/// [`parse_curve_csv`] rejects a value whose magnitude exceeds this (1e30, in the curve's
/// length unit; the observable universe is about 1e27 m). Writhe multiplies up to four
/// coordinates, so a finite but huge value (say 1e85) overflows to infinity or NaN there.
pub const MAX_ABS: f64 = 1e30;

/// Parse CSV text: a header row, then rows `x,y,z,d1x,d1y,d1z` (row `i`'s
/// `d1` is the director of the edge starting at node `i`; for an open curve
/// the last row's `d1` is ignored). Blank lines are skipped; fields may be
/// surrounded by whitespace. A header `s,x,y,z,d1x,d1y,d1z` (the `final.csv` of
/// `slither run`) marks a leading arc-length column, which is skipped.
///
/// Errors carry the 1-based line number and say what is wrong: wrong field
/// count, a field that is not a number, a non-finite value or one beyond [`MAX_ABS`], a zero director
/// (for rows whose director is used), a first line that looks like data
/// instead of a header, fewer than 3 data rows, a zero-length edge (a node repeated), a
/// director along its edge's tangent (see [`ALONG_TANGENT_TOL`]), or a curve that doubles
/// back (antiparallel consecutive edges, see [`ANTIPARALLEL_TOL`]). A UTF-8 byte order mark
/// before the header is skipped.
///
/// With `closed`, a last row that repeats the first node (within [`REPEAT_TOL`] of the mean
/// edge length) is dropped: the closing edge is implied and must not be written twice.
pub fn parse_curve_csv(text: &str, closed: bool) -> Result<FramedCurve, CsvError> {
    const NAMES: [&str; 6] = ["x", "y", "z", "d1x", "d1y", "d1z"];
    let mut nodes: Vec<V3> = Vec::new();
    let mut d1: Vec<V3> = Vec::new();
    let mut row_lines: Vec<usize> = Vec::new();
    let mut last_line = 0;
    // A leading `s` column (as in `slither run`'s final.csv: s,x,y,z,d1x,d1y,d1z) is skipped.
    let mut skip = 0;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    for (idx, raw) in text.lines().enumerate() {
        let line_no = idx + 1;
        last_line = line_no;
        let line = raw.trim();
        if idx == 0 {
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            if fields.len() == 6 && fields.iter().all(|f| f.parse::<f64>().is_ok()) {
                return Err(CsvError {
                    line: 1,
                    message: "first line looks like data; a header row \
                              (e.g. x,y,z,d1x,d1y,d1z) is required"
                        .to_string(),
                });
            }
            if fields.len() == 7 && fields[0] == "s" {
                skip = 1;
            }
            continue;
        }
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).skip(skip).collect();
        if fields.len() != 6 {
            return Err(CsvError {
                line: line_no,
                message: format!(
                    "expected 6 fields (x,y,z,d1x,d1y,d1z), found {}",
                    fields.len()
                ),
            });
        }
        let mut v = [0.0; 6];
        for (k, f) in fields.iter().enumerate() {
            let x: f64 = f.parse().map_err(|_| CsvError {
                line: line_no,
                message: format!("field {} ({}) is not a number: {:?}", k + 1, NAMES[k], f),
            })?;
            if !x.is_finite() {
                return Err(CsvError {
                    line: line_no,
                    message: format!("field {} ({}) is not finite: {:?}", k + 1, NAMES[k], f),
                });
            }
            if x.abs() > MAX_ABS {
                return Err(CsvError {
                    line: line_no,
                    message: format!(
                        "field {} ({}) = {:?} is out of range: allowed magnitude at most {MAX_ABS:e}",
                        k + 1,
                        NAMES[k],
                        f
                    ),
                });
            }
            v[k] = x;
        }
        nodes.push([v[0], v[1], v[2]]);
        d1.push([v[3], v[4], v[5]]);
        row_lines.push(line_no);
    }
    if last_line == 0 {
        return Err(CsvError {
            line: 1,
            message: "empty input: missing header row".to_string(),
        });
    }
    if nodes.len() < 3 {
        return Err(CsvError {
            line: last_line,
            message: format!("fewer than 3 data rows (found {})", nodes.len()),
        });
    }
    if closed && nodes.len() > 3 {
        // A closed curve written with its first node repeated at the end: the repeated node
        // (and the director of the zero-length edge it would start) is dropped.
        let n = nodes.len();
        let mean_edge = (0..n - 1)
            .map(|i| norm(&sub(&nodes[i + 1], &nodes[i])))
            .sum::<f64>()
            / (n - 1) as f64;
        if norm(&sub(&nodes[n - 1], &nodes[0])) <= REPEAT_TOL * mean_edge {
            nodes.pop();
            d1.pop();
            row_lines.pop();
        }
    }
    if !closed {
        d1.pop();
    }
    let n = nodes.len();
    for (k, d) in d1.iter().enumerate() {
        if norm(d) == 0.0 {
            return Err(CsvError {
                line: row_lines[k],
                message: "director d1 is the zero vector".to_string(),
            });
        }
        let e = sub(&nodes[(k + 1) % n], &nodes[k]);
        let Some(t) = unit(&e) else {
            return Err(CsvError {
                line: row_lines[k],
                message: format!(
                    "the edge from this row's node to the node of line {} has zero length (a repeated node)",
                    row_lines[(k + 1) % n]
                ),
            });
        };
        if norm(&reject(d, &t)) <= ALONG_TANGENT_TOL * norm(d) {
            return Err(CsvError {
                line: row_lines[k],
                message: format!(
                    "director d1 = {d:?} lies along its edge's tangent {t:?}; it must have a component perpendicular to the edge (more than {ALONG_TANGENT_TOL} of its length)"
                ),
            });
        }
    }
    // Consecutive edges must not reverse: edge k-1 into node k and edge k out of it.
    let edges = if closed { n } else { n - 1 };
    let tangent = |k: usize| unit(&sub(&nodes[(k + 1) % n], &nodes[k]));
    let first = if closed { 0 } else { 1 };
    for k in first..edges {
        let prev = (k + edges - 1) % edges;
        if let (Some(a), Some(b)) = (tangent(prev), tangent(k)) {
            let c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            if 1.0 + c <= ANTIPARALLEL_TOL {
                return Err(CsvError {
                    line: row_lines[k],
                    message: format!(
                        "the curve doubles back at this row's node (node {k}, counting from 0): the edges into and out of it are antiparallel (turning angle {:.4} deg), so parallel transport, twist and writhe are undefined there",
                        c.clamp(-1.0, 1.0).acos().to_degrees()
                    ),
                });
            }
        }
    }
    Ok(FramedCurve { nodes, d1, closed })
}
