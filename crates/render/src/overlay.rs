//! An image composited over the end of every frame (the colour legend): drawn on the
//! GPU into the frame's own colour target, so that a window that shows the target
//! without reading it back shows it too, and a PNG read back has it.

use image::RgbaImage;

use crate::Gpu;
use crate::wire::COLOR_FORMAT;

const SHADER: &str = r"
struct Place {
    // x, y: the image's top-left pixel in the frame; z, w: the frame's size.
    at: vec4<f32>,
};
@group(0) @binding(0) var<uniform> place: Place;
@group(0) @binding(1) var image: texture_2d<f32>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let corner = vec2<f32>(f32(i & 1u), f32(i >> 1u));
    let pixel = place.at.xy + corner * vec2<f32>(textureDimensions(image));
    let ndc = pixel / place.at.zw * 2.0 - 1.0;
    return vec4<f32>(ndc.x, -ndc.y, 0.0, 1.0);
}

// One texel per pixel, unfiltered: text stays as sharp as it was rasterized.
@fragment
fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let texel = vec2<i32>(floor(p.xy - place.at.xy));
    return textureLoad(image, texel, 0);
}
";

/// The top-left pixel of an overlay of `image` size (width, height) in a frame of
/// `frame` size: at the frame's right edge, vertically centred (outside a frame
/// smaller than the image).
pub fn overlay_origin(frame: (u32, u32), image: (u32, u32)) -> [i64; 2] {
    let (w, h) = (i64::from(image.0), i64::from(image.1));
    [i64::from(frame.0) - w, (i64::from(frame.1) - h) / 2]
}

/// The overlay's image on the GPU and the pipeline that blends it over a frame.
pub(crate) struct Overlay {
    pipeline: wgpu::RenderPipeline,
    place: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    size: (u32, u32),
}

impl Overlay {
    /// Uploads `image` (RGBA8, straight alpha) to be drawn at the right edge of each
    /// frame, vertically centred.
    pub(crate) fn new(gpu: &Gpu, image: &RgbaImage) -> Self {
        let device = &gpu.device;
        let size = wgpu::Extent3d {
            width: image.width().max(1),
            height: image.height().max(1),
            depth_or_array_layers: 1,
        };
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("overlay"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        if image.width() > 0 && image.height() > 0 {
            gpu.queue.write_texture(
                texture.as_image_copy(),
                image.as_raw(),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * image.width()),
                    rows_per_image: Some(image.height()),
                },
                size,
            );
        }
        let place = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("overlay place"),
            size: 16,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("overlay"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("overlay"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleStrip,
                ..Default::default()
            },
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: COLOR_FORMAT,
                    blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("overlay"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: place.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(
                        &texture.create_view(&Default::default()),
                    ),
                },
            ],
        });
        Overlay {
            pipeline,
            place,
            bind_group,
            size: (size.width, size.height),
        }
    }

    /// Records the overlay's pass over `color`, a frame of `width` x `height`.
    pub(crate) fn encode(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        (width, height): (u32, u32),
    ) {
        let [left, top] = overlay_origin((width, height), self.size);
        let place = [left as f32, top as f32, width as f32, height as f32];
        gpu.queue
            .write_buffer(&self.place, 0, bytemuck::cast_slice(&place));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("overlay"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.draw(0..4, 0..1);
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use image::Rgba;

    use crate::renderer::test_renderer;
    use crate::{Camera, Style, View};

    #[test]
    fn the_overlay_is_blended_at_the_right_edge_vertically_centred() {
        let mut r = test_renderer();
        // Opaque red on the left column, half-transparent black on the right.
        let mut image = image::RgbaImage::new(2, 4);
        for y in 0..4 {
            image.put_pixel(0, y, Rgba([255, 0, 0, 255]));
            image.put_pixel(1, y, Rgba([0, 0, 0, 128]));
        }
        let view = View {
            camera: Camera::fit_points([Vec3::ZERO, Vec3::ONE], 1.0, 1.0, (0.0, 60.0), 1.0),
            width: 9,
            height: 10,
            bounds: (Vec3::ZERO, Vec3::ONE),
        };
        r.set_overlay(Some(&image));
        let frame = r.render(&[], &view, &Style::default()).expect("a frame");
        r.set_overlay(None);
        let plain = r.render(&[], &view, &Style::default()).expect("a frame");
        assert_eq!(super::overlay_origin((9, 10), (2, 4)), [7, 3]);
        for (x, y, p) in frame.enumerate_pixels() {
            let expect = match (x, y) {
                (7, 3..7) => [255, 0, 0, 255],
                (8, 3..7) => [127, 127, 127, 255],
                _ => [255; 4],
            };
            let near = p.0.iter().zip(expect).all(|(a, b)| a.abs_diff(b) <= 1);
            assert!(near, "pixel {x},{y}: {:?}, not {expect:?}", p.0);
        }
        assert!(
            plain.pixels().all(|p| p.0 == [255; 4]),
            "the overlay stayed"
        );
    }
}
