//! Property decks read onto a grid that came from elsewhere (an EGRID with its PORO in
//! a GRDECL file beside it).

use std::path::Path;

use strata_grid::grdecl::read_properties;
use strata_grid::synth::{SynthParams, generate};

fn shared_data() -> Option<&'static Path> {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"));
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("skipping: ../shared/data not found");
        None
    }
}

#[test]
fn a_property_deck_adds_its_arrays_cell_by_cell() {
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("props.grdecl");
    // 3 x 2 x 1 cells: PORO with a repeat, NTG with a default (undefined) value.
    std::fs::write(
        &deck,
        "-- properties only\nPORO\n 0.1 0.2 4*0.3 /\nNTG\n 5*1 1* /\n",
    )
    .unwrap();
    let mut grid = generate(&SynthParams {
        nx: 3,
        ny: 2,
        nz: 1,
        faults: 0,
        seed: 1,
    })
    .unwrap();
    let names = read_properties(&mut grid, &deck).unwrap();
    assert_eq!(names, vec!["NTG".to_string(), "PORO".to_string()]);
    let poro = grid.property("PORO").unwrap();
    assert_eq!(poro[[0, 0, 1]], 0.2);
    assert_eq!(poro[[0, 1, 2]], 0.3);
    assert!(grid.property("NTG").unwrap()[[0, 1, 2]].is_nan());

    std::fs::write(&deck, "PORO\n 0.1 0.2 /\n").unwrap();
    let err = read_properties(&mut grid, &deck).unwrap_err().to_string();
    assert!(
        err.contains("props.grdecl") && err.contains("PORO"),
        "{err}"
    );
    std::fs::write(&deck, "ACTNUM\n 6*1 /\n").unwrap();
    let err = read_properties(&mut grid, &deck).unwrap_err().to_string();
    assert!(err.contains("ACTNUM"), "{err}");
}

#[test]
fn reek_egrid_gets_poro_from_its_grdecl() {
    let Some(data) = shared_data() else { return };
    let mut grid = strata_grid::open(&data.join("reek/REEK.EGRID")).unwrap();
    let names = read_properties(&mut grid, &data.join("reek/reek_sim_poro.grdecl")).unwrap();
    assert_eq!(names, vec!["PORO".to_string()]);
    let poro = grid.property("PORO").unwrap();
    let active: Vec<f32> = poro
        .iter()
        .zip(grid.actnum.iter())
        .filter(|&(_, &a)| a)
        .map(|(&p, _)| p)
        .collect();
    assert_eq!(active.len(), 35_838);
    assert!(
        active.iter().all(|p| (0.0..0.5).contains(p)),
        "PORO out of range"
    );
    // The deck's first value belongs to cell (1, 1, 1).
    assert!((poro[[0, 0, 0]] - 0.177_493_92).abs() < 1e-6);
}
