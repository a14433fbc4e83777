//! Where does the S-start's mesh error come from? Runs a scene at a mesh and step with one
//! ingredient of the discretization changed, over an ensemble of perturbed runs (the friction
//! coefficients times `1 + 1e-7 k`, `k = 0..K`: the S-start at 50 elements has two outcomes
//! depending on such changes), and prints `v_s/v_m` of every run and the ensemble's mean.
//!
//! Ingredients (`VARIANT`):
//! * `point`: the muscle couples sampled at the nodes (point value times the Voronoi length),
//!   the library's discretization;
//! * `cell`: the couples integrated over each node's Voronoi cell (four-point Gauss-Legendre);
//! * `coarse-couple:NC`: the couples as the `NC`-element mesh samples them (point values at
//!   its nodes, interpolated linearly), on this mesh;
//! * `coarse-mass:NC`: mass and weight lumped at the `NC`-element mesh's nodes (every other
//!   node keeps 5 % of its own), on this mesh.
//!
//! Contact resolution cannot be changed from here: the budget in the guide coarsened it with a
//! temporary filter on the contact candidates (every k-th node), which is not in the library.
//!
//! ```sh
//! cargo run --release --example mesh_budget -- SCENE.toml ELEMENTS DT VARIANT K [FIRST_K]
//! ```
use slither::gait::{Actuation, Gait};
use slither::model::Model;
use slither::rod::dof;
use slither::{observe, problem, sim};
use std::path::Path;

/// Gauss-Legendre nodes and weights on [-1, 1], 4 points.
const GL4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
];

enum Sampling {
    Point,
    Cell,
    Coarse(usize),
}

struct Couples {
    gait: Gait,
    sampling: Sampling,
}

impl Actuation for Couples {
    fn rest_strains(&self, t: f64, m: &Model, kappa0: &mut [[f64; 2]], m0: &mut [f64]) {
        let density = |s: f64| -> [f64; 2] {
            match self.sampling {
                Sampling::Point | Sampling::Cell => self.gait.couple_at(s, t),
                Sampling::Coarse(nc) => {
                    let h = m.length / nc as f64;
                    let j = ((s / h).floor() as usize).min(nc - 1);
                    let w = s / h - j as f64;
                    let a = self.gait.couple_at(j as f64 * h, t);
                    let b = self.gait.couple_at((j + 1) as f64 * h, t);
                    [a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1])]
                }
            }
        };
        for i in 1..m.nodes - 1 {
            let l = m.voronoi[i];
            let s = m.arc_length(i);
            let mm = match self.sampling {
                Sampling::Point => {
                    let c = density(s);
                    [c[0] * l, c[1] * l]
                }
                _ => {
                    let mut acc = [0.0; 2];
                    for (x, w) in GL4 {
                        let c = density(s + 0.5 * l * x);
                        acc[0] += 0.5 * l * w * c[0];
                        acc[1] += 0.5 * l * w * c[1];
                    }
                    acc
                }
            };
            kappa0[i] = [
                m.natural_curvature[0] * l - mm[0] / m.bend,
                m.natural_curvature[1] * l - mm[1] / m.bend,
            ];
            m0[i] = m.natural_twist * l;
        }
    }
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    if a.len() < 5 {
        eprintln!("usage: mesh_budget SCENE.toml ELEMENTS DT VARIANT K [FIRST_K]");
        std::process::exit(2);
    }
    let base = problem::load(Path::new(&a[0])).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(2)
    });
    let elements: usize = a[1].parse().expect("ELEMENTS");
    let dt: f64 = a[2].parse().expect("DT");
    let variant = a[3].as_str();
    let k_count: usize = a[4].parse().expect("K");
    let k_first: usize = a.get(5).map_or(0, |s| s.parse().expect("FIRST_K"));
    let (name, arg) = variant.split_once(':').unwrap_or((variant, "0"));
    let nc: usize = arg.parse().expect("NC");
    let mut vs = Vec::new();
    for k in k_first..k_first + k_count {
        let mut p = base.clone();
        p.rod.elements = elements;
        p.time.dt = Some(dt);
        let f = 1.0 + 1e-7 * k as f64;
        if let Some(g) = p.ground.as_mut() {
            g.mu_forward *= f;
            g.mu_backward *= f;
            g.mu_sideways *= f;
        }
        let mut m = Model::new(&p);
        let sampling = match name {
            "point" => Sampling::Point,
            "cell" | "coarse-mass" => Sampling::Cell,
            "coarse-couple" => Sampling::Coarse(nc),
            _ => panic!("unknown variant {name}"),
        };
        if name == "coarse-mass" {
            let ratio = elements / nc;
            assert!(ratio * nc == elements, "NC must divide ELEMENTS");
            let eps = 0.05;
            let total: f64 = m.real.clone().map(|i| m.mass[dof::node(i)]).sum();
            let lc = m.length / nc as f64;
            for (k, i) in m.real.clone().enumerate() {
                let own = m.mass[dof::node(i)];
                let mass = if k % ratio == 0 {
                    let lv = if k == 0 || k == elements {
                        0.5 * lc
                    } else {
                        lc
                    };
                    (1.0 - eps) * m.line_density() * lv + eps * own
                } else {
                    eps * own
                };
                for c in 0..3 {
                    m.mass[dof::node(i) + c] = mass;
                }
            }
            let now: f64 = m.real.clone().map(|i| m.mass[dof::node(i)]).sum();
            assert!((now - total).abs() < 1e-12 * total);
        }
        let act = Box::new(Couples {
            gait: m.gait.clone(),
            sampling,
        });
        let o = sim::run(&m, act, &mut |_| {}, &mut |_| {});
        let v = if o.error.is_none() {
            let ends = [o.frames[0].clone(), o.frames[o.frames.len() - 1].clone()];
            let fl = observe::fields(&m, &ends);
            observe::observe(&m, &ends, &fl).v_s_over_v_m
        } else {
            f64::NAN
        };
        println!(
            "{variant} {elements} {dt:e} k={k} v={v:.5} wall={:.2}{}",
            o.wall_time_s,
            o.error.map_or(String::new(), |e| format!(" failed: {e}"))
        );
        vs.push(v);
    }
    let n = vs.len() as f64;
    let mean = vs.iter().sum::<f64>() / n;
    let sd = (vs.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt();
    println!("{variant} {elements} {dt:e} mean={mean:.5} sd={sd:.5} n={n}");
}
