//! The geometric baseline for isolines: contour polylines extracted on the CPU by
//! marching triangles and drawn as line primitives, as the contour filters of common
//! visualization toolkits do. It is what the texture isolines are measured against:
//! exact positions, but aliased one-pixel lines, a CPU pass and an upload whenever the
//! field or the levels change, and geometry that grows with the number of levels.

use std::collections::HashMap;

use bytemuck::{Pod, Zeroable};
use strata_grid::SurfaceMesh;
use wgpu::util::DeviceExt;

use crate::wire::{Drawable, FrameTargets, PipelineContext, frame_target, reversed_depth};
use crate::{Error, Gpu, Isolines, Result};

/// One contour line: points in the mesh's display frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline {
    /// The field value this line follows.
    pub level: f32,
    /// The line's points in order.
    pub points: Vec<[f32; 3]>,
    /// The last point joins the first.
    pub closed: bool,
}

/// The levels of `isolines` within `[lo, hi]`, at most `limit` of them (the lowest).
pub fn levels(isolines: &Isolines, lo: f32, hi: f32, limit: usize) -> Vec<f32> {
    if lo.is_nan() || hi.is_nan() || lo > hi || isolines.validate().is_none() {
        return Vec::new();
    }
    let first = ((lo - isolines.offset) / isolines.spacing).ceil() as i64;
    (first..)
        .map(|k| isolines.value(k))
        .take_while(|&v| v <= hi)
        .take(limit)
        .collect()
}

/// Marching triangles: the contours of the per-vertex `field` at each of `levels`,
/// joined into polylines across shared edges. A vertex counts as above a level when
/// its value is at least the level, so every edge is cut at most once and the pieces
/// of neighbouring triangles meet at the same point. Triangles with a non-finite
/// corner are skipped.
pub fn marching_triangles(mesh: &SurfaceMesh, field: &[f32], levels: &[f32]) -> Vec<Polyline> {
    let mut out = Vec::new();
    if field.len() != mesh.vertex_count() {
        return out;
    }
    for &level in levels {
        // Crossing points, keyed by the edge (lower vertex index first) they lie on,
        // and the segments between them.
        let mut point_of: HashMap<(u32, u32), usize> = HashMap::new();
        let mut points: Vec<[f32; 3]> = Vec::new();
        let mut segments: Vec<[usize; 2]> = Vec::new();
        for tri in &mesh.triangles {
            let f = tri.map(|v| field[v as usize]);
            if f.iter().any(|v| !v.is_finite()) {
                continue;
            }
            let mut cut = [0usize; 2];
            let mut n = 0;
            for e in 0..3 {
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                let (fa, fb) = (f[e], f[(e + 1) % 3]);
                if (fa >= level) == (fb >= level) {
                    continue;
                }
                let key = (a.min(b), a.max(b));
                let id = *point_of.entry(key).or_insert_with(|| {
                    let (pa, pb) = (
                        mesh.positions[key.0 as usize],
                        mesh.positions[key.1 as usize],
                    );
                    let (fa, fb) = (field[key.0 as usize], field[key.1 as usize]);
                    let t = (level - fa) / (fb - fa);
                    points.push(std::array::from_fn(|k| pa[k] + t * (pb[k] - pa[k])));
                    points.len() - 1
                });
                if n < 2 {
                    cut[n] = id;
                }
                n += 1;
            }
            if n == 2 {
                segments.push(cut);
            }
        }
        out.extend(join(level, &points, &segments));
    }
    out
}

/// Joins segments that share end points into polylines.
fn join(level: f32, points: &[[f32; 3]], segments: &[[usize; 2]]) -> Vec<Polyline> {
    let mut at: Vec<Vec<usize>> = vec![Vec::new(); points.len()];
    for (s, seg) in segments.iter().enumerate() {
        at[seg[0]].push(s);
        at[seg[1]].push(s);
    }
    let mut used = vec![false; segments.len()];
    let mut lines = Vec::new();
    // Open lines start at points with one segment; what is left is closed loops.
    let starts = (0..points.len())
        .filter(|&p| at[p].len() == 1)
        .chain(0..points.len());
    for start in starts {
        if !at[start].iter().any(|&s| !used[s]) {
            continue;
        }
        let mut chain = vec![start];
        let mut here = start;
        while let Some(&s) = at[here].iter().find(|&&s| !used[s]) {
            used[s] = true;
            here = if segments[s][0] == here {
                segments[s][1]
            } else {
                segments[s][0]
            };
            chain.push(here);
        }
        let closed = chain.len() > 2 && chain.first() == chain.last();
        if closed {
            chain.pop();
        }
        lines.push(Polyline {
            level,
            points: chain.iter().map(|&p| points[p]).collect(),
            closed,
        });
    }
    lines
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct LineVertex {
    position: [f32; 3],
}

/// The line-primitive pipeline of the baseline.
pub struct ContourTechnique {
    pipeline: wgpu::RenderPipeline,
}

impl ContourTechnique {
    /// Builds the line pipeline once, for every mesh drawn with it.
    pub fn new(ctx: &PipelineContext) -> Self {
        let device = &ctx.gpu.device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("contour lines"),
            source: wgpu::ShaderSource::Wgsl(
                concat!(
                    include_str!("wire/common.wgsl"),
                    include_str!("contour.wgsl")
                )
                .into(),
            ),
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("contour lines"),
            bind_group_layouts: &[Some(ctx.frame_layout)],
            immediate_size: 0,
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x3];
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("contour lines"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_contour"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<LineVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                })],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::LineList,
                ..Default::default()
            },
            depth_stencil: Some(reversed_depth(false)),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_contour"),
                compilation_options: Default::default(),
                targets: &[frame_target(Some(wgpu::BlendState::ALPHA_BLENDING))],
            }),
            multiview_mask: None,
            cache: None,
        });
        ContourTechnique { pipeline }
    }

    /// Uploads the polylines as a line list.
    pub fn prepare(&self, gpu: &Gpu, lines: &[Polyline]) -> Result<ContourLines> {
        let mut vertices = Vec::new();
        for line in lines {
            let n = line.points.len();
            let segments = if line.closed { n } else { n.saturating_sub(1) };
            for s in 0..segments {
                vertices.push(LineVertex {
                    position: line.points[s],
                });
                vertices.push(LineVertex {
                    position: line.points[(s + 1) % n],
                });
            }
        }
        if vertices.is_empty() {
            return Err(Error::Invalid("no contour line to draw".into()));
        }
        let buffer = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("contour lines"),
                contents: bytemuck::cast_slice(&vertices),
                usage: wgpu::BufferUsages::VERTEX,
            });
        Ok(ContourLines {
            pipeline: self.pipeline.clone(),
            buffer,
            vertex_count: vertices.len() as u32,
        })
    }
}

/// Contour polylines ready to draw over an already drawn surface (they test against
/// its depth, pulled slightly towards the eye, and do not write depth).
pub struct ContourLines {
    pipeline: wgpu::RenderPipeline,
    buffer: wgpu::Buffer,
    vertex_count: u32,
}

impl Drawable for ContourLines {
    fn encode(&self, frame: &FrameTargets, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = frame.begin_pass(encoder, "contour lines");
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        pass.set_vertex_buffer(0, self.buffer.slice(..));
        pass.draw(0..self.vertex_count, 0..1);
    }

    /// Line segments, not triangles.
    fn triangles(&self) -> usize {
        0
    }

    fn bytes(&self) -> u64 {
        self.buffer.size()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circles_of_a_paraboloid_close_and_lie_on_their_level() {
        let n = 40;
        let mesh = SurfaceMesh::structured(n, n, |i, j| {
            [
                i as f32 / n as f32 * 2.0 - 1.0,
                j as f32 / n as f32 * 2.0 - 1.0,
                0.0,
            ]
        });
        let field: Vec<f32> = mesh
            .positions
            .iter()
            .map(|p| p[0] * p[0] + p[1] * p[1])
            .collect();
        let lines = marching_triangles(&mesh, &field, &[0.23, 0.47]);
        assert_eq!(lines.len(), 2, "one closed circle per level");
        for line in &lines {
            assert!(line.closed);
            let r = line.level.sqrt();
            for p in &line.points {
                let d = (p[0] * p[0] + p[1] * p[1]).sqrt();
                // Linear interpolation on 0.05-wide cells: within a few thousandths.
                assert!((d - r).abs() < 4e-3, "{d} vs {r}");
            }
        }
        // Points of a level are shared by neighbouring triangles, not duplicated.
        let total: usize = lines.iter().map(|l| l.points.len()).sum();
        let mut unique: Vec<[u32; 3]> = lines
            .iter()
            .flat_map(|l| l.points.iter().map(|p| p.map(f32::to_bits)))
            .collect();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), total);
    }

    #[test]
    fn open_lines_end_on_the_border_and_undefined_triangles_are_skipped() {
        let mesh = SurfaceMesh::structured(4, 2, |i, j| [i as f32, j as f32, 0.0]);
        let mut field: Vec<f32> = mesh.positions.iter().map(|p| p[0]).collect();
        let lines = marching_triangles(&mesh, &field, &[1.5]);
        assert_eq!(lines.len(), 1);
        assert!(!lines[0].closed);
        assert_eq!(lines[0].points.len(), 5, "{:?}", lines[0].points);
        assert!(lines[0].points.iter().all(|p| (p[0] - 1.5).abs() < 1e-6));
        // An undefined value at node (1, 1) removes the four triangles around it that
        // the line crosses: one segment is left, in cell (1, 0).
        field[6] = f32::NAN;
        let lines = marching_triangles(&mesh, &field, &[1.5]);
        assert_eq!(lines.len(), 1);
        assert_eq!(lines[0].points.len(), 2);
        assert!(lines[0].points.iter().all(|p| p[1] <= 1.0));
    }

    #[test]
    fn levels_follow_spacing_and_offset() {
        let iso = Isolines {
            offset: 0.1,
            ..Isolines::new(0.25)
        };
        assert_eq!(levels(&iso, 0.0, 1.0, 100), vec![0.1, 0.35, 0.6, 0.85]);
        assert_eq!(levels(&iso, 0.0, 1.0, 2).len(), 2);
        assert!(levels(&iso, 1.0, 0.0, 100).is_empty());
    }
}
