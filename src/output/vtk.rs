//! ParaView export of a trajectory as VTK XML PolyData (one `.vtp` file per frame) plus a `.pvd`
//! collection that ParaView opens as a time series.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

/// Escapes the characters that may not appear inside an XML attribute value.
fn xml_attr(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// File name of frame `k` inside `dir/vtk/`: `frame_00000.vtp`, `frame_00001.vtp`, ...
pub fn frame_file_name(k: usize) -> String {
    format!("frame_{k:05}.vtp")
}

/// ParaView export: writes `dir/vtk/frame_00000.vtp`, `frame_00001.vtp`, ... (one ASCII VTK XML
/// PolyData file per frame: the points are the node positions in m, in node order; a single Lines
/// cell runs through all nodes; each entry of `point_data` becomes a Float64 PointData array of
/// that name) and `dir/vtk/frames.pvd` (a Collection with one DataSet per frame, `timestep` = the
/// frame's time in s, `file` = the frame's path relative to the `.pvd`). Creates `dir/vtk/` if
/// needed; frame files of an earlier, longer export are left in place but are not listed.
///
/// Arguments: `times[k]` (s) and `positions[k][i]` (m) for frame k and node i; `point_data` holds
/// `(name, values)` with `values[k][i]` for frame k and node i, in whatever unit the caller
/// documents in the name (e.g. "curvature_1_per_m"). Per-edge quantities must be interpolated to
/// the nodes by the caller. Non-finite values are written as `NaN` / `inf` / `-inf`.
///
/// Errors: `InvalidInput` if `positions.len() != times.len()`, if a point-data array does not have
/// one row per frame and one value per node of that frame, or if a name is empty; any I/O error.
pub fn write_vtk(
    dir: &Path,
    times: &[f64],
    positions: &[Vec<[f64; 3]>],
    point_data: &[(&str, Vec<Vec<f64>>)],
) -> io::Result<()> {
    if positions.len() != times.len() {
        return Err(invalid(format!(
            "write_vtk: {} position frames but {} times",
            positions.len(),
            times.len()
        )));
    }
    for (name, vals) in point_data {
        if name.is_empty() {
            return Err(invalid(
                "write_vtk: point-data array with an empty name".into(),
            ));
        }
        if vals.len() != times.len() {
            return Err(invalid(format!(
                "write_vtk: point data \"{name}\" has {} frames but there are {} times",
                vals.len(),
                times.len()
            )));
        }
        for (k, (row, pos)) in vals.iter().zip(positions).enumerate() {
            if row.len() != pos.len() {
                return Err(invalid(format!(
                    "write_vtk: point data \"{name}\" has {} values in frame {k} but the frame has {} nodes",
                    row.len(),
                    pos.len()
                )));
            }
        }
    }

    let vtk_dir = dir.join("vtk");
    std::fs::create_dir_all(&vtk_dir)?;
    for (k, pos) in positions.iter().enumerate() {
        let mut w = BufWriter::new(File::create(vtk_dir.join(frame_file_name(k)))?);
        write_frame(&mut w, pos, point_data.iter().map(|(n, v)| (*n, &v[k][..])))?;
        w.flush()?;
    }

    let mut w = BufWriter::new(File::create(vtk_dir.join("frames.pvd"))?);
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">"#
    )?;
    writeln!(w, "  <Collection>")?;
    for (k, t) in times.iter().enumerate() {
        writeln!(
            w,
            r#"    <DataSet timestep="{}" group="" part="0" file="{}"/>"#,
            num(*t),
            frame_file_name(k)
        )?;
    }
    writeln!(w, "  </Collection>")?;
    writeln!(w, "</VTKFile>")?;
    w.flush()
}

/// Shortest round-trip decimal form (no exponent for ordinary magnitudes, `e` notation for very
/// small or large ones), `NaN`, `inf` or `-inf`.
fn num(v: f64) -> String {
    let a = v.abs();
    if v != 0.0 && v.is_finite() && !(1e-4..1e15).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

fn write_frame<'a>(
    w: &mut impl Write,
    pos: &[[f64; 3]],
    arrays: impl Iterator<Item = (&'a str, &'a [f64])> + Clone,
) -> io::Result<()> {
    let n = pos.len();
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">"#
    )?;
    writeln!(w, "  <PolyData>")?;
    let lines = usize::from(n > 0);
    writeln!(
        w,
        r#"    <Piece NumberOfPoints="{n}" NumberOfVerts="0" NumberOfLines="{lines}" NumberOfStrips="0" NumberOfPolys="0">"#
    )?;
    let first = arrays.clone().next().map(|(name, _)| name);
    match first {
        Some(name) => writeln!(w, r#"      <PointData Scalars="{}">"#, xml_attr(name))?,
        None => writeln!(w, "      <PointData>")?,
    }
    for (name, vals) in arrays {
        writeln!(
            w,
            r#"        <DataArray type="Float64" Name="{}" NumberOfComponents="1" format="ascii">"#,
            xml_attr(name)
        )?;
        for chunk in vals.chunks(8) {
            let line: Vec<String> = chunk.iter().map(|v| num(*v)).collect();
            writeln!(w, "          {}", line.join(" "))?;
        }
        writeln!(w, "        </DataArray>")?;
    }
    writeln!(w, "      </PointData>")?;
    writeln!(w, "      <Points>")?;
    writeln!(
        w,
        r#"        <DataArray type="Float64" Name="Points" NumberOfComponents="3" format="ascii">"#
    )?;
    for p in pos {
        writeln!(w, "          {} {} {}", num(p[0]), num(p[1]), num(p[2]))?;
    }
    writeln!(w, "        </DataArray>")?;
    writeln!(w, "      </Points>")?;
    writeln!(w, "      <Lines>")?;
    writeln!(
        w,
        r#"        <DataArray type="Int64" Name="connectivity" format="ascii">"#
    )?;
    let idx: Vec<usize> = (0..n).collect();
    for chunk in idx.chunks(16) {
        let line: Vec<String> = chunk.iter().map(|i| i.to_string()).collect();
        writeln!(w, "          {}", line.join(" "))?;
    }
    writeln!(w, "        </DataArray>")?;
    writeln!(
        w,
        r#"        <DataArray type="Int64" Name="offsets" format="ascii">"#
    )?;
    if n > 0 {
        writeln!(w, "          {n}")?;
    }
    writeln!(w, "        </DataArray>")?;
    writeln!(w, "      </Lines>")?;
    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </PolyData>")?;
    writeln!(w, "</VTKFile>")
}
