//! How a frame looks: line style, colours, colour map.

use crate::wire::Attenuation;
use crate::{GridLines, Isolines, Scale};

/// How line coverage is computed in the fragment shader (DESIGN.md section 3): from
/// the mip-mapped wireframe texture, or analytically from the coordinate's gradient.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Coverage {
    #[default]
    /// Sampled from the mip-mapped wireframe texture: any line profile, and the attenuation table.
    Texture,
    /// Computed from the coordinate's screen gradient: no texture taps.
    Analytic,
}

/// Hidden-line styles of Rossignac & van Emmerik (1992): which edges are drawn, and
/// how the hidden ones look. Contour edges are those of the surface outline (edges with
/// one triangle) and of its silhouette (the two triangles face opposite ways).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum HiddenLines {
    /// TEHS: every edge, hidden ones suppressed.
    #[default]
    Suppressed,
    /// TEHD: every edge, hidden ones dashed.
    Dashed,
    /// CEHS: contour edges only, hidden ones suppressed.
    ContoursSuppressed,
    /// CEHD: contour edges only, hidden ones dashed.
    ContoursDashed,
}

impl HiddenLines {
    /// Every style with its command-line name (Rossignac & van Emmerik's abbreviations).
    pub const ALL: [(&'static str, HiddenLines); 4] = [
        ("tehs", HiddenLines::Suppressed),
        ("tehd", HiddenLines::Dashed),
        ("cehs", HiddenLines::ContoursSuppressed),
        ("cehd", HiddenLines::ContoursDashed),
    ];

    /// The style named `name`, ignoring case.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|&(_, h)| h)
    }

    /// The command-line name of this style.
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(_, h)| *h == self)
            .map_or("tehs", |(n, _)| n)
    }

    /// Only contour edges are drawn.
    pub fn contours_only(self) -> bool {
        matches!(
            self,
            HiddenLines::ContoursSuppressed | HiddenLines::ContoursDashed
        )
    }

    /// Hidden edges are drawn, dashed.
    pub fn dashed(self) -> bool {
        matches!(self, HiddenLines::Dashed | HiddenLines::ContoursDashed)
    }
}

/// Colour maps for properties (from the `colorous` crate).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Colormap {
    #[default]
    /// colorous's viridis: perceptually uniform, the default.
    Viridis,
    /// colorous's turbo.
    Turbo,
    /// colorous's cividis: readable with colour-vision deficiency.
    Cividis,
    /// colorous's magma.
    Magma,
    /// colorous's inferno.
    Inferno,
    /// colorous's plasma.
    Plasma,
    /// colorous's spectral (diverging).
    Spectral,
}

impl Colormap {
    /// Every colour map with its command-line name.
    pub const ALL: [(&'static str, Colormap); 7] = [
        ("viridis", Colormap::Viridis),
        ("turbo", Colormap::Turbo),
        ("cividis", Colormap::Cividis),
        ("magma", Colormap::Magma),
        ("inferno", Colormap::Inferno),
        ("plasma", Colormap::Plasma),
        ("spectral", Colormap::Spectral),
    ];

    /// The colour map named `name`, ignoring case.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|&(_, c)| c)
    }

    /// 256 RGBA8 entries.
    pub fn table(self) -> Vec<u8> {
        let g = match self {
            Colormap::Viridis => colorous::VIRIDIS,
            Colormap::Turbo => colorous::TURBO,
            Colormap::Cividis => colorous::CIVIDIS,
            Colormap::Magma => colorous::MAGMA,
            Colormap::Inferno => colorous::INFERNO,
            Colormap::Plasma => colorous::PLASMA,
            Colormap::Spectral => colorous::SPECTRAL,
        };
        (0..256)
            .flat_map(|i| {
                let c = g.eval_rational(i, 256);
                [c.r, c.g, c.b, 255]
            })
            .collect()
    }
}

/// Major cell lines, as map grids draw them: every `every`-th cell line (and every
/// `every`²-th) stays drawn, in its own colour, while the other lines fade out where
/// their spacing on screen gets too small to tell them apart (see `cell_lines` in
/// wire/common.wgsl). Grids whose cells are a pixel or two then show their structure
/// instead of a uniform sheet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MajorLines {
    /// Every `every`-th cell line is major, counted from the grid's first node (at
    /// least 2).
    pub every: u32,
    /// Spacing on screen, in pixels, at which a level of lines is gone; it is drawn
    /// whole from three times that spacing.
    pub fade: f32,
    /// Colour of the major lines, linear RGBA.
    pub color: [f32; 4],
}

impl Default for MajorLines {
    fn default() -> Self {
        MajorLines {
            every: 10,
            fade: 4.0,
            color: [0.05, 0.12, 0.4, 1.0],
        }
    }
}

/// Fault traces: where a layer surface is split, each side's cell edge drawn over the
/// surfaces in its own colour and thickness, the same at every zoom (wire/faults.rs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaultLines {
    /// Thickness in pixels.
    pub thickness: f32,
    /// Colour, linear RGBA.
    pub color: [f32; 4],
}

impl Default for FaultLines {
    fn default() -> Self {
        FaultLines {
            thickness: 2.5,
            color: [0.84, 0.15, 0.16, 1.0],
        }
    }
}

/// Everything about a frame's look that is not geometry or camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Style {
    /// Line thickness in pixels (σ).
    pub thickness: f32,
    /// Line colour, linear RGBA.
    pub wire_color: [f32; 4],
    /// How lines fade with distance from the eye.
    pub attenuation: Attenuation,
    /// Whether line coverage comes from the texture or is computed.
    pub coverage: Coverage,
    /// Lines alone, in the primitive's colour, instead of over the shaded surface.
    pub isolation: bool,
    /// Surface colour when not coloured by a property.
    pub solid_color: [f32; 4],
    /// The colour map scalars are drawn with.
    pub colormap: Colormap,
    /// Scalar range mapped onto the colour map; `None` draws the solid colour.
    pub scalar_range: Option<(f32, f32)>,
    /// How values within the range map onto the colour map.
    pub scale: Scale,
    /// Colour behind the surfaces, linear RGBA.
    pub background: [f32; 4],
    /// Largest fraction of a coordinate unit a half line may cover (saturation cap).
    pub cap: f32,
    /// Width of the wireframe texture's level 0.
    pub texture_width: u32,
    /// Which edges are drawn and how hidden ones look (not every technique has all).
    pub hidden: HiddenLines,
    /// Isolines of the per-vertex scalar (or of the isoline technique's field).
    pub isolines: Option<Isolines>,
    /// Map grid lines.
    pub grid_lines: Option<GridLines>,
    /// Major cell lines, the others fading; `None`: every cell line alike.
    pub major: Option<MajorLines>,
    /// Fault traces over the cell lines; `None`: none.
    pub faults: Option<FaultLines>,
}

impl Default for Style {
    fn default() -> Self {
        Style {
            thickness: 1.5,
            wire_color: [0.05, 0.05, 0.05, 1.0],
            attenuation: Attenuation::None,
            coverage: Coverage::Texture,
            isolation: false,
            solid_color: [0.78, 0.74, 0.66, 1.0],
            colormap: Colormap::Viridis,
            scalar_range: None,
            scale: Scale::Linear,
            background: [1.0, 1.0, 1.0, 1.0],
            cap: 1.0 / 3.0,
            texture_width: 4096,
            hidden: HiddenLines::Suppressed,
            isolines: None,
            grid_lines: None,
            major: None,
            faults: None,
        }
    }
}

/// Parses `#rrggbb`, `#rrggbbaa` or a few colour names into linear RGBA in 0..1.
pub fn parse_color(s: &str) -> Option<[f32; 4]> {
    let named = match s.to_ascii_lowercase().as_str() {
        "black" => Some("000000"),
        "white" => Some("ffffff"),
        "red" => Some("d62728"),
        "blue" => Some("1f77b4"),
        "green" => Some("2ca02c"),
        "grey" | "gray" => Some("808080"),
        "yellow" => Some("ffd700"),
        _ => None,
    };
    let hex = named.unwrap_or(s.trim_start_matches('#'));
    if !(hex.len() == 6 || hex.len() == 8) || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    let byte = |i: usize| {
        u8::from_str_radix(&hex[i..i + 2], 16)
            .ok()
            .map(|v| f32::from(v) / 255.0)
    };
    Some([
        byte(0)?,
        byte(2)?,
        byte(4)?,
        if hex.len() == 8 { byte(6)? } else { 1.0 },
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_parse() {
        assert_eq!(parse_color("#ff0000"), Some([1.0, 0.0, 0.0, 1.0]));
        assert_eq!(parse_color("black"), Some([0.0, 0.0, 0.0, 1.0]));
        assert_eq!(
            parse_color("#00000080").map(|c| (c[3] * 255.0).round()),
            Some(128.0)
        );
        assert_eq!(parse_color("#12345"), None);
        assert_eq!(parse_color("#gg0000"), None);
    }

    #[test]
    fn colormaps_have_256_entries() {
        for (name, c) in Colormap::ALL {
            assert_eq!(c.table().len(), 1024, "{name}");
            assert_eq!(Colormap::from_name(name), Some(c));
        }
    }
}
