//! Tests of the topology module: the twist and writhe densities over sliding windows (against
//! direct sums, their cost counted) and the curve CSV reader.

use super::tests::{director, torus_knot, twisted_ring, Rng};
use super::*;

// 4a. uniformly twisted straight rod (non-uniform spacing, tilted axis)
#[test]
fn densities_straight_rod_uniform_twist() {
    let tau0 = 2.0; // rad per metre
    let dir = unit(&[1.0, 2.0, -0.5]).unwrap();
    let e1 = any_perpendicular(&dir);
    let e2 = cross(&dir, &e1);
    let mut s = vec![0.0];
    for i in 0..60 {
        let last = *s.last().unwrap();
        s.push(last + 0.05 * (1.0 + 0.3 * (1.7 * i as f64).sin()));
    }
    let nodes: Vec<V3> = s
        .iter()
        .map(|&si| add(&[0.3, -1.0, 2.0], &scale(&dir, si)))
        .collect();
    let d1: Vec<V3> = (0..s.len() - 1)
        .map(|e| {
            let a = tau0 * 0.5 * (s[e] + s[e + 1]);
            add(&scale(&e1, a.cos()), &scale(&e2, a.sin()))
        })
        .collect();
    let c = FramedCurve {
        nodes,
        d1,
        closed: false,
    };
    let delta = 0.37;
    let d = densities(&c, delta);
    assert!(d.s.len() > 10);
    for k in 0..d.s.len() {
        assert!((d.s[k] - s[k]).abs() < 1e-12);
        assert!(d.s[k] + delta <= s[s.len() - 1] + 1e-9);
        assert!(
            (d.tau[k] - tau0 / (2.0 * PI)).abs() < 1e-9,
            "tau[{k}]={}",
            d.tau[k]
        );
        assert!(d.omega[k].abs() < 1e-12, "omega[{k}]={}", d.omega[k]);
        assert_eq!(d.lambda[k], d.tau[k] + d.omega[k]);
    }
    // the last fitting window is present
    let last_start = *d.s.last().unwrap();
    assert!(s
        .iter()
        .any(|&si| si > last_start && si + delta > s[s.len() - 1] + 1e-9));
}

// 4a'. a window far out along the curve, where `a + delta` rounds to `a` (a node at 1e26 m,
// as a typo in a curve file gives): its densities are finite, not 0 / 0
#[test]
fn densities_stay_finite_where_the_window_is_below_the_arc_length_resolution() {
    let mut nodes: Vec<V3> = (0..12)
        .map(|i| {
            let t = 0.5 * i as f64;
            [t.cos(), t.sin(), 0.1 * t]
        })
        .collect();
    nodes[11][0] = 0.708669774291e26;
    let c = FramedCurve {
        d1: vec![[0.0, 0.0, 1.0]; 11],
        nodes,
        closed: false,
    };
    let d = densities(&c, 1.0);
    assert!(!d.lambda.is_empty());
    for k in 0..d.s.len() {
        assert!(
            d.tau[k].is_finite() && d.omega[k].is_finite() && d.lambda[k].is_finite(),
            "window {k} at s = {:e}: tau {} omega {}",
            d.s[k],
            d.tau[k],
            d.omega[k]
        );
    }
}

// 4b. helix writhe density has the helix's sign
#[test]
fn densities_helix_sign() {
    let helix = |pitch: f64| {
        let n = 401;
        let nodes: Vec<V3> = (0..n)
            .map(|i| {
                let t = 8.0 * PI * i as f64 / (n - 1) as f64;
                [t.cos(), t.sin(), pitch * t]
            })
            .collect();
        let d1 = (0..n - 1)
            .map(|i| {
                let m = scale(&add(&nodes[i], &nodes[i + 1]), 0.5);
                director(&nodes[i], &nodes[i + 1], &[-m[0], -m[1], 0.0], 0.0)
            })
            .collect();
        FramedCurve {
            nodes,
            d1,
            closed: false,
        }
    };
    let right = densities(&helix(0.2), 7.0);
    let left = densities(&helix(-0.2), 7.0);
    assert!(!right.s.is_empty());
    assert_eq!(right.s.len(), left.s.len());
    for k in 0..right.s.len() {
        assert!(
            right.omega[k] > 1e-3,
            "right-handed omega[{k}]={}",
            right.omega[k]
        );
        assert!(
            left.omega[k] < -1e-3,
            "left-handed omega[{k}]={}",
            left.omega[k]
        );
        assert!((right.omega[k] + left.omega[k]).abs() < 1e-12);
    }
    // a window covering the whole curve reproduces the curve's writhe
    let c = helix(0.2);
    let total: f64 = (0..c.nodes.len() - 1)
        .map(|i| norm(&sub(&c.nodes[i + 1], &c.nodes[i])))
        .sum();
    let whole = densities(&c, total);
    assert_eq!(whole.s.len(), 1);
    assert!((whole.omega[0] * total - writhe(&c.nodes, false)).abs() < 1e-10);
}

// 4c. closed curves: a full-length window integrates the total twist
#[test]
fn densities_closed_full_window_gives_total_twist() {
    let c = torus_knot(2.0, 3.0, 150, 1);
    let n = c.nodes.len();
    let total: f64 = (0..n)
        .map(|i| norm(&sub(&c.nodes[(i + 1) % n], &c.nodes[i])))
        .sum();
    let d = densities(&c, total);
    assert_eq!(d.s.len(), n);
    let tw = twist(&c);
    for k in 0..n {
        assert!(
            (d.tau[k] * total - tw).abs() < 1e-9,
            "{} vs {tw}",
            d.tau[k] * total
        );
    }
    assert!(densities(&c, 1.01 * total).s.is_empty());
    assert!(densities(&c, -1.0).s.is_empty());
}

// 5. CSV
fn to_csv(c: &FramedCurve) -> String {
    let mut s = String::from("x,y,z,d1x,d1y,d1z\n");
    for (i, r) in c.nodes.iter().enumerate() {
        let d = c.d1.get(i).copied().unwrap_or([0.0, 0.0, 1.0]);
        s += &format!("{},{},{},{},{},{}\n", r[0], r[1], r[2], d[0], d[1], d[2]);
    }
    s
}

#[test]
fn csv_round_trip() {
    let closed = torus_knot(3.0, 2.0, 50, 1);
    assert_eq!(parse_curve_csv(&to_csv(&closed), true).unwrap(), closed);
    let mut open = twisted_ring(20, 2);
    open.closed = false;
    open.d1.pop();
    assert_eq!(parse_curve_csv(&to_csv(&open), false).unwrap(), open);
    // whitespace, CRLF and blank lines are tolerated
    let text = "x, y, z, d1x, d1y, d1z\r\n0, 0, 0, 0, 1, 0\r\n\r\n1,0,0, 0,1,0\r\n2,0,0,0,1,0\r\n";
    let c = parse_curve_csv(text, false).unwrap();
    assert_eq!(c.nodes.len(), 3);
    assert_eq!(c.d1.len(), 2);
}

#[test]
fn csv_errors_report_line_numbers() {
    let h = "x,y,z,d1x,d1y,d1z\n";
    let ok = "0,0,0,0,1,0\n";
    let cases: Vec<(String, usize, &str)> = vec![
        (
            format!("{h}{ok}{ok}1,2,3,4,5\n{ok}"),
            4,
            "expected 6 fields",
        ),
        (format!("{h}{ok}{ok}{ok}1,2,abc,0,1,0\n"), 5, "not a number"),
        (format!("{h}{ok}1,2,inf,0,1,0\n{ok}"), 3, "not finite"),
        (format!("{h}{ok}1,2,3,0,NaN,0\n{ok}"), 3, "not finite"),
        (format!("{h}{ok}1,2,-3e85,0,1,0\n{ok}"), 3, "out of range"),
        (format!("{h}{ok}{ok}"), 3, "fewer than 3"),
        (format!("{ok}{ok}{ok}{ok}"), 1, "header"),
        (String::new(), 1, "empty"),
        (format!("{h}{ok}1,0,0,0,0,0\n{ok}"), 3, "zero"),
    ];
    for (text, line, what) in cases {
        let err = parse_curve_csv(&text, true).unwrap_err();
        assert_eq!(err.line, line, "{text:?}: {err}");
        assert!(err.message.contains(what), "{err}");
        assert!(err.to_string().starts_with(&format!("line {line}:")));
    }
    // the last row's director is ignored for open curves
    let text = format!("{h}{ok}1,0,0,0,1,0\n2,0,0,0,0,0\n");
    assert!(parse_curve_csv(&text, false).is_ok());
    let e: Box<dyn std::error::Error> = Box::new(parse_curve_csv("", true).unwrap_err());
    assert!(!e.to_string().is_empty());
}

/// The largest coordinates the reader accepts still give finite topology and densities
/// (a helix of radius 1e29: writhe multiplies up to four coordinates).
#[test]
fn csv_largest_accepted_coordinates_give_finite_topology() {
    let r = 0.99 * MAX_ABS;
    let mut text = String::from("x,y,z,d1x,d1y,d1z\n");
    for i in 0..12 {
        let t = i as f64 * 0.5;
        text += &format!(
            "{:e},{:e},{:e},0,0,1\n",
            r * t.cos(),
            r * t.sin(),
            0.08 * r * t
        );
    }
    for closed in [false, true] {
        let c = parse_curve_csv(&text, closed).unwrap();
        let t = topology(&c);
        assert!(t.tw.is_finite() && t.wr.is_finite(), "{t:?}");
        let d = densities(&c, r);
        assert!(!d.lambda.is_empty() && d.lambda.iter().all(|x| x.is_finite()));
    }
}

/// The windows' writhe computed directly: the sub-polygon of each window (its whole edges
/// and the interpolated last point), summed pair by pair with [`writhe`].
fn direct_window_writhe(c: &FramedCurve, d: &Densities, delta: f64) -> Vec<f64> {
    let n = c.nodes.len();
    let m = edge_count(n, c.closed);
    let lens: Vec<f64> = (0..m)
        .map(|e| norm(&sub(&c.nodes[(e + 1) % n], &c.nodes[e])))
        .collect();
    let total: f64 = lens.iter().sum();
    d.s.iter()
        .enumerate()
        .map(|(w, &a)| {
            let i = (0..n)
                .position(|k| lens[..k].iter().sum::<f64>() == a)
                .unwrap();
            let b = (a + delta).min(if c.closed { f64::INFINITY } else { total });
            let mut pts = vec![c.nodes[i]];
            let mut pos = a;
            for k in i..i + m {
                let e = k % m;
                let (p, q) = (c.nodes[e], c.nodes[(e + 1) % n]);
                if pos + lens[e] >= b - 1e-12 * total.max(delta) {
                    let f = ((b - pos) / lens[e]).clamp(0.0, 1.0);
                    pts.push(add(&p, &scale(&sub(&q, &p), f)));
                    break;
                }
                pts.push(q);
                pos += lens[e];
            }
            let _ = w;
            writhe(&pts, false)
        })
        .collect()
}

#[test]
fn sliding_window_writhe_equals_the_direct_sum() {
    // A random walk (open) and a trefoil (closed), windows of several sizes, some ending
    // inside an edge and one exactly at nodes.
    let mut rng = Rng(99);
    let mut walk = vec![[0.0; 3]];
    for _ in 0..80 {
        let last = *walk.last().unwrap();
        let step = scale(
            &unit(&[rng.sym(), rng.sym(), rng.sym()]).unwrap(),
            0.5 + rng.next(),
        );
        walk.push(add(&last, &step));
    }
    let d1: Vec<V3> = (0..walk.len() - 1)
        .map(|i| director(&walk[i], &walk[i + 1], &[0.3, -0.2, 1.0], 0.1 * i as f64))
        .collect();
    let open = FramedCurve {
        nodes: walk,
        d1,
        closed: false,
    };
    let knot = torus_knot(2.0, 3.0, 90, 1);
    for (c, deltas) in [(&open, [3.3, 10.0, 25.7]), (&knot, [1.1, 4.0, 9.5])] {
        for delta in deltas {
            let d = densities(c, delta);
            assert!(d.s.len() > 10, "{delta}: {} windows", d.s.len());
            let direct = direct_window_writhe(c, &d, delta);
            let mut largest: f64 = 0.0;
            for (k, wr) in direct.iter().enumerate() {
                largest = largest.max(wr.abs());
                let got = d.omega[k] * delta;
                assert!((got - wr).abs() < 1e-12, "window {k}: {got} vs {wr}");
            }
            assert!(largest > 1e-4, "windows should writhe: {largest}");
        }
    }
}

#[test]
fn shortened_last_window_keeps_the_count_and_divides_by_its_length() {
    // A uniformly twisted straight rod of 10 unit edges, windows of 3: at rest 8 windows
    // fit; compressed by 1e-4 only 7 do, and the 8th is shortened, not NaN or missing.
    let rod = |scale_: f64| {
        let nodes: Vec<V3> = (0..=10).map(|i| [scale_ * i as f64, 0.0, 0.0]).collect();
        let d1 = (0..10)
            .map(|e| {
                let a = 0.5 * (e as f64 + 0.5);
                [0.0, a.cos(), a.sin()]
            })
            .collect();
        FramedCurve {
            nodes,
            d1,
            closed: false,
        }
    };
    assert_eq!(densities(&rod(1.0), 3.0).s.len(), 8);
    let squeezed = rod(1.0 - 1e-4);
    assert_eq!(densities(&squeezed, 3.0).s.len(), 7);
    let d = densities_shortened(&squeezed, 3.0, 8);
    assert_eq!(d.s.len(), 8);
    let rate = 0.5 / (1.0 - 1e-4) / (2.0 * PI);
    for k in 0..8 {
        assert!((d.tau[k] - rate).abs() < 1e-9, "tau[{k}] = {}", d.tau[k]);
        assert!(d.lambda[k].is_finite());
    }
}

#[test]
fn csv_closed_repeated_closing_node_is_dropped() {
    let ring = twisted_ring(40, -1);
    let mut text = to_csv(&ring);
    let r = ring.nodes[0];
    let d = ring.d1[0];
    text += &format!("{},{},{},{},{},{}\n", r[0], r[1], r[2], d[0], d[1], d[2]);
    let c = parse_curve_csv(&text, true).unwrap();
    assert_eq!(c, ring);
    assert!((gauss_link(&c, 1e-3) + 1.0).abs() < 1e-6);
}

#[test]
fn csv_rejects_a_director_along_the_tangent_and_a_zero_edge() {
    let h = "x,y,z,d1x,d1y,d1z\n";
    let text = format!("{h}0,0,0,0,0,1\n1,0,0,0,0,1\n1,1,0,0,0,1\n0,1,0,0,-3,0\n");
    let e = parse_curve_csv(&text, true).unwrap_err();
    assert_eq!(e.line, 5, "{e}");
    assert!(e.message.contains("along its edge's tangent"), "{e}");
    let text = format!("{h}0,0,0,0,1,0\n1,0,0,0,1,0\n1,0,0,0,1,0\n0,1,0,1,0,0\n");
    let e = parse_curve_csv(&text, false).unwrap_err();
    assert_eq!(e.line, 3, "{e}");
    assert!(e.message.contains("zero length"), "{e}");
}

/// The densities of a fine mesh cost `O(n w)` pair evaluations (`w` edges per window), not
/// the `O(n w^2)` of a direct writhe per window: work counted, not timed. A 4000-edge helix
/// with windows of a tenth of its length (400 edges each): the direct sum would take
/// `sum over windows of w^2 / 2`, about 3e8 pairs; sliding adds and removes each window's
/// entering and leaving edge (`~ 2 w` pairs per window) and sums the partial last edge afresh
/// (`~ w`), about `3 n w` = 4.8e6 pairs in all.
#[test]
fn densities_of_a_fine_mesh_are_not_cubic() {
    let n = 4001;
    let nodes: Vec<V3> = (0..n)
        .map(|i| {
            let t = 40.0 * PI * i as f64 / (n - 1) as f64;
            [t.cos(), t.sin(), 0.2 * t]
        })
        .collect();
    let d1 = (0..n - 1)
        .map(|i| {
            let m = [
                0.5 * (nodes[i][0] + nodes[i + 1][0]),
                0.5 * (nodes[i][1] + nodes[i + 1][1]),
            ];
            [-m[0], -m[1], 0.0]
        })
        .collect();
    let c = FramedCurve {
        nodes,
        d1,
        closed: false,
    };
    let total: f64 = (0..n - 1)
        .map(|i| norm(&sub(&c.nodes[i + 1], &c.nodes[i])))
        .sum();
    let before = PAIRS.with(|p| p.get());
    let d = densities(&c, total / 10.0);
    let pairs = PAIRS.with(|p| p.get()) - before;
    let windows = d.s.len() as u64;
    let w = (n as u64 - 1) / 10;
    let direct = windows * w * w / 2;
    println!("{windows} windows of {w} edges: {pairs} pair evaluations (direct: {direct})");
    assert!(windows > 3500, "{windows} windows");
    // A right-handed helix writhes positively in every window.
    assert!(d.omega.iter().all(|&w| w > 0.0));
    assert!(
        pairs <= 4 * windows * w,
        "{pairs} pair evaluations for {windows} windows of {w} edges (O(n w) would be {})",
        3 * windows * w
    );
    assert!(pairs * 50 < direct, "{pairs} vs direct {direct}");
}
