//! `dist`: the single-pass wireframe of Bærentzen et al. ("Shader-Based Wireframe
//! Drawing", 2008; NVIDIA's SolidWireframe by Gateau, 2007). Each corner gets its
//! window-space distance to the opposite edge; interpolated without perspective
//! correction the minimum is the fragment's distance to the nearest edge, and the
//! line intensity is I(d) = exp2(-2 d²). A quad's diagonal is marked per triangle and
//! never drawn (Gateau's quad pattern); triangles with a corner behind the near plane
//! take Gateau's path, which passes the visible parts of the edges as window lines.
//!
//! The paper does the per-triangle work in a geometry shader, which wgpu lacks: here
//! the vertex shader pulls its whole triangle from storage buffers (a non-indexed draw
//! of 3 T vertices). The hidden-line styles: TEHD and CEHD draw the polygons a second
//! time behind the visible surface (depth test "farther", no depth writes) with only
//! their edges, dashed; CEHS and CEHD keep the contour edges only, found per frame
//! from the vertex across each edge.

use std::rc::Rc;

use strata_grid::SurfaceMesh;

use super::lines::{
    EdgeTable, LazyPipelines, PassSpec, PulledVertices, bind_buffers, check_mesh, chunks, shader,
    storage, storage_layout, triangle_records,
};
use super::{Drawable, FrameTargets, PipelineContext, Technique, WireMode};
use crate::{Gpu, HiddenLines, Result};

/// Which pipeline: contour edges only, and the hidden (dashed) pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct Variant {
    contours: bool,
    hidden: bool,
}

pub struct DistTechnique {
    pipelines: Rc<LazyPipelines<Variant>>,
    layout: wgpu::BindGroupLayout,
}

impl DistTechnique {
    pub fn new(ctx: &PipelineContext) -> Self {
        let device = &ctx.gpu.device;
        let layout = storage_layout(device, "dist", &[0, 1, 2], wgpu::ShaderStages::VERTEX);
        let module = shader(device, "dist", include_str!("distance.wgsl"));
        let pipeline_layout = layout.clone();
        let pipelines = LazyPipelines::new(ctx, move |v: Variant, device, frame_layout| {
            let layouts = [&pipeline_layout];
            let constants = [("CONTOURS", f64::from(u8::from(v.contours)))];
            let fs = if v.hidden {
                "fs_dist_hidden"
            } else {
                "fs_dist"
            };
            let mut spec = PassSpec::new("dist", &module, "vs_dist", fs);
            spec.extra_layouts = &layouts;
            spec.constants = &constants;
            if v.hidden {
                spec.depth = Some((wgpu::CompareFunction::Less, false));
            }
            spec.build(device, frame_layout)
        });
        DistTechnique { pipelines, layout }
    }
}

impl Technique for DistTechnique {
    fn mode(&self) -> WireMode {
        WireMode::Dist
    }

    fn prepare(&self, gpu: &Gpu, mesh: &SurfaceMesh) -> Result<Box<dyn Drawable>> {
        check_mesh(mesh)?;
        let vertices = PulledVertices::new(gpu, mesh, "dist vertices")?;
        let records = triangle_records(mesh, &EdgeTable::new(mesh));
        let mut bytes = vertices.bytes();
        let mut draws = Vec::new();
        for range in chunks(gpu, records.len(), 32) {
            let triangles = storage(
                gpu,
                "dist triangles",
                bytemuck::cast_slice(&records[range.clone()]),
            )?;
            bytes += triangles.size();
            let group = bind_buffers(
                &gpu.device,
                "dist",
                &self.layout,
                &[
                    (0, &vertices.positions),
                    (1, &vertices.scalars),
                    (2, &triangles),
                ],
            );
            draws.push((group, 3 * range.len() as u32));
        }
        Ok(Box::new(DistDraw {
            pipelines: self.pipelines.clone(),
            draws,
            triangles: mesh.triangles.len(),
            bytes,
        }))
    }
}

struct DistDraw {
    pipelines: Rc<LazyPipelines<Variant>>,
    /// Per chunk of triangles: its bind group and vertex count.
    draws: Vec<(wgpu::BindGroup, u32)>,
    triangles: usize,
    bytes: u64,
}

impl Drawable for DistDraw {
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder) {
        let hidden = frame.style.hidden;
        let mut pass = frame.begin_pass(encoder, "dist");
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        // The visible surface first: the hidden pass tests against its depth.
        for dashed in [false, true] {
            if dashed && !hidden.dashed() {
                continue;
            }
            pass.set_pipeline(&self.pipelines.get(Variant {
                contours: hidden.contours_only(),
                hidden: dashed,
            }));
            for (group, count) in &self.draws {
                pass.set_bind_group(1, group, &[]);
                pass.draw(0..*count, 0..1);
            }
        }
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
}
