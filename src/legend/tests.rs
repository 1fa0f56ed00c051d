use super::*;

fn labels(ticks: &[(f64, String)]) -> Vec<&str> {
    ticks.iter().map(|(_, l)| l.as_str()).collect()
}

#[test]
fn linear_ticks_are_round_between_the_labelled_ends() {
    // The sample's PORO range: steps of 0.05, the ends as they are.
    let ticks = linear_ticks(0.0615, 0.2968, 6);
    assert_eq!(
        labels(&ticks),
        ["0.0615", "0.10", "0.15", "0.20", "0.25", "0.2968"]
    );
    // A round value next to an end gives way to it.
    let ticks = linear_ticks(0.0, 1000.0, 6);
    assert_eq!(labels(&ticks), ["0", "200", "400", "600", "800", "1000"]);
    let ticks = linear_ticks(-3.0, 3.0, 6);
    assert_eq!(labels(&ticks), ["-3", "-2", "-1", "0", "1", "2", "3"]);
    assert!(ticks.windows(2).all(|w| w[0].0 < w[1].0));
    // A value close to an end is dropped: 0.1 is 0.0385 from 0.0615 (< 0.4 x 0.1).
    let ticks = linear_ticks(0.0615, 0.5, 5);
    assert_eq!(labels(&ticks), ["0.0615", "0.2", "0.3", "0.4", "0.5"]);
}

#[test]
fn log_ticks_are_decades_or_their_multiples() {
    let ticks = log_ticks(1.0, 5000.0);
    assert_eq!(labels(&ticks), ["1", "10", "100", "1000", "5000"]);
    // Under two decades: 1, 2 and 5 times each; 100 is too close to the end.
    let ticks = log_ticks(3.0, 120.0);
    assert_eq!(labels(&ticks), ["3", "5", "10", "20", "50", "120"]);
    // Beyond eight decades every other one.
    let ticks = log_ticks(1.0e-3, 1.0e7);
    assert_eq!(
        labels(&ticks),
        ["0.001", "0.01", "1", "100", "10000", "1e6", "1e7"]
    );
    assert!(log_ticks(0.0, 10.0).is_empty());
}

#[test]
fn values_are_written_short() {
    assert_eq!(format_value(0.0), "0");
    assert_eq!(format_value(12.5), "12.5");
    assert_eq!(format_value(1.0 / 3.0), "0.3333");
    assert_eq!(format_value(250_000.0), "2.5e5");
    assert_eq!(format_value(-0.0002), "-2e-4");
}

#[test]
fn ticks_sit_where_the_scale_puts_them() {
    let legend = Legend::new(
        "PERMX",
        Some("mD"),
        (Colormap::Viridis, Scale::Log),
        (1.0, 1000.0),
        &[],
    );
    let Entries::Ticks(ticks) = &legend.entries else {
        panic!("a log legend has ticks");
    };
    let at = |v: f64| ticks.iter().find(|t| t.value == v).map(|t| t.fraction);
    assert!((at(10.0).unwrap() - 1.0 / 3.0).abs() < 1e-9);
    assert!((at(100.0).unwrap() - 2.0 / 3.0).abs() < 1e-9);
    assert_eq!(legend.title(), "PERMX (mD)");
}

#[test]
fn codes_are_integers_each_its_colour() {
    let codes = codes_of("FIPNUM", [3.0, 1.0, f32::NAN, 3.0, 2.0]).unwrap();
    assert_eq!(codes, [1, 2, 3]);
    let message = codes_of("PORO", [1.0, 0.25]).unwrap_err().to_string();
    assert!(
        message.contains("PORO") && message.contains("0.25"),
        "{message}"
    );
    let many = codes_of("ID", (0..=MAX_CODES).map(|v| v as f32));
    assert!(many.unwrap_err().to_string().contains("more than 1000"));
    let legend = Legend::new(
        "FIPNUM",
        None,
        (Colormap::Viridis, Scale::Categorical),
        (1.0, 3.0),
        &codes,
    );
    let Entries::Codes(codes) = &legend.entries else {
        panic!("a categorical legend has codes");
    };
    assert_eq!(codes[1].colour, categorical_colour(2));
    assert_ne!(codes[0].colour, codes[1].colour);
    assert_eq!(legend.title(), "FIPNUM");
}

#[test]
fn labels_too_close_give_way_to_the_ends() {
    let legend = Legend::new(
        "PERMX",
        Some("mD"),
        (Colormap::Viridis, Scale::Log),
        (1.28, 21998.0),
        &[],
    );
    let labelled = |height| -> Vec<bool> {
        let layout = legend.layout(height).expect("a layout");
        layout.ticks.iter().map(|t| t.1).collect()
    };
    // 1.28, 10, 100, 1000, 10000, 21998: at 800 px every label fits; at 300 px
    // 10000 comes within a line of the top end's label and gives way.
    assert_eq!(labelled(800), [true; 6]);
    assert_eq!(labelled(300), [true, true, true, true, false, true]);
    let layout = legend.layout(400).expect("a layout");
    assert!(
        layout.ticks.windows(2).all(|w| w[0].0 > w[1].0),
        "high values higher up"
    );
}
