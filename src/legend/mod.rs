//! The colour legend: what it says (this module), how it is laid out and drawn
//! ([`Legend::image`], `draw.rs`) and the units it names (`units.rs`).
//!
//! A [`Legend`] is computed from a scene and its model by the engine and drawn on
//! the CPU into a small RGBA image, which the renderer blends over the end of every
//! frame ([`strata_render::Renderer::set_overlay`]), so `strata render`'s PNG and a
//! window showing the frame both have it.

mod draw;
mod units;

use std::collections::BTreeSet;

use strata_render::{Colormap, Scale, categorical_colour};

pub use draw::Layout;
pub use units::{UnitSystem, unit};

use crate::{Error, Result};

/// What a colour legend says.
#[derive(Clone, Debug, PartialEq)]
pub struct Legend {
    /// The property's name.
    pub property: String,
    /// Its unit, where known.
    pub unit: Option<&'static str>,
    /// The colour map of a linear or log scale.
    pub colormap: Colormap,
    /// How values map onto colours.
    pub scale: Scale,
    /// The values at the colour map's ends.
    pub range: (f32, f32),
    /// Tick marks along the bar, or the codes of a categorical scale.
    pub entries: Entries,
}

/// The marks of a legend.
#[derive(Clone, Debug, PartialEq)]
pub enum Entries {
    /// Values along a colour bar, low to high.
    Ticks(Vec<Tick>),
    /// The codes present, each a swatch of its colour.
    Codes(Vec<Code>),
}

/// A value marked along the colour bar.
#[derive(Clone, Debug, PartialEq)]
pub struct Tick {
    /// The value.
    pub value: f64,
    /// Where it is along the bar: 0 at the low end, 1 at the high end.
    pub fraction: f64,
    /// The value as written.
    pub label: String,
}

/// A code of a categorical property.
#[derive(Clone, Debug, PartialEq)]
pub struct Code {
    /// The code.
    pub code: i64,
    /// Its name, where the model names its codes (ROFF discrete properties).
    pub name: Option<String>,
    /// Its colour, as the cells are drawn.
    pub colour: [u8; 3],
}

/// Most codes a categorical property may have: more are not region codes.
pub const MAX_CODES: usize = 1000;

impl Legend {
    /// The legend of `property` coloured on `scale` with `colormap` over `range`;
    /// `codes` are those present (a categorical scale's entries, from
    /// [`codes_of`]).
    pub fn new(
        property: &str,
        unit: Option<&'static str>,
        (colormap, scale): (Colormap, Scale),
        range: (f32, f32),
        codes: &[i64],
    ) -> Self {
        let entries = match scale {
            Scale::Categorical => Entries::Codes(
                codes
                    .iter()
                    .map(|&code| Code {
                        code,
                        name: None,
                        colour: categorical_colour(code),
                    })
                    .collect(),
            ),
            Scale::Linear | Scale::Log => {
                let (lo, hi) = (f64::from(range.0), f64::from(range.1));
                let values = if scale == Scale::Log {
                    log_ticks(lo, hi)
                } else {
                    linear_ticks(lo, hi, 6)
                };
                Entries::Ticks(
                    values
                        .into_iter()
                        .filter_map(|(value, label)| {
                            let fraction = scale.fraction(value, (lo, hi))?;
                            Some(Tick {
                                value,
                                fraction,
                                label,
                            })
                        })
                        .collect(),
                )
            }
        };
        Legend {
            property: property.to_string(),
            unit,
            colormap,
            scale,
            range,
            entries,
        }
    }

    /// The title: the property and its unit.
    pub fn title(&self) -> String {
        match self.unit {
            Some(unit) => format!("{} ({unit})", self.property),
            None => self.property.clone(),
        }
    }
}

/// The distinct integer codes among `values` (undefined ones skipped), sorted; a
/// value that is not an integer, or more than [`MAX_CODES`] codes, is refused for
/// a categorical scale, naming `property`.
pub fn codes_of(property: &str, values: impl IntoIterator<Item = f32>) -> Result<Vec<i64>> {
    let mut codes = BTreeSet::new();
    for v in values.into_iter().filter(|v| v.is_finite()) {
        if v.fract() != 0.0 || v.abs() > 1.0e9 {
            return Err(Error::scene(format!(
                "colour: a categorical scale colours integer codes (FIPNUM, SATNUM, zones), \
                 and {property} has the value {v}: use --scale linear or log"
            )));
        }
        codes.insert(v as i64);
        if codes.len() > MAX_CODES {
            return Err(Error::scene(format!(
                "colour: {property} has more than {MAX_CODES} distinct values, too many codes \
                 for a categorical scale: use --scale linear or log"
            )));
        }
    }
    Ok(codes.into_iter().collect())
}

/// Round values (1, 2 or 5 times a power of ten apart, about `count` of them) within
/// `lo..=hi`, labelled with as many decimals as the step needs, and the range's ends,
/// labelled as they are, where no round value is close to them.
pub fn linear_ticks(lo: f64, hi: f64, count: usize) -> Vec<(f64, String)> {
    let span = hi - lo;
    if !(span > 0.0 && span.is_finite()) {
        return vec![(lo, format_value(lo))];
    }
    let raw = span / count.max(1) as f64;
    let power = raw.log10().floor();
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * 10f64.powf(power))
        .find(|s| *s >= raw * 0.999)
        .unwrap_or(10f64.powf(power + 1.0));
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let near_end = |v: f64| (v - lo).abs() < 0.4 * step || (hi - v).abs() < 0.4 * step;
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    let mut ticks = vec![(lo, format_value(lo))];
    for k in first..=last {
        let v = k as f64 * step;
        if !near_end(v) {
            // -0.0 written as 0.
            let v = if v == 0.0 { 0.0 } else { v };
            ticks.push((v, format!("{v:.decimals$}")));
        }
    }
    ticks.push((hi, format_value(hi)));
    ticks
}

/// Powers of ten within `lo..=hi` (every other one beyond eight decades), with 2 and
/// 5 times them where the range spans less than two decades, and the range's ends
/// where no such value is close to them (within a tenth of a decade).
pub fn log_ticks(lo: f64, hi: f64) -> Vec<(f64, String)> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Vec::new();
    }
    let (a, b) = (lo.log10(), hi.log10());
    let decades = b - a;
    let stride = if decades > 8.0 { 2 } else { 1 };
    let multiples: &[f64] = if decades < 2.0 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0]
    };
    let near_end = |v: f64| (v.log10() - a).abs() < 0.1 || (b - v.log10()).abs() < 0.1;
    let mut ticks = vec![(lo, format_value(lo))];
    for p in (a.floor() as i32..=b.ceil() as i32).filter(|p| p % stride == 0) {
        for m in multiples {
            let v = m * 10f64.powi(p);
            if v >= lo && v <= hi && !near_end(v) {
                ticks.push((v, format_value(v)));
            }
        }
    }
    ticks.push((hi, format_value(hi)));
    ticks
}

/// `v` in at most four significant digits, without trailing zeros; in exponent form
/// from 10^5 up and below 10^-3.
pub fn format_value(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1.0e-3..1.0e5).contains(&a) {
        let text = format!("{v:.3e}");
        return match text.split_once('e') {
            Some((m, e)) => format!("{}e{e}", trim_zeros(m)),
            None => text,
        };
    }
    let decimals = if a == 0.0 {
        0
    } else {
        (3 - a.log10().floor() as i32).max(0) as usize
    };
    trim_zeros(&format!("{v:.decimals$}")).to_string()
}

/// `text` (a decimal number) without trailing zeros after its point, nor the point.
fn trim_zeros(text: &str) -> &str {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        text
    }
}

#[cfg(test)]
mod tests;
