//! Merging the output directories of a sharded sweep into one.
use super::cell::Cell;
use super::csv::{comparable_row, read_phase_csv, Format};
use super::refine::Refinement;
use super::sweep::{finish, write_info, RunInfo};
use super::PhaseError;
use crate::problem;
use crate::studies::problem_hash;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// What [`merge()`] combined.
#[derive(Debug)]
pub struct Merged {
    /// Every cell, weight-major.
    pub cells: Vec<Cell>,
    /// Cells found in more than one directory (with identical results).
    pub duplicates: usize,
    /// The bisection of the boundaries, when the shards' phase file asked for it.
    pub refinement: Option<Refinement>,
    /// The growth line and how many of its sizes were simulated now (`growth = { ... }`).
    pub growth: Option<(super::growth::GrowthLine, usize)>,
}

/// Combine the `phase.csv` of shard directories (of one phase file and base problem, checked
/// with their `phase.json`) into `out`: the same `phase.csv` (rows in grid order),
/// `phase.json` and figures as an unsharded run. Refuses directories of other grids or base
/// files, cells found twice with different results, and a grid with missing cells (listed).
/// The phase file named in the shards' `phase.json` is read again: merge follows it, and
/// refuses (naming each difference) when its settings no longer are the shards' ([`changes`]:
/// the base problem by its effective content, the grid, `refine`, `verify`, the protocol,
/// `growth`, `[accuracy]`). When it cannot be read (a merge from another directory), the
/// shards' record is followed. When the phase file asks for `refine = true`, the boundaries
/// are bisected here, into `out/refine.csv` (resumable as in an unsharded run), with the base
/// problem read again (refused if its effective content changed since: [`problem_hash`]).
/// `refine_report(done, cell)` is called after each refinement simulation.
pub fn merge(
    dirs: &[PathBuf],
    out: &Path,
    refine_report: &(dyn Fn(usize, &Cell) + Sync),
    growth_report: &(dyn Fn(usize, &Cell) + Sync),
) -> Result<Merged, PhaseError> {
    let mut reference: Option<RunInfo> = None;
    let mut found: HashMap<(u64, u64), (Cell, String)> = HashMap::new();
    let mut duplicates = 0;
    for dir in dirs {
        let info = read_info(dir)?;
        match &reference {
            None => reference = Some(info.clone()),
            Some(r) => same_run(r, &info, dir)?,
        }
        duplicates += shard_rows(dir, &info, &mut found)?;
    }
    let info =
        reference.ok_or_else(|| mismatch(Path::new("."), "no directories to merge".into()))?;
    let grid: Vec<(f64, f64)> = info
        .weight
        .iter()
        .flat_map(|&w| info.torque.iter().map(move |&g| (w, g)))
        .collect();
    let missing: Vec<String> = grid
        .iter()
        .filter(|(w, g)| !found.contains_key(&(w.to_bits(), g.to_bits())))
        .map(|(w, g)| format!("(W {w}, G {g})"))
        .collect();
    if !missing.is_empty() {
        return Err(PhaseError::Missing {
            count: missing.len(),
            cells: missing
                .iter()
                .take(10)
                .cloned()
                .collect::<Vec<_>>()
                .join(", "),
        });
    }
    // The current phase file, when readable, must still be the one the shards ran.
    let settings = info.parsed_settings().map_err(|why| PhaseError::Merge {
        dir: PathBuf::from(&info.phase_file),
        why: format!("phase.json's settings: {why}"),
    })?;
    let settings: Vec<&problem::set::Setting> = settings.iter().collect();
    if let Ok(ph) = super::file::load_with(Path::new(&info.phase_file), &settings) {
        let diff = changes(&info, &ph);
        if !diff.is_empty() {
            return Err(PhaseError::Merge {
                dir: PathBuf::from(&info.phase_file),
                why: format!(
                    "the phase file changed since the shards ran: {}; re-run the shards with the current file (or restore it) before merging",
                    diff.join("; ")
                ),
            });
        }
    }
    let base_hash = u64::from_str_radix(&info.base_hash, 16).expect("checked above");
    let hash = info.protocol.row_hash(base_hash);
    let hash = info.verify.map_or(hash, |v| v.row_hash(hash));
    // The base problem, for the refinement's and the growth line's simulations: the file the
    // shards ran, unchanged.
    let base = followup_base(&info, &settings, base_hash)?;
    let cells: Vec<Cell> = grid
        .iter()
        .map(|(w, g)| found[&(w.to_bits(), g.to_bits())].0.clone())
        .collect();
    std::fs::create_dir_all(out).map_err(|source| PhaseError::Io {
        file: out.to_path_buf(),
        source,
    })?;
    let format = Format {
        verified: info.verify.is_some(),
        periodic: info.periodic,
    };
    let mut text = format!("{}\n", format.header());
    for c in &cells {
        text += &(c.row(hash, format.periodic) + "\n");
    }
    let csv = out.join("phase.csv");
    std::fs::write(&csv, text).map_err(|source| PhaseError::Io { file: csv, source })?;
    write_info(
        out,
        &RunInfo {
            shard: None,
            ..info.clone()
        },
    )?;
    let refine = base
        .as_ref()
        .zip(info.refine_steps)
        .map(|(b, k)| (b, hash, k, info.verify, info.protocol));
    let refinement = finish(
        out,
        &info.weight,
        &info.torque,
        &cells,
        refine,
        refine_report,
    )?;
    let growth = match (&base, &info.growth) {
        (Some(b), Some(g)) => Some(super::sweep::grow(
            out,
            b,
            base_hash,
            g,
            info.verify.as_ref(),
            &cells,
            growth_report,
        )?),
        _ => None,
    };
    Ok(Merged {
        cells,
        duplicates,
        refinement,
        growth,
    })
}

/// A directory that cannot be merged, and why.
fn mismatch(dir: &Path, why: String) -> PhaseError {
    PhaseError::Merge {
        dir: dir.to_path_buf(),
        why,
    }
}
/// A shard directory's `phase.json`.
fn read_info(dir: &Path) -> Result<RunInfo, PhaseError> {
    let file = dir.join("phase.json");
    let text = std::fs::read_to_string(&file).map_err(|e| {
        mismatch(
            dir,
            format!("no readable phase.json ({e}): not a `slither phase` output directory"),
        )
    })?;
    let info: RunInfo = serde_json::from_str(&text)
        .map_err(|e| mismatch(dir, format!("phase.json is not valid: {e}")))?;
    Ok(info)
}

/// Whether two shards' records are of the same study (base, refinement, protocol,
/// verification, columns and grid); `Err` names what differs, in `dir`.
fn same_run(r: &RunInfo, info: &RunInfo, dir: &Path) -> Result<(), PhaseError> {
    if r.base_hash != info.base_hash {
        return Err(mismatch(
            dir,
            format!(
                "base problem {} (hash {}) differs from {} (hash {})",
                info.base_file, info.base_hash, r.base_file, r.base_hash
            ),
        ));
    }
    if r.refine_steps != info.refine_steps {
        let say = |k: Option<usize>| {
            k.map_or("refine = false".to_string(), |k| {
                format!("refine = true, refine_steps = {k}")
            })
        };
        return Err(mismatch(
            dir,
            format!(
                "ran with {}, another directory with {}",
                say(info.refine_steps),
                say(r.refine_steps)
            ),
        ));
    }
    if r.protocol != info.protocol {
        return Err(mismatch(
            dir,
            format!(
                "ran with {:?}, another directory with {:?}",
                info.protocol, r.protocol
            ),
        ));
    }
    if r.verify != info.verify {
        let say = |v: &Option<super::Verify>| {
            v.map_or("no verification".to_string(), |v| format!("verify = {v:?}"))
        };
        return Err(mismatch(
            dir,
            format!(
                "ran with {}, another directory with {}",
                say(&info.verify),
                say(&r.verify)
            ),
        ));
    }
    if r.periodic != info.periodic {
        let say = |p: bool| {
            if p {
                "the periodic columns (a gait with a launch period)"
            } else {
                "no periodic columns"
            }
        };
        return Err(mismatch(
            dir,
            format!(
                "its rows have {}, another directory's {} (a shard written by another version of slither?): re-run the shard",
                say(info.periodic),
                say(r.periodic)
            ),
        ));
    }
    if r.weight != info.weight || r.torque != info.torque {
        return Err(mismatch(
            dir,
            format!(
                "grid W {:?} x G {:?} differs from W {:?} x G {:?}",
                info.weight, info.torque, r.weight, r.torque
            ),
        ));
    }
    Ok(())
}

/// Add the rows of the shard in `dir` (recorded as `info`) to `found`, each checked: its
/// regime agrees with its values, and a cell already found has the same result. Returns how
/// many were found already.
fn shard_rows(
    dir: &Path,
    info: &RunInfo,
    found: &mut HashMap<(u64, u64), (Cell, String)>,
) -> Result<usize, PhaseError> {
    let mut duplicates = 0;
    let hash = u64::from_str_radix(&info.base_hash, 16)
        .map_err(|_| mismatch(dir, "phase.json: base_hash is not hexadecimal".into()))?;
    let hash = info.protocol.row_hash(hash);
    let hash = info.verify.map_or(hash, |v| v.row_hash(hash));
    let csv = dir.join("phase.csv");
    let rows = read_phase_csv(&csv, hash)?;
    let want = Format {
        verified: info.verify.is_some(),
        periodic: info.periodic,
    };
    if !rows.fresh {
        rows.format
            .check(want, &csv, "cannot merge it (re-run the shard)")?;
    }
    for (key, c) in rows.cells {
        // A row's regime is a function of its values: a label that disagrees was edited
        // (or written by another version) and would enter the map unchecked.
        if let (crate::studies::optimize::Status::Ok, Some(stated)) = (c.status, c.regime) {
            let computed = crate::observe::classify(&c.regime_inputs()).0;
            if computed != stated {
                return Err(mismatch(
                    dir,
                    format!(
                        "cell W = {}, G = {}: phase.csv says regime {stated} but its values give {computed} (a row edited by hand, or written by another version): re-run the shard",
                        c.weight, c.torque
                    ),
                ));
            }
        }
        let row = comparable_row(&c, hash);
        match found.get(&key) {
            Some((_, seen)) if *seen == row => duplicates += 1,
            Some(_) => {
                return Err(mismatch(
                    dir,
                    format!(
                        "cell W = {}, G = {} is also in another directory with a different result",
                        c.weight, c.torque
                    ),
                ))
            }
            None => {
                found.insert(key, (c, row));
            }
        }
    }
    Ok(duplicates)
}

/// The base problem for the refinement's and the growth line's simulations (`None` when the
/// study has neither): the file the shards ran, unchanged (checked by its hash), at the
/// chosen model with `[accuracy]`.
fn followup_base(
    info: &RunInfo,
    settings: &[&problem::set::Setting],
    base_hash: u64,
) -> Result<Option<problem::Problem>, PhaseError> {
    Ok(match (info.refine_steps, &info.growth) {
        (None, None) => None,
        _ => {
            let path = PathBuf::from(&info.base_file);
            let refuse = |why: String| PhaseError::Merge {
                dir: path.clone(),
                why: format!(
                    "cannot refine the boundaries (refine = true) or run the growth line: {why}"
                ),
            };
            let text = std::fs::read_to_string(&path).map_err(|e| {
                refuse(format!(
                    "the base problem named in phase.json is not readable ({e}); merge from the directory the shards ran in"
                ))
            })?;
            // With `[accuracy]` the rows are keyed by the file and the chosen model: the file
            // is checked against the choice's own record, and refined at that model.
            let (file_hash, shards_hash) = match &info.accuracy {
                Some(c) => (
                    u64::from_str_radix(&c.base_file_hash, 16).ok(),
                    c.base_file_hash.clone(),
                ),
                None => (Some(base_hash), info.base_hash.clone()),
            };
            let (_, base_settings) = problem::set::split(settings, &super::file::TABLES);
            let base = problem::parse_with(&text, &path, &base_settings)
                .map(|(_, p)| p)
                .map_err(|e| refuse(e.to_string()))?;
            if Some(problem_hash(&base)) != file_hash {
                return Err(refuse(format!(
                    "the base problem changed since the shards ran (hash {:016x}, the shards' {})",
                    problem_hash(&base),
                    shards_hash
                )));
            }
            // Rows of the shards and of the refinement or growth line written here have the
            // same columns.
            if base.gait.kind.has_launch_period() != info.periodic {
                return Err(refuse(format!(
                    "the shards' rows {} the periodic columns and its gait {} a launch period: shards written by another version of slither; re-run them",
                    if info.periodic { "have" } else { "lack" },
                    if info.periodic { "lacks" } else { "has" },
                )));
            }
            Some(match &info.accuracy {
                Some(c) => c.apply(&base),
                None => base,
            })
        }
    })
}

/// How the phase file `ph` (as read now) differs from what the shards recorded in `info`, one
/// phrase per setting ("refine: the file now says refine = false, the shards ran refine =
/// true, refine_steps = 3"); empty when it is the file they ran.
pub fn changes(info: &RunInfo, ph: &super::Phase) -> Vec<String> {
    let mut out = Vec::new();
    let mut differ = |what: &str, now: String, then: String| {
        if now != then {
            out.push(format!(
                "{what}: the file now says {now}, the shards ran {then}"
            ));
        }
    };
    let shards_file_hash = info
        .accuracy
        .as_ref()
        .map_or(info.base_hash.clone(), |c| c.base_file_hash.clone());
    differ(
        "base problem",
        format!("{} (hash {:016x})", ph.base_path.display(), ph.base_hash),
        format!("{} (hash {shards_file_hash})", info.base_file),
    );
    differ(
        "grid",
        format!("W {:?} x G {:?}", ph.weight, ph.torque),
        format!("W {:?} x G {:?}", info.weight, info.torque),
    );
    let refine = |k: Option<usize>| {
        k.map_or("refine = false".to_string(), |k| {
            format!("refine = true, refine_steps = {k}")
        })
    };
    differ("refine", refine(ph.refine), refine(info.refine_steps));
    let verify = |v: Option<super::Verify>| {
        v.map_or("no verification".to_string(), |v| format!("verify = {v:?}"))
    };
    differ("verify", verify(ph.verify), verify(info.verify));
    differ(
        "protocol",
        format!("{:?}", ph.protocol),
        format!("{:?}", info.protocol),
    );
    differ(
        "growth",
        format!("{:?}", ph.growth),
        format!("{:?}", info.growth),
    );
    let accuracy = |a: Option<(f64, usize)>| {
        a.map_or("no [accuracy]".to_string(), |(t, m)| {
            format!("[accuracy] target = {t}, max_elements = {m}")
        })
    };
    differ(
        "accuracy",
        accuracy(ph.accuracy.as_ref().map(|a| (a.target, a.max_elements))),
        accuracy(info.accuracy.as_ref().map(|c| (c.target, c.max_elements))),
    );
    out
}
