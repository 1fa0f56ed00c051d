//! The values the command line's options take, parsed and checked: views, sizes,
//! layers, colours ranges, isoline spacings, grid lines, techniques.

use strata::render::{HiddenLines, WireMode};
use strata::scene::IsolineSpec;

/// LO,HI: finite, LO below HI.
pub(crate) fn parse_range(s: &str) -> Result<[f32; 2], String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>().map_err(|e| format!("{x:?}: {e}")))
        .collect::<Result<_, _>>()?;
    match v.as_slice() {
        [lo, hi] if lo.is_finite() && hi.is_finite() && lo < hi => Ok([*lo, *hi]),
        _ => Err(format!("expected LO,HI, finite with LO < HI, got {s:?}")),
    }
}

/// SPACING[,X0[,Y0]]: Y0 defaults to X0, both to 0.
pub(crate) fn parse_grid_lines(s: &str) -> Result<(f64, f64, f64), String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>().map_err(|e| format!("{x:?}: {e}")))
        .collect::<Result<_, _>>()?;
    let (spacing, x0, y0) = match v.as_slice() {
        [d] => (*d, 0.0, 0.0),
        [d, x] => (*d, *x, *x),
        [d, x, y] => (*d, *x, *y),
        _ => return Err(format!("expected SPACING[,X0[,Y0]], got {s:?}")),
    };
    if !(spacing > 0.0 && spacing.is_finite() && x0.is_finite() && y0.is_finite()) {
        return Err(format!(
            "grid lines {s:?}: spacing must be positive, origin finite"
        ));
    }
    Ok((spacing, x0, y0))
}

/// Which isolines `--iso` asks for: the spacing (about ten lines over the range when
/// `None`) and every how many lines one is major.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct IsoSpacing {
    spacing: Option<f32>,
    major_every: u32,
}

impl IsoSpacing {
    /// The isolines of `property` (a hierarchy's own when `None`) at this spacing.
    pub(crate) fn spec(&self, property: Option<&str>) -> IsolineSpec {
        IsolineSpec {
            spacing: self.spacing,
            major_every: self.major_every,
            ..IsolineSpec::of(property)
        }
    }
}

/// PROPERTY[:SPACING[:MAJOR_EVERY]], as `strata render --iso` takes it.
pub(crate) fn parse_iso(s: &str) -> Result<(String, IsoSpacing), String> {
    let (name, rest) = s.split_once(':').unwrap_or((s, ""));
    if name.is_empty() {
        return Err(format!(
            "expected PROPERTY[:SPACING[:MAJOR_EVERY]], got {s:?}"
        ));
    }
    Ok((name.to_string(), parse_iso_spacing(rest)?))
}

/// [SPACING[:MAJOR_EVERY]]: a positive spacing, and every fifth line major by default.
pub(crate) fn parse_iso_spacing(s: &str) -> Result<IsoSpacing, String> {
    if s.is_empty() {
        return Ok(IsoSpacing {
            spacing: None,
            major_every: 5,
        });
    }
    let mut parts = s.split(':');
    let spacing = parts.next().map(|v| {
        v.trim()
            .parse::<f32>()
            .ok()
            .filter(|x| *x > 0.0 && x.is_finite())
            .ok_or_else(|| format!("{v:?} is not a positive spacing"))
    });
    let major = parts
        .next()
        .map(|v| v.trim().parse::<u32>().map_err(|e| format!("{v:?}: {e}")))
        .transpose()?
        .unwrap_or(5);
    if parts.next().is_some() {
        return Err(format!("expected SPACING[:MAJOR_EVERY], got {s:?}"));
    }
    Ok(IsoSpacing {
        spacing: spacing.transpose()?,
        major_every: major,
    })
}

pub(crate) fn parse_wire(s: &str) -> Result<WireMode, String> {
    WireMode::from_name(s).ok_or_else(|| {
        format!(
            "unknown wire mode {s:?}; one of {}",
            strata::render::wire_mode_names().join(", ")
        )
    })
}

pub(crate) fn parse_hidden(s: &str) -> Result<HiddenLines, String> {
    HiddenLines::from_name(s)
        .ok_or_else(|| format!("unknown hidden-line style {s:?}; one of tehs, tehd, cehs, cehd"))
}

/// A 1-based inclusive range of layers, A..B.
pub(crate) fn parse_layers(s: &str) -> Result<(usize, usize), String> {
    parse_one_based(s, "layer")
}

/// A 1-based inclusive range of cells along I or J, A..B.
pub(crate) fn parse_cells(s: &str) -> Result<(usize, usize), String> {
    parse_one_based(s, "cell")
}

/// A..B, both 1-based `what`s, A at most B.
fn parse_one_based(s: &str, what: &str) -> Result<(usize, usize), String> {
    let (a, b) = s
        .split_once("..")
        .ok_or_else(|| format!("expected A..B, got {s:?}"))?;
    let num = |v: &str| {
        v.trim()
            .parse::<usize>()
            .ok()
            .filter(|&n| n >= 1)
            .ok_or_else(|| format!("{v:?} is not a 1-based {what}"))
    };
    let (a, b) = (num(a)?, num(b)?);
    if a > b {
        return Err(format!("{what} range {a}..{b} is empty"));
    }
    Ok((a, b))
}

pub(crate) fn parse_view(s: &str) -> Result<(f32, f32, f32), String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>().map_err(|e| format!("{x:?}: {e}")))
        .collect::<Result<_, _>>()?;
    match v.as_slice() {
        _ if v.iter().any(|x| !x.is_finite()) => Err(format!("{s:?}: not finite")),
        [az, el] => Ok((*az, *el, 1.0)),
        [az, el, d] if *d > 0.0 => Ok((*az, *el, *d)),
        _ => Err(format!("expected AZ,EL[,DIST] with DIST > 0, got {s:?}")),
    }
}

/// `--zscale F`: a vertical exaggeration, positive and finite (0 would flatten the
/// model onto the map, which `--view 0,90` already shows).
pub(crate) fn parse_zscale(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(z) if z > 0.0 && z.is_finite() => Ok(z),
        Ok(_) => Err(format!(
            "{s:?}: the vertical exaggeration must be positive and finite"
        )),
        Err(e) => Err(format!("{s:?}: {e}")),
    }
}

/// `--centre I,J`: a 1-based column of cells.
pub(crate) fn parse_column(s: &str) -> Result<[u32; 2], String> {
    let v: Vec<u32> = s
        .split(',')
        .map(|x| x.trim().parse::<u32>().ok().filter(|&n| n >= 1))
        .collect::<Option<_>>()
        .ok_or_else(|| format!("expected I,J with 1-based cell indices, got {s:?}"))?;
    match v.as_slice() {
        [i, j] => Ok([*i, *j]),
        _ => Err(format!("expected I,J with 1-based cell indices, got {s:?}")),
    }
}

pub(crate) fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WxH, got {s:?}"))?;
    let dim = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|&n| (1..=16384).contains(&n))
            .ok_or_else(|| format!("{v:?} is not a size in 1..16384"))
    };
    Ok((dim(w)?, dim(h)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iso_options_give_a_spacing_or_about_ten_round_lines() {
        let (name, iso) = parse_iso("PORO").expect("a property alone");
        assert_eq!(name, "PORO");
        assert_eq!(iso.spec(Some("PORO")), IsolineSpec::of(Some("PORO")));
        let (_, iso) = parse_iso("PORO:0.01:4").expect("spacing and major");
        let spec = iso.spec(Some("PORO"));
        assert_eq!((spec.spacing, spec.major_every), (Some(0.01), 4));
        assert_eq!(parse_iso_spacing("").map(|i| i.major_every), Ok(5));
        for bad in [":0.1", "PORO:-1", "PORO:0.1:x", "PORO:0.1:2:3"] {
            assert!(parse_iso(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn views_and_exaggerations_are_finite() {
        assert_eq!(parse_view("30,35"), Ok((30.0, 35.0, 1.0)));
        assert_eq!(parse_view("120, -20, 0.05"), Ok((120.0, -20.0, 0.05)));
        for bad in [
            "nan,10",
            "10,inf",
            "10,20,NaN",
            "10,20,0",
            "10",
            "10,20,1,2",
        ] {
            assert!(parse_view(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_zscale("2.5"), Ok(2.5));
        for bad in ["0", "-1", "inf", "nan", "x"] {
            assert!(parse_zscale(bad).is_err(), "{bad}");
        }
    }
}
