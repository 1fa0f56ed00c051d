//! The window's GPU side: its surface, and egui painting the panel and the engine's
//! frame texture onto it.

use std::sync::Arc;

use egui_wgpu::{Renderer as EguiRenderer, RendererOptions, ScreenDescriptor};
use strata_render::Gpu;
use winit::window::Window;

use crate::{Error, Result};

/// A window's surface and the egui painter drawing into it.
pub struct WindowGpu {
    /// The window drawn into.
    pub window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    egui: EguiRenderer,
    /// The engine's frame texture as egui knows it, and the texture registered (a new
    /// size makes a new texture, registered again).
    frame: Option<(egui::TextureId, wgpu::Texture)>,
}

/// Opens an instance that knows `window`'s display, a surface on it and the best
/// adapter presenting to it: the device the engine draws with.
pub fn open(window: Arc<Window>, vsync: bool) -> Result<(WindowGpu, Gpu)> {
    let display = Box::new(window.clone());
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
        display,
    ));
    let surface = instance
        .create_surface(window.clone())
        .map_err(|e| Error::Window(format!("no surface on the window: {e}")))?;
    let gpu = Gpu::for_surface(&instance, &surface)?;
    let caps = surface.get_capabilities(&gpu.adapter);
    // egui paints gamma-space colours, and the engine's frame is gamma-space bytes:
    // a format that does not encode to sRGB again shows both as drawn.
    let format = caps
        .formats
        .iter()
        .copied()
        .find(|f| !f.is_srgb())
        .or_else(|| caps.formats.first().copied())
        .ok_or_else(|| Error::Window("the surface offers no format".into()))?;
    let size = window.inner_size();
    let config = wgpu::SurfaceConfiguration {
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        format,
        width: size.width.max(1),
        height: size.height.max(1),
        present_mode: if vsync {
            wgpu::PresentMode::AutoVsync
        } else {
            wgpu::PresentMode::AutoNoVsync
        },
        desired_maximum_frame_latency: 2,
        alpha_mode: caps
            .alpha_modes
            .first()
            .copied()
            .unwrap_or(wgpu::CompositeAlphaMode::Auto),
        view_formats: vec![],
        color_space: wgpu::SurfaceColorSpace::Auto,
    };
    surface.configure(&gpu.device, &config);
    let egui = EguiRenderer::new(
        &gpu.device,
        format,
        RendererOptions {
            // Dithering would add noise to the engine's picture.
            dithering: false,
            ..RendererOptions::default()
        },
    );
    let window_gpu = WindowGpu {
        window,
        surface,
        config,
        egui,
        frame: None,
    };
    Ok((window_gpu, gpu))
}

impl WindowGpu {
    /// Follows a new window size.
    pub fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) {
        if width > 0 && height > 0 {
            self.config.width = width;
            self.config.height = height;
            self.surface.configure(&gpu.device, &self.config);
        }
    }

    /// The egui texture showing `frame` (the engine's frame texture), registered
    /// again when the engine made a new one.
    pub fn frame_texture(&mut self, gpu: &Gpu, frame: &wgpu::Texture) -> egui::TextureId {
        if let Some((id, registered)) = &self.frame
            && registered == frame
        {
            return *id;
        }
        let view = frame.create_view(&Default::default());
        let id = match self.frame.take() {
            Some((id, _)) => {
                self.egui.update_egui_texture_from_wgpu_texture(
                    &gpu.device,
                    &view,
                    wgpu::FilterMode::Nearest,
                    id,
                );
                id
            }
            None => {
                self.egui
                    .register_native_texture(&gpu.device, &view, wgpu::FilterMode::Nearest)
            }
        };
        self.frame = Some((id, frame.clone()));
        id
    }

    /// Paints egui's output (the panel, and the frame as an image) and presents it.
    pub fn paint(
        &mut self,
        gpu: &Gpu,
        ctx: &egui::Context,
        mut output: egui::FullOutput,
    ) -> Result<()> {
        // Texture changes are applied whether or not this frame is presented: later
        // frames paint with them.
        for (id, deltas) in output.textures_delta.set.drain() {
            for delta in deltas {
                self.egui
                    .update_texture(&gpu.device, &gpu.queue, id, &delta);
            }
        }
        let presented = self.present(
            gpu,
            ctx,
            std::mem::take(&mut output.shapes),
            output.pixels_per_point,
        );
        for id in output.textures_delta.free.drain() {
            self.egui.free_texture(&id);
        }
        presented
    }

    fn present(
        &mut self,
        gpu: &Gpu,
        ctx: &egui::Context,
        shapes: Vec<egui::epaint::ClippedShape>,
        ppp: f32,
    ) -> Result<()> {
        let surface_texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&gpu.device, &self.config);
                return Ok(());
            }
            // Skipped: a later frame paints again.
            _ => return Ok(()),
        };
        let primitives = ctx.tessellate(shapes, ppp);
        let screen = ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point: ppp,
        };
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let mut commands =
            self.egui
                .update_buffers(&gpu.device, &gpu.queue, &mut encoder, &primitives, &screen);
        let view = surface_texture.texture.create_view(&Default::default());
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("window"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.egui
                .render(&mut pass.forget_lifetime(), &primitives, &screen);
        }
        commands.push(encoder.finish());
        gpu.queue.submit(commands);
        self.window.pre_present_notify();
        gpu.queue.present(surface_texture);
        Ok(())
    }
}
