//! The retained scene renderer: a [`Scene`] in, pictures out, rebuilding only what a
//! change of scene invalidates.
//!
//! # How it works
//! A [`SceneRenderer`] holds three things, each made from the one before: the
//! [`Model`] read from the scene's files, the *content* built from it (the surfaces
//! and their GPU buffers, a decimated scene, an open hierarchy), and the GPU
//! [`Renderer`]. [`SceneRenderer::set_scene`] compares the new scene with the old
//! field by field: new files read the model again; new layers, I/J range filters,
//! sides, property, level of detail, technique or isoline field build the content
//! again; anything else (camera, size, line style, colours, isoline spacing, grid
//! lines) is drawn by the next frame from what is held. [`Counters`] says how often each happened.
//! A model already in memory is handed over with [`SceneRenderer::set_model`] and
//! then held as a read one is.
//!
//! The content takes one of three forms:
//! - **whole**: one mesh of every drawn surface, full or decimated (`render`,
//!   `render --lod`); a frame frames it and draws it.
//! - **parts**: a scene of more active cells than [`Scene::part_cells`]; a frame
//!   frames it in one pass over its corners and builds, draws and drops a part at a
//!   time, so its memory is one part's.
//! - **hierarchy**: a `.lod` file, memory mapped; a frame chooses its nodes for the
//!   camera and draws them over the model's cells.
//!
//! # Why not rebuild per frame
//! Reading a model and extracting its surfaces costs many times a frame's draw, and
//! a window or a script that turns the camera would pay it every time. Holding the
//! GPU buffers makes the next frame cost the draw alone.

mod decimated;
mod hierarchy;
mod legend;
mod look;
mod model;
mod parts;
mod pick;
mod whole;

use std::time::Instant;

pub use model::{Model, stray_warning};
pub use pick::Pick;
use strata_render::image::RgbaImage;
use strata_render::{Output, Renderer, View};

use crate::progress::ProgressFn;
use crate::scene::{Lod, Scene};
use crate::{Error, Result};

/// Something the engine has to say about what it read, built or drew.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Note {
    /// A problem the picture works around (a skipped INCLUDE, a stray corner).
    Warning(String),
    /// Something the user should know about the picture (colours interpolated, a
    /// budget below what keeps the outlines).
    Note(String),
    /// What was done and how (the decimation, the nodes chosen).
    Info(String),
}

/// How often the engine did each kind of work, from its start: what a test or a
/// benchmark reads to see that a new camera rebuilt nothing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Models read.
    pub models_read: usize,
    /// Contents built: surfaces extracted (and decimated), or a hierarchy opened.
    pub contents_built: usize,
    /// Frames drawn.
    pub frames: usize,
}

/// A frame and what went into it.
pub struct Frame {
    /// The picture, RGBA8, rows top to bottom.
    pub image: RgbaImage,
    /// What was drawn.
    pub report: FrameReport,
}

/// What a frame drew, and how long it took.
#[derive(Clone, Debug, Default)]
pub struct FrameReport {
    /// Triangles drawn.
    pub triangles: usize,
    /// What was drawn, in words (triangles, parts, nodes).
    pub drawn: String,
    /// The property colouring the cells and the range the colour map spans.
    pub colouring: Option<(String, (f32, f32))>,
    /// The wireframe technique's name.
    pub technique: &'static str,
    /// The line coverage used (texture or analytic).
    pub coverage: strata_render::Coverage,
    /// The adapter that drew the frame, in words.
    pub adapter: String,
    /// No part of the model covers a pixel: the picture is the background alone.
    pub blank: bool,
    /// Seconds reading and building before the frame (0 when all was held).
    pub build_seconds: f64,
    /// Seconds drawing the frame.
    pub draw_seconds: f64,
    /// Of the drawing, seconds choosing a hierarchy's nodes for the view (0 for other
    /// content).
    pub select_seconds: f64,
    /// The hierarchy nodes drawn (`None` for other content).
    pub nodes: Option<usize>,
    /// GPU memory allocated, in bytes, where the backend reports it (Vulkan and
    /// DirectX 12 do, through their allocator; OpenGL and Metal do not).
    pub gpu_bytes: Option<u64>,
    /// What reading, building and drawing had to say, in order.
    pub notes: Vec<Note>,
    /// The view drawn (camera, size, depth range) and the display origin of the
    /// positions drawn: what picking and a window's mouse work from.
    pub view: Option<(View, [f64; 3])>,
}

/// What a frame draws from: see the module docs.
enum Content {
    Whole(Box<whole::Whole>),
    Parts(Box<parts::Parts>),
    Hierarchy(Box<hierarchy::Hierarchy>),
}

/// Draws [`Scene`]s, holding what one frame built for the next.
pub struct SceneRenderer {
    renderer: Option<Renderer>,
    scene: Scene,
    model: Option<Model>,
    content: Option<Content>,
    /// Notes made while reading or building, given with the next frame.
    pending: Vec<Note>,
    progress: Option<Box<ProgressFn>>,
    counters: Counters,
    last_view: Option<(View, [f64; 3])>,
    /// The legend the renderer shows.
    legend: legend::Shown,
}

impl SceneRenderer {
    /// An engine for `scene` (checked), on the best adapter found when it first
    /// draws ([`strata_render::Gpu::new`]). Nothing is read until then.
    pub fn new(scene: Scene) -> Result<Self> {
        scene.check()?;
        Ok(SceneRenderer {
            renderer: None,
            scene,
            model: None,
            content: None,
            pending: Vec::new(),
            progress: None,
            counters: Counters::default(),
            last_view: None,
            legend: legend::Shown::default(),
        })
    }

    /// An engine for `scene` drawing with `renderer` (an adapter of one's choice).
    pub fn with_renderer(scene: Scene, renderer: Renderer) -> Result<Self> {
        let mut engine = Self::new(scene)?;
        engine.renderer = Some(renderer);
        Ok(engine)
    }

    /// Hears of the progress of long steps (framing and drawing a scene in parts).
    pub fn on_progress(&mut self, progress: Box<ProgressFn>) {
        self.progress = Some(progress);
    }

    /// The scene drawn next.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// How often each kind of work was done.
    pub fn counters(&self) -> Counters {
        self.counters
    }

    /// The model read, once a frame has read it.
    pub fn model(&self) -> Option<&Model> {
        self.model.as_ref()
    }

    /// Cells along I, J and K of what is drawn: the model read, or the model a
    /// hierarchy was built from; `None` before the first frame.
    pub fn dims(&self) -> Option<[usize; 3]> {
        if let Some(model) = &self.model {
            let d = model.grid.dims();
            return Some([d.nx, d.ny, d.nz]);
        }
        match &self.content {
            Some(Content::Hierarchy(hierarchy)) => Some(hierarchy.dims()),
            _ => None,
        }
    }

    /// Reads the scene's model where it is not held yet, without building anything:
    /// what a front end looks at (the cell count, say) before it settles the scene.
    pub fn open_model(&mut self) -> Result<Option<&Model>> {
        if self.model.is_none()
            && let Some(source) = &self.scene.model
            && !matches!(self.scene.lod, Lod::Hierarchy { .. })
        {
            let (model, notes) = Model::open(source)?;
            self.pending.extend(notes);
            self.model = Some(model);
            self.counters.models_read += 1;
        }
        Ok(self.model.as_ref())
    }

    /// The GPU renderer, opened on first use.
    pub fn renderer(&mut self) -> Result<&mut Renderer> {
        opened(&mut self.renderer)
    }

    /// Draws `scene` from now on; what its changes invalidate is dropped and built
    /// again by the next frame. A scene that fails its checks leaves the last one.
    pub fn set_scene(&mut self, scene: Scene) -> Result<()> {
        scene.check()?;
        if scene.model != self.scene.model {
            self.model = None;
            self.content = None;
        } else if content_key(&scene) != content_key(&self.scene) {
            self.content = None;
        }
        self.scene = scene;
        Ok(())
    }

    /// Draws `model`, already in memory, in place of reading the scene's model: the
    /// scene's `model` becomes `model.source` and what was built is dropped (with the
    /// notes of [`Model::from_grid`] given with the next frame). The rules of
    /// [`Self::set_scene`] hold after it: a scene naming the same source keeps the
    /// model, and a new camera rebuilds nothing; a scene naming another reads that.
    pub fn set_model(&mut self, model: Model, notes: Vec<Note>) {
        self.scene.model = Some(model.source.clone());
        self.model = Some(model);
        self.content = None;
        self.pending.extend(notes);
    }

    /// Reads the model and builds the content where they are not held, then draws
    /// a frame of the scene and reads its pixels back.
    pub fn render(&mut self) -> Result<Frame> {
        let (image, mut report) = self.frame(Output::Pixels)?;
        let image = image.ok_or_else(|| Error::scene("no pixels read back"))?;
        report.blank = background_only(&image, &self.scene, self.legend.area(&image));
        Ok(Frame { image, report })
    }

    /// Draws a frame as [`SceneRenderer::render`] does, but leaves it in the
    /// renderer's frame texture ([`Renderer::frame_texture`]) for a window to show,
    /// without reading it back.
    pub fn draw(&mut self) -> Result<FrameReport> {
        self.frame(Output::Texture).map(|(_, report)| report)
    }

    /// The cell under pixel `(x, y)` (from the top left) of the last frame drawn, and
    /// the point hit; `None` where the pixel shows no cell.
    pub fn pick(&self, x: f32, y: f32) -> Result<Option<Pick>> {
        let (view, _) = self
            .last_view
            .ok_or_else(|| Error::scene("nothing drawn yet to pick from"))?;
        let ray = pick::Ray::through(&view, x, y);
        match &self.content {
            Some(Content::Whole(whole)) => {
                let model = self.model.as_ref().ok_or_else(no_model)?;
                Ok(whole.pick(&ray, model))
            }
            Some(Content::Parts(_)) => Err(Error::scene(
                "a scene drawn in parts holds no mesh to pick from; pick in a smaller \
                 selection of layers or columns, or in its hierarchy",
            )),
            Some(Content::Hierarchy(hierarchy)) => hierarchy.pick(&ray),
            None => Err(Error::scene("nothing built to pick from")),
        }
    }

    /// Where the map point `point` (x, y, depth) falls in the last frame drawn, in
    /// pixels from its top left corner (continuous: pixel `(x, y)` spans `x..x + 1`);
    /// `None` behind the eye or before the first frame. A window draws its marks
    /// (the picked cell's edges) there.
    pub fn pixel_of(&self, point: [f64; 3]) -> Option<[f32; 2]> {
        let (view, origin) = self.last_view?;
        pick::pixel_of(&view, origin, point)
    }

    /// The frame drawn last: its view and display origin (for picking).
    pub fn last_view(&self) -> Option<(View, [f64; 3])> {
        self.last_view
    }

    fn frame(&mut self, output: Output) -> Result<(Option<RgbaImage>, FrameReport)> {
        let start = Instant::now();
        self.ensure_content()?;
        let built = start.elapsed().as_secs_f64();
        let drawing = Instant::now();
        let renderer = opened(&mut self.renderer)?;
        let scene = &self.scene;
        if let Some(content) = &self.content {
            let built = (content, self.counters.contents_built);
            (self.legend).update(scene, built, self.model.as_ref(), renderer)?;
        }
        let progress = self.progress.as_deref();
        let (image, mut report) = match self.content.as_mut() {
            Some(Content::Whole(whole)) => {
                whole.draw(renderer, self.model.as_ref(), scene, output)?
            }
            Some(Content::Parts(parts)) => {
                let model = self.model.as_ref().ok_or_else(no_model)?;
                parts.draw(renderer, model, scene, progress, output)?
            }
            Some(Content::Hierarchy(hierarchy)) => hierarchy.draw(renderer, scene, output)?,
            None => return Err(Error::scene("nothing built to draw")),
        };
        report.build_seconds = built;
        report.draw_seconds = drawing.elapsed().as_secs_f64();
        report.technique = scene.wire.technique.name();
        report.adapter = renderer.gpu.describe();
        report.gpu_bytes = (renderer.gpu.device)
            .generate_allocator_report()
            .map(|r| r.total_allocated_bytes);
        let mut notes = std::mem::take(&mut self.pending);
        notes.append(&mut report.notes);
        report.notes = notes;
        self.last_view = report.view;
        self.counters.frames += 1;
        Ok((image, report))
    }

    /// A hierarchy scene's choice of nodes for its camera, in words, without drawing
    /// (no GPU needed): what `strata lod view` prints with no output file.
    pub fn describe_selection(&mut self) -> Result<Vec<Note>> {
        self.ensure_content()?;
        match &self.content {
            Some(Content::Hierarchy(hierarchy)) => {
                let mut notes = std::mem::take(&mut self.pending);
                notes.extend(hierarchy.plan(&self.scene)?.notes);
                Ok(notes)
            }
            _ => Err(Error::scene("only a hierarchy's selection is described")),
        }
    }

    /// Reads the model and builds the content where they are not held.
    fn ensure_content(&mut self) -> Result<()> {
        if self.content.is_some() {
            return Ok(());
        }
        if let Lod::Hierarchy { file, .. } = &self.scene.lod {
            let hierarchy = hierarchy::Hierarchy::open(file, &self.scene)?;
            self.content = Some(Content::Hierarchy(Box::new(hierarchy)));
            self.counters.contents_built += 1;
            return Ok(());
        }
        self.open_model()?;
        let model = self.model.as_mut().ok_or_else(no_model)?;
        model.use_step(self.scene.colour.step)?;
        let scene = &self.scene;
        let content = match parts::Parts::plan(model, scene)? {
            parts::Plan::Parts(parts) => Content::Parts(parts),
            parts::Plan::Whole(options) => {
                let renderer = opened(&mut self.renderer)?;
                let (whole, notes) = whole::Whole::build(renderer, model, scene, options)?;
                self.pending.extend(notes);
                Content::Whole(Box::new(whole))
            }
        };
        self.content = Some(content);
        self.counters.contents_built += 1;
        Ok(())
    }
}

/// Whether `image` is `scene`'s background alone (black with lines in isolation,
/// white otherwise) outside the legend's `area` (`[x0, y0, x1, y1)`).
fn background_only(image: &RgbaImage, scene: &Scene, area: Option<[i64; 4]>) -> bool {
    let clear = if scene.wire.isolation {
        [0, 0, 0, 255]
    } else {
        [255; 4]
    };
    let legend = |x: u32, y: u32| {
        let (x, y) = (i64::from(x), i64::from(y));
        area.is_some_and(|[x0, y0, x1, y1]| x >= x0 && x < x1 && y >= y0 && y < y1)
    };
    image
        .enumerate_pixels()
        .all(|(x, y, p)| p.0 == clear || legend(x, y))
}

/// The renderer in `slot`, opened on the best adapter found when there is none yet.
fn opened(slot: &mut Option<Renderer>) -> Result<&mut Renderer> {
    match slot {
        Some(renderer) => Ok(renderer),
        empty => Ok(empty.insert(Renderer::headless()?)),
    }
}

fn no_model() -> Error {
    Error::scene("scene: no model")
}

/// What the content is built from: a scene that differs from another here needs its
/// surfaces (or hierarchy) built again; one that differs elsewhere only a new frame.
fn content_key(scene: &Scene) -> impl PartialEq + use<> {
    let colour = &scene.colour;
    (
        scene.lod.clone(),
        (scene.layers, scene.i, scene.j, scene.inactive),
        scene.sides,
        (
            colour.property.clone(),
            colour.solid,
            colour.step,
            colour.smooth,
        ),
        scene.wire.technique,
        scene
            .isolines
            .as_ref()
            .map(|iso| (iso.property.clone(), iso.adjust)),
        scene.part_cells,
    )
}
