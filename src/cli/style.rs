//! The frame and line-style options that `strata render` and `strata lod view` share,
//! so a hierarchy is drawn exactly as the model it was built from.

use anyhow::{Result, anyhow};
use clap::{Args, ValueEnum};
use strata::render::{Colormap, HiddenLines, Scale, WireMode};

use super::parse::{
    parse_cells, parse_column, parse_grid_lines, parse_hidden, parse_layers, parse_range,
    parse_size, parse_view, parse_wire, parse_zscale,
};
use strata::scene::{Attenuate, CameraSpec, CoverageChoice, GridLineSpec, Scene, WireStyle};

#[derive(Clone, Copy, ValueEnum)]
enum AttenuateArg {
    None,
    Intensity,
    Thickness,
}

#[derive(Clone, Copy, ValueEnum)]
enum CoverageArg {
    /// Analytic on CPU rasterizers, the texture on GPUs.
    Auto,
    Texture,
    Analytic,
}

impl From<CoverageArg> for CoverageChoice {
    fn from(arg: CoverageArg) -> Self {
        match arg {
            CoverageArg::Auto => CoverageChoice::Auto,
            CoverageArg::Texture => CoverageChoice::Texture,
            CoverageArg::Analytic => CoverageChoice::Analytic,
        }
    }
}

impl From<AttenuateArg> for Attenuate {
    fn from(arg: AttenuateArg) -> Self {
        match arg {
            AttenuateArg::None => Attenuate::None,
            AttenuateArg::Intensity => Attenuate::Intensity,
            AttenuateArg::Thickness => Attenuate::Thickness,
        }
    }
}

/// Where the camera looks from and the picture's size.
#[derive(Args)]
pub struct FrameArgs {
    /// Vertical exaggeration.
    #[arg(long, default_value_t = 5.0, value_parser = parse_zscale)]
    pub zscale: f32,
    /// View: azimuth (degrees clockwise from north), elevation (degrees), and optionally
    /// distance as a multiple of the fitting distance.
    #[arg(long, default_value = "30,35", value_parser = parse_view)]
    pub view: (f32, f32, f32),
    /// Look at the top of the column of cells I,J (1-based, as `info --cell`) instead
    /// of the middle of the model: the centre of that cell's face on the first drawn
    /// layer that has it. With --view's distance below 1, a close-up there.
    #[arg(long, value_name = "I,J", value_parser = parse_column)]
    pub centre: Option<[u32; 2]>,
    /// Image size WxH.
    #[arg(long, default_value = "1200x900", value_parser = parse_size)]
    pub size: (u32, u32),
}

/// How lines and surfaces look.
#[derive(Args)]
pub struct StyleArgs {
    /// Wireframe technique: none, global, quad, tex, texgs, bias, dist, idbuffer.
    #[arg(long, default_value = "global", value_parser = parse_wire)]
    pub wire: WireMode,
    /// Hidden-line style (Rossignac & van Emmerik): tehs hides hidden edges, tehd dashes
    /// them, cehs and cehd draw contour edges only (outlines and silhouettes). bias,
    /// dist and idbuffer draw all four; the texture techniques tehs only.
    #[arg(long, default_value = "tehs", value_parser = parse_hidden)]
    hidden: HiddenLines,
    /// Line thickness in pixels.
    #[arg(long, default_value_t = 1.5)]
    thickness: f32,
    /// Line colour: #rrggbb[aa] or a name (black, white, red, ...).
    #[arg(long, default_value = "#141414")]
    wire_color: String,
    /// Fade or thin lines with distance.
    #[arg(long, value_enum, default_value = "none")]
    attenuate: AttenuateArg,
    /// Line coverage from the mip-mapped texture or evaluated analytically (auto:
    /// analytic on CPU rasterizers, where it is the faster, the texture on GPUs).
    #[arg(long, value_enum, default_value = "auto")]
    coverage: CoverageArg,
    /// Lines alone, in the cells' colours, without the shaded surface.
    #[arg(long)]
    isolation: bool,
    /// Every N-th cell line (and every N²-th) is major: drawn in --major-color while
    /// the others fade out where cells get small on screen, so a dense grid keeps its
    /// structure (0: every line alike).
    #[arg(long, value_name = "N", default_value_t = 10)]
    major: u32,
    /// Spacing on screen, in pixels, at which a level of cell lines has faded out; it
    /// is drawn whole from three times that spacing.
    #[arg(long, value_name = "PX", default_value_t = 4.0)]
    fade: f32,
    /// Colour of the major cell lines: #rrggbb[aa] or a name.
    #[arg(long, default_value = "#0d1f66")]
    major_color: String,
    /// Thickness in pixels of the fault traces, drawn over the cell lines at every
    /// zoom (0: none).
    #[arg(long, value_name = "PX", default_value_t = 2.5)]
    fault_thickness: f32,
    /// Colour of the fault traces: #rrggbb[aa] or a name.
    #[arg(long, default_value = "#d62728")]
    fault_color: String,
    /// Colour map: viridis, turbo, cividis, magma, inferno, plasma, spectral.
    #[arg(long, default_value = "viridis")]
    colormap: String,
    /// Map grid lines: SPACING[,X0[,Y0]] in map units, through map (X0, Y0).
    #[arg(long, value_parser = parse_grid_lines)]
    grid_lines: Option<(f64, f64, f64)>,
    /// Property values at the two ends of the colour map: LO,HI (default: the range
    /// of the drawn cells' values).
    #[arg(long, value_name = "LO,HI", value_parser = parse_range)]
    range: Option<[f32; 2]>,
    /// How values map onto the colour map: linear; log (ln of the values, for
    /// properties that span decades such as permeability; the range must be
    /// positive, and cells at or below zero inside a given --range draw grey as
    /// undefined); categorical (integer codes such as FIPNUM or SATNUM, each a
    /// colour of the Tableau 20 palette, never blended).
    #[arg(long, default_value = "linear", value_parser = parse_scale)]
    scale: Scale,
    /// No colour legend (by default one is drawn at the right edge when the cells are
    /// coloured by a property).
    #[arg(long)]
    no_legend: bool,
}

fn parse_scale(s: &str) -> Result<Scale, String> {
    Scale::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = Scale::ALL.iter().map(|(n, _)| *n).collect();
        format!("unknown colour scale {s:?}; one of {}", names.join(", "))
    })
}

impl StyleArgs {
    /// Sets the line style, colour map and grid lines of `scene` as these options say.
    pub fn apply(&self, scene: &mut Scene) -> Result<()> {
        scene.wire = WireStyle {
            technique: self.wire,
            hidden: self.hidden,
            thickness: self.thickness,
            color: self.wire_color.clone(),
            attenuate: self.attenuate.into(),
            coverage: self.coverage.into(),
            isolation: self.isolation,
            major: self.major,
            fade: self.fade,
            major_color: self.major_color.clone(),
            fault_thickness: self.fault_thickness,
            fault_color: self.fault_color.clone(),
        };
        scene.colour.colormap = Colormap::from_name(&self.colormap)
            .ok_or_else(|| anyhow!("unknown colour map {:?}", self.colormap))?;
        scene.colour.range = self.range;
        scene.colour.scale = self.scale;
        scene.legend = !self.no_legend;
        scene.grid_lines = self.grid_lines.map(|(spacing, x0, y0)| GridLineSpec {
            spacing,
            origin: [x0, y0],
        });
        Ok(())
    }
}

impl FrameArgs {
    /// Sets the camera and size of `scene` as these options say.
    pub fn apply(&self, scene: &mut Scene) {
        let (azimuth, elevation, distance) = self.view;
        scene.camera = CameraSpec {
            azimuth,
            elevation,
            distance,
            z_scale: self.zscale,
            centre: self.centre,
            target: None,
        };
        scene.size = [self.size.0, self.size.1];
    }
}

/// Which layers a picture draws, and whether their side faces: `strata render` and
/// `strata lod view` alike.
#[derive(Args)]
pub struct LayerArgs {
    /// One layer, 1-based.
    #[arg(long, conflicts_with = "layers")]
    layer: Option<usize>,
    /// A range of layers, 1-based and inclusive: A..B.
    #[arg(long, value_parser = parse_layers)]
    layers: Option<(usize, usize)>,
    /// Also draw the drawn layers' side faces: the outer shell and fault walls.
    #[arg(long)]
    pub sides: bool,
    /// Range filter along I: columns of cells A..B, 1-based and inclusive. The cells
    /// outside are left out and, with --sides, the walls they leave are drawn.
    #[arg(long, value_name = "A..B", value_parser = parse_cells)]
    i_range: Option<(usize, usize)>,
    /// Range filter along J, as --i-range.
    #[arg(long, value_name = "A..B", value_parser = parse_cells)]
    j_range: Option<(usize, usize)>,
    /// Draw inactive cells too (those not pinched out), grey: where the model has
    /// cells the simulation leaves out.
    #[arg(long)]
    inactive: bool,
}

impl LayerArgs {
    /// Sets the drawn layers and sides of `scene`: 1-based and inclusive, all when
    /// neither option is given.
    pub fn apply(&self, scene: &mut Scene) {
        scene.layers = match (self.layer, self.layers) {
            (Some(k), _) => Some([k, k]),
            (None, Some((a, b))) => Some([a, b]),
            (None, None) => None,
        };
        scene.sides = self.sides;
        scene.i = self.i_range.map(|(a, b)| [a, b]);
        scene.j = self.j_range.map(|(a, b)| [a, b]);
        scene.inactive = self.inactive;
    }
}
