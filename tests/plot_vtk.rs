//! Figures (PNG) and ParaView export (VTK XML): files decode, carry content and text, and list the
//! right frames and arrays.

use slither::output::vtk::write_vtk;
use slither::plot::{kymograph, series, snapshots, xy, xy_log_log, PlotError};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("slither_plot_vtk_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Checks the PNG signature and the IHDR chunk by hand; returns (width, height, file size).
fn png_info(path: &Path) -> (u32, u32, usize) {
    let b = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(b.len() > 33, "{}: too short for a PNG", path.display());
    assert_eq!(
        &b[..8],
        b"\x89PNG\r\n\x1a\n",
        "{}: not a PNG signature",
        path.display()
    );
    let len = u32::from_be_bytes(b[8..12].try_into().unwrap());
    assert_eq!(len, 13, "IHDR length");
    assert_eq!(&b[12..16], b"IHDR", "first chunk must be IHDR");
    let w = u32::from_be_bytes(b[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(b[20..24].try_into().unwrap());
    assert!(b.windows(4).any(|q| q == b"IDAT"), "no IDAT chunk");
    assert_eq!(
        &b[b.len() - 8..b.len() - 4],
        b"IEND",
        "no IEND chunk at the end"
    );
    (w, h, b.len())
}

fn assert_figure(path: &Path) {
    let (w, h, size) = png_info(path);
    assert!(w > 300 && h > 300, "{}: {w}x{h} px", path.display());
    assert!(
        size > 8_000,
        "{}: only {size} bytes: too little content",
        path.display()
    );
}

/// A travelling curvature wave kappa(s, t) = A sin(2 pi (s/lambda - t/T)), 1/m.
fn wave(ns: usize, nt: usize) -> (Vec<f64>, Vec<f64>, Vec<Vec<f64>>) {
    let s: Vec<f64> = (0..ns).map(|i| 0.5 * i as f64 / (ns - 1) as f64).collect();
    let t: Vec<f64> = (0..nt).map(|j| 2.0 * j as f64 / (nt - 1) as f64).collect();
    let v = t
        .iter()
        .map(|&tt| {
            s.iter()
                .map(|&ss| 8.0 * (2.0 * PI * (ss / 0.25 - tt)).sin())
                .collect()
        })
        .collect();
    (s, t, v)
}

#[test]
fn kymograph_png_with_text() {
    let d = tmp("kymo");
    let (s, t, v) = wave(40, 120);
    let a = d.join("kappa.png");
    let b = d.join("kappa_untitled.png");
    kymograph(
        &a,
        "Curvature kymograph",
        "curvature κ (1/m)",
        &s,
        &t,
        &v,
        true,
    )
    .unwrap();
    kymograph(&b, "", "curvature κ (1/m)", &s, &t, &v, true).unwrap();
    assert_figure(&a);
    assert_figure(&b);
    // The only difference is the title text: if text did not render, the images would be equal.
    let (ba, bb) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert_ne!(
        ba, bb,
        "title text did not change the image: text is not rendered"
    );
    // Same layout, different glyphs: only rendered text can tell these apart.
    let c1 = d.join("title_a.png");
    let c2 = d.join("title_b.png");
    kymograph(&c1, "Kymograph AAAA", "curvature κ (1/m)", &s, &t, &v, true).unwrap();
    kymograph(&c2, "Kymograph BBBB", "curvature κ (1/m)", &s, &t, &v, true).unwrap();
    assert_ne!(
        std::fs::read(&c1).unwrap(),
        std::fs::read(&c2).unwrap(),
        "glyphs are not drawn"
    );

    // Sequential map, positive data.
    let vpos: Vec<Vec<f64>> = v
        .iter()
        .map(|r| r.iter().map(|x| x.abs()).collect())
        .collect();
    let c = d.join("abs.png");
    kymograph(&c, "|κ|", "|κ| (1/m)", &s, &t, &vpos, false).unwrap();
    assert_figure(&c);
    assert_ne!(std::fs::read(&c).unwrap(), ba);
}

#[test]
fn kymograph_mismatch_is_an_error() {
    let d = tmp("kymo_err");
    let (s, t, v) = wave(10, 20);
    let p = d.join("bad.png");
    // Fewer times than rows.
    match kymograph(&p, "x", "y", &s, &t[..19], &v, true) {
        Err(PlotError::Mismatch(m)) => assert!(
            m.contains("t_over_t") && m.contains("20") && m.contains("19"),
            "{m}"
        ),
        other => panic!("expected a mismatch error, got {other:?}"),
    }
    // One row with a wrong node count.
    let mut v2 = v.clone();
    v2[7].pop();
    match kymograph(&p, "x", "y", &s, &t, &v2, false) {
        Err(PlotError::Mismatch(m)) => assert!(
            m.contains("values[7]") && m.contains("9") && m.contains("10"),
            "{m}"
        ),
        other => panic!("expected a mismatch error, got {other:?}"),
    }
    // s shorter than the rows.
    assert!(matches!(
        kymograph(&p, "x", "y", &s[..9], &t, &v, true),
        Err(PlotError::Mismatch(_))
    ));
    // Non-increasing time is invalid, not a panic.
    let mut t2 = t.clone();
    t2[3] = t2[2];
    assert!(matches!(
        kymograph(&p, "x", "y", &s, &t2, &v, true),
        Err(PlotError::Invalid(_))
    ));
    assert!(!p.exists(), "no file should be written on error");
}

#[test]
fn snapshots_png() {
    let d = tmp("snap");
    let n = 30;
    let frames: Vec<(f64, Vec<[f64; 3]>)> = (0..5)
        .map(|k| {
            let t = 0.5 * k as f64;
            let pts = (0..n)
                .map(|i| {
                    let s = 0.5 * i as f64 / (n - 1) as f64;
                    [
                        0.05 * t - s,
                        0.04 * (2.0 * PI * (s / 0.25 - t)).sin(),
                        0.002 * (PI * s / 0.5).sin(),
                    ]
                })
                .collect();
            (t, pts)
        })
        .collect();
    let p = d.join("snap.png");
    snapshots(&p, "Body snapshots", &frames).unwrap();
    assert_figure(&p);
    // Planar body (z = 0 everywhere) must also work.
    let flat: Vec<(f64, Vec<[f64; 3]>)> = frames
        .iter()
        .map(|(t, p)| (*t, p.iter().map(|q| [q[0], q[1], 0.0]).collect()))
        .collect();
    let q = d.join("flat.png");
    snapshots(&q, "Planar", &flat).unwrap();
    assert_figure(&q);
    assert!(matches!(
        snapshots(&q, "x", &[]),
        Err(PlotError::Invalid(_))
    ));
}

#[test]
fn series_png() {
    let d = tmp("series");
    let t: Vec<f64> = (0..200).map(|i| 0.01 * i as f64).collect();
    let tw: Vec<f64> = t.iter().map(|x| 0.3 * (2.0 * PI * x).sin()).collect();
    let wr: Vec<f64> = t.iter().map(|x| 1.0 - 0.3 * (2.0 * PI * x).sin()).collect();
    let lk: Vec<f64> = tw.iter().zip(&wr).map(|(a, b)| a + b).collect();
    let p = d.join("lk.png");
    series(
        &p,
        "Link, twist and writhe",
        "turns",
        &t,
        &[("Tw", tw.clone()), ("Wr", wr), ("Lk", lk)],
    )
    .unwrap();
    assert_figure(&p);
    match series(&p, "x", "y", &t, &[("Tw", tw[..10].to_vec())]) {
        Err(PlotError::Mismatch(m)) => assert!(m.contains("Tw"), "{m}"),
        other => panic!("expected a mismatch error, got {other:?}"),
    }
}

#[test]
fn xy_png_linear_and_log() {
    let d = tmp("xy");
    let a: Vec<(f64, f64)> = (1..=8)
        .map(|k| (0.1 * k as f64, 0.02 * (k as f64).sqrt()))
        .collect();
    let b: Vec<(f64, f64)> = (1..=8)
        .map(|k| (0.1 * k as f64, -0.01 + 0.004 * k as f64))
        .collect();
    let p = d.join("speed.png");
    xy(
        &p,
        "Speed vs writhe",
        "writhe Wr (turns)",
        "speed (m/s)",
        &[("lateral", a), ("sidewinding", b)],
        false,
        false,
    )
    .unwrap();
    assert_figure(&p);
    let wp: Vec<(f64, f64)> = (0..6)
        .map(|k| (10f64.powi(-k), 3.0 * 10f64.powi(k)))
        .collect();
    let wp2: Vec<(f64, f64)> = (0..6)
        .map(|k| (10f64.powi(-k), 1e-3 * 10f64.powi(-2 * k)))
        .collect();
    let q = d.join("wp.png");
    xy(
        &q,
        "Work-precision",
        "error (m)",
        "wall time (s)",
        &[("implicit Euler", wp), ("BDF2", wp2)],
        true,
        true,
    )
    .unwrap();
    assert_figure(&q);
    assert!(matches!(
        xy(
            &q,
            "x",
            "x",
            "y",
            &[("neg", vec![(-1.0, 1.0)])],
            true,
            false
        ),
        Err(PlotError::Invalid(_))
    ));
}

/// A cost against the element count over less than two powers of ten: `xy` draws it on linear
/// axes (its ticks include 150 and 250), `xy_log_log` keeps the log axes with ticks at 1, 2 and
/// 5 times the powers of ten (50, 100, 200, and no 150).
#[test]
fn xy_log_log_keeps_log_axes_on_narrow_data() {
    let d = tmp("xy_log_log");
    let cost: Vec<(f64, f64)> = [50.0, 100.0, 200.0, 400.0]
        .iter()
        .map(|&n| (n, 0.006 * n))
        .collect();
    let labels = |svg: &str| -> Vec<String> {
        svg.split("<text")
            .skip(1)
            .filter_map(|t| Some(t[t.find('>')? + 1..t.find("</text>")?].trim().to_string()))
            .collect()
    };
    let lin = d.join("linear.svg");
    xy(
        &lin,
        "",
        "elements",
        "s",
        &[("cost", cost.clone())],
        true,
        true,
    )
    .unwrap();
    let lin_labels = labels(&std::fs::read_to_string(&lin).unwrap());
    assert!(lin_labels.iter().any(|l| l == "150"), "{lin_labels:?}");
    let log = d.join("log.svg");
    xy_log_log(&log, "", "elements", "s", &[("cost", cost)]).unwrap();
    let log_labels = labels(&std::fs::read_to_string(&log).unwrap());
    for tick in ["50", "100", "200", "0.5", "1", "2"] {
        assert!(
            log_labels.iter().any(|l| l == tick),
            "no tick {tick}: {log_labels:?}"
        );
    }
    assert!(!log_labels.iter().any(|l| l == "150"), "{log_labels:?}");
    assert!(matches!(
        xy_log_log(&log, "", "x", "y", &[("neg", vec![(-1.0, 1.0)])]),
        Err(PlotError::Invalid(_))
    ));
}

/// Value of attribute `name` in the XML tag text `tag`.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!("{name}=\"");
    let i = tag.find(&key)? + key.len();
    Some(&tag[i..i + tag[i..].find('"')?])
}

/// The whitespace-separated numbers inside the DataArray named `name`.
fn data_array(xml: &str, name: &str) -> Vec<f64> {
    let key = format!("Name=\"{name}\"");
    let i = xml
        .find(&key)
        .unwrap_or_else(|| panic!("no DataArray {name}"));
    let open = i + xml[i..].find('>').unwrap() + 1;
    let close = open + xml[open..].find("</DataArray>").unwrap();
    xml[open..close]
        .split_whitespace()
        .map(|w| w.parse::<f64>().unwrap())
        .collect()
}

#[test]
fn vtk_export() {
    let d = tmp("vtk");
    let nodes = 11;
    let times = [0.0, 0.25, 0.5];
    let positions: Vec<Vec<[f64; 3]>> = times
        .iter()
        .map(|t| {
            (0..nodes)
                .map(|i| [0.1 * i as f64 + t, 0.01 * (i as f64 + t).sin(), 0.0])
                .collect()
        })
        .collect();
    let kappa: Vec<Vec<f64>> = times
        .iter()
        .map(|t| (0..nodes).map(|i| t * i as f64).collect())
        .collect();
    let press: Vec<Vec<f64>> = times.iter().map(|_| vec![1.5e-7; nodes]).collect();
    write_vtk(
        &d,
        &times,
        &positions,
        &[("curvature_1_per_m", kappa.clone()), ("pressure_Pa", press)],
    )
    .unwrap();

    let pvd = std::fs::read_to_string(d.join("vtk/frames.pvd")).unwrap();
    assert!(pvd.contains(r#"type="Collection""#));
    let sets: Vec<&str> = pvd.lines().filter(|l| l.contains("<DataSet")).collect();
    assert_eq!(sets.len(), times.len(), "{pvd}");
    for (k, (line, t)) in sets.iter().zip(times).enumerate() {
        let ts: f64 = attr(line, "timestep").unwrap().parse().unwrap();
        assert_eq!(ts, t);
        let file = attr(line, "file").unwrap();
        assert_eq!(file, format!("frame_{k:05}.vtp"));
        let vtp = std::fs::read_to_string(d.join("vtk").join(file)).unwrap();
        assert!(vtp.contains(r#"type="PolyData""#));
        let piece = vtp.lines().find(|l| l.contains("<Piece")).unwrap();
        assert_eq!(attr(piece, "NumberOfPoints"), Some(&*nodes.to_string()));
        assert_eq!(attr(piece, "NumberOfLines"), Some("1"));
        let pts = data_array(&vtp, "Points");
        assert_eq!(pts.len(), 3 * nodes);
        assert_eq!(pts[3 * 4], positions[k][4][0]);
        let kap = data_array(&vtp, "curvature_1_per_m");
        assert_eq!(kap, kappa[k]);
        assert_eq!(data_array(&vtp, "pressure_Pa"), vec![1.5e-7; nodes]);
        let conn = data_array(&vtp, "connectivity");
        assert_eq!(conn, (0..nodes).map(|i| i as f64).collect::<Vec<_>>());
        assert_eq!(data_array(&vtp, "offsets"), vec![nodes as f64]);
    }

    // Wrong sizes are errors.
    let short: Vec<Vec<f64>> = times.iter().map(|_| vec![0.0; nodes - 1]).collect();
    let e = write_vtk(&d, &times, &positions, &[("twist", short)]).unwrap_err();
    assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
    assert!(e.to_string().contains("twist"), "{e}");
    assert!(write_vtk(&d, &times[..2], &positions, &[]).is_err());
}
