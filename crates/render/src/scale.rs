//! Colour scales: how a cell's value becomes a place on the colour map. One
//! mechanism for every technique: the frame uniform `scalar` and the colour-map
//! texture that `base_color` in `wire/common.wgsl` reads, so whole, decimated, in
//! parts, hierarchies, smooth and flat cells all colour the same way.

use crate::Colormap;

/// How values map onto colours.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Scale {
    /// The range's low end to its high end, evenly.
    #[default]
    Linear,
    /// ln(value) over ln(low)..ln(high): for values that span decades (permeability).
    /// The range must be positive; values at or below zero are drawn as undefined.
    Log,
    /// Integer codes (FIPNUM, SATNUM, zones), each a colour of [`CATEGORICAL`] by its
    /// code modulo the palette's length, never a blend of two.
    Categorical,
}

/// Tableau 20's colours, the ten saturated ones first and their light partners
/// after, so that neighbouring codes differ in hue, not only in lightness.
pub const CATEGORICAL: [[u8; 3]; 20] = [
    [0x4e, 0x79, 0xa7],
    [0xf2, 0x8e, 0x2b],
    [0x59, 0xa1, 0x4f],
    [0xb6, 0x99, 0x2d],
    [0x49, 0x98, 0x94],
    [0xe1, 0x57, 0x59],
    [0x79, 0x70, 0x6e],
    [0xd3, 0x72, 0x95],
    [0xb0, 0x7a, 0xa1],
    [0x9d, 0x76, 0x60],
    [0xa0, 0xcb, 0xe8],
    [0xff, 0xbe, 0x7d],
    [0x8c, 0xd1, 0x7d],
    [0xf1, 0xce, 0x63],
    [0x86, 0xbc, 0xb6],
    [0xff, 0x9d, 0x9a],
    [0xba, 0xb0, 0xac],
    [0xfa, 0xbf, 0xd2],
    [0xd4, 0xa6, 0xc8],
    [0xd7, 0xb5, 0xa6],
];

impl Scale {
    /// Every scale with its command-line name.
    pub const ALL: [(&'static str, Scale); 3] = [
        ("linear", Scale::Linear),
        ("log", Scale::Log),
        ("categorical", Scale::Categorical),
    ];

    /// The scale named `name`, ignoring case.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|&(_, s)| s)
    }

    /// The command-line name of this scale.
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(_, s)| *s == self)
            .map_or("linear", |(n, _)| n)
    }

    /// Where `value` falls on the colour map spanning `(lo, hi)`, 0 at `lo` and 1 at
    /// `hi` (unclamped); `None` where the scale has no place for it (a log scale's
    /// value at or below zero). The shader's `base_color` computes the same.
    pub fn fraction(self, value: f64, (lo, hi): (f64, f64)) -> Option<f64> {
        match self {
            Scale::Linear | Scale::Categorical => Some((value - lo) / (hi - lo)),
            Scale::Log if value > 0.0 && lo > 0.0 && hi > lo => {
                Some((value.ln() - lo.ln()) / (hi.ln() - lo.ln()))
            }
            Scale::Log => None,
        }
    }

    /// The frame uniform `scalar` for `range` (`None`: a solid colour): x, y the
    /// start and 1 / length of the mapped range (of ln values for a log scale, the
    /// palette's length for a categorical one); z 1 coloured by value; w the scale.
    pub(crate) fn uniform(self, range: Option<(f32, f32)>) -> [f32; 4] {
        let Some((lo, hi)) = range else {
            return [0.0; 4];
        };
        let span = |a: f32, b: f32| 1.0 / (b - a).max(f32::MIN_POSITIVE);
        match self {
            Scale::Linear => [lo, span(lo, hi), 1.0, 0.0],
            Scale::Log => {
                let (a, b) = (
                    lo.max(f32::MIN_POSITIVE).ln(),
                    hi.max(f32::MIN_POSITIVE).ln(),
                );
                [a, span(a, b), 1.0, 1.0]
            }
            Scale::Categorical => [CATEGORICAL.len() as f32, 0.0, 1.0, 2.0],
        }
    }

    /// The 256 RGBA8 texels of the colour-map texture: `colormap`'s, or the
    /// categorical palette in its first texels.
    pub(crate) fn table(self, colormap: Colormap) -> Vec<u8> {
        match self {
            Scale::Categorical => (0..256)
                .flat_map(|i| {
                    let [r, g, b] = CATEGORICAL[i % CATEGORICAL.len()];
                    [r, g, b, 255]
                })
                .collect(),
            Scale::Linear | Scale::Log => colormap.table(),
        }
    }
}

/// The colour of integer `code` on a categorical scale.
pub fn categorical_colour(code: i64) -> [u8; 3] {
    CATEGORICAL[code.rem_euclid(CATEGORICAL.len() as i64) as usize]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_fractions_are_even_per_decade() {
        let range = (1.0, 1000.0);
        let f = |v| Scale::Log.fraction(v, range).unwrap();
        assert!(f(1.0).abs() < 1e-12);
        assert!((f(10.0) - 1.0 / 3.0).abs() < 1e-12);
        assert!((f(1000.0) - 1.0).abs() < 1e-12);
        assert_eq!(Scale::Log.fraction(0.0, range), None);
        assert_eq!(Scale::Linear.fraction(5.0, (0.0, 10.0)), Some(0.5));
    }

    #[test]
    fn categorical_colours_repeat_only_after_the_palette() {
        let colours: Vec<[u8; 3]> = (0..20).map(categorical_colour).collect();
        for (i, a) in colours.iter().enumerate() {
            assert!(colours[i + 1..].iter().all(|b| b != a), "code {i}");
        }
        assert_eq!(categorical_colour(-1), categorical_colour(19));
        assert_eq!(categorical_colour(20), categorical_colour(0));
        let table = Scale::Categorical.table(Colormap::Viridis);
        assert_eq!(&table[4..7], &categorical_colour(1));
    }

    #[test]
    fn names_round_trip() {
        for (name, s) in Scale::ALL {
            assert_eq!(Scale::from_name(name), Some(s));
            assert_eq!(s.name(), name);
        }
    }
}
