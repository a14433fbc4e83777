//! Assembly of the energy, gradient and (projected) Hessian of all rod terms on a bent,
//! twisted rod whose frozen frames belong to an earlier shape, at 50 and 200 elements.
// Index loops over dof indices read as the math does.
#![allow(clippy::needless_range_loop)]
use criterion::{criterion_group, criterion_main, Criterion};
use slither::band::Assembly;
use slither::energy::reference::closed::Closed;
use slither::energy::reference::terms::{Bend, Twist};
use slither::energy::{self, Ctx};
use slither::model::Model;
use slither::problem;
use slither::rod::dof;
use slither::state::State;
use std::hint::black_box;
use std::path::Path;

struct Rng(u64);
impl Rng {
    fn sym(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

fn setup(elements: usize) -> (Model, State, Vec<f64>, Vec<[f64; 2]>, Vec<f64>) {
    let text = format!(
        r#"
[rod]
length = 1.0
diameter = 0.02
elements = {elements}
bending_stiffness = 1e-2
twist_stiffness = 8e-3
[time]
dt = 1e-3
duration = 1.0
"#
    );
    let m = Model::new(&problem::parse(&text, Path::new("bench")).unwrap());
    let mut r = Rng(0x9E3779B97F4A7C15);
    let mut s = State::initial(&m);
    let l0 = m.rest_len[0];
    for k in 0..m.ndof {
        s.q[k] += 0.3 * l0 * r.sym();
    }
    s.update_frames();
    let mut q = s.q.clone();
    for k in 0..m.ndof {
        q[k] += 0.15 * l0 * r.sym();
    }
    for j in 0..m.nodes - 1 {
        q[dof::edge(j)] = 2.0 * r.sym();
    }
    let kappa0 = (0..m.nodes)
        .map(|_| [0.3 * r.sym(), 0.3 * r.sym()])
        .collect();
    let m0 = (0..m.nodes).map(|_| 0.3 * r.sym()).collect();
    (m, s, q, kappa0, m0)
}

fn bench_assembly(c: &mut Criterion) {
    let mut g = c.benchmark_group("assembly");
    let terms = energy::rod_terms();
    for n in [50, 200] {
        let (m, s, q, kappa0, m0) = setup(n);
        let ctx = Ctx {
            model: &m,
            frames: &s.frames,
            kappa0: &kappa0,
            m0: &m0,
            gravity: [0.0, 0.0, -9.81],
            rest_len: &m.rest_len,
            elastic_scale: 1.0,
        };
        let mut asm = Assembly::new(m.ndof);
        for project in [true, false] {
            g.bench_function(format!("{n}_elements_project_{project}"), |b| {
                b.iter(|| {
                    asm.clear();
                    black_box(energy::total(
                        &terms,
                        &ctx,
                        black_box(&q),
                        Some(&mut asm),
                        project,
                    ))
                })
            });
        }
        // The separate closed-form bending and twist terms (the default before the fused
        // stencil), for the ratio in one run.
        let separate: Vec<Box<dyn energy::Term>> = vec![
            Box::new(energy::stretch::Stretch),
            Box::new(Bend(Closed)),
            Box::new(Twist(Closed)),
            Box::new(energy::gravity::Gravity),
        ];
        g.bench_function(format!("{n}_elements_project_false_separate"), |b| {
            b.iter(|| {
                asm.clear();
                black_box(energy::total(
                    &separate,
                    &ctx,
                    black_box(&q),
                    Some(&mut asm),
                    false,
                ))
            })
        });
        g.bench_function(format!("{n}_elements_energy_only"), |b| {
            b.iter(|| black_box(energy::total(&terms, &ctx, black_box(&q), None, false)))
        });
    }
    g.finish();
}

/// One node's bending and twist value, gradient and Hessian together (intrinsic coordinates,
/// edge frames included; `fused_edges_shared` computes each edge frame once, as the assembly
/// does), by the staged jets and by the closed forms, averaged over the 49
/// interior nodes of the 50-element rod of [`setup`].
fn bench_stencil(c: &mut Criterion) {
    use slither::energy::local::intrinsic;
    use slither::energy::reference::jets::EdgeJets;
    use slither::energy::reference::terms::{Jets, StencilDerivatives};
    use slither::energy::stencil::{BendStencil, TwistStencil};
    let mut g = c.benchmark_group("stencil_per_node");
    let (m, s, q, kappa0, m0) = setup(50);
    let nodes: Vec<usize> = (1..m.nodes - 1).collect();
    fn per_node<D: StencilDerivatives>(
        d: &D,
        m: &Model,
        s: &State,
        q: &[f64],
        kappa0: &[[f64; 2]],
        m0: &[f64],
        i: usize,
    ) -> f64 {
        let frame = &s.frames[i - 1];
        let y = intrinsic(q, i);
        let [e0, e1] = EdgeJets::of_stencil(frame, &y);
        let bend = BendStencil {
            frame,
            kappa0: kappa0[i],
            coef: m.bend / (2.0 * m.voronoi[i]),
        };
        let twist = TwistStencil {
            frame,
            m0: m0[i],
            coef: m.twist / (2.0 * m.voronoi[i]),
        };
        let b = d.bend(&bend, [&e0, &e1], &y);
        let t = d.twist(&twist, [&e0, &e1], &y);
        b.0 + t.0 + b.2[(3, 4)] + t.2[(1, 2)]
    }
    let count = nodes.len() as u64;
    g.throughput(criterion::Throughput::Elements(count));
    g.bench_function("jets", |b| {
        b.iter(|| {
            nodes
                .iter()
                .map(|&i| per_node(&Jets, &m, &s, black_box(&q), &kappa0, &m0, i))
                .sum::<f64>()
        })
    });
    g.bench_function("fused", |b| {
        use slither::energy::bend_twist::{node_local, EdgeFrame, NodeStencil};
        b.iter(|| {
            nodes
                .iter()
                .map(|&i| {
                    let frame = &s.frames[i - 1];
                    let y = intrinsic(black_box(&q), i);
                    let e0 =
                        EdgeFrame::new([y[0], y[1], y[2]], frame.t_old[0], frame.a1_old[0], y[6]);
                    let e1 =
                        EdgeFrame::new([y[3], y[4], y[5]], frame.t_old[1], frame.a1_old[1], y[7]);
                    let st = NodeStencil {
                        frame,
                        kappa0: kappa0[i],
                        bend: m.bend / (2.0 * m.voronoi[i]),
                        m0: m0[i],
                        twist: m.twist / (2.0 * m.voronoi[i]),
                    };
                    let l = node_local(&st, [&e0, &e1]);
                    l.0 + l.2[(3, 4)] + l.2[(1, 2)]
                })
                .sum::<f64>()
        })
    });
    // As the assembly does it: each edge's frame once, shared by its two nodes.
    g.bench_function("fused_edges_shared", |b| {
        use slither::energy::bend_twist::{node_local, EdgeFrame, NodeStencil};
        b.iter(|| {
            let q = black_box(&q);
            let edges: Vec<EdgeFrame> = (0..m.nodes - 1)
                .map(|j| {
                    let (fr, k) = (&s.frames[j.saturating_sub(1)], usize::from(j > 0));
                    let (a, b) = (dof::node(j), dof::node(j + 1));
                    let e = [q[b] - q[a], q[b + 1] - q[a + 1], q[b + 2] - q[a + 2]];
                    EdgeFrame::new(e, fr.t_old[k], fr.a1_old[k], q[dof::edge(j)])
                })
                .collect();
            nodes
                .iter()
                .map(|&i| {
                    let st = NodeStencil {
                        frame: &s.frames[i - 1],
                        kappa0: kappa0[i],
                        bend: m.bend / (2.0 * m.voronoi[i]),
                        m0: m0[i],
                        twist: m.twist / (2.0 * m.voronoi[i]),
                    };
                    let l = node_local(&st, [&edges[i - 1], &edges[i]]);
                    l.0 + l.2[(3, 4)] + l.2[(1, 2)]
                })
                .sum::<f64>()
        })
    });
    g.bench_function("closed_form", |b| {
        b.iter(|| {
            nodes
                .iter()
                .map(|&i| per_node(&Closed, &m, &s, black_box(&q), &kappa0, &m0, i))
                .sum::<f64>()
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(2)).warm_up_time(std::time::Duration::from_millis(500));
    targets = bench_assembly, bench_stencil
}
criterion_main!(benches);
