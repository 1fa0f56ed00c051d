//! A scene of more active cells than a part holds, drawn a part at a time: runs of
//! layers (a larger layer in bands of rows), their tops, then the bottom, then their
//! sides, each built, drawn and dropped before the next, so that a model of any size
//! draws in about the memory of one part, and the picture is the one mesh's.

use strata_grid::faults::fault_traces_across_row;
use strata_grid::outline::{InteriorEdge, OutlineEdge, surface_edges};
use strata_grid::{CornerPointGrid, SurfaceMesh};
use strata_render::glam::Vec3;
use strata_render::image::RgbaImage;
use strata_render::{HiddenLines, IsolineOptions, Output, Renderer, WireMode};

use super::whole::{colouring, corner_field, field_options, scene_options};
use super::{FrameReport, Model, look};
use crate::error::Context;
use crate::memory::check_memory;
use crate::progress::{Progress, ProgressFn, Stage};
use crate::scene::{Lod, Scene};
use crate::surfaces::{self, Part, SceneExtent, SceneOptions, column_top};
use crate::{Error, Result};

/// How a scene of a model is drawn ([`Parts::plan`]).
pub enum Plan {
    /// As one mesh, of the surfaces these options ask for.
    Whole(SceneOptions),
    /// A part at a time.
    Parts(Box<Parts>),
}

/// The parts of a scene, and the framing pass of the last view drawn.
pub struct Parts {
    options: SceneOptions,
    parts: Vec<Part>,
    range: Option<(f32, f32)>,
    /// The isoline field's scene (the property averaged onto nodes) and its range.
    iso: Option<(SceneOptions, (f32, f32))>,
    /// The extent found for a view direction, picture shape and exaggeration: the
    /// same for every distance and centre, so a new one is made only when they change.
    extent: Option<([f32; 4], SceneExtent)>,
}

impl Parts {
    /// How `scene`'s surfaces of `model` are drawn: in parts when there is more than
    /// one run of layers, else whole; after refusing a part larger than the memory
    /// there is.
    pub fn plan(model: &Model, scene: &Scene) -> Result<Plan> {
        let grid = &model.grid;
        let decimated = matches!(scene.lod, Lod::Decimated { .. });
        let options = scene_options(model, scene)?;
        let parts = surfaces::parts(grid, &options, scene.part_cells as usize)?;
        let largest = parts.iter().map(|p| p.cells(grid)).max().unwrap_or(0);
        let wire = scene.wire.technique;
        check_memory(
            largest as f64 * wire.bytes_per_cell(scene.isolines.is_some()),
            &format!("the {largest} active cells of the largest part"),
            "to draw (lower --part-cells)",
        )?;
        if !surfaces::drawn_in_parts(&parts) {
            return Ok(Plan::Whole(options));
        }
        let count = parts.len();
        let cells = scene.part_cells;
        // What needs the whole scene at once is refused before the passes over the parts.
        let whole = |what: String, instead: &str| {
            Error::scene(format!(
                "{what} the whole scene at once, and these layers hold more than --part-cells \
                 {cells} active cells ({count} parts): raise --part-cells, draw fewer layers, \
                 or {instead}"
            ))
        };
        if decimated {
            return Err(whole(
                "--lod decimates".into(),
                "build a hierarchy with `strata lod build` and draw it with `strata lod view`",
            ));
        }
        if !wire.draws_alone() {
            let alone: Vec<&str> = WireMode::ALL
                .into_iter()
                .filter(|m| m.draws_alone() && *m != WireMode::None)
                .map(WireMode::name)
                .collect();
            let instead = format!("use --wire {}", alone.join(", "));
            return Err(whole(format!("--wire {} draws", wire.name()), &instead));
        }
        if scene.wire.hidden != HiddenLines::Suppressed {
            let what = format!("--hidden {} needs", scene.wire.hidden.name());
            return Err(whole(what, "use --hidden tehs"));
        }
        let iso = match &scene.isolines {
            Some(iso) => {
                let name = iso
                    .property
                    .as_deref()
                    .ok_or_else(|| Error::scene("--iso: which property's isolines?"))?;
                Some(field_options(model, &options, name)?)
            }
            None => None,
        };
        Ok(Plan::Parts(Box::new(Parts {
            range: surfaces::colour_range_of(grid, &options)?,
            options,
            parts,
            iso,
            extent: None,
        })))
    }

    /// What the cells are coloured by: see [`SceneOptions`].
    pub fn options(&self) -> &SceneOptions {
        &self.options
    }

    /// The property colouring the cells and its range over them.
    pub fn colouring(&self) -> Option<(String, (f32, f32))> {
        colouring(&self.options, self.range)
    }

    /// Frames the scene for `scene`'s camera (one pass over the corners, held for the
    /// next frame of the same direction), then builds, draws and drops each part the
    /// picture may show, reporting to `progress`.
    pub fn draw(
        &mut self,
        renderer: &mut Renderer,
        model: &Model,
        scene: &Scene,
        progress: Option<&ProgressFn>,
        output: Output,
    ) -> Result<(Option<RgbaImage>, FrameReport)> {
        let grid = &model.grid;
        let origin = grid.display_origin();
        let isolines = self
            .iso
            .as_ref()
            .zip(scene.isolines.as_ref())
            .map(|((_, range), spec)| look::isolines(spec, *range));
        let style = look::style(
            scene,
            renderer.gpu.info.device_type,
            self.range,
            [origin[0], origin[1]],
            isolines,
        )?;
        let aspect = look::aspect(scene);
        self.find_extent(grid, model, scene, progress)?;
        let Some((_, extent)) = &self.extent else {
            return Err(surfaces::nothing_to_draw(grid, &self.options));
        };
        let framing = &extent.framing;
        let Some(bounds) = framing.bounds() else {
            return Err(surfaces::nothing_to_draw(grid, &self.options));
        };
        let camera = framing.camera(scene.camera.distance);
        let camera = match scene.camera.centre {
            Some([i, j]) => camera.centred_on(Vec3::from(column_top(
                grid,
                &self.options,
                [i - 1, j - 1],
                origin,
            )?)),
            None => camera,
        };
        let camera = look::aimed(scene, camera, origin);
        let view = look::view(scene, camera, bounds);
        // What a part shows: its faces not wholly off the picture, which would draw no
        // pixel. In a close-up most go, and most of the layers' faces are not even
        // built: only the columns in view are. A part wholly in the picture is drawn as
        // built. Side faces that turn their back stay (unlike a hierarchy's): at an
        // outline they may take a pixel, and the picture is the one mesh's.
        let columns = extent.columns_in_view(&view.camera, aspect);
        let in_view = |mesh: SurfaceMesh| match mesh.bounds() {
            Some(bounds) if surfaces::box_in_view(bounds, &view.camera, aspect) => mesh,
            _ => surfaces::faces_in_view(&mesh, &view.camera, aspect, false),
        };
        let wire = scene.wire.technique;
        let adjust = scene.isolines.as_ref().map(|iso| iso.adjust);
        let (mut drawn, mut triangles) = (0, 0);
        let count = self.parts.len();
        let mut done = 0;
        let mut queue = self.parts.iter();
        let (options, iso) = (&self.options, &self.iso);
        let faults = style.faults.is_some();
        // The outline's outer half, which the texture techniques draw, unless the
        // scene's side walls (a part of their own) go down from the whole outline.
        let wired = wire.draws_edges() && !options.sides;
        let ny = grid.dims().ny;
        // The fault traces, outline edges and silhouettes on a band's border with the
        // band before, which neither finds alone, drawn after the band.
        let mut border: Vec<Box<dyn strata_render::wire::Drawable>> = Vec::new();
        let image = renderer.render_parts_to(&view, &style, output, |r| -> Result<_> {
            if let Some(lines) = border.pop() {
                return Ok(Some(lines));
            }
            for part in queue.by_ref() {
                done += 1;
                if let Some(report) = progress {
                    report(Progress {
                        stage: Stage::Parts,
                        done,
                        total: count,
                    });
                }
                let build = |options| {
                    surfaces::build_part_on_all_cores(grid, options, part, origin, &columns)
                };
                let mesh = in_view(build(options)?);
                if mesh.triangle_count() == 0 {
                    continue;
                }
                // A band is cut from its layer along its first and last rows' lines.
                let mut cut_rows = Vec::new();
                if let Part::Band { layer, face, rows } = part {
                    cut_rows.extend(
                        [rows.start, rows.end]
                            .into_iter()
                            .filter(|&j| j > 0 && j < ny)
                            .map(|j| j as u32),
                    );
                    if rows.start > 0 && (faults || wired) {
                        let strip = Part::Band {
                            layer: *layer,
                            face: *face,
                            rows: rows.start - 1..rows.start + 1,
                        };
                        let strip = surfaces::build_part(grid, options, &strip, origin, &columns)?;
                        let line = rows.start as u32;
                        if faults {
                            let segments = fault_traces_across_row(&strip, line);
                            border.extend(r.prepare_fault_traces(&segments)?);
                        }
                        if wired {
                            let found = surface_edges(&strip);
                            let on_border = |along_i: bool, l: u32| along_i && l == line;
                            let edges: Vec<OutlineEdge> = found
                                .outline
                                .into_iter()
                                .filter(|e| on_border(e.along_i, e.line))
                                .collect();
                            let shared: Vec<InteriorEdge> = found
                                .interior
                                .into_iter()
                                .filter(|e| on_border(e.along_i, e.line))
                                .collect();
                            border.extend(r.prepare_border_edges(&edges, Some((&strip, &shared)))?);
                        }
                    }
                }
                drawn += 1;
                triangles += mesh.triangle_count();
                let drawable = match (iso, adjust) {
                    (Some((smooth_options, _)), Some(adjust)) => {
                        let smooth = in_view(build(smooth_options)?);
                        let field = corner_field(options, &smooth, &mesh)?;
                        let iso_options = IsolineOptions {
                            adjust,
                            wire: wire == WireMode::Global,
                        };
                        r.prepare_isolines_band(
                            &mesh,
                            Some(&field),
                            iso_options,
                            wired.then_some(&cut_rows),
                        )?
                    }
                    _ => r
                        .prepare_band(&mesh, wire, wired.then_some(&cut_rows))
                        .with_context(|| format!("preparing the {} wireframe", wire.name()))?,
                };
                return Ok(Some(drawable));
            }
            Ok(None)
        })?;
        let report = FrameReport {
            triangles,
            drawn: format!(
                "{triangles} triangles (of {} in the scene) in {drawn} of {count} parts",
                extent.triangles
            ),
            colouring: colouring(&self.options, style.scalar_range),
            coverage: style.coverage,
            view: Some((view, origin)),
            ..FrameReport::default()
        };
        Ok((image, report))
    }

    /// Holds the extent of the scene for `scene`'s view direction, picture shape and
    /// exaggeration: the one held already, or a new pass over the corners.
    fn find_extent(
        &mut self,
        grid: &CornerPointGrid,
        model: &Model,
        scene: &Scene,
        progress: Option<&ProgressFn>,
    ) -> Result<()> {
        let c = &scene.camera;
        let key = [c.azimuth, c.elevation, look::aspect(scene), c.z_scale];
        if self.extent.as_ref().is_none_or(|(held, _)| *held != key) {
            let origin = grid.display_origin();
            let framed = model.stray.as_ref().map(|s| s.rest.to_display(origin));
            let framing = look::framing(scene, framed);
            let extent = surfaces::scene_extent(grid, &self.options, origin, framing, progress)?;
            self.extent = Some((key, extent));
        }
        Ok(())
    }
}
