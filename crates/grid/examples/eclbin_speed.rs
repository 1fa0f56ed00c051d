//! EGRID write and read throughput on a generated grid:
//! `cargo run --release -p strata-grid --example eclbin_speed -- [NX NY NZ] [--runs N] [--json]`.
//!
//! Writes the grid to a scratch file, reads it back `runs` times (the file is then in
//! the page cache: this measures decoding, not the disk) and reports MB/s of file
//! bytes (10^6 bytes per second) for the write and the best read.

use std::time::Instant;

use strata_grid::synth::{SynthParams, generate};
use strata_grid::{ReadOptions, eclbin};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let json = args.iter().any(|a| a == "--json");
    let runs = args
        .iter()
        .position(|a| a == "--runs")
        .and_then(|i| args.get(i + 1))
        .map_or(Ok(5), |s| s.parse())?;
    let dims: Vec<usize> = args
        .iter()
        .take_while(|a| !a.starts_with("--"))
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let [nx, ny, nz] = dims[..] else {
        return Err("give NX NY NZ (e.g. 400 400 200)".into());
    };

    let grid = generate(&SynthParams {
        nx,
        ny,
        nz,
        faults: 6,
        seed: 1,
    })?;
    let path =
        std::env::temp_dir().join(format!("strata-eclbin-speed-{}.EGRID", std::process::id()));
    let t = Instant::now();
    eclbin::write_egrid(&grid, &path)?;
    let write_s = t.elapsed().as_secs_f64();
    let bytes = std::fs::metadata(&path)?.len() as f64;

    let options = ReadOptions {
        grid_only: true,
        ..ReadOptions::default()
    };
    let mut read_s = Vec::new();
    for _ in 0..runs {
        let t = Instant::now();
        let back = eclbin::read_egrid(&path, &options)?;
        read_s.push(t.elapsed().as_secs_f64());
        if back.zcorn != grid.zcorn || back.actnum != grid.actnum {
            return Err("read back a different grid".into());
        }
    }
    std::fs::remove_file(&path)?;
    let mb = bytes / 1e6;
    // With --runs 0 only the write is measured (and the peak memory of writing).
    let read_mb_s = read_s
        .iter()
        .copied()
        .reduce(f64::min)
        .map(|best| mb / best);
    if json {
        println!(
            "{{\"nx\":{nx},\"ny\":{ny},\"nz\":{nz},\"file_mb\":{mb:.1},\"threads\":{},\"write_s\":{write_s:.3},\"write_mb_s\":{:.0},\"read_s\":{read_s:?},\"read_mb_s\":{}}}",
            rayon::current_num_threads(),
            mb / write_s,
            read_mb_s.map_or("null".to_string(), |r| format!("{r:.0}"))
        );
    } else {
        println!(
            "{nx} x {ny} x {nz}: {mb:.1} MB, {} threads",
            rayon::current_num_threads()
        );
        println!("write {write_s:.3} s = {:.0} MB/s", mb / write_s);
        if let Some(r) = read_mb_s {
            println!("read, best of {runs}: {r:.0} MB/s (read times {read_s:.3?} s)");
        }
    }
    Ok(())
}
