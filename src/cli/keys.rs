//! `slither keys`: the user guide's generated references, printed from the definitions the
//! code uses (`slither::problem::keys` for problem-file keys, `slither::output::schema` for
//! what runs write). `tests/docs.rs` keeps `docs/book/src/keys.md` and
//! `docs/book/src/outputs.md` equal to them.
use slither::{output, problem};
use std::process::ExitCode;

/// `slither keys` arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Print every problem-file key with its unit, default, allowed values and meaning, as
    /// Markdown (the guide's docs/book/src/keys.md). The default.
    #[arg(long)]
    pub markdown: bool,
    /// Print every key of summary.json and every column of phase.csv and history.csv with
    /// its unit and meaning, as Markdown (the guide's docs/book/src/outputs.md).
    #[arg(long, conflicts_with = "markdown")]
    pub outputs_markdown: bool,
}

/// Print the chosen reference on stdout.
pub fn keys(a: &Args) -> ExitCode {
    if a.outputs_markdown {
        print!("{}", output::schema::markdown());
    } else {
        print!("{}", problem::reference::markdown());
    }
    ExitCode::SUCCESS
}
