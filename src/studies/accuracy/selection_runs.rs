//! The runs of the accuracy selection ([`super`]): each model simulated (in parallel, one
//! per core) or read back from the journal, and its `v_s/v_m`.

use super::*;

/// The model of `p` at (`elements`, `res`), run.
pub(super) fn simulate(p: &Problem, elements: usize, res: Resolution) -> (Model, Outcome) {
    let model = Model::new(&accuracy_problem(p, elements, res));
    let muscles = Box::new(crate::gait::Muscles {
        gait: model.gait.clone(),
    });
    let outcome = crate::sim::run(&model, muscles, &mut |_| {}, &mut |_| {});
    (model, outcome)
}

/// Run the models of `wanted` that were not made yet, in parallel (one simulation per core),
/// or read them back from the journal, and add them to `done` in the order asked, one line
/// each to `log`. Each run made is appended to the journal as it finishes.
pub(super) fn run_missing(
    p: &Problem,
    wanted: &[(usize, Resolution)],
    done: &mut Vec<Done>,
    mut journal: Option<&mut Journal>,
    log: &mut dyn FnMut(&str),
) {
    let mut todo: Vec<(usize, Resolution)> = Vec::new();
    let mut read_back: Vec<Done> = Vec::new();
    for &(e, r) in wanted {
        let listed = |d: &Done| d.run.elements == e && d.res.same(r);
        if made(done, e, r).is_some()
            || todo.iter().any(|&(f, q)| f == e && q.same(r))
            || read_back.iter().any(listed)
        {
            continue;
        }
        match journal.as_deref().and_then(|j| j.find(e, r)) {
            Some(run) => read_back.push(Done {
                res: r,
                run: run.clone(),
                ran: None,
            }),
            None => todo.push((e, r)),
        }
    }
    if !todo.is_empty() {
        // Announce the batch: its runs report only when all of them have finished.
        log(&format!(
            "accuracy: running {}",
            todo.iter()
                .map(|(e, r)| format!("{e} elements, {r}"))
                .collect::<Vec<_>>()
                .join("; ")
        ));
    }
    let shared = Mutex::new(journal.as_deref_mut());
    let new: Vec<Done> = todo
        .par_iter()
        .map(|&(elements, res)| {
            let (model, outcome) = simulate(p, elements, res);
            let v = if outcome.error.is_none() {
                speed_ratio(&model, &outcome)
            } else {
                f64::NAN
            };
            let d = Done {
                res,
                run: AccuracyRun {
                    elements,
                    dt: res.dt(),
                    error_tolerance: res.tolerance(),
                    v_s_over_v_m: v,
                    steps: outcome.steps.accepted,
                    wall_time_s: outcome.wall_time_s,
                    status: outcome
                        .error
                        .as_ref()
                        .map_or("ok".into(), |e| e.to_string()),
                },
                ran: Some((model, outcome)),
            };
            if let Some(j) = shared.lock().unwrap_or_else(|e| e.into_inner()).as_mut() {
                j.append(&d.run);
            }
            d
        })
        .collect();
    let origin = journal
        .as_deref()
        .map(|j| format!(" (read back from {})", j.path.display()))
        .unwrap_or_default();
    for (d, from) in read_back
        .into_iter()
        .map(|d| (d, origin.as_str()))
        .chain(new.into_iter().map(|d| (d, "")))
    {
        let r = &d.run;
        log(&format!(
            "accuracy: {} elements, {}: v_s/v_m {:.5}, {} steps, {:.2} s{}{from}",
            r.elements,
            d.res,
            r.v_s_over_v_m,
            r.steps,
            r.wall_time_s,
            if r.status == "ok" {
                String::new()
            } else {
                format!(" (failed: {})", r.status)
            }
        ));
        done.push(d);
    }
}

/// `v_s/v_m` of a run by the definition of [`crate::observe`], measured on its first and last
/// frame ([`crate::observe::Measure::Ends`]); NaN without frames.
fn speed_ratio(model: &Model, o: &Outcome) -> f64 {
    if o.observed.is_empty() {
        return f64::NAN;
    }
    let ends = crate::observe::Measure::Ends;
    crate::observe::measure(model, o, ends, &mut |_| {})
        .1
        .v_s_over_v_m
}
