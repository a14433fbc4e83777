//! Movies and ground tracks of a run: the GIF is valid, has one frame per recorded output and
//! its frames differ; the body's pixel centroid follows the trajectory's centroid; a clip read
//! back from a run directory equals the one built in memory; `slither movie` renders a stored
//! run.

use slither::model::Model;
use slither::observe;
use slither::output;
use slither::plot::movie::{self, ContactState, MovieOptions, View};
use slither::sim;
use std::path::{Path, PathBuf};

/// The bundled sliding rod (launched along +x, stops after 0.116 m at t = 0.463 s) run in
/// memory: model, frames and fields.
fn slide() -> (Model, Vec<sim::Frame>, observe::Fields) {
    let p = slither::problem::load(Path::new("problems/slide.toml")).unwrap();
    let m = Model::new(&p);
    let o = sim::run_gait(&m, p.solver.integrator, &mut |_| {}, &mut |_| {}).unwrap();
    assert!(o.error.is_none(), "{:?}", o.error);
    let fl = observe::fields(&m, &o.frames);
    (m, o.frames, fl)
}

/// Decoded GIF frames as RGBA, with the picture size: each frame as a viewer shows it, drawn
/// over the previous one (the movie's frames after the first hold only what changed, the rest
/// transparent, and are kept, not disposed).
fn decode(bytes: &[u8]) -> (usize, usize, Vec<Vec<u8>>) {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts.read_info(bytes).expect("a valid GIF header");
    let (w, h) = (d.width() as usize, d.height() as usize);
    let mut canvas = vec![0u8; 4 * w * h];
    let mut frames = Vec::new();
    while let Some(f) = d.read_next_frame().expect("a valid GIF frame") {
        let (fx, fy, fw, fh) = (
            f.left as usize,
            f.top as usize,
            f.width as usize,
            f.height as usize,
        );
        assert!(fx + fw <= w && fy + fh <= h, "frame inside the picture");
        if frames.is_empty() {
            assert_eq!((fx, fy, fw, fh), (0, 0, w, h), "a full first frame");
        } else {
            assert_eq!(f.dispose, gif::DisposalMethod::Keep);
        }
        for y in 0..fh {
            for x in 0..fw {
                let p = &f.buffer[4 * (y * fw + x)..4 * (y * fw + x) + 4];
                if p[3] != 0 {
                    let i = 4 * ((fy + y) * w + fx + x);
                    canvas[i..i + 4].copy_from_slice(p);
                }
            }
        }
        frames.push(canvas.clone());
    }
    (w, h, frames)
}

/// Centroid (px) of the body-coloured pixels (saturated: max - min channel > 50; the ground,
/// grid, shadow, sky and text are grey) in rows `rows`, and their count.
fn body_centroid(rgba: &[u8], w: usize, rows: (usize, usize)) -> (f64, f64, usize) {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0usize);
    for y in rows.0..rows.1 {
        for x in 0..w {
            let p = &rgba[4 * (y * w + x)..4 * (y * w + x) + 3];
            let (hi, lo) = (*p.iter().max().unwrap(), *p.iter().min().unwrap());
            if hi - lo > 50 {
                sx += x as f64;
                sy += y as f64;
                n += 1;
            }
        }
    }
    (sx / n.max(1) as f64, sy / n.max(1) as f64, n)
}

#[test]
fn gif_of_a_sliding_rod_follows_its_centroid() {
    let (m, frames, fl) = slide();
    let clip = output::movie::clip_from_run(&m, &frames, &fl, "slide", None);
    // The rod slides, then sticks: both states appear, and nothing is in the air.
    let states: Vec<ContactState> = clip.contact.iter().flatten().copied().collect();
    assert!(states.contains(&ContactState::Sliding) && states.contains(&ContactState::Stuck));
    assert!(!states.contains(&ContactState::Air));
    let opts = MovieOptions {
        view: View::Top,
        ..Default::default()
    };
    let bytes = movie::movie_bytes(&clip, &opts).unwrap();
    let (w, h, images) = decode(&bytes);
    assert_eq!((w as u32, h as u32), opts.size);
    // One frame per recorded output (61 fit in 15 s at 10 fps).
    assert_eq!(images.len(), frames.len());
    assert_eq!(
        movie::frame_picks(frames.len(), opts.fps, opts.max_seconds).len(),
        frames.len()
    );
    // Frames differ while the rod moves (the last ones, at rest, differ only by the clock).
    for k in 1..20 {
        assert_ne!(
            images[k - 1],
            images[k],
            "frames {} and {k} are equal",
            k - 1
        );
    }
    // The body's pixel centroid in the scene (text bands excluded) against the trajectory's
    // centroid along x (the heading, screen right in the top view).
    let (y0, y1) = movie::scene_rows(opts.size);
    let px: Vec<(f64, f64, usize)> = images
        .iter()
        .map(|im| body_centroid(im, w, (y0 as usize, y1 as usize)))
        .collect();
    let cx: Vec<f64> = (0..frames.len()).map(|k| clip.centroid(k)[0]).collect();
    for (k, p) in px.iter().enumerate() {
        // The whole rod is on screen: about L/a = 50 diameters long, several px thick.
        assert!(p.2 > 500, "frame {k}: only {} body pixels", p.2);
    }
    for k in 1..px.len() {
        // Monotone like the trajectory (which only moves forward), to a pixel's rounding.
        assert!(cx[k] >= cx[k - 1] - 1e-9);
        assert!(
            px[k].0 >= px[k - 1].0 - 0.3,
            "frame {k}: pixel centroid went back from {} to {}",
            px[k - 1].0,
            px[k].0
        );
        // Sideways it stays put.
        assert!((px[k].1 - px[0].1).abs() < 1.0);
    }
    // Pixels follow metres linearly: fitted scale, residual within a pixel.
    let n = px.len() as f64;
    let (mx, mp) = (
        cx.iter().sum::<f64>() / n,
        px.iter().map(|p| p.0).sum::<f64>() / n,
    );
    let sxx: f64 = cx.iter().map(|c| (c - mx).powi(2)).sum();
    let sxp: f64 = cx.iter().zip(&px).map(|(c, p)| (c - mx) * (p.0 - mp)).sum();
    let alpha = sxp / sxx;
    let travel = px.last().unwrap().0 - px[0].0;
    assert!(travel > 30.0, "the body moved only {travel} px on screen");
    for (c, p) in cx.iter().zip(&px) {
        let fit = mp + alpha * (c - mx);
        assert!((p.0 - fit).abs() < 1.0, "pixel {} vs fit {fit}", p.0);
    }
    // The fitted scale is the picture's: the 0.116 m slide spans travel px.
    let metres = cx.last().unwrap() - cx[0];
    assert!((alpha * metres - travel).abs() < 2.0);
}

#[test]
fn views_and_colourings_render() {
    let (m, frames, fl) = slide();
    let clip = output::movie::clip_from_run(&m, &frames, &fl, "slide", Some("N".into()));
    for view in [View::ThreeD, View::Side] {
        for colour in [
            movie::Colouring::Contact,
            movie::Colouring::Elevation,
            movie::Colouring::Lambda,
        ] {
            let opts = MovieOptions {
                view,
                colour,
                fps: 50.0,
                max_seconds: 0.5,
                size: (320, 200),
            };
            let bytes = movie::movie_bytes(&clip, &opts).unwrap();
            let (_, _, images) = decode(&bytes);
            // 61 frames do not fit in 0.5 s at 50 fps: a stride of 3 gives 21 and the last.
            let picks = movie::frame_picks(frames.len(), 50.0, 0.5);
            assert_eq!(picks, (0..frames.len()).step_by(3).collect::<Vec<_>>());
            assert_eq!(images.len(), picks.len());
            assert_ne!(images[0], images[1]);
        }
    }
    // Bad options are refused with a message.
    let bad = MovieOptions {
        fps: 0.0,
        ..Default::default()
    };
    let e = movie::movie_bytes(&clip, &bad).unwrap_err().to_string();
    assert!(e.contains("fps"), "{e}");
}

fn tmp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("slither_movie_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn clip_from_a_run_directory_equals_the_clip_in_memory() {
    let (m, frames, fl) = slide();
    let d = tmp_dir("dir");
    let extra = [
        ("elevation", fl.elevation.clone()),
        ("slip_speed", fl.slip.clone()),
        ("lambda", fl.lambda.clone()),
    ];
    output::write_trajectory(&d, &m, &frames, &extra).unwrap();
    let a = output::movie::clip_from_run(&m, &frames, &fl, "slide", None);
    let b = output::movie::clip_from_dir(&d).unwrap();
    assert_eq!(a.t, b.t);
    assert_eq!(a.x, b.x);
    assert_eq!(a.contact, b.contact);
    assert_eq!((a.diameter, a.length), (b.diameter, b.length));
    assert_eq!(a.stuck_speed, b.stuck_speed);
    assert_eq!(a.period, b.period);
    let same = |p: &Vec<Vec<f64>>, q: &Vec<Vec<f64>>| {
        p.len() == q.len()
            && p.iter()
                .flatten()
                .zip(q.iter().flatten())
                .all(|(x, y)| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()))
    };
    assert!(same(&a.lambda, &b.lambda));
    // The movie of the stored run: one frame per stored output, written where asked.
    let opts = MovieOptions {
        view: View::Side,
        colour: movie::Colouring::Elevation,
        ..Default::default()
    };
    let (path, stats) = output::movie::movie_of_dir(&d, &opts, None).unwrap();
    assert_eq!(path, d.join("movie_side_elevation.gif"));
    let (_, _, images) = decode(&std::fs::read(&path).unwrap());
    assert_eq!((images.len(), stats.frames), (frames.len(), frames.len()));
    // Tracks: PNG and SVG.
    output::movie::write_tracks(&d, &b).unwrap();
    assert!(std::fs::metadata(d.join("tracks.png")).unwrap().len() > 1000);
    let svg = std::fs::read_to_string(d.join("tracks.svg")).unwrap();
    assert!(svg.contains("<svg"));
    // An npz without positions is refused, naming the array.
    std::fs::write(d.join("trajectory.npz"), b"not a zip").unwrap();
    assert!(output::movie::clip_from_dir(&d).is_err());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn slither_movie_renders_a_stored_run() {
    let d = tmp_dir("cli");
    let bin = env!("CARGO_BIN_EXE_slither");
    let o = std::process::Command::new(bin)
        .args(["run", "problems/slide.toml", "--quiet", "--out"])
        .arg(&d)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // Every run writes its movie and tracks with its figures.
    for f in ["movie.gif", "tracks.png", "tracks.svg"] {
        assert!(d.join(f).is_file(), "{f} missing");
    }
    let clip = output::movie::clip_from_dir(&d).unwrap();
    // The regime shown is the summary's.
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap()).unwrap();
    assert_eq!(clip.regime.as_deref(), summary["regime"].as_str());
    assert!(clip.regime.is_some());
    let (_, _, run_movie) = decode(&std::fs::read(d.join("movie.gif")).unwrap());
    assert_eq!(run_movie.len(), clip.t.len());
    // `slither movie` from the stored trajectory.npz, top view, 20 fps, to a chosen file.
    let out = d.join("top.gif");
    let o = std::process::Command::new(bin)
        .arg("movie")
        .arg(&d)
        .args([
            "--view",
            "top",
            "--colour",
            "elevation",
            "--fps",
            "20",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(&out).unwrap();
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts.read_info(&bytes[..]).unwrap();
    let first = dec.read_next_frame().unwrap().unwrap().delay;
    assert_eq!(first, 5, "20 fps is 5 hundredths of a second per frame");
    let (_, _, images) = decode(&bytes);
    assert_eq!(images.len(), clip.t.len());
    assert_ne!(images[0], images[10]);
    // A bad view is refused with the allowed values.
    let o = std::process::Command::new(bin)
        .arg("movie")
        .arg(&d)
        .args(["--view", "front"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("3d, top, side"));
    // A still: one PNG frame of the chosen size.
    let png = d.join("still.png");
    let o = std::process::Command::new(bin)
        .arg("movie")
        .arg(&d)
        .args(["--still", "0.2", "--size", "320x200", "--out"])
        .arg(&png)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    // Width and height in the IHDR chunk.
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    assert_eq!((be(16), be(20)), (320, 200));
    let _ = std::fs::remove_dir_all(&d);
    // `--no-plots` skips the movie with the figures.
    let o = std::process::Command::new(bin)
        .args([
            "run",
            "problems/slide.toml",
            "--quiet",
            "--no-plots",
            "--out",
        ])
        .arg(&d)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(d.join("summary.json").is_file() && !d.join("movie.gif").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn output_movie_false_skips_the_movie_alone() {
    let d = tmp_dir("off");
    let text = std::fs::read_to_string("problems/slide.toml").unwrap();
    assert!(text.contains("[output]"));
    let problem = d.join("slide.toml");
    std::fs::write(
        &problem,
        text.replace("[output]", "[output]\nmovie = false"),
    )
    .unwrap();
    let bin = env!("CARGO_BIN_EXE_slither");
    let run = |extra: &[&str]| {
        let out = d.join("out");
        let o = std::process::Command::new(bin)
            .arg("run")
            .arg(&problem)
            .args(["--quiet", "--out"])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out
    };
    let out = run(&[]);
    assert!(out.join("tracks.png").is_file() && out.join("snapshots.png").is_file());
    assert!(!out.join("movie.gif").exists());
    // `--movie` writes it for one run all the same.
    let out = run(&["--movie"]);
    assert!(out.join("movie.gif").is_file());
    let _ = std::fs::remove_dir_all(&d);
}
