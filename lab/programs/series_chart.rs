//! A line chart of named series from a CSV file (`label,x,y` rows after a header), for
//! scripts that measure in Python and draw with the crate's charts:
//!
//!     cargo run --release --example series_chart -- IN.csv OUT.png TITLE X_LABEL Y_LABEL [--log-x]

use slither::plot;
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 5 {
        eprintln!("usage: series_chart IN.csv OUT.png TITLE X_LABEL Y_LABEL [--log-x]");
        std::process::exit(2);
    }
    let text = std::fs::read_to_string(&args[0]).unwrap_or_else(|e| {
        eprintln!("series_chart: {}: {e}", args[0]);
        std::process::exit(1)
    });
    let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for (line_no, line) in text.lines().enumerate().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let parsed = (f.len() == 3)
            .then(|| {
                Some((
                    f[1].trim().parse::<f64>().ok()?,
                    f[2].trim().parse::<f64>().ok()?,
                ))
            })
            .flatten();
        let Some(point) = parsed else {
            eprintln!(
                "series_chart: {}:{}: expected label,x,y",
                args[0],
                line_no + 1
            );
            std::process::exit(1)
        };
        match series.iter_mut().find(|(l, _)| l == f[0]) {
            Some((_, pts)) => pts.push(point),
            None => series.push((f[0].to_string(), vec![point])),
        }
    }
    let named: Vec<(&str, Vec<(f64, f64)>)> = series
        .iter()
        .map(|(l, p)| (l.as_str(), p.clone()))
        .collect();
    let log_x = args.iter().any(|a| a == "--log-x");
    if let Err(e) = plot::xy(
        Path::new(&args[1]),
        &args[2],
        &args[3],
        &args[4],
        &named,
        log_x,
        false,
    ) {
        eprintln!("series_chart: {e}");
        std::process::exit(1)
    }
    println!("chart: {}", args[1]);
}
