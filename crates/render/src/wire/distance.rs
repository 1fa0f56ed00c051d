//! `dist`: the single-pass wireframe of Bærentzen et al. ("Shader-Based Wireframe
//! Drawing", 2008; NVIDIA's SolidWireframe by Gateau, 2007). Each corner gets its
//! window-space distance to the opposite edge; interpolated without perspective
//! correction the minimum is the fragment's distance to the nearest edge, and the
//! line intensity is I(d) = exp2(-2 d²). A quad's diagonal is marked per triangle and
//! never drawn (Gateau's quad pattern); triangles with a corner behind the near plane
//! take Gateau's path, which passes the visible parts of the edges as window lines.
//!
//! The paper does the per-triangle work in a geometry shader, which wgpu lacks. Two
//! ways were measured on lavapipe, and the compute prepass was the faster on every
//! mesh (`docs/performance.md`, "Wireframe techniques"). Pulling (a non-indexed draw whose
//! vertex shader reads its whole triangle from storage) projects every corner three times
//! in llvmpipe's single-threaded vertex stage; the compute prepass kept here projects each
//! corner once, on the multi-threaded compute pool, and writes per corner its clip position
//! and distances (times w, see distance.wgsl) and per triangle Gateau's lines, which the
//! draw reads back. The hidden-line styles: TEHD and CEHD draw the polygons a second time
//! behind the visible surface (depth test "farther", no depth writes) with only their
//! edges, dashed; CEHS and CEHD keep the contour edges only, found per frame from the
//! vertex across each edge.

use std::sync::{Arc, Mutex, PoisonError};

use strata_grid::SurfaceMesh;

use super::lines::{
    EdgeTable, LazyPipelines, PassSpec, PulledMesh, TRIANGLE_RECORD_VERTICES, check_mesh, shader,
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

/// Layouts of group 1: the prepass's and the draw's.
struct Layouts {
    compute: wgpu::BindGroupLayout,
    draw: wgpu::BindGroupLayout,
}

/// The prepass pipelines, built on first use (without and with contours).
struct Prepass {
    device: wgpu::Device,
    layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    built: Mutex<[Option<wgpu::ComputePipeline>; 2]>,
}

impl Prepass {
    fn get(&self, contours: bool) -> wgpu::ComputePipeline {
        let mut built = self.built.lock().unwrap_or_else(PoisonError::into_inner);
        built[usize::from(contours)]
            .get_or_insert_with(|| {
                let constants = [("CONTOURS", f64::from(u8::from(contours)))];
                self.device
                    .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some("dist prepass"),
                        layout: Some(&self.layout),
                        module: &self.module,
                        entry_point: Some("cs_dist"),
                        compilation_options: wgpu::PipelineCompilationOptions {
                            constants: &constants,
                            ..Default::default()
                        },
                        cache: None,
                    })
            })
            .clone()
    }
}

fn buffer_entry(
    binding: u32,
    read_only: bool,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

pub struct DistTechnique {
    pipelines: Arc<LazyPipelines<Variant>>,
    prepass: Arc<Prepass>,
    layouts: Arc<Layouts>,
}

impl DistTechnique {
    pub fn new(ctx: &PipelineContext) -> Self {
        let device = &ctx.gpu.device;
        let layout = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        let (vertex, compute) = (wgpu::ShaderStages::VERTEX, wgpu::ShaderStages::COMPUTE);
        let layouts = Arc::new(Layouts {
            compute: layout(
                "dist prepass",
                &[
                    buffer_entry(0, true, compute),
                    buffer_entry(1, true, compute),
                    buffer_entry(2, true, compute),
                    buffer_entry(3, false, compute),
                ],
            ),
            draw: storage_layout(device, "dist after prepass", &[0, 1, 2, 4], vertex),
        });
        let module = shader(device, "dist", include_str!("distance.wgsl"));
        let prepass = Arc::new(Prepass {
            device: device.clone(),
            layout: device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("dist prepass"),
                bind_group_layouts: &[Some(ctx.frame_layout), Some(&layouts.compute)],
                immediate_size: 0,
            }),
            module: module.clone(),
            built: Mutex::new([None, None]),
        });
        let l = layouts.clone();
        let pipelines = LazyPipelines::new(ctx, move |v: Variant, device, frame_layout| {
            let group = [&l.draw];
            let constants = [("CONTOURS", f64::from(u8::from(v.contours)))];
            let fs = if v.hidden {
                "fs_dist_hidden"
            } else {
                "fs_dist"
            };
            let mut spec = PassSpec::new("dist", &module, "vs_dist_prepass", fs);
            spec.extra_layouts = &group;
            spec.constants = &constants;
            if v.hidden {
                spec.depth = Some((wgpu::CompareFunction::Less, false));
            }
            spec.build(device, frame_layout)
        });
        DistTechnique {
            pipelines,
            prepass,
            layouts,
        }
    }
}

impl Technique for DistTechnique {
    fn mode(&self) -> WireMode {
        WireMode::Dist
    }

    fn prepare(&self, gpu: &Gpu, mesh: &SurfaceMesh) -> Result<Box<dyn Drawable>> {
        check_mesh(mesh)?;
        let mut pulled = PulledMesh::new(gpu, mesh, "dist vertices")?;
        let records = triangle_records(mesh, &EdgeTable::new(mesh));
        let mut bytes = 0;
        let mut draws = Vec::new();
        // The prepass writes 8 vec4 per triangle: two per corner, two for Gateau's lines.
        pulled.for_each_chunk(gpu, &records, &TRIANGLE_RECORD_VERTICES, 128, |chunk| {
            let triangles = storage(gpu, "dist triangles", bytemuck::cast_slice(chunk.items))?;
            let corners = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("dist corners"),
                size: 128 * chunk.items.len() as u64,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            });
            bytes += triangles.size();
            let group = |label, layout, binding| {
                let own = [(2, &triangles), (binding, &corners)];
                chunk.bind_group(&gpu.device, label, layout, &own)
            };
            draws.push(Chunk {
                draw: group("dist", &self.layouts.draw, 4),
                compute: group("dist prepass", &self.layouts.compute, 3),
                triangles: chunk.items.len() as u32,
            });
            Ok(())
        })?;
        bytes += pulled.bytes();
        Ok(Box::new(DistDraw {
            pipelines: self.pipelines.clone(),
            prepass: self.prepass.clone(),
            draws,
            triangles: mesh.triangles.len(),
            bytes,
        }))
    }
}

/// One chunk of triangles: the bind groups of the prepass and of the draw.
struct Chunk {
    draw: wgpu::BindGroup,
    compute: wgpu::BindGroup,
    triangles: u32,
}

struct DistDraw {
    pipelines: Arc<LazyPipelines<Variant>>,
    prepass: Arc<Prepass>,
    draws: Vec<Chunk>,
    triangles: usize,
    bytes: u64,
}

impl Drawable for DistDraw {
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder) {
        let hidden = frame.style.hidden;
        let contours = hidden.contours_only();
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("dist prepass"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.prepass.get(contours));
            pass.set_bind_group(0, frame.frame_bind_group, &[]);
            for chunk in &self.draws {
                pass.set_bind_group(1, &chunk.compute, &[]);
                pass.dispatch_workgroups(chunk.triangles.div_ceil(64), 1, 1);
            }
        }
        let mut pass = frame.begin_pass(encoder, "dist");
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        // The visible surface first: the hidden pass tests against its depth.
        for dashed in [false, true] {
            if dashed && !hidden.dashed() {
                continue;
            }
            pass.set_pipeline(&self.pipelines.get(Variant {
                contours,
                hidden: dashed,
            }));
            for chunk in &self.draws {
                pass.set_bind_group(1, &chunk.draw, &[]);
                pass.draw(0..3 * chunk.triangles, 0..1);
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
