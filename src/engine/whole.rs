//! A scene drawn as one mesh, at full resolution or decimated: built once, framed
//! and drawn for each camera.

use strata_grid::SurfaceMesh;
use strata_grid::outline::outline_edges;
use strata_render::glam::Vec3;
use strata_render::image::RgbaImage;
use strata_render::wire::Drawable;
use strata_render::{IsolineOptions, Output, Renderer, WireMode};

use super::decimated::{self, Decimation};
use super::pick::{Pick, Ray, hit_cell};
use super::{FrameReport, Model, Note, look};
use crate::error::Context;
use crate::scene::{Lod, Scene};
use crate::surfaces::{self, SceneOptions, build, column_top};
use crate::{Error, Result};

/// One mesh of every drawn surface, on the GPU.
pub struct Whole {
    mesh: SurfaceMesh,
    options: SceneOptions,
    /// The range of the colouring property's values over the drawn cells.
    range: Option<(f32, f32)>,
    /// The range of the isoline field's values, when isolines are drawn.
    iso_range: Option<(f32, f32)>,
    drawable: Box<dyn Drawable>,
    /// On a decimated surface, the outer half of the original's outline.
    original_outline: Option<Box<dyn Drawable>>,
}

impl Whole {
    /// Builds the surfaces of `model` that `options` ask for (`scene`'s, see
    /// [`scene_options`]), decimated where the scene asks, and uploads them.
    pub fn build(
        renderer: &mut Renderer,
        model: &Model,
        scene: &Scene,
        options: SceneOptions,
    ) -> Result<(Self, Vec<Note>)> {
        let grid = &model.grid;
        let decimation = match &scene.lod {
            Lod::Decimated {
                percent,
                cover,
                stitch,
            } => Some(Decimation {
                percent: *percent,
                cover: *cover,
                stitch: *stitch,
            }),
            Lod::Full => None,
            Lod::Hierarchy { .. } => return Err(Error::scene("a hierarchy is not one mesh")),
        };
        let wire = technique(scene)?;
        if decimation.is_some_and(|d| d.cover) && wire != WireMode::Global {
            return Err(Error::scene(format!(
                "--cover draws with --wire global, not {}",
                wire.name()
            )));
        }
        let global = wire == WireMode::Global;
        // The global coordinates find the original's cells, their colours and
        // isolines, with or without the original's grid lines over them.
        let by_cells = global || wire == WireMode::None;
        let mut notes = Vec::new();
        // The outline's outer half (drawn by the texture techniques), unless side
        // walls go down from it: on a decimated surface, the original's.
        let outlined = wire.draws_edges() && !options.sides;
        let mut original_outline = Vec::new();
        let (mesh, range, mut cells) = match decimation {
            Some(decimation) => {
                let (surfaces, stacked) = surfaces::build_stacked_surfaces(grid, &options)?;
                if outlined {
                    original_outline = surfaces[..stacked].iter().flat_map(outline_edges).collect();
                }
                let origin = surfaces.first().map_or([0.0; 3], |s| s.origin);
                let framed = model.stray.as_ref().map(|s| s.rest.to_display(origin));
                let decimated = decimated::decimate_scene(
                    renderer,
                    (&surfaces, stacked, framed),
                    &decimation,
                    scene.camera.z_scale,
                    by_cells,
                    &mut notes,
                )?;
                let range = surfaces::colour_range_of(grid, &options)?;
                (decimated.0, range, decimated.1)
            }
            None => {
                let (mesh, range) = build(grid, &options)?;
                (mesh, range, None)
            }
        };
        if decimation.is_some() && !mesh.scalars.is_empty() && !by_cells {
            notes.push(Note::Note(format!(
                "with --wire {}, colours are interpolated between the decimated surface's \
                 nodes; --wire global or none colours each cell as the original does",
                wire.name()
            )));
        }
        // Isolines follow the property interpolated between nodes, whatever colours
        // the cells: one value per triangle corner of `mesh`, or on a decimated
        // surface the original's values at its cells' corners.
        let mut field = None;
        let iso_range =
            match scene.isolines.as_ref() {
                Some(iso) => {
                    let name = iso
                        .property
                        .as_deref()
                        .ok_or_else(|| Error::scene("--iso: which property's isolines?"))?;
                    let (smooth_options, iso_range) = field_options(model, &options, name)?;
                    let (smooth, _) = build(grid, &smooth_options)?;
                    match (&mut cells, decimation) {
                        (Some(cells), Some(_)) => {
                            cells.corners =
                                Some(cells.cover.corner_values(&smooth).context(
                                    "the original's isoline field at the cells' corners",
                                )?);
                        }
                        (None, Some(_)) => {
                            return Err(Error::scene("--lod with --iso needs the scene's cells"));
                        }
                        (_, None) => field = Some(corner_field(&options, &smooth, &mesh)?),
                    }
                    Some(iso_range)
                }
                None => None,
            };
        let adjust = scene.isolines.as_ref().map(|iso| iso.adjust);
        let outline: Option<&[u32]> = outlined.then_some(&[]);
        let drawable = match (&cells, &field, adjust) {
            (Some(cells), _, _) => renderer
                .prepare_cells(&mesh, &cells.draw(global))
                .context("preparing the global wireframe over the original's cells")?,
            (None, Some(field), Some(adjust)) => renderer.prepare_isolines_band(
                &mesh,
                Some(field),
                IsolineOptions {
                    adjust,
                    wire: global,
                },
                outline,
            )?,
            _ => renderer
                .prepare_band(&mesh, wire, outline)
                .with_context(|| format!("preparing the {} wireframe", wire.name()))?,
        };
        let original_outline = renderer
            .prepare_outline_edges(&original_outline)
            .context("preparing the original's outline")?;
        let whole = Whole {
            mesh,
            options,
            range,
            iso_range,
            drawable,
            original_outline,
        };
        Ok((whole, notes))
    }

    /// The cell `ray` meets first, and where.
    pub fn pick(&self, ray: &Ray, model: &Model) -> Option<Pick> {
        let hit = ray.nearest(&self.mesh)?;
        let point = ray.map_point(hit.distance, self.mesh.origin);
        let nz = model.grid.dims().nz;
        let layers = self
            .options
            .layers
            .as_ref()
            .map_or([0, nz.saturating_sub(1)], |r| {
                [r.start, r.end.saturating_sub(1)]
            });
        let cell = hit_cell(&self.mesh, &hit, point[2], &model.grid, layers)?;
        Some(Pick { cell, point })
    }

    /// What the cells are coloured by: see [`SceneOptions`].
    pub fn options(&self) -> &SceneOptions {
        &self.options
    }

    /// The property colouring the cells and its range over them.
    pub fn colouring(&self) -> Option<(String, (f32, f32))> {
        colouring(&self.options, self.range)
    }

    /// Frames the mesh as `scene`'s camera sees it and draws it.
    pub fn draw(
        &self,
        renderer: &mut Renderer,
        model: Option<&Model>,
        scene: &Scene,
        output: Output,
    ) -> Result<(Option<RgbaImage>, FrameReport)> {
        let mesh = &self.mesh;
        let stray = model.and_then(|m| m.stray.as_ref());
        let mut framing = look::framing(scene, stray.map(|s| s.rest.to_display(mesh.origin)));
        framing.add(mesh.positions.iter().map(|&p| Vec3::from(p)));
        let bounds = framing
            .bounds()
            .ok_or_else(|| Error::scene("empty scene"))?;
        let camera = framing.camera(scene.camera.distance);
        let camera = match (scene.camera.centre, model) {
            (Some([i, j]), Some(model)) => camera.centred_on(Vec3::from(column_top(
                &model.grid,
                &self.options,
                [i - 1, j - 1],
                mesh.origin,
            )?)),
            _ => camera,
        };
        let camera = look::aimed(scene, camera, mesh.origin);
        let view = look::view(scene, camera, bounds);
        let isolines = match (&scene.isolines, self.iso_range) {
            (Some(spec), Some(range)) => Some(look::isolines(spec, range)),
            _ => None,
        };
        let style = look::style(
            scene,
            renderer.gpu.info.device_type,
            self.range,
            [mesh.origin[0], mesh.origin[1]],
            isolines,
        )?;
        let drawables: Vec<&dyn Drawable> = std::iter::once(self.drawable.as_ref())
            .chain(self.original_outline.as_deref())
            .collect();
        let image = renderer.render_to(&drawables, &view, &style, output)?;
        let report = FrameReport {
            triangles: mesh.triangle_count(),
            drawn: format!("{} triangles", mesh.triangle_count()),
            colouring: colouring(&self.options, style.scalar_range),
            coverage: style.coverage,
            view: Some((view, mesh.origin)),
            ..FrameReport::default()
        };
        Ok((image, report))
    }
}

/// The property and range a frame's colours span, for its report.
pub fn colouring(
    options: &SceneOptions,
    range: Option<(f32, f32)>,
) -> Option<(String, (f32, f32))> {
    Some((options.property.clone()?, range?))
}

/// The wireframe technique of `scene`: any but quad on decimated surfaces, whose
/// per-face coordinates need the model's cell faces.
pub fn technique(scene: &Scene) -> Result<WireMode> {
    let wire = scene.wire.technique;
    let what = match scene.lod {
        Lod::Full => return Ok(wire),
        Lod::Decimated { .. } => "--lod",
        Lod::Hierarchy { .. } => "lod view",
    };
    if wire == WireMode::Quad {
        return Err(Error::scene(format!(
            "{what} draws decimated surfaces, which have no cell faces for --wire quad's \
             per-face coordinates: --wire global draws the model's cell lines on them, \
             --wire tex their own triangles"
        )));
    }
    Ok(wire)
}

/// Which surfaces of `model` `scene` draws, checked: layers within the model, a
/// property it has, isolines drawn with a technique that can.
pub fn scene_options(model: &Model, scene: &Scene) -> Result<SceneOptions> {
    let grid = &model.grid;
    let colour = &scene.colour;
    let property = model.colouring_property(colour.property.as_deref(), colour.solid);
    if let Some(name) = &property
        && grid.property(name).is_none()
    {
        return Err(Error::scene(format!(
            "{}: no property {name}",
            model.source.path.display()
        )));
    }
    let wire = scene.wire.technique;
    if scene.isolines.is_some() && !matches!(wire, WireMode::Global | WireMode::None) {
        return Err(Error::scene(format!(
            "--iso draws with --wire global or none, not {}",
            wire.name()
        )));
    }
    let d = grid.dims();
    Ok(SceneOptions {
        cut: scene.cut([d.nx, d.ny])?,
        inactive: scene.inactive,
        layers: scene.layer_range(d.nz)?,
        sides: scene.sides,
        property,
        flat_cells: !colour.smooth && scene.lod == Lod::Full,
    })
}

/// The scene `options` asks for with property `name` averaged onto its nodes, whose
/// values are then the isoline field, and the range of its defined values.
pub fn field_options(
    model: &Model,
    options: &SceneOptions,
    name: &str,
) -> Result<(SceneOptions, (f32, f32))> {
    let grid = &model.grid;
    if grid.property(name).is_none() {
        return Err(Error::scene(format!(
            "--iso: the model has no property {name}"
        )));
    }
    let smooth_options = SceneOptions {
        property: Some(name.to_string()),
        flat_cells: false,
        ..options.clone()
    };
    let range = surfaces::colour_range_of(grid, &smooth_options)?
        .ok_or_else(|| Error::scene(format!("--iso: {name} has no defined value here")))?;
    Ok((smooth_options, range))
}

/// The isoline field of `smooth` (the scene of [`field_options`]) per triangle corner
/// of `mesh`, the same surfaces built with `options`.
pub fn corner_field(
    options: &SceneOptions,
    smooth: &SurfaceMesh,
    mesh: &SurfaceMesh,
) -> Result<Vec<f32>> {
    let cell_painted = options.flat_cells && options.property.is_some();
    let field = surfaces::corner_field(smooth, cell_painted);
    if field.len() != 3 * mesh.triangle_count() {
        return Err(Error::scene(format!(
            "--iso: {} isoline values for {} triangles",
            field.len(),
            mesh.triangle_count()
        )));
    }
    Ok(field)
}
