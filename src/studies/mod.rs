//! Studies: many runs of a base problem, each one a [`crate::pipeline`]-style simulation of a
//! variant, and what they find.
//!
//! * [`optimize`]: gait optimisation (MODEL section 7): the study file, the search space, the
//!   objective, the argmin search, `history.csv` and `optimum.json`.
//! * [`phase`]: the regime phase diagram (MODEL section 6): the phase file, the sweep, its
//!   shards and their merge, the boundaries and their refinement, growth lines.
//! * [`accuracy`]: the model (mesh and time resolution) chosen for a target error: the
//!   selection of `slither run --accuracy` and a study's `[accuracy]` table.
//! * [`ensemble`]: a problem re-run with perturbed inputs (`slither run --ensemble`, the phase
//!   study's verification, the optimiser's check of its best point).
//!
//! Shared by the studies: the resume keys' hashes ([`problem_hash`], `digest.rs`) and
//! `csv_field` for the free-text fields of their CSV files.

pub mod accuracy;
mod digest;
pub mod ensemble;
pub mod optimize;
pub mod phase;

pub(crate) use digest::fnv1a;
pub use digest::problem_hash;

/// A free-text value (a failure reason) as one CSV field of the result files: commas and line
/// breaks become `;`, other control characters spaces, so a row stays one line of fixed width.
pub(crate) fn csv_field(s: &str) -> String {
    s.chars()
        .map(|c| match c {
            ',' | '\n' | '\r' => ';',
            c if c.is_control() => ' ',
            c => c,
        })
        .collect()
}
