//! The window's life: opening it on the engine, and per frame the script, the panel,
//! the mouse and keys, the engine's frame and egui's painting.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use egui::{Key, PointerButton, Sense};
use strata_render::Renderer;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::{Window, WindowId};

use super::background::{self, Build};
use super::panel::{self, Facts, PanelState, Request};
use super::script::{Command, set_field};
use super::stats::{Stats, Summary, write_json};
use super::window::{self, WindowGpu};
use super::{Options, controls};
use crate::cell::CellInfo;
use crate::engine::Pick;
use crate::scene::{Lod, ModelSource};
use crate::{Error, FrameReport, Result, Scene, SceneRenderer};

/// The window and everything it holds between frames.
pub struct App {
    options: Options,
    /// The scene as the panel, mouse, keys and script left it.
    scene: Scene,
    /// The last scene drawn without an error, which a refused one falls back to.
    good: Scene,
    engine: Option<SceneRenderer>,
    window: Option<WindowGpu>,
    ctx: egui::Context,
    egui_state: Option<egui_winit::State>,
    panel: PanelState,
    facts: Option<Facts>,
    frame_texture: Option<egui::TextureId>,
    help: bool,
    script: Option<Runner>,
    stats: Stats,
    failure: Option<Error>,
    played: Instant,
    shots: usize,
    /// The hierarchy being built behind a preview, and the scene asked for.
    build: Option<(Build, Scene)>,
    /// A hierarchy to build once the preview is on screen (the model, the property
    /// it stores and the scene asked for): started before, it would take a core from
    /// the first picture.
    queued: Option<(ModelSource, Option<String>, Scene)>,
    /// When the last frame was drawn.
    drawn: Instant,
}

/// A script being run: the lines left, and the frames the current one still takes.
struct Runner {
    commands: VecDeque<Command>,
    /// Degrees per frame and frames left of an orbit.
    orbit: Option<(f32, u32)>,
    /// Frames left to draw with nothing changed.
    frames: u32,
}

/// What the panel and the mouse asked for in one frame.
#[derive(Default)]
struct Gestures {
    /// The picture's size in pixels.
    size: [u32; 2],
    orbit: [f32; 2],
    pan: [f32; 2],
    /// Wheel notches, and the pixel under the cursor.
    zoom: Option<(f32, [f32; 2])>,
    centre_at: Option<[f32; 2]>,
    pick_at: Option<[f32; 2]>,
    keys: Vec<Key>,
    requests: Vec<Request>,
}

impl App {
    /// A window for `options`, run by `commands` when a script gives them.
    pub fn new(options: Options, commands: Option<Vec<Command>>) -> Self {
        let scene = options.scene.clone();
        App {
            stats: Stats::new(options.stats_file.clone()),
            good: scene.clone(),
            scene,
            options,
            engine: None,
            window: None,
            ctx: egui::Context::default(),
            egui_state: None,
            panel: PanelState::default(),
            facts: None,
            frame_texture: None,
            help: false,
            script: commands.map(|commands| Runner {
                commands: commands.into(),
                orbit: None,
                frames: 2,
            }),
            failure: None,
            played: Instant::now(),
            shots: 0,
            build: None,
            queued: None,
            drawn: Instant::now(),
        }
    }

    /// The frame statistics once the window is closed, or why it failed.
    pub fn finish(self) -> Result<Summary> {
        if let Some(failure) = self.failure {
            return Err(failure);
        }
        self.stats.write()?;
        Ok(self.stats.summary())
    }

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let [w, h] = self.options.size;
        let attributes = Window::default_attributes()
            .with_title("strata")
            .with_inner_size(PhysicalSize::new(w, h));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| Error::Window(e.to_string()))?,
        );
        // A script measures frames: they are not held back to the display's rate.
        let (window_gpu, gpu) = window::open(window.clone(), self.script.is_none())?;
        let max_texture = gpu.limits.max_texture_dimension_2d as usize;
        let renderer = Renderer::new(gpu)?;
        self.engine = Some(SceneRenderer::with_renderer(self.scene.clone(), renderer)?);
        self.egui_state = Some(egui_winit::State::new(
            self.ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(max_texture),
        ));
        self.window = Some(window_gpu);
        if let Err(e) = self.settle_scene() {
            self.panel.error = Some(e.to_string());
        }
        window.request_redraw();
        Ok(())
    }

    /// A model too large to draw whole opens on its hierarchy kept beside it, or on a
    /// preview while the hierarchy is built ([`background`]).
    fn settle_scene(&mut self) -> Result<()> {
        let Some(source) = self.scene.model.clone() else {
            return Ok(());
        };
        if self.scene.lod != Lod::Full {
            return Ok(());
        }
        if let Some(lod) = background::kept(&source.path) {
            self.scene = background::on_hierarchy(&self.scene, &lod);
            return Ok(());
        }
        let Some(engine) = self.engine.as_mut() else {
            return Ok(());
        };
        let Some(model) = engine.open_model()? else {
            return Ok(());
        };
        if (model.grid.active_count() as u64) <= self.scene.part_cells {
            return Ok(());
        }
        let property = self
            .scene
            .colour
            .property
            .clone()
            .or_else(|| model.grid.property("PORO").map(|_| "PORO".to_string()));
        let asked = self.scene.clone();
        self.scene = background::preview(&asked, model);
        self.queued = Some((source, property, asked));
        Ok(())
    }

    /// Starts the hierarchy's build queued by [`Self::settle_scene`], if any.
    fn start_build(&mut self) {
        if let Some((source, property, asked)) = self.queued.take() {
            let destination = background::destination(&source.path);
            self.build = Some((Build::start(source, property, destination), asked));
        }
    }

    /// Follows the hierarchy's build: the scene asked for, on the hierarchy, once it is
    /// done (`wait`: blocking until then).
    fn follow_build(&mut self, wait: bool) {
        if wait {
            self.start_build();
        }
        let Some((build, asked)) = &mut self.build else {
            return;
        };
        let Some(finished) = build.finished(wait) else {
            return;
        };
        match finished {
            Ok(path) => {
                let asked = Scene {
                    camera: self.scene.camera,
                    size: self.scene.size,
                    ..asked.clone()
                };
                self.scene = background::on_hierarchy(&asked, &path);
                self.panel.message = Some(format!("hierarchy built: {}", path.display()));
            }
            Err(e) => self.panel.error = Some(format!("building the hierarchy: {e}")),
        }
        self.build = None;
    }

    /// One frame: script, panel and gestures, the engine's frame, painting, and what
    /// the script asked to be done with the frame.
    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let start = Instant::now();
        self.follow_build(false);
        let after = self.run_script();
        self.play();
        let (Some(window), Some(state)) = (&self.window, &mut self.egui_state) else {
            return Ok(());
        };
        let raw = state.take_egui_input(&window.window);
        let ctx = self.ctx.clone();
        let mut gestures = Gestures::default();
        let mut output = ctx.run_ui(raw, |ui| self.ui(ui, &mut gestures));
        self.apply(&gestures);
        let report = self.draw_scene();
        let (Some(window), Some(state), Some(engine)) =
            (&mut self.window, &mut self.egui_state, &mut self.engine)
        else {
            return Ok(());
        };
        state.handle_platform_output(&window.window, std::mem::take(&mut output.platform_output));
        let renderer = engine.renderer()?;
        if let Some(frame) = renderer.frame_texture() {
            let first = self.frame_texture.is_none();
            self.frame_texture = Some(window.frame_texture(&renderer.gpu, frame));
            if first {
                window.window.request_redraw();
            }
        }
        window.paint(&renderer.gpu, &ctx, output)?;
        if report.is_some() {
            // The first picture is on screen: the build may take its cores.
            self.start_build();
        }
        if let Some(report) = report {
            self.stats
                .record(1e3 * start.elapsed().as_secs_f64(), &report);
        }
        for command in after {
            self.after_frame(command, event_loop);
        }
        for request in std::mem::take(&mut gestures.requests) {
            self.request(request);
        }
        Ok(())
    }

    /// The panel, the help overlay and the picture with its mouse handling.
    fn ui(&mut self, ui: &mut egui::Ui, gestures: &mut Gestures) {
        let facts = self.facts.clone().unwrap_or_default();
        let stat = self.stats.last().cloned();
        let building = match (&self.build, &self.queued) {
            (Some((build, _)), _) => Some(build.fraction()),
            (None, queued) => queued.as_ref().map(|_| 0.0),
        };
        egui::Panel::right("scene")
            .default_size(300.0)
            .show(ui, |ui| {
                gestures.requests = panel::show(
                    ui,
                    &mut self.scene,
                    &facts,
                    &mut self.panel,
                    stat.as_ref(),
                    building,
                );
            });
        egui::CentralPanel::no_frame().show(ui, |ui| {
            let rect = ui.available_rect_before_wrap();
            let ppp = ui.ctx().pixels_per_point();
            gestures.size = [
                (rect.width() * ppp).round().max(1.0) as u32,
                (rect.height() * ppp).round().max(1.0) as u32,
            ];
            let response = ui.allocate_rect(rect, Sense::click_and_drag());
            if let Some(id) = self.frame_texture {
                let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
                ui.painter().image(id, rect, uv, egui::Color32::WHITE);
            }
            self.mark_picked(ui.painter(), rect.min, ppp);
            let pixel = |pos: egui::Pos2| [(pos.x - rect.min.x) * ppp, (pos.y - rect.min.y) * ppp];
            let delta = response.drag_delta() * ppp;
            if response.dragged_by(PointerButton::Primary) {
                gestures.orbit = [delta.x, delta.y];
            } else if response.dragged_by(PointerButton::Secondary)
                || response.dragged_by(PointerButton::Middle)
            {
                gestures.pan = [delta.x, delta.y];
            }
            if let Some(pos) = response.hover_pos() {
                let scroll = ui.input(|i| i.smooth_scroll_delta.y);
                if scroll != 0.0 {
                    gestures.zoom = Some((scroll / 50.0, pixel(pos)));
                }
            }
            if let Some(pos) = response.interact_pointer_pos() {
                if response.double_clicked() {
                    gestures.centre_at = Some(pixel(pos));
                } else if response.clicked() {
                    gestures.pick_at = Some(pixel(pos));
                }
            }
            if self.help {
                help(ui);
            }
        });
        if !ui.ctx().egui_wants_keyboard_input() {
            let keys = [
                Key::F,
                Key::T,
                Key::S,
                Key::W,
                Key::N,
                Key::E,
                Key::Plus,
                Key::Equals,
                Key::Minus,
                Key::Space,
                Key::F12,
                Key::H,
                Key::F1,
            ];
            gestures.keys = keys
                .into_iter()
                .filter(|k| ui.input(|i| i.key_pressed(*k)))
                .collect();
        }
    }

    /// Turns the frame's gestures and keys into a new camera, a pick or a request.
    fn apply(&mut self, gestures: &Gestures) {
        self.scene.size = gestures.size;
        let camera = &mut self.scene.camera;
        if gestures.orbit != [0.0; 2] {
            controls::orbit(camera, gestures.orbit[0], gestures.orbit[1]);
        }
        let Some(engine) = &self.engine else {
            return;
        };
        let last = engine.last_view();
        if let Some((view, origin)) = last
            && gestures.pan != [0.0; 2]
        {
            controls::pan(camera, &view, origin, gestures.pan[0], gestures.pan[1]);
        }
        let point_at = |[x, y]: [f32; 2]| engine.pick(x, y).ok().flatten().map(|p| p.point);
        if let (Some((view, origin)), Some((steps, at))) = (last, gestures.zoom) {
            controls::zoom(camera, &view, origin, steps, point_at(at));
        }
        if let Some(point) = gestures.centre_at.and_then(point_at) {
            camera.target = Some(point);
        }
        for key in &gestures.keys {
            match key {
                Key::F => controls::fit(camera),
                Key::T => controls::view_from(camera, 0.0, 90.0),
                Key::S => controls::view_from(camera, 0.0, 10.0),
                Key::W => controls::view_from(camera, 90.0, 10.0),
                Key::N => controls::view_from(camera, 180.0, 10.0),
                Key::E => controls::view_from(camera, 270.0, 10.0),
                Key::Plus | Key::Equals => camera.distance *= 0.8,
                Key::Minus => camera.distance /= 0.8,
                Key::Space => self.panel.playing = !self.panel.playing,
                Key::H | Key::F1 => self.help = !self.help,
                _ => {}
            }
        }
        if gestures.keys.contains(&Key::F12) {
            self.shots += 1;
            self.panel.shot_file = format!("strata-view-{}.png", self.shots);
            self.request(Request::Screenshot);
        }
        if let Some(at) = gestures.pick_at {
            self.pick(at);
        }
    }

    /// Gives the edited scene to the engine and draws it; a scene the engine refuses
    /// is shown as the error, and the last good one is drawn again.
    fn draw_scene(&mut self) -> Option<FrameReport> {
        let engine = self.engine.as_mut()?;
        let fresh = self.scene != self.good;
        let held = engine.renderer().is_ok_and(|r| r.frame_texture().is_some());
        if !fresh && held && self.script.is_none() && engine.counters().frames > 0 {
            // The frame on screen is this scene's: only the panel is painted again.
            return None;
        }
        self.drawn = Instant::now();
        let drawn = engine
            .set_scene(self.scene.clone())
            .and_then(|()| engine.draw());
        match drawn {
            Ok(report) => {
                if fresh {
                    self.panel.error = None;
                }
                self.good = self.scene.clone();
                if self.facts.as_ref().is_none_or(|f| f.dims.is_none()) {
                    self.facts = Some(engine.model().map_or_else(
                        || Facts {
                            dims: engine.dims(),
                            ..Facts::default()
                        },
                        facts,
                    ));
                }
                Some(report)
            }
            Err(e) => {
                eprintln!("strata view: {e}");
                self.panel.error = Some(e.to_string());
                self.scene = self.good.clone();
                let again = engine
                    .set_scene(self.good.clone())
                    .and_then(|()| engine.draw());
                again.ok()
            }
        }
    }

    /// Runs the script's lines up to the next that needs a frame; returns those to run
    /// on the frame drawn next.
    fn run_script(&mut self) -> Vec<Command> {
        let Some(runner) = &mut self.script else {
            return Vec::new();
        };
        if let Some((degrees, left)) = runner.orbit {
            controls::orbit(
                &mut self.scene.camera,
                -degrees / controls::DEGREES_PER_PIXEL,
                0.0,
            );
            runner.orbit = (left > 1).then_some((degrees, left - 1));
            return Vec::new();
        }
        if runner.frames > 0 {
            runner.frames -= 1;
            return Vec::new();
        }
        while let Some(command) = runner.commands.pop_front() {
            match command {
                Command::Orbit { degrees, frames } => {
                    runner.orbit = Some((degrees / frames as f32, frames));
                    return self.run_script();
                }
                Command::Set { path, value } => match set_field(&self.scene, &path, value) {
                    Ok(scene) => self.scene = scene,
                    Err(e) => {
                        eprintln!("strata view: {e}");
                        self.panel.error = Some(e.to_string());
                    }
                },
                Command::Frames(n) => {
                    runner.frames = n.saturating_sub(1);
                    return Vec::new();
                }
                Command::Wait => {
                    self.follow_build(true);
                    return Vec::new();
                }
                after => return vec![after],
            }
        }
        vec![Command::Quit]
    }

    /// Runs a script line that works on the frame just drawn.
    fn after_frame(&mut self, command: Command, event_loop: &ActiveEventLoop) {
        let done = match command {
            Command::Pick([x, y]) => self.print_pick(x, y),
            Command::Screenshot(path, size) => self.screenshot(&path, size),
            Command::Save(path) => write_json(&path, &self.scene),
            Command::Load(path) => self.load(&path),
            Command::Quit => {
                event_loop.exit();
                Ok(())
            }
            _ => Ok(()),
        };
        if let Err(e) = done {
            eprintln!("strata view: {e}");
            self.panel.error = Some(e.to_string());
        }
    }

    fn request(&mut self, request: Request) {
        let file =
            |name: &str, default: &str| PathBuf::from(if name.is_empty() { default } else { name });
        let done = match request {
            Request::SaveScene => {
                write_json(&file(&self.panel.scene_file, "scene.json"), &self.scene)
            }
            Request::LoadScene => self.load(&file(&self.panel.scene_file, "scene.json")),
            Request::Screenshot => {
                let size = parse_size(&self.panel.shot_size);
                let path = file(&self.panel.shot_file, "strata-view.png");
                self.screenshot(&path, size)
            }
        };
        match done {
            Ok(()) => self.panel.message = Some(format!("{request:?} done")),
            Err(e) => self.panel.error = Some(e.to_string()),
        }
    }

    /// Reads a scene file; the window keeps its size.
    fn load(&mut self, path: &Path) -> Result<()> {
        let mut scene = Scene::load(path)?;
        scene.size = self.scene.size;
        self.scene = scene;
        Ok(())
    }

    /// Draws the scene once more, read back, at `size` or the window's, into `path`.
    fn screenshot(&mut self, path: &Path, size: Option<[u32; 2]>) -> Result<()> {
        let engine = self
            .engine
            .as_mut()
            .ok_or_else(|| Error::Window("no engine".into()))?;
        let mut shot = self.good.clone();
        if let Some(size) = size {
            shot.size = size;
        }
        engine.set_scene(shot)?;
        let frame = engine.render();
        engine.set_scene(self.good.clone())?;
        // Written aside and renamed: whoever waits for the file sees it whole.
        let part = path.with_extension("part.png");
        let failed = |e: &dyn std::fmt::Display| Error::File {
            path: path.to_path_buf(),
            message: e.to_string(),
        };
        frame?.image.save(&part).map_err(|e| failed(&e))?;
        std::fs::rename(&part, path).map_err(|e| failed(&e))
    }

    /// Picks the cell at frame pixel `(x, y)` into the panel: where the ray met it,
    /// and its corners and values where the model is open (a hierarchy alone names
    /// the cell only).
    fn pick(&mut self, at: [f32; 2]) -> (Option<Pick>, Option<CellInfo>) {
        let Some(engine) = self.engine.as_ref() else {
            return (None, None);
        };
        let picked = engine.pick(at[0], at[1]).and_then(|pick| {
            let info = match (pick, engine.model()) {
                (Some(pick), Some(model)) => {
                    let file = model.source.path.display().to_string();
                    Some(CellInfo::of(&model.grid, file, pick.cell.map(|c| c + 1))?)
                }
                _ => None,
            };
            Ok((pick, info))
        });
        match picked {
            Ok((pick, info)) => {
                self.panel.picked = pick.map(|p| (p, info.clone()));
                (pick, info)
            }
            Err(e) => {
                self.panel.error = Some(e.to_string());
                (None, None)
            }
        }
    }

    /// Marks the picked cell over the picture whose top left corner is at `corner`
    /// (`ppp` pixels per point): its twelve edges where its corners are known, else a
    /// ring around the point hit. Drawn over everything, in a colour of its own, so it
    /// shows through the surfaces that hide part of the cell.
    fn mark_picked(&self, painter: &egui::Painter, corner: egui::Pos2, ppp: f32) {
        let (Some(engine), Some((pick, info))) = (&self.engine, &self.panel.picked) else {
            return;
        };
        let at = |point: [f64; 3]| {
            engine
                .pixel_of(point)
                .map(|[x, y]| corner + egui::vec2(x, y) / ppp)
        };
        let dark = egui::Stroke::new(4.0, egui::Color32::BLACK);
        let bright = egui::Stroke::new(2.0, PICKED_COLOUR);
        match info {
            Some(info) => {
                let edges = CELL_EDGES
                    .iter()
                    .filter_map(|&[a, b]| Some([at(info.corners[a])?, at(info.corners[b])?]));
                let edges: Vec<_> = edges.collect();
                for stroke in [dark, bright] {
                    for &edge in &edges {
                        painter.line_segment(edge, stroke);
                    }
                }
            }
            None => {
                if let Some(centre) = at(pick.point) {
                    painter.circle_stroke(centre, 6.0, dark);
                    painter.circle_stroke(centre, 6.0, bright);
                }
            }
        }
    }

    /// A script's pick, printed as one JSON line: `{"pick": {"pixel", "ijk" (1-based),
    /// "point" (x, y, depth), "cell"}}`, the cell as `info --cell --json` gives it;
    /// nulls where the pixel shows no cell.
    fn print_pick(&mut self, x: f32, y: f32) -> Result<()> {
        #[derive(serde::Serialize)]
        struct Picked {
            pixel: [f32; 2],
            ijk: Option<[usize; 3]>,
            point: Option<[f64; 3]>,
            cell: Option<CellInfo>,
        }
        let (pick, cell) = self.pick([x, y]);
        let picked = Picked {
            pixel: [x, y],
            ijk: pick.map(|p| p.cell.map(|c| c + 1)),
            point: pick.map(|p| p.point),
            cell,
        };
        let line = serde_json::to_string(&std::collections::BTreeMap::from([("pick", picked)]))
            .map_err(|e| Error::scene(e.to_string()))?;
        println!("{line}");
        Ok(())
    }

    /// Advances the report step while playing.
    fn play(&mut self) {
        let Some(facts) = &self.facts else {
            return;
        };
        if !self.panel.playing || facts.steps.is_empty() || self.played.elapsed().as_millis() < 500
        {
            return;
        }
        self.played = Instant::now();
        let at = self
            .scene
            .colour
            .step
            .and_then(|s| facts.steps.iter().position(|(n, _)| *n == s))
            .map_or(0, |at| (at + 1) % facts.steps.len());
        self.scene.colour.step = Some(facts.steps[at].0);
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none()
            && let Err(e) = self.open(event_loop)
        {
            self.failure = Some(e);
            event_loop.exit();
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match &event {
            WindowEvent::CloseRequested => {
                event_loop.exit();
                return;
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw(event_loop) {
                    self.failure = Some(e);
                    event_loop.exit();
                }
                return;
            }
            WindowEvent::Resized(size) => {
                if let (Some(window), Some(engine)) = (&mut self.window, &mut self.engine)
                    && let Ok(renderer) = engine.renderer()
                {
                    window.resize(&renderer.gpu, size.width, size.height);
                }
            }
            _ => {}
        }
        if let (Some(window), Some(state)) = (&self.window, &mut self.egui_state) {
            let response = state.on_window_event(&window.window, &event);
            if response.repaint {
                window.window.request_redraw();
            }
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(window) = &self.window else {
            return;
        };
        if self.script.is_some() || self.panel.playing {
            window.window.request_redraw();
        } else if self.build.is_some() || self.queued.is_some() {
            // The progress bar moves twice a second; the build keeps the cores.
            let next = self.drawn + std::time::Duration::from_millis(500);
            if Instant::now() >= next {
                window.window.request_redraw();
            }
            event_loop.set_control_flow(ControlFlow::WaitUntil(next));
        } else {
            event_loop.set_control_flow(ControlFlow::Wait);
        }
    }
}

/// What the panel shows of `model`.
fn facts(model: &crate::engine::Model) -> Facts {
    let grid = &model.grid;
    let d = grid.dims();
    let mut properties: Vec<String> = grid.properties.keys().cloned().collect();
    if let Some(step) = grid.report_steps.last() {
        properties.extend(
            step.arrays
                .keys()
                .filter(|n| !properties.contains(n))
                .cloned()
                .collect::<Vec<_>>(),
        );
    }
    Facts {
        dims: Some([d.nx, d.ny, d.nz]),
        properties,
        steps: grid
            .report_steps
            .iter()
            .map(|s| {
                (
                    s.number,
                    s.date.map(|(y, m, d)| format!("{y:04}-{m:02}-{d:02}")),
                )
            })
            .collect(),
    }
}

/// `WIDTHxHEIGHT`, or `None` for anything else (the window's size).
fn parse_size(text: &str) -> Option<[u32; 2]> {
    let (w, h) = text.trim().split_once('x')?;
    Some([w.trim().parse().ok()?, h.trim().parse().ok()?])
}

/// The keys, over the picture.
fn help(ui: &mut egui::Ui) {
    egui::Window::new("Keys and mouse")
        .collapsible(false)
        .resizable(false)
        .show(ui.ctx(), |ui| {
            egui::Grid::new("keys").show(ui, |ui| {
                for (key, what) in controls::KEYS {
                    ui.label(key);
                    ui.label(what);
                    ui.end_row();
                }
            });
        });
}

/// The colour the picked cell is marked in: a magenta that no colour map uses.
const PICKED_COLOUR: egui::Color32 = egui::Color32::from_rgb(255, 0, 255);

/// A cell's twelve edges, as pairs of its corners in `CellInfo`'s order (top face
/// (I,J) (I+1,J) (I,J+1) (I+1,J+1), then the bottom face).
const CELL_EDGES: [[usize; 2]; 12] = [
    [0, 1],
    [1, 3],
    [3, 2],
    [2, 0],
    [4, 5],
    [5, 7],
    [7, 6],
    [6, 4],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];
