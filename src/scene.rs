//! A scene: everything a picture depends on, as data.
//!
//! A [`Scene`] names the model (or hierarchy) and says which cells, how they are
//! coloured and lined, from where they are seen and at what size. It is what every
//! front end edits: the command line parses its flags into one (`strata render
//! --save-scene` writes it), a window changes its fields, a script builds it. JSON
//! round-trips it exactly (`serde_json`), and a field left out of a file takes its
//! default, the command line's.
//!
//! Layers and cells are 1-based here, as `strata info --cell` names them; the engine
//! turns them into the 0-based ranges the crates take.

use std::path::PathBuf;

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use strata_render::{Colormap, HiddenLines, RangeAdjust, Scale, WireMode, parse_color};

use crate::{Error, Result};

/// Everything a picture depends on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Scene {
    /// The model read; `None` only where a hierarchy is drawn on its own
    /// ([`Lod::Hierarchy`]), which holds its surfaces and property.
    pub model: Option<ModelSource>,
    /// Full resolution, decimated to a share of the triangles, or a hierarchy file.
    pub lod: Lod,
    /// Layers drawn, 1-based and inclusive; all when `None`.
    pub layers: Option<[usize; 2]>,
    /// Range filter along I: columns of cells drawn, 1-based and inclusive; all when
    /// `None`. The cells outside are left out and, with `sides`, the walls they leave
    /// are drawn, the model cut open.
    pub i: Option<[usize; 2]>,
    /// Range filter along J, as `i`.
    pub j: Option<[usize; 2]>,
    /// Inactive cells drawn too (those not pinched out), in the colour of an
    /// undefined value: where the model has cells the simulation leaves out.
    pub inactive: bool,
    /// Also the drawn layers' side faces: the outer shell and fault walls.
    pub sides: bool,
    /// How the cells are coloured.
    pub colour: Colouring,
    /// How the cell wireframe is drawn.
    pub wire: WireStyle,
    /// Isolines of a property; none when `None`.
    pub isolines: Option<IsolineSpec>,
    /// Map grid lines; none when `None`.
    pub grid_lines: Option<GridLineSpec>,
    /// Where the camera looks from.
    pub camera: CameraSpec,
    /// Picture width and height in pixels.
    pub size: [u32; 2],
    /// The colour legend at the right edge (when the cells are coloured by a
    /// property).
    pub legend: bool,
    /// Active cells a part may hold: a larger scene is drawn a part at a time, in the
    /// memory of one part (see `strata render --help`).
    pub part_cells: u64,
}

/// A model file and what goes with it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSource {
    /// GRDECL deck, DATA deck or EGRID (its INIT and UNRST beside it are read too).
    pub path: PathBuf,
    /// GRDECL decks of per-cell properties to add (e.g. PORO beside an EGRID).
    #[serde(default)]
    pub props: Vec<PathBuf>,
    /// The grid only: no properties or results, and missing INCLUDE files skipped.
    #[serde(default)]
    pub grid_only: bool,
}

impl ModelSource {
    /// The model at `path`, with nothing added.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        ModelSource {
            path: path.into(),
            props: Vec::new(),
            grid_only: false,
        }
    }
}

/// Level of detail.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Lod {
    /// Every cell face as the model has it.
    #[default]
    Full,
    /// The surfaces decimated to `percent` of their triangles in all, split by how
    /// much of each is seen (`strata render --lod`).
    Decimated {
        /// Share of the triangles kept, in (0, 100].
        percent: f64,
        /// Outlines, holes and fault traces grow only outward.
        #[serde(default)]
        cover: bool,
        /// Surfaces that share an outline meet again along it.
        #[serde(default)]
        stitch: bool,
    },
    /// A hierarchy written by `strata lod build`, its nodes chosen per frame.
    Hierarchy {
        /// The `.lod` file.
        file: PathBuf,
        /// Largest projected error of a chosen node, in pixels (0: full resolution;
        /// infinite, written `"inf"`: the coarsest level).
        #[serde(with = "pixels", default = "one_pixel")]
        pixels: f32,
    },
}

fn one_pixel() -> f32 {
    1.0
}

/// How cells are coloured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Colouring {
    /// The property; PORO when the model has it and this is `None` (a hierarchy
    /// colours by the property it stores).
    pub property: Option<String>,
    /// A solid colour, no property.
    pub solid: bool,
    /// Report step (its number, SEQNUM) whose arrays a solution property is read
    /// from; the last when `None`.
    pub step: Option<i32>,
    /// Values interpolated between nodes instead of each cell painted flat.
    pub smooth: bool,
    /// The colour map.
    #[serde(with = "named")]
    pub colormap: Colormap,
    /// Values at the two ends of the colour map; the property's range over the drawn
    /// cells when `None`.
    pub range: Option<[f32; 2]>,
    /// How values map onto the colour map: linear, log (a positive range is needed;
    /// values at or below zero draw as undefined) or categorical (integer codes, a
    /// palette colour each).
    #[serde(with = "named")]
    pub scale: Scale,
}

impl Default for Colouring {
    fn default() -> Self {
        Colouring {
            property: None,
            solid: false,
            step: None,
            smooth: false,
            colormap: Colormap::Viridis,
            range: None,
            scale: Scale::Linear,
        }
    }
}

impl Colouring {
    /// Refuses a scale its other fields contradict: a log scale over a typed range
    /// not all positive, a categorical one interpolated between nodes.
    fn check(&self) -> Result<()> {
        match (self.scale, self.range) {
            (Scale::Log, Some([lo, hi])) if lo <= 0.0 => Err(Error::scene(format!(
                "colour: a log scale of {} needs a positive range, not [{lo}, {hi}]",
                self.property
                    .as_deref()
                    .unwrap_or("the default property (PORO)")
            ))),
            (Scale::Categorical, _) if self.smooth => Err(Error::scene(
                "colour: a categorical scale paints each cell its code's colour; codes are \
                 not interpolated between nodes (smooth)",
            )),
            _ => Ok(()),
        }
    }
}

/// How the wireframe is drawn.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WireStyle {
    /// The technique (`strata render --wire`).
    #[serde(with = "named")]
    pub technique: WireMode,
    /// Hidden-line style (Rossignac & van Emmerik).
    #[serde(with = "named")]
    pub hidden: HiddenLines,
    /// Line thickness in pixels.
    pub thickness: f32,
    /// Line colour: `#rrggbb[aa]` or a name.
    pub color: String,
    /// Lines fade or thin with distance.
    pub attenuate: Attenuate,
    /// Coverage from the mip-mapped texture or evaluated analytically.
    pub coverage: CoverageChoice,
    /// Lines alone, in the cells' colours, on black.
    pub isolation: bool,
    /// Every `major`-th cell line (and every `major`²-th) is major: drawn in
    /// `major_color` while the others fade out where cells get small on screen; 0:
    /// every line alike (`strata render --major`).
    pub major: u32,
    /// Spacing on screen, in pixels, at which a level of cell lines has faded out; it
    /// is drawn whole from three times that spacing (`--fade`).
    pub fade: f32,
    /// Colour of the major lines: `#rrggbb[aa]` or a name.
    pub major_color: String,
    /// Thickness in pixels of the fault traces, drawn over the cell lines at every
    /// zoom; 0: none (`--fault-thickness`).
    pub fault_thickness: f32,
    /// Colour of the fault traces: `#rrggbb[aa]` or a name.
    pub fault_color: String,
}

/// The largest `WireStyle::major`: its square, the coarsest level of lines, stays an
/// integer the shader's floats hold exactly.
pub const MAX_MAJOR: u32 = 1000;

impl Default for WireStyle {
    fn default() -> Self {
        WireStyle {
            technique: WireMode::Global,
            hidden: HiddenLines::Suppressed,
            thickness: 1.5,
            color: "#141414".to_string(),
            attenuate: Attenuate::None,
            coverage: CoverageChoice::Auto,
            isolation: false,
            major: 10,
            fade: 4.0,
            major_color: "#0d1f66".to_string(),
            fault_thickness: 2.5,
            fault_color: "#d62728".to_string(),
        }
    }
}

/// Whether lines change with distance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Attenuate {
    /// The same everywhere.
    #[default]
    None,
    /// Fainter farther away.
    Intensity,
    /// Thinner farther away.
    Thickness,
}

/// Where line coverage comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CoverageChoice {
    /// Analytic on CPU rasterizers, where it is the faster, the texture on GPUs.
    #[default]
    Auto,
    /// The mip-mapped wireframe texture.
    Texture,
    /// Evaluated from the coordinate's screen gradient.
    Analytic,
}

/// Isolines of a property.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IsolineSpec {
    /// The property; a hierarchy's stored one when `None` (and only then).
    #[serde(default)]
    pub property: Option<String>,
    /// Value between lines; about ten lines over the property's range when `None`.
    #[serde(default)]
    pub spacing: Option<f32>,
    /// Every how many lines one is major.
    #[serde(default = "five")]
    pub major_every: u32,
    /// The per-triangle range adjust (`on`, `off`, `paper2010`, `paper2011`).
    #[serde(with = "named", default)]
    pub adjust: RangeAdjust,
}

fn five() -> u32 {
    5
}

impl IsolineSpec {
    /// Isolines of `property` (`None`: a hierarchy's own), about ten over its range.
    pub fn of(property: Option<&str>) -> Self {
        IsolineSpec {
            property: property.map(str::to_string),
            spacing: None,
            major_every: 5,
            adjust: RangeAdjust::On,
        }
    }
}

/// Map grid lines.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridLineSpec {
    /// Distance between lines in map units.
    pub spacing: f64,
    /// A map point where an x line and a y line cross.
    #[serde(default)]
    pub origin: [f64; 2],
}

/// Where the camera looks from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraSpec {
    /// Degrees clockwise from north.
    pub azimuth: f32,
    /// Degrees above the horizon.
    pub elevation: f32,
    /// Distance as a multiple of the distance that fits the model in the picture.
    pub distance: f32,
    /// Vertical exaggeration.
    pub z_scale: f32,
    /// Look at the top of this column of cells (1-based I, J) instead of the middle
    /// of the model.
    pub centre: Option<[u32; 2]>,
    /// Look at this point (map x, map y, depth, as the model's corners are given)
    /// instead: where a window pans to or centres on a picked point.
    pub target: Option<[f64; 3]>,
}

impl Default for CameraSpec {
    fn default() -> Self {
        CameraSpec {
            azimuth: 30.0,
            elevation: 35.0,
            distance: 1.0,
            z_scale: 5.0,
            centre: None,
            target: None,
        }
    }
}

impl Default for Scene {
    fn default() -> Self {
        Scene {
            model: None,
            lod: Lod::Full,
            layers: None,
            i: None,
            j: None,
            inactive: false,
            sides: false,
            colour: Colouring::default(),
            wire: WireStyle::default(),
            isolines: None,
            grid_lines: None,
            camera: CameraSpec::default(),
            size: [1200, 900],
            legend: true,
            part_cells: 2_000_000,
        }
    }
}

impl Scene {
    /// The default scene of the model at `path`.
    pub fn of_model(path: impl Into<PathBuf>) -> Self {
        Scene {
            model: Some(ModelSource::new(path)),
            ..Scene::default()
        }
    }

    /// The default scene of the hierarchy file at `file`, at 1 px of error.
    pub fn of_hierarchy(file: impl Into<PathBuf>) -> Self {
        Scene {
            lod: Lod::Hierarchy {
                file: file.into(),
                pixels: 1.0,
            },
            ..Scene::default()
        }
    }

    /// The scene in a JSON file.
    pub fn load(path: &std::path::Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::SceneFile {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        Self::from_json(&text).map_err(|e| Error::SceneFile {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
    }

    /// The scene a JSON text describes, checked ([`Scene::check`]).
    pub fn from_json(text: &str) -> Result<Self> {
        let scene: Scene =
            serde_json::from_str(text).map_err(|e| Error::scene(format!("scene: {e}")))?;
        scene.check()?;
        Ok(scene)
    }

    /// The scene as pretty JSON.
    pub fn to_json(&self) -> String {
        // A scene holds only strings, numbers, booleans and finite floats (infinite
        // pixels are written as a string), which JSON always takes.
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Writes the scene as JSON to `path`.
    pub fn save(&self, path: &std::path::Path) -> Result<()> {
        std::fs::write(path, self.to_json() + "\n").map_err(|e| Error::SceneFile {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
    }

    /// Refuses values no picture can be made of, whoever set them (a file, a
    /// window, a script), with the field named; what depends on the model (layers
    /// within it, a property it has) is checked when it is read.
    pub fn check(&self) -> Result<()> {
        let bad = |what: String| Err(Error::scene(what));
        if self.model.is_none() && !matches!(self.lod, Lod::Hierarchy { .. }) {
            return bad("scene: no model (only a hierarchy is drawn without one)".into());
        }
        match &self.lod {
            Lod::Decimated { percent, .. } if !(*percent > 0.0 && *percent <= 100.0) => {
                return bad(format!("lod: percent {percent} is not in (0, 100]"));
            }
            Lod::Hierarchy { pixels, .. } if pixels.is_nan() || *pixels < 0.0 => {
                return bad(format!("lod: pixels {pixels} is not at least 0"));
            }
            _ => {}
        }
        for (name, range) in [("layers", self.layers), ("i", self.i), ("j", self.j)] {
            if let Some([a, b]) = range
                && (a < 1 || a > b)
            {
                return bad(format!("{name} [{a}, {b}]: 1-based, first <= last"));
            }
        }
        let wire = &self.wire;
        if !(wire.thickness > 0.0 && wire.thickness.is_finite()) {
            return bad(format!(
                "wire: thickness {} is not positive",
                wire.thickness
            ));
        }
        if parse_color(&wire.color).is_none() {
            return bad(format!("wire: color {:?} is not a colour", wire.color));
        }
        if wire.major == 1 || wire.major > MAX_MAJOR {
            return bad(format!(
                "wire: major {} is neither 0 (none) nor in 2..={MAX_MAJOR}",
                wire.major
            ));
        }
        if !(wire.fade > 0.0 && wire.fade.is_finite()) {
            return bad(format!("wire: fade {} is not positive", wire.fade));
        }
        if parse_color(&wire.major_color).is_none() {
            return bad(format!(
                "wire: major_color {:?} is not a colour",
                wire.major_color
            ));
        }
        if !(wire.fault_thickness >= 0.0 && wire.fault_thickness.is_finite()) {
            return bad(format!(
                "wire: fault_thickness {} is not 0 or more",
                wire.fault_thickness
            ));
        }
        if parse_color(&wire.fault_color).is_none() {
            return bad(format!(
                "wire: fault_color {:?} is not a colour",
                wire.fault_color
            ));
        }
        if let Some(iso) = &self.isolines
            && iso.spacing.is_some_and(|s| !(s > 0.0 && s.is_finite()))
        {
            return bad(format!(
                "isolines: spacing {:?} is not positive",
                iso.spacing
            ));
        }
        if let Some(g) = &self.grid_lines
            && !(g.spacing > 0.0 && g.spacing.is_finite() && g.origin.iter().all(|v| v.is_finite()))
        {
            return bad("grid_lines: spacing must be positive, origin finite".into());
        }
        if let Some([lo, hi]) = self.colour.range
            && !(lo.is_finite() && hi.is_finite() && lo < hi)
        {
            return bad(format!(
                "colour: range [{lo}, {hi}] must be finite, low < high"
            ));
        }
        self.colour.check()?;
        if self.colour.scale == Scale::Categorical
            && self.lod != Lod::Full
            && !matches!(self.wire.technique, WireMode::Global | WireMode::None)
        {
            return bad(format!(
                "colour: a categorical scale paints each cell its code's colour, and decimated \
                 surfaces drawn with --wire {} interpolate between nodes: use --wire global or none",
                self.wire.technique.name()
            ));
        }
        let c = &self.camera;
        if ![c.azimuth, c.elevation].iter().all(|v| v.is_finite()) {
            return bad("camera: azimuth and elevation must be finite".into());
        }
        if !(c.distance > 0.0 && c.distance.is_finite()) {
            return bad(format!("camera: distance {} is not positive", c.distance));
        }
        if !(c.z_scale > 0.0 && c.z_scale.is_finite()) {
            return bad(format!("camera: z_scale {} is not positive", c.z_scale));
        }
        if c.centre.is_some_and(|[i, j]| i < 1 || j < 1) {
            return bad("camera: centre is a 1-based column I, J".into());
        }
        if !self.size.iter().all(|n| (1..=16384).contains(n)) {
            return bad(format!("size {:?}: each in 1..16384", self.size));
        }
        if self.part_cells == 0 {
            return bad("part_cells: at least 1".into());
        }
        Ok(())
    }

    /// The files the scene reads: the model, its property decks, a hierarchy. A front
    /// end refuses to write over them.
    pub fn inputs(&self) -> Vec<PathBuf> {
        let model = self.model.iter();
        let mut inputs: Vec<PathBuf> = model
            .flat_map(|m| std::iter::once(m.path.clone()).chain(m.props.iter().cloned()))
            .collect();
        if let Lod::Hierarchy { file, .. } = &self.lod {
            inputs.push(file.clone());
        }
        inputs
    }

    /// The drawn layers, 0-based and end-exclusive, of a model of `nz` layers; all
    /// when `None`.
    pub fn layer_range(&self, nz: usize) -> Result<Option<std::ops::Range<usize>>> {
        match self.layers {
            None => Ok(None),
            Some([a, b]) if a >= 1 && a <= b && b <= nz => Ok(Some(a - 1..b)),
            Some([a, b]) if a == b => Err(Error::scene(format!(
                "layer {a} is not within the model's 1..{nz}"
            ))),
            Some([a, b]) => Err(Error::scene(format!(
                "layers {a}..{b} are not within the model's 1..{nz}"
            ))),
        }
    }
}

impl Scene {
    /// The range filter's columns, 0-based and end-exclusive, of a model of `nx` x
    /// `ny` columns; `None` when neither `i` nor `j` filters.
    pub fn cut(&self, [nx, ny]: [usize; 2]) -> Result<Option<strata_grid::Columns>> {
        if self.i.is_none() && self.j.is_none() {
            return Ok(None);
        }
        let range = |name: &str, range: Option<[usize; 2]>, n: usize| match range {
            None => Ok(0..n),
            Some([a, b]) if a >= 1 && a <= b && b <= n => Ok(a - 1..b),
            Some([a, b]) => Err(Error::scene(format!(
                "cells {name} {a}..{b} are not within the model's 1..{n}"
            ))),
        };
        Ok(Some(strata_grid::Columns {
            i: range("I", self.i, nx)?,
            j: range("J", self.j, ny)?,
        }))
    }
}

/// The names the command line takes for the render crate's enums, in a scene's JSON.
pub trait Named: Sized + Copy + 'static {
    /// What the value is, for messages.
    const KIND: &'static str;
    /// Every value with its name.
    fn all() -> Vec<(&'static str, Self)>;
    /// The value's name.
    fn name(self) -> &'static str;
    /// The value of a name (any case).
    fn from_name(name: &str) -> Option<Self> {
        Self::all()
            .into_iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, v)| v)
    }
}

/// The name of `value` among `all`.
fn name_in<T: PartialEq>(all: &[(&'static str, T)], value: &T) -> &'static str {
    all.iter().find(|(_, v)| v == value).map_or("", |(n, _)| n)
}

impl Named for WireMode {
    const KIND: &'static str = "wire technique";
    fn all() -> Vec<(&'static str, Self)> {
        WireMode::ALL.iter().map(|&m| (m.name(), m)).collect()
    }
    fn name(self) -> &'static str {
        WireMode::name(self)
    }
}

impl Named for HiddenLines {
    const KIND: &'static str = "hidden-line style";
    fn all() -> Vec<(&'static str, Self)> {
        HiddenLines::ALL.to_vec()
    }
    fn name(self) -> &'static str {
        HiddenLines::name(self)
    }
}

impl Named for Colormap {
    const KIND: &'static str = "colour map";
    fn all() -> Vec<(&'static str, Self)> {
        Colormap::ALL.to_vec()
    }
    fn name(self) -> &'static str {
        name_in(&Colormap::ALL, &self)
    }
}

impl Named for Scale {
    const KIND: &'static str = "colour scale";
    fn all() -> Vec<(&'static str, Self)> {
        Scale::ALL.to_vec()
    }
    fn name(self) -> &'static str {
        Scale::name(self)
    }
}

impl Named for RangeAdjust {
    const KIND: &'static str = "range adjust";
    fn all() -> Vec<(&'static str, Self)> {
        RangeAdjust::ALL.to_vec()
    }
    fn name(self) -> &'static str {
        name_in(&RangeAdjust::ALL, &self)
    }
}

/// Serde by name for [`Named`] values.
mod named {
    use super::*;

    pub fn serialize<S: Serializer, T: Named>(value: &T, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(value.name())
    }

    pub fn deserialize<'de, D: Deserializer<'de>, T: Named>(d: D) -> Result<T, D::Error> {
        let name = String::deserialize(d)?;
        T::from_name(&name).ok_or_else(|| {
            let names: Vec<&str> = T::all().into_iter().map(|(n, _)| n).collect();
            serde::de::Error::custom(format!(
                "unknown {} {name:?}; one of {}",
                T::KIND,
                names.join(", ")
            ))
        })
    }
}

/// Serde for a pixel error that may be infinite: a number, or `"inf"`.
mod pixels {
    use super::*;

    #[derive(Serialize, Deserialize)]
    #[serde(untagged)]
    enum Pixels {
        Finite(f32),
        Named(String),
    }

    pub fn serialize<S: Serializer>(value: &f32, s: S) -> Result<S::Ok, S::Error> {
        if value.is_infinite() {
            Pixels::Named("inf".into()).serialize(s)
        } else {
            Pixels::Finite(*value).serialize(s)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f32, D::Error> {
        match Pixels::deserialize(d)? {
            Pixels::Finite(v) => Ok(v),
            Pixels::Named(s) if s == "inf" => Ok(f32::INFINITY),
            Pixels::Named(s) => Err(serde::de::Error::custom(format!(
                "pixels {s:?}: a number or \"inf\""
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn everything_set() -> Scene {
        Scene {
            model: Some(ModelSource {
                path: "model.egrid".into(),
                props: vec!["poro.grdecl".into()],
                grid_only: true,
            }),
            lod: Lod::Decimated {
                percent: 12.5,
                cover: true,
                stitch: false,
            },
            layers: Some([2, 7]),
            i: Some([3, 40]),
            j: None,
            inactive: true,
            sides: true,
            colour: Colouring {
                property: Some("PRESSURE".into()),
                solid: false,
                step: Some(3),
                smooth: true,
                colormap: Colormap::Turbo,
                range: Some([0.05, 0.3]),
                scale: Scale::Log,
            },
            wire: WireStyle {
                technique: WireMode::TexGs,
                hidden: HiddenLines::ContoursDashed,
                thickness: 2.25,
                color: "#ff000080".into(),
                attenuate: Attenuate::Thickness,
                coverage: CoverageChoice::Texture,
                isolation: true,
                major: 5,
                fade: 2.5,
                major_color: "#204080".into(),
                fault_thickness: 4.0,
                fault_color: "yellow".into(),
            },
            isolines: Some(IsolineSpec {
                property: Some("PORO".into()),
                spacing: Some(0.02),
                major_every: 4,
                adjust: RangeAdjust::Paper2010,
            }),
            grid_lines: Some(GridLineSpec {
                spacing: 250.0,
                origin: [456_000.125, 5_930_000.5],
            }),
            camera: CameraSpec {
                azimuth: 123.4,
                elevation: -12.5,
                distance: 0.3,
                z_scale: 2.5,
                centre: Some([10, 4]),
                target: Some([456_500.5, 6_780_600.25, 1650.0]),
            },
            size: [640, 480],
            legend: false,
            part_cells: 12_345,
        }
    }

    #[test]
    fn scales_and_the_legend_default_and_are_checked() {
        let with =
            |colour: &str| format!(r#"{{"model": {{"path": "m.grdecl"}}, "colour": {colour}}}"#);
        // A scene written before scales and legends reads as linear, with a legend.
        let old = Scene::from_json(&with(r#"{"colormap": "turbo"}"#)).expect("reads");
        assert_eq!((old.colour.scale, old.legend), (Scale::Linear, true));
        let scene = Scene::from_json(&with(r#"{"scale": "categorical"}"#)).expect("reads");
        assert_eq!(scene.colour.scale, Scale::Categorical);
        let errors = [
            (r#"{"scale": "cubic"}"#, "unknown colour scale \"cubic\""),
            (
                r#"{"scale": "log", "property": "PERMX", "range": [0, 10]}"#,
                "a log scale of PERMX needs a positive range, not [0, 10]",
            ),
            (
                r#"{"scale": "categorical", "smooth": true}"#,
                "not interpolated between nodes",
            ),
        ];
        let decimated = r#"{"model": {"path": "m.grdecl"}, "lod": {"kind": "decimated", "percent": 10},
            "wire": {"technique": "tex"}, "colour": {"scale": "categorical"}}"#;
        let message = Scene::from_json(decimated)
            .expect_err("refused")
            .to_string();
        assert!(message.contains("--wire tex interpolate"), "{message}");
        for (colour, expect) in errors {
            let message = Scene::from_json(&with(colour))
                .expect_err(colour)
                .to_string();
            assert!(message.contains(expect), "{colour}: {message}");
        }
    }

    #[test]
    fn a_scene_round_trips_through_json_exactly() {
        let scene = everything_set();
        let back = Scene::from_json(&scene.to_json()).expect("its own JSON reads back");
        assert_eq!(back, scene);
        let hierarchy = Scene {
            model: None,
            lod: Lod::Hierarchy {
                file: "m.lod".into(),
                pixels: f32::INFINITY,
            },
            ..Scene::default()
        };
        let json = hierarchy.to_json();
        assert!(json.contains("\"inf\""), "{json}");
        assert_eq!(Scene::from_json(&json).expect("reads back"), hierarchy);
    }

    #[test]
    fn fields_left_out_take_the_command_line_defaults() {
        let scene = Scene::from_json(r#"{"model": {"path": "m.grdecl"}}"#).expect("a scene");
        assert_eq!(scene, Scene::of_model("m.grdecl"));
        let lod = Scene::from_json(r#"{"lod": {"kind": "hierarchy", "file": "m.lod"}}"#);
        assert_eq!(lod.expect("a scene"), Scene::of_hierarchy("m.lod"));
    }

    #[test]
    fn wrong_fields_and_values_are_named() {
        let said = |json: &str| {
            Scene::from_json(json)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default()
        };
        let model = r#""model": {"path": "m.grdecl"}"#;
        assert!(
            said(&format!(
                "{{{model}, \"colour\": {{\"colourmap\": \"x\"}}}}"
            ))
            .contains("unknown field `colourmap`")
        );
        assert!(
            said(&format!(
                "{{{model}, \"wire\": {{\"technique\": \"lines\"}}}}"
            ))
            .contains("unknown wire technique \"lines\"; one of none, global")
        );
        assert!(
            said(&format!("{{{model}, \"wire\": {{\"thickness\": -1}}}}"))
                .contains("thickness -1 is not positive")
        );
        assert!(said(&format!("{{{model}, \"size\": [0, 10]}}")).contains("size [0, 10]"));
        assert!(said(&format!("{{{model}, \"layers\": [3, 2]}}")).contains("layers [3, 2]"));
        assert!(said(r#"{"sides": true}"#).contains("no model"));
        assert!(
            said(&format!(
                "{{{model}, \"lod\": {{\"kind\": \"decimated\", \"percent\": 0}}}}"
            ))
            .contains("percent 0 is not in (0, 100]")
        );
        assert!(said("{").contains("scene: EOF while parsing"));
        for (wire, says) in [
            (
                r#"{"major": 1}"#,
                "major 1 is neither 0 (none) nor in 2..=1000",
            ),
            (r#"{"major": 1001}"#, "major 1001 is neither"),
            (r#"{"fade": 0}"#, "fade 0 is not positive"),
            (
                r#"{"major_color": "mauve"}"#,
                "major_color \"mauve\" is not a colour",
            ),
            (
                r#"{"fault_thickness": -1}"#,
                "fault_thickness -1 is not 0 or more",
            ),
            (
                r#"{"fault_color": "x"}"#,
                "fault_color \"x\" is not a colour",
            ),
        ] {
            let json = format!("{{{model}, \"wire\": {wire}}}");
            assert!(said(&json).contains(says), "{wire}: {}", said(&json));
        }
    }

    #[test]
    fn a_scene_written_before_major_lines_draws_them_and_zero_turns_them_off() {
        let old = r##"{"model": {"path": "m.grdecl"}, "wire": {"technique": "global",
            "hidden": "tehs", "thickness": 1.5, "color": "#141414", "attenuate": "none",
            "coverage": "auto", "isolation": false}}"##;
        let scene = Scene::from_json(old).expect("an older scene reads");
        assert_eq!((scene.wire.major, scene.wire.fade), (10, 4.0));
        assert_eq!(scene.wire.fault_thickness, 2.5);
        let off = Scene::from_json(r#"{"model": {"path": "m"}, "wire": {"major": 0}}"#)
            .expect("major 0 reads");
        assert_eq!(off.wire.major, 0);
    }

    #[test]
    fn layers_are_checked_against_the_model() {
        let scene = |layers| Scene {
            layers,
            ..Scene::of_model("m")
        };
        assert_eq!(scene(Some([3, 3])).layer_range(5).ok(), Some(Some(2..3)));
        assert_eq!(scene(Some([2, 5])).layer_range(5).ok(), Some(Some(1..5)));
        assert_eq!(scene(None).layer_range(5).ok(), Some(None));
        let said = |r: Result<_>| r.err().map(|e| e.to_string()).unwrap_or_default();
        assert_eq!(
            said(scene(Some([6, 6])).layer_range(5)),
            "layer 6 is not within the model's 1..5"
        );
        assert_eq!(
            said(scene(Some([4, 6])).layer_range(5)),
            "layers 4..6 are not within the model's 1..5"
        );
    }
}
