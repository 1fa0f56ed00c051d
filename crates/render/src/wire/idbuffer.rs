//! `idbuffer`: the ID-buffer method of Bærentzen et al. ("Shader-Based Wireframe
//! Drawing", 2008, section 3), the general one of their two: lines are decoupled from
//! polygon rasterization, so it draws the outer half of silhouette and outline edges
//! that the single-pass methods (theirs and the texture ones) cannot.
//!
//! 1. the polygons (a cell face's two triangles are one polygon) write their ID and
//!    depth into an ID buffer (and the frame's depth);
//! 2. every real edge is drawn as a screen-aligned quad; a fragment keeps the
//!    prefiltered intensity I(d) = exp2(-2 d²) of its distance to the segment when the
//!    ID under it is one of the edge's polygons or its depth passes the test (the
//!    silhouette case), max-blended into a line buffer;
//! 3. the polygons are shaded with the depth test "equal", mixing in the line buffer,
//!    and a window-filling pass blends the lines' outer halves over the background.
//!
//! The paper draws each polygon's edges once per polygon with its own ID; here each
//! edge is drawn once carrying both its polygons' IDs, which keeps the same fragments
//! (the max blend of two equal intensities is one of them) with half the quads.
//! Per-triangle data comes by vertex pulling. Hidden-line styles: in TEHD/CEHD the
//! fragments that fail both tests go, dashed, to a second channel of the line buffer
//! that shading mixes under the visible lines; CEHS/CEHD keep contour edges only.

use std::cell::RefCell;
use std::sync::Arc;

use strata_grid::SurfaceMesh;

use super::lines::{
    EDGE_VERTICES, EdgeTable, LazyPipelines, PassSpec, PulledMesh, TRIANGLE_RECORD_VERTICES,
    check_mesh, shader, storage, storage_layout, triangle_records,
};
use super::{Drawable, FrameTargets, PipelineContext, Technique, WireMode, frame_target};
use crate::renderer::frame_texture;
use crate::{Gpu, HiddenLines, Result};

/// Polygon ID plus one, and the polygon's depth bits.
const ID_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;
/// r: visible line intensity, g: hidden line intensity.
const LINE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg8Unorm;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Pass {
    Id,
    Edges { contours: bool, hidden: bool },
    Shade,
    Window,
}

/// The bind group layouts beyond the frame's.
struct Layouts {
    /// Group 1 of the polygon passes: positions, scalars, triangles.
    polygons: wgpu::BindGroupLayout,
    /// Group 1 of the edge pass: positions, scalars, edges.
    edges: wgpu::BindGroupLayout,
    /// Group 2 of the edge pass: the ID buffer.
    tests: wgpu::BindGroupLayout,
    /// Group 2 of shading: the line buffer.
    lines: wgpu::BindGroupLayout,
}

pub struct IdBufferTechnique {
    pipelines: Arc<LazyPipelines<Pass>>,
    layouts: Arc<Layouts>,
}

fn texture_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

impl IdBufferTechnique {
    pub fn new(ctx: &PipelineContext) -> Self {
        let device = &ctx.gpu.device;
        let vertex = wgpu::ShaderStages::VERTEX;
        let texture_layout = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        let layouts = Arc::new(Layouts {
            polygons: storage_layout(device, "idbuffer polygons", &[0, 1, 2], vertex),
            edges: storage_layout(device, "idbuffer edges", &[0, 1, 3], vertex),
            tests: texture_layout(
                "idbuffer tests",
                &[texture_entry(0, wgpu::TextureSampleType::Uint)],
            ),
            lines: texture_layout(
                "idbuffer lines",
                &[texture_entry(
                    2,
                    wgpu::TextureSampleType::Float { filterable: false },
                )],
            ),
        });
        let module = shader(device, "idbuffer", include_str!("idbuffer.wgsl"));
        let l = layouts.clone();
        let pipelines = LazyPipelines::new(ctx, move |pass: Pass, device, frame_layout| {
            let (contours, hidden) = match pass {
                Pass::Edges { contours, hidden } => (contours, hidden),
                _ => (false, false),
            };
            let constants = [
                ("CONTOURS", f64::from(u8::from(contours))),
                ("HIDDEN", f64::from(u8::from(hidden))),
            ];
            let id_layouts = [&l.polygons];
            let edge_layouts = [&l.edges, &l.tests];
            let shade_layouts = [&l.polygons, &l.lines];
            let mut spec = match pass {
                Pass::Id => {
                    let mut spec = PassSpec::new("idbuffer ids", &module, "vs_poly", "fs_id");
                    spec.extra_layouts = &id_layouts;
                    spec.targets = vec![Some(ID_FORMAT.into())];
                    spec
                }
                Pass::Edges { .. } => {
                    let mut spec = PassSpec::new("idbuffer edges", &module, "vs_edge", "fs_edge");
                    spec.extra_layouts = &edge_layouts;
                    spec.depth = None;
                    let max = wgpu::BlendComponent {
                        src_factor: wgpu::BlendFactor::One,
                        dst_factor: wgpu::BlendFactor::One,
                        operation: wgpu::BlendOperation::Max,
                    };
                    spec.targets = vec![Some(wgpu::ColorTargetState {
                        format: LINE_FORMAT,
                        blend: Some(wgpu::BlendState {
                            color: max,
                            alpha: max,
                        }),
                        write_mask: wgpu::ColorWrites::ALL,
                    })];
                    spec
                }
                Pass::Shade => {
                    let mut spec = PassSpec::new("idbuffer shade", &module, "vs_poly", "fs_shade");
                    spec.extra_layouts = &shade_layouts;
                    spec.depth = Some((wgpu::CompareFunction::Equal, false));
                    spec
                }
                Pass::Window => {
                    let mut spec =
                        PassSpec::new("idbuffer window", &module, "vs_window", "fs_window");
                    spec.extra_layouts = &shade_layouts;
                    spec.depth = Some((wgpu::CompareFunction::Equal, false));
                    spec.targets = vec![frame_target(super::lines::BLEND_OVER)];
                    spec
                }
            };
            spec.constants = &constants;
            spec.build(device, frame_layout)
        });
        IdBufferTechnique { pipelines, layouts }
    }
}

impl Technique for IdBufferTechnique {
    fn mode(&self) -> WireMode {
        WireMode::IdBuffer
    }

    fn prepare(&self, gpu: &Gpu, mesh: &SurfaceMesh) -> Result<Box<dyn Drawable>> {
        check_mesh(mesh)?;
        let device = &gpu.device;
        let mut pulled = PulledMesh::new(gpu, mesh, "idbuffer vertices")?;
        let table = EdgeTable::new(mesh);
        let records = triangle_records(mesh, &table);
        let polygon = |t: u32| records.get(t as usize).map_or(0, |r| r[7] + 1);
        // Per edge, the two records of `edges` in idbuffer.wgsl: the edge, then the
        // polygons on either side.
        let edges: Vec<[u32; 8]> = table
            .edges
            .iter()
            .zip(&table.triangles)
            .map(|(e, t)| [e[0], e[1], e[2], e[3], polygon(t[0]), polygon(t[1]), 0, 0])
            .collect();
        let mut bytes = 0;
        let mut polygons = Vec::new();
        pulled.for_each_chunk(gpu, &records, &TRIANGLE_RECORD_VERTICES, 32, |chunk| {
            let triangles = storage(gpu, "idbuffer triangles", bytemuck::cast_slice(chunk.items))?;
            bytes += triangles.size();
            let group = chunk.bind_group(
                device,
                "idbuffer polygons",
                &self.layouts.polygons,
                &[(2, &triangles)],
            );
            polygons.push((group, 3 * chunk.items.len() as u32));
            Ok(())
        })?;
        let mut lines = Vec::new();
        pulled.for_each_chunk(gpu, &edges, &EDGE_VERTICES, 32, |chunk| {
            let buffer = storage(gpu, "idbuffer edges", bytemuck::cast_slice(chunk.items))?;
            bytes += buffer.size();
            let group = chunk.bind_group(
                device,
                "idbuffer edges",
                &self.layouts.edges,
                &[(3, &buffer)],
            );
            lines.push((group, 6 * chunk.items.len() as u32));
            Ok(())
        })?;
        bytes += pulled.bytes();
        Ok(Box::new(IdBufferDraw {
            device: device.clone(),
            pipelines: self.pipelines.clone(),
            layouts: self.layouts.clone(),
            polygons,
            lines,
            triangles: mesh.triangles.len(),
            bytes,
            targets: RefCell::new(None),
        }))
    }
}

/// The ID and line buffers, at the frame's size.
struct IdTargets {
    size: (u32, u32),
    ids: wgpu::TextureView,
    ids_group: wgpu::BindGroup,
    lines: wgpu::TextureView,
    lines_group: wgpu::BindGroup,
}

struct IdBufferDraw {
    device: wgpu::Device,
    pipelines: Arc<LazyPipelines<Pass>>,
    layouts: Arc<Layouts>,
    /// Per chunk of triangles: bind group and vertex count.
    polygons: Vec<(wgpu::BindGroup, u32)>,
    /// Per chunk of edges: bind group and vertex count.
    lines: Vec<(wgpu::BindGroup, u32)>,
    triangles: usize,
    bytes: u64,
    targets: RefCell<Option<IdTargets>>,
}

impl IdBufferDraw {
    /// The ID and line buffers for a `width` x `height` frame, made on first use and
    /// when the frame size changes.
    fn targets(&self, width: u32, height: u32) -> std::cell::RefMut<'_, Option<IdTargets>> {
        let mut targets = self.targets.borrow_mut();
        if targets.as_ref().is_none_or(|t| t.size != (width, height)) {
            let texture = |label, format| {
                let usage =
                    wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
                frame_texture(&self.device, label, (width, height), format, usage)
                    .create_view(&Default::default())
            };
            let ids = texture("idbuffer ids", ID_FORMAT);
            let lines = texture("idbuffer lines", LINE_FORMAT);
            let group = |label, layout, binding, view| {
                self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(label),
                    layout,
                    entries: &[wgpu::BindGroupEntry {
                        binding,
                        resource: wgpu::BindingResource::TextureView(view),
                    }],
                })
            };
            *targets = Some(IdTargets {
                size: (width, height),
                ids_group: group("idbuffer ids", &self.layouts.tests, 0, &ids),
                lines_group: group("idbuffer lines", &self.layouts.lines, 2, &lines),
                ids,
                lines,
            });
        }
        targets
    }
}

/// A render pass that clears `view` to zero, with the frame's depth when given.
fn clearing_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
    depth: Option<&wgpu::TextureView>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: depth.map(|view| wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

impl Drawable for IdBufferDraw {
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder) {
        let hidden = frame.style.hidden;
        let targets = self.targets(frame.width, frame.height);
        let Some(targets) = targets.as_ref() else {
            return;
        };
        {
            let mut pass = clearing_pass(encoder, "idbuffer ids", &targets.ids, Some(frame.depth));
            pass.set_pipeline(&self.pipelines.get(Pass::Id));
            pass.set_bind_group(0, frame.frame_bind_group, &[]);
            for (group, count) in &self.polygons {
                pass.set_bind_group(1, group, &[]);
                pass.draw(0..*count, 0..1);
            }
        }
        {
            let mut pass = clearing_pass(encoder, "idbuffer edges", &targets.lines, None);
            pass.set_pipeline(&self.pipelines.get(Pass::Edges {
                contours: hidden.contours_only(),
                hidden: hidden.dashed(),
            }));
            pass.set_bind_group(0, frame.frame_bind_group, &[]);
            pass.set_bind_group(2, &targets.ids_group, &[]);
            for (group, count) in &self.lines {
                pass.set_bind_group(1, group, &[]);
                pass.draw(0..*count, 0..1);
            }
        }
        let mut pass = frame.begin_pass(encoder, "idbuffer shade");
        pass.set_pipeline(&self.pipelines.get(Pass::Shade));
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        pass.set_bind_group(2, &targets.lines_group, &[]);
        for (group, count) in &self.polygons {
            pass.set_bind_group(1, group, &[]);
            pass.draw(0..*count, 0..1);
        }
        pass.set_pipeline(&self.pipelines.get(Pass::Window));
        pass.draw(0..3, 0..1);
    }

    fn triangles(&self) -> usize {
        self.triangles
    }

    fn bytes(&self) -> u64 {
        self.bytes
    }

    fn supports(&self, _: HiddenLines) -> bool {
        true
    }

    fn draws_alone(&self) -> bool {
        WireMode::IdBuffer.draws_alone()
    }
}
