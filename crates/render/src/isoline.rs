//! Isolines of a scalar field (Celes & Abraham 2011 section 6, Figs. 13b-15; 2010
//! section V, Figs. 10-12): the field goes through a texture matrix to the coordinate
//! `s = 2 (f - offset) / spacing + 1`, odd on the isolines, and the wireframe texture
//! draws them with the wireframe's thickness in pixels. Every fragment path draws them
//! from its interpolated scalar (`extra_lines` in wire/common.wgsl); this module adds
//! the paper's range adjust, which needs the three corner values of each triangle.
//!
//! # The range adjust, and which paper's formula
//!
//! Where the field's gradient is small, a coordinate unit spans more pixels than the
//! texture has texels and the texture is magnified: lines thicken (Fig. 14c). The
//! papers fix it per triangle (a geometry shader): when the range `[m, M]` of the
//! three coordinates holds exactly one line, they scale the coordinates so that the
//! range becomes one period. wgpu has no geometry shader, so here a compute prepass
//! over triangles writes three adjusted coordinates per triangle into a per-corner
//! buffer that a de-indexed draw reads as a vertex attribute.
//!
//! The two papers print different pivots for that scale. With the lines at the
//! integers (the papers' texture), the range holds exactly one line when
//! `floor(M) - floor(m) == 1`, and that line is `u = fM = floor(M)`. An affine map
//! `u' = (u - p) / range + p` leaves only its pivot `p` where it was: a fragment is
//! on the line after the adjust when `u' = fM`, i.e. at `u = p + (fM - p) range`.
//! With the 2010 pivot `p = fM` that is `u = fM`: the isoline stays at its value.
//! With the 2011 journal's `p = fm` it is `u = fm + range`, which is the isoline's
//! value only when the range is exactly 1: the line moves by `(1 - range)` units
//! towards the triangle's minimum corner, by a different amount in every triangle, so
//! the drawn line is neither at its value nor continuous across triangle edges. The
//! 2010 formula (`fM`) is right; the 2011 one is a misprint. `tests::papers_formulas`
//! checks this on the prepass itself, and tests/isolines.rs measures the displacement
//! in images.
//!
//! strata's adjust ([`RangeAdjust::On`]) keeps the 2010 pivot and chooses the factor
//! from the triangle's gradient on screen (the prepass runs every frame): just enough
//! to stop magnification, never putting a corner more than half a period from the
//! line, never below 1. The reasons are in `adjust_to_view` (isoline.wgsl).
//!
//! # Two fixes for one problem
//!
//! `coverage_texture` (wire/common.wgsl) already keeps the width below level 0 by
//! rescaling the distance to the line per fragment, which is the same scale-around-
//! the-line done per pixel with the exact gradient; the fragment paths rely on it and
//! need no prepass. This technique samples the texture as the paper does, never finer
//! than level 0, so that the adjust is what keeps the width: with
//! [`RangeAdjust::Off`] the lines thicken where the field is flat (measured in
//! tests/isolines.rs, to several times their width; `docs/performance.md`), with
//! [`RangeAdjust::On`] they do not.

use bytemuck::{Pod, Zeroable};
use strata_grid::SurfaceMesh;
use wgpu::util::DeviceExt;

use crate::wire::{Drawable, FrameTargets, PipelineContext, PipelineRequest, chunks, pipeline};
use crate::{Error, Gpu, Result};

/// The value written for an undefined scalar (see `UNDEFINED_SCALAR` in common.wgsl).
const UNDEFINED_SCALAR: f32 = -3.0e38;

/// Which isolines to draw and how they look.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Isolines {
    /// Field difference between neighbouring lines.
    pub spacing: f32,
    /// A field value on a line (a major one when `major_every` > 1).
    pub offset: f32,
    /// Every `major_every`-th line, counted from `offset`, is major (full opacity; the
    /// others are drawn at half). 0 or 1: all lines alike.
    pub major_every: u32,
    /// Line colour; alpha scales the coverage of major lines.
    pub color: [f32; 4],
}

impl Isolines {
    /// Lines every `spacing`, through 0, every fifth one major, near black.
    pub fn new(spacing: f32) -> Self {
        Isolines {
            spacing,
            offset: 0.0,
            major_every: 5,
            color: [0.02, 0.02, 0.02, 1.0],
        }
    }

    /// `None` unless the spacing is positive and finite and the offset finite.
    pub(crate) fn validate(&self) -> Option<()> {
        (self.spacing > 0.0 && self.spacing.is_finite() && self.offset.is_finite()).then_some(())
    }

    /// The frame uniform `iso`: (2 / spacing, offset, major_every, 1).
    pub(crate) fn uniform(&self) -> [f32; 4] {
        [
            2.0 / self.spacing,
            self.offset,
            self.major_every as f32,
            1.0,
        ]
    }

    /// The value of the isoline with index `k` (0 at `offset`).
    pub fn value(&self, k: i64) -> f32 {
        self.offset + k as f32 * self.spacing
    }
}

/// The per-triangle range adjust of the isoline coordinates (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum RangeAdjust {
    /// Coordinates straight from the texture matrix: where the field is nearly flat
    /// the texture is magnified and lines thicken (the paper's Fig. 14c).
    Off,
    /// strata's: the 2010 pivot, a factor from the gradient on screen.
    #[default]
    On,
    /// The 2010 paper's formula as printed (pivot fM, range scaled to one period).
    Paper2010,
    /// The 2011 journal's formula as printed (pivot fm): moves isolines off their
    /// values; kept to show it.
    Paper2011,
}

impl RangeAdjust {
    /// Every adjust with its command-line name.
    pub const ALL: [(&'static str, RangeAdjust); 4] = [
        ("off", RangeAdjust::Off),
        ("on", RangeAdjust::On),
        ("paper2010", RangeAdjust::Paper2010),
        ("paper2011", RangeAdjust::Paper2011),
    ];

    /// The adjust named `name`, ignoring case.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|&(_, a)| a)
    }

    fn code(self) -> u32 {
        match self {
            RangeAdjust::Off => 0,
            RangeAdjust::On => 1,
            RangeAdjust::Paper2010 => 2,
            RangeAdjust::Paper2011 => 3,
        }
    }
}

/// How a mesh is drawn by the isoline technique.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IsolineOptions {
    /// How the per-triangle range adjust keeps isolines thin where the field is flat.
    pub adjust: RangeAdjust,
    /// Also draw the wireframe of the global coordinates (cell edges of layers).
    pub wire: bool,
}

/// One corner of the de-indexed mesh: position, global coordinates, colour scalar,
/// isoline field.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Corner {
    position: [f32; 3],
    uv: [f32; 2],
    scalar: f32,
    field: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Params {
    mode: u32,
    triangles: u32,
    row: u32,
    pad: u32,
}

const WORKGROUP: u32 = 64;

/// The isoline pipelines: the adjust prepass and the draws with and without wire.
pub(crate) struct IsolineTechnique {
    adjust: wgpu::ComputePipeline,
    draw_wire: wgpu::RenderPipeline,
    draw_plain: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

fn shader(device: &wgpu::Device) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("isolines"),
        source: wgpu::ShaderSource::Wgsl(
            concat!(
                include_str!("wire/common.wgsl"),
                include_str!("isoline.wgsl")
            )
            .into(),
        ),
    })
}

const CORNER_ATTRIBUTES: [wgpu::VertexAttribute; 3] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x2, 2 => Float32];
const S_ATTRIBUTES: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![3 => Float32];

impl IsolineTechnique {
    pub(crate) fn new(ctx: &PipelineContext) -> Self {
        let device = &ctx.gpu.device;
        let storage = |binding, read_only| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("isoline prepass"),
            entries: &[
                storage(0, true),
                storage(1, false),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        let module = shader(device);
        let compute_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("isoline prepass"),
            bind_group_layouts: &[Some(ctx.frame_layout), Some(&layout)],
            immediate_size: 0,
        });
        let adjust = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("isoline range adjust"),
            layout: Some(&compute_layout),
            module: &module,
            entry_point: Some("cs_adjust"),
            compilation_options: Default::default(),
            cache: None,
        });
        let buffers = [
            Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Corner>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &CORNER_ATTRIBUTES,
            }),
            Some(wgpu::VertexBufferLayout {
                array_stride: 4,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &S_ATTRIBUTES,
            }),
        ];
        let draw_wire = pipeline(
            ctx,
            &PipelineRequest {
                buffers: &buffers,
                ..PipelineRequest::new("isolines + wire", &module, ("vs_iso", "fs_iso_wire"))
            },
        );
        let draw_plain = pipeline(
            ctx,
            &PipelineRequest {
                buffers: &buffers,
                ..PipelineRequest::new("isolines", &module, ("vs_iso", "fs_iso"))
            },
        );
        IsolineTechnique {
            adjust,
            draw_wire,
            draw_plain,
            layout,
        }
    }

    /// Uploads `mesh` de-indexed. `field` holds the isoline field per triangle corner
    /// (3 per triangle, in triangle order); `None` takes `mesh.scalars` (0 where the
    /// mesh has none). Colours come from `mesh.scalars` either way.
    pub(crate) fn prepare(
        &self,
        gpu: &Gpu,
        mesh: &SurfaceMesh,
        field: Option<&[f32]>,
        options: IsolineOptions,
    ) -> Result<IsolineDraw> {
        if mesh.triangles.is_empty() {
            return Err(Error::Invalid(
                "nothing to draw: the mesh has no triangles".into(),
            ));
        }
        mesh.validate().map_err(Error::Invalid)?;
        let corners_len = 3 * mesh.triangles.len();
        if let Some(f) = field
            && f.len() != corners_len
        {
            return Err(Error::Invalid(format!(
                "isoline field has {} values for {} triangle corners",
                f.len(),
                corners_len
            )));
        }
        let scalar = |v: usize| match mesh.scalars.get(v) {
            Some(s) if s.is_finite() => *s,
            Some(_) => UNDEFINED_SCALAR,
            None => 0.0,
        };
        let defined = |f: f32| if f.is_finite() { f } else { UNDEFINED_SCALAR };
        let corners: Vec<Corner> = mesh
            .triangles
            .iter()
            .flatten()
            .enumerate()
            .map(|(i, &v)| {
                let v = v as usize;
                Corner {
                    position: mesh.positions[v],
                    uv: mesh.texcoords[v],
                    scalar: scalar(v),
                    field: field.map_or_else(|| scalar(v), |f| defined(f[i])),
                }
            })
            .collect();
        // The prepass binds the corners as storage: a mesh whose corners exceed one
        // binding is cut into chunks of whole triangles that each fit one.
        let chunks = chunks(gpu, mesh.triangles.len(), 3 * std::mem::size_of::<Corner>())
            .into_iter()
            .map(|range| self.chunk(gpu, &corners[3 * range.start..3 * range.end], options))
            .collect();
        Ok(IsolineDraw {
            adjust: self.adjust.clone(),
            draw: if options.wire {
                self.draw_wire.clone()
            } else {
                self.draw_plain.clone()
            },
            chunks,
        })
    }

    /// The buffers and prepass bindings of `corners` (whole triangles), which fit one
    /// storage binding.
    fn chunk(&self, gpu: &Gpu, corners: &[Corner], options: IsolineOptions) -> IsolineChunk {
        let device = &gpu.device;
        let corner_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("isoline corners"),
            contents: bytemuck::cast_slice(corners),
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
        });
        let adjusted = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("isoline coordinates"),
            size: 4 * corners.len() as u64,
            usage: wgpu::BufferUsages::VERTEX
                | wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let triangles = (corners.len() / 3) as u32;
        let groups = triangles.div_ceil(WORKGROUP);
        let max_x = gpu.limits.max_compute_workgroups_per_dimension.max(1);
        let dispatch = (groups.min(max_x), groups.div_ceil(max_x));
        let params = Params {
            mode: options.adjust.code(),
            triangles,
            row: dispatch.0 * WORKGROUP,
            pad: 0,
        };
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("isoline prepass"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("isoline prepass"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: corner_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: adjusted.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: params.as_entire_binding(),
                },
            ],
        });
        IsolineChunk {
            bind_group,
            corners: corner_buffer,
            adjusted,
            dispatch,
            vertex_count: corners.len() as u32,
        }
    }
}

/// A mesh drawn with range-adjusted isolines, in chunks that each fit a binding.
pub(crate) struct IsolineDraw {
    adjust: wgpu::ComputePipeline,
    draw: wgpu::RenderPipeline,
    pub(crate) chunks: Vec<IsolineChunk>,
}

/// Whole triangles of an [`IsolineDraw`]: their corners, their adjusted isoline
/// coordinates (one per corner) and the prepass that writes them.
pub(crate) struct IsolineChunk {
    bind_group: wgpu::BindGroup,
    corners: wgpu::Buffer,
    pub(crate) adjusted: wgpu::Buffer,
    dispatch: (u32, u32),
    vertex_count: u32,
}

impl IsolineDraw {
    /// Records the prepass alone: the adjusted coordinates for the view of the frame
    /// whose bind group is `frame_bind_group`.
    pub(crate) fn encode_prepass(
        &self,
        frame_bind_group: &wgpu::BindGroup,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("isoline range adjust"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.adjust);
        pass.set_bind_group(0, frame_bind_group, &[]);
        for chunk in &self.chunks {
            pass.set_bind_group(1, &chunk.bind_group, &[]);
            pass.dispatch_workgroups(chunk.dispatch.0, chunk.dispatch.1, 1);
        }
    }
}

impl Drawable for IsolineDraw {
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder) {
        // The adjust depends on the view, so it runs every frame, as the paper's
        // geometry shader does.
        self.encode_prepass(frame.frame_bind_group, encoder);
        let mut pass = frame.begin_pass(encoder, "isolines");
        pass.set_pipeline(&self.draw);
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        for chunk in &self.chunks {
            pass.set_vertex_buffer(0, chunk.corners.slice(..));
            pass.set_vertex_buffer(1, chunk.adjusted.slice(..));
            pass.draw(0..chunk.vertex_count, 0..1);
        }
    }

    fn triangles(&self) -> usize {
        self.chunks
            .iter()
            .map(|c| c.vertex_count as usize / 3)
            .sum()
    }

    fn bytes(&self) -> u64 {
        self.chunks
            .iter()
            .map(|c| c.corners.size() + c.adjusted.size())
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::renderer::test_renderer;
    use crate::{Camera, Renderer, Style, View};

    /// One triangle whose isoline coordinates are s = (2.6, 3.1, 3.4): the line s = 3
    /// crosses it, at 80 % of the way from corner 0 to corner 1.
    fn triangle() -> SurfaceMesh {
        SurfaceMesh {
            positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            texcoords: vec![[0.0; 2]; 3],
            // s = 2 f + 1 with spacing 1 and offset 0.
            scalars: vec![0.8, 1.05, 1.2],
            triangles: vec![[0, 1, 2]],
            ..SurfaceMesh::default()
        }
    }

    /// A `width` x `height` view straight down from `distance` above `at` (z = 0)
    /// onto a flat mesh within `[0, extent]`.
    fn looking_down(
        at: Vec3,
        distance: f32,
        fov_y_deg: f32,
        (width, height): (u32, u32),
        extent: Vec3,
    ) -> View {
        let mut camera = Camera::look_at(at + Vec3::Z * distance, at, Vec3::Y);
        camera.fov_y_deg = fov_y_deg;
        View {
            camera,
            width,
            height,
            bounds: (Vec3::ZERO, extent),
        }
    }

    fn adjusted(r: &mut Renderer, adjust: RangeAdjust, distance: f32) -> Vec<f32> {
        let view = looking_down(
            Vec3::new(0.3, 0.3, 0.0),
            distance,
            35.0,
            (256, 256),
            Vec3::new(1.0, 1.0, 0.0),
        );
        let style = Style {
            isolines: Some(Isolines {
                offset: 0.0,
                ..Isolines::new(1.0)
            }),
            ..Style::default()
        };
        r.isoline_coordinates(&triangle(), None, adjust, &view, &style)
            .expect("prepass")
    }

    /// Where the adjusted coordinate reaches the line on edge 0 -> 1, as a fraction.
    fn line_on_edge(s: &[f32]) -> f32 {
        (3.0 - s[0]) / (s[1] - s[0])
    }

    #[test]
    fn papers_formulas() {
        let mut r = test_renderer();
        let off = adjusted(&mut r, RangeAdjust::Off, 3.0);
        assert!(
            (off[0] - 2.6).abs() < 1e-5 && (off[2] - 3.4).abs() < 1e-5,
            "{off:?}"
        );
        assert!((line_on_edge(&off) - 0.8).abs() < 1e-5);
        // 2010, pivot fM: the range (0.4 units of u = 0.8 of s) becomes one period
        // and the line stays at 80 % of the edge.
        let p2010 = adjusted(&mut r, RangeAdjust::Paper2010, 3.0);
        let range = p2010.iter().fold(f32::MIN, |a, &b| a.max(b))
            - p2010.iter().fold(f32::MAX, |a, &b| a.min(b));
        assert!((range - 2.0).abs() < 1e-4, "{p2010:?}");
        assert!((line_on_edge(&p2010) - 0.8).abs() < 1e-4, "{p2010:?}");
        // 2011, pivot fm: the same range, but the line is no longer where s = 3: it
        // left the edge (u' = 2 at u = fm + range = 1.4, below the triangle's minimum).
        let p2011 = adjusted(&mut r, RangeAdjust::Paper2011, 3.0);
        let at = line_on_edge(&p2011);
        assert!(
            (at - 0.8).abs() > 0.5,
            "2011 line at {at} of the edge: {p2011:?}"
        );
        // strata's: the line where it was, no corner further than one unit from it.
        // Near, the triangle is big on screen and the coordinate changes slowly...
        let near = adjusted(&mut r, RangeAdjust::On, 3.0);
        assert!((line_on_edge(&near) - 0.8).abs() < 1e-4, "{near:?}");
        assert!(
            near.iter().all(|s| (s - 3.0).abs() <= 1.0 + 1e-5),
            "{near:?}"
        );
        assert!(near[0] < 2.6 - 1e-3, "near: scaled up, {near:?}");
        // ... far away it changes fast enough on screen: no adjust at all.
        let far = adjusted(&mut r, RangeAdjust::On, 3000.0);
        assert_eq!(far, off);
    }

    #[test]
    fn a_mesh_beyond_one_binding_is_drawn_in_chunks() {
        // 20 x 10 cells, 400 triangles, a field rising across them.
        let mut mesh = SurfaceMesh::structured(20, 10, |i, j| [i as f32, j as f32, 0.0]);
        mesh.scalars = mesh
            .positions
            .iter()
            .map(|p| 0.11 * p[0] + 0.07 * p[1])
            .collect();
        let view = looking_down(
            Vec3::new(10.0, 5.0, 0.0),
            30.0,
            45.0,
            (320, 240),
            Vec3::new(20.0, 10.0, 0.0),
        );
        let style = Style {
            isolines: Some(Isolines::new(0.25)),
            ..Style::default()
        };
        let options = IsolineOptions {
            adjust: RangeAdjust::On,
            wire: true,
        };
        let mut r = test_renderer();
        let mut draw = |binding: Option<u64>| {
            let limit = r.gpu.limits.max_storage_buffer_binding_size;
            if let Some(bytes) = binding {
                r.gpu.limits.max_storage_buffer_binding_size = bytes;
            }
            let drawn = r
                .prepare_isolines(&mesh, None, options)
                .and_then(|drawable| {
                    let image = r.render(&[drawable.as_ref()], &view, &style)?;
                    let s = r.isoline_coordinates(&mesh, None, options.adjust, &view, &style)?;
                    Ok((image, s))
                });
            r.gpu.limits.max_storage_buffer_binding_size = limit;
            drawn.expect("drawn")
        };
        let (whole, whole_s) = draw(None);
        // Bindings of 37 triangles' corners: 11 chunks.
        let corner = std::mem::size_of::<Corner>() as u64;
        let (chunked, chunked_s) = draw(Some(37 * 3 * corner));
        // The lines are there (dark pixels on the light grey surface), and chunks draw
        // them exactly as one buffer does.
        let dark = whole.pixels().filter(|p| p.0[0] < 100).count();
        assert!(dark > 2000, "{dark} isoline or wire pixels");
        assert_eq!(chunked_s.len(), 3 * 400);
        assert_eq!(chunked_s, whole_s);
        let differ = whole
            .pixels()
            .zip(chunked.pixels())
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(differ, 0, "pixels drawn otherwise in chunks");
    }
}
