//! `slither topology`: twist, writhe and link of a framed curve given as CSV.
use slither::{problem, topology};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    /// CSV file with a header row.
    pub curve: PathBuf,
    /// The curve is closed (its last edge returns to the first node); adds `lk_gauss`.
    #[arg(long)]
    pub closed: bool,
}

pub fn topo(args: &Args) -> ExitCode {
    let (path, closed) = (args.curve.as_path(), args.closed);
    let text = match problem::read(path) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let c = match topology::parse_curve_csv(&text, closed) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {}:{}: {}", path.display(), e.line, e.message);
            return ExitCode::from(2);
        }
    };
    let t = topology::topology(&c);
    let mut v = serde_json::json!({ "tw": t.tw, "wr": t.wr, "lk": t.lk });
    if closed {
        let len: f64 = (0..c.nodes.len())
            .map(|i| {
                let a = c.nodes[i];
                let b = c.nodes[(i + 1) % c.nodes.len()];
                ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        v["lk_gauss"] = serde_json::json!(topology::gauss_link(&c, 1e-3 * len));
    }
    println!("{v}");
    ExitCode::SUCCESS
}
