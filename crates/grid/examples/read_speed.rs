//! Median read time of model files, geometry and properties, for any format
//! `open` reads: `cargo run --release -p strata-grid --example read_speed -- FILE... [--runs N]
//! [--grid-only]` (`--grid-only`: geometry and ACTNUM, as `strata bench io` times).
//!
//! One untimed read first (the file is then in the page cache: this measures decoding,
//! not the disk); prints per file its size, median milliseconds and MB/s (10^6 bytes).

use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let runs = args
        .iter()
        .position(|a| a == "--runs")
        .and_then(|i| args.get(i + 1))
        .map_or(Ok(5), |s| s.parse::<usize>())?;
    let options = strata_grid::ReadOptions {
        grid_only: args.iter().any(|a| a == "--grid-only"),
        ..strata_grid::ReadOptions::default()
    };
    let files = args.iter().take_while(|a| !a.starts_with("--"));
    for file in files {
        let path = std::path::Path::new(file);
        let bytes = std::fs::metadata(path)?.len() as f64;
        strata_grid::open_with(path, &options)?;
        let mut times: Vec<f64> = (0..runs.max(1))
            .map(|_| {
                let start = Instant::now();
                strata_grid::open_with(path, &options).map(|_| start.elapsed().as_secs_f64())
            })
            .collect::<Result<_, _>>()?;
        times.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        println!(
            "{file}: {:.2} MB, median {:.2} ms of {} reads, {:.0} MB/s",
            bytes / 1e6,
            median * 1e3,
            times.len(),
            bytes / 1e6 / median
        );
    }
    Ok(())
}
