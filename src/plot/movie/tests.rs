//! Tests of the movie's plan and frames: the body between the text bands at small sizes, the
//! side view's ground panel.

use super::*;

/// An S-shaped body of 40 nodes, 0.5 m long, 1 cm thick, drifting along x over 20 frames.
fn clip() -> Clip {
    let (n, nt, l, a) = (40, 20, 0.5, 0.01);
    let t: Vec<f64> = (0..nt).map(|k| k as f64 * 0.05).collect();
    let x = t
        .iter()
        .map(|&tk| {
            (0..n)
                .map(|i| {
                    let s = l * (1.0 - i as f64 / (n - 1) as f64);
                    [s + 0.05 * tk, 0.05 * (10.0 * s - 6.0 * tk).sin(), 0.5 * a]
                })
                .collect()
        })
        .collect();
    Clip {
        title: "test".into(),
        t,
        x,
        contact: vec![vec![ContactState::Stuck; n]; nt],
        diameter: a,
        length: l,
        period: Some(0.5),
        gait_speed: Some(0.28),
        stuck_speed: 1e-3,
        ..Clip::default()
    }
}

/// On small pictures too the body stays between the text bands, in every view.
#[test]
fn the_body_stays_clear_of_the_text_at_small_sizes() {
    let c = clip();
    for view in [View::ThreeD, View::Top, View::Side] {
        for size in [(160, 120), (240, 160), (480, 300)] {
            let opts = MovieOptions {
                view,
                size,
                ..MovieOptions::default()
            };
            let plan = Plan::new(&c, opts).unwrap();
            let (y0, y1) = scene_rows(size);
            for j in [0, plan.picks.len() - 1] {
                let f = plan.render(j).unwrap();
                let w = size.0 as usize;
                let rows: Vec<usize> = (0..size.1 as usize)
                    .filter(|&y| f.body[y * w..(y + 1) * w].iter().any(|&b| b))
                    .collect();
                assert!(!rows.is_empty(), "{view:?} {size:?}: no body");
                assert!(
                    rows[0] >= y0 as usize && *rows.last().unwrap() < y1 as usize,
                    "{view:?} {size:?} frame {j}: body on rows {}..={}, scene {y0}..{y1}",
                    rows[0],
                    rows.last().unwrap()
                );
            }
        }
    }
}

/// The side view's scene keeps the sky colour above its ground panel (it used to draw the
/// ground's grid across the whole picture).
#[test]
fn the_side_view_has_sky_above_its_ground_panel() {
    let opts = MovieOptions {
        view: View::Side,
        ..MovieOptions::default()
    };
    let c = clip();
    let plan = Plan::new(&c, opts).unwrap();
    let f = plan.render(0).unwrap();
    let (y0, _) = scene_rows(opts.size);
    let w = opts.size.0 as usize;
    let row = &f.rgb[3 * w * (y0 as usize + 2)..3 * w * (y0 as usize + 3)];
    assert!(row.chunks(3).all(|p| p == raster::SKY), "{:?}", &row[..12]);
}
