//! The wireframe texture (Celes & Abraham, section 3): a 2D array texture whose width
//! holds half a line at its right end, mip-mapped so that the line keeps its thickness
//! in pixels at every level, with small levels capped to a fraction of the level so
//! that dense meshes do not saturate. Array layers encode depth attenuation (the
//! paper's second texture axis, Fig. 8): a plain 2D texture would lose that axis at
//! the small mip levels, whose height shrinks with their width.
//!
//! Each level is drawn for two texels per pixel and already filtered by the pixel:
//! a texel holds the coverage of a one-pixel box (two texels) centred on it. The
//! paper's level (one texel per pixel, texel-box coverage) cannot draw a 1 px line:
//! the line's centre is the mirror point between two half-covered texels, and
//! bilinear filtering makes a 2 px band of half coverage. Two texels per pixel put
//! samples a quarter pixel either side of the centre, so the bilinear profile is the
//! box-filtered line to within a few hundredths of a pixel. The shader samples one
//! level with the coordinate rescaled so that its texels are exactly half a pixel
//! (see `coverage_texture` in common.wgsl), which keeps the width exact between
//! levels, where trilinear blending would not.

/// How lines fade with distance from the eye.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Attenuation {
    #[default]
    /// Lines keep their intensity and thickness at any depth.
    None,
    /// Lines fade towards the far end of the scene.
    Intensity,
    /// Lines get thinner towards the far end of the scene.
    Thickness,
}

impl Attenuation {
    /// The shader's code for this mode (see `common.wgsl`).
    pub(crate) fn code(self) -> f32 {
        match self {
            Attenuation::None => 0.0,
            Attenuation::Intensity => 1.0,
            Attenuation::Thickness => 2.0,
        }
    }
}

/// Number of attenuation layers when attenuating.
pub const ATTENUATION_LAYERS: u32 = 16;

/// What the texture encodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WireTextureSpec {
    /// Width of level 0 in texels (one coordinate unit); a power of two.
    pub width: u32,
    /// Line thickness in pixels (at least 0.5).
    pub thickness: f32,
    /// Largest fraction of a coordinate unit a half line may cover (1/3 in the paper).
    pub cap: f32,
    /// How lines fade with depth (the texture's second axis).
    pub attenuation: Attenuation,
}

impl Default for WireTextureSpec {
    fn default() -> Self {
        WireTextureSpec {
            width: 4096,
            thickness: 2.0,
            cap: 1.0 / 3.0,
            attenuation: Attenuation::None,
        }
    }
}

impl WireTextureSpec {
    /// Array layers. Without attenuation two identical ones: wgpu's GL backend makes a
    /// one-layer texture a plain `TEXTURE_2D`, which cannot be viewed as an array.
    pub fn layers(&self) -> u32 {
        match self.attenuation {
            Attenuation::None => 2,
            _ => ATTENUATION_LAYERS,
        }
    }

    /// Mip levels down to one texel, so that lines stay σ pixels wide at any zoom.
    pub fn mip_levels(&self) -> u32 {
        self.width.max(1).ilog2() + 1
    }

    /// Thickness and intensity of layer `layer` (the curves of `common.wgsl`).
    fn layer_style(&self, layer: u32) -> (f32, f32) {
        let a = if self.layers() > 1 {
            layer as f32 / (self.layers() - 1) as f32
        } else {
            0.0
        };
        match self.attenuation {
            Attenuation::None => (self.thickness, 1.0),
            Attenuation::Intensity => (self.thickness, 1.0 - 0.85 * a),
            Attenuation::Thickness => ((self.thickness * (1.0 - 0.65 * a)).max(0.5), 1.0),
        }
    }

    /// Texels per pixel at the level the shader samples.
    pub const TEXELS_PER_PIXEL: f32 = 2.0;

    /// Coverage of each texel of `level` in `layer`. The level's `w` texels span one
    /// coordinate unit; with mirrored repeat the lines sit at texel positions `w`
    /// (the right end), `-w` and `3w`, each `2h` texels wide with
    /// `h = min(thickness, cap w)`: a line of `thickness` pixels at two texels per
    /// pixel, at most `cap` units wide on each side. Texel `t` holds the coverage of
    /// the box of one pixel (two texels) centred on it, `[t - 0.5, t + 1.5]`.
    pub fn level_coverage(&self, layer: u32, level: u32) -> Vec<f32> {
        let w = (self.width >> level).max(1) as f32;
        let (thickness, intensity) = self.layer_style(layer);
        let half = (0.5 * Self::TEXELS_PER_PIXEL * thickness).min(self.cap * w);
        let r = 0.5 * Self::TEXELS_PER_PIXEL;
        let overlap = |a0: f32, a1: f32, b0: f32, b1: f32| (a1.min(b1) - a0.max(b0)).max(0.0);
        (0..w as u32)
            .map(|t| {
                let c = t as f32 + 0.5;
                let covered: f32 = [-w, w, 3.0 * w]
                    .iter()
                    .map(|&line| overlap(c - r, c + r, line - half, line + half))
                    .sum();
                (covered / (2.0 * r)).min(1.0) * intensity
            })
            .collect()
    }

    /// Creates and fills the texture.
    pub(crate) fn upload(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> wgpu::Texture {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("wireframe texture"),
            size: wgpu::Extent3d {
                width: self.width,
                height: 1,
                depth_or_array_layers: self.layers(),
            },
            mip_level_count: self.mip_levels(),
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        for layer in 0..self.layers() {
            for level in 0..self.mip_levels() {
                let texels: Vec<u8> = self
                    .level_coverage(layer, level)
                    .iter()
                    .flat_map(|&c| [255, 255, 255, (c * 255.0).round() as u8])
                    .collect();
                let w = (self.width >> level).max(1);
                queue.write_texture(
                    wgpu::TexelCopyTextureInfo {
                        texture: &texture,
                        mip_level: level,
                        origin: wgpu::Origin3d {
                            x: 0,
                            y: 0,
                            z: layer,
                        },
                        aspect: wgpu::TextureAspect::All,
                    },
                    &texels,
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(4 * w),
                        rows_per_image: Some(1),
                    },
                    wgpu::Extent3d {
                        width: w,
                        height: 1,
                        depth_or_array_layers: 1,
                    },
                );
            }
        }
        texture
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thickness_three_at_two_texels_per_pixel() {
        // A half line of 1.5 px is 3 texels; filtered by a 2-texel box, the last two
        // texels read 1, then 0.75 and 0.25 across the edge 3 texels from the end.
        let spec = WireTextureSpec {
            thickness: 3.0,
            ..Default::default()
        };
        let l0 = spec.level_coverage(0, 0);
        assert_eq!(l0.len(), 4096);
        assert_eq!(&l0[4090..], &[0.0, 0.0, 0.25, 0.75, 1.0, 1.0]);
    }

    #[test]
    fn every_level_keeps_the_thickness_until_the_cap() {
        let spec = WireTextureSpec {
            thickness: 5.0,
            ..Default::default()
        };
        for level in 0..spec.mip_levels() {
            let w = (4096 >> level) as f32;
            let covered: f32 = spec.level_coverage(0, level).iter().sum();
            // Half a line: 2.5 px at 2 texels per pixel, or a third of the level.
            let want = (5.0f32).min(w / 3.0);
            assert!(
                (covered - want).abs() < 1e-4,
                "level {level}: {covered} vs {want}"
            );
            // Never more than a third of the level.
            assert!(covered / w <= 1.0 / 3.0 + 1e-6);
        }
    }

    #[test]
    fn attenuation_layers_fade_or_thin() {
        let spec = WireTextureSpec {
            thickness: 4.0,
            attenuation: Attenuation::Thickness,
            ..Default::default()
        };
        // Half lines of 2 px and 0.7 px, at 2 texels per pixel.
        let near: f32 = spec.level_coverage(0, 0).iter().sum();
        let far: f32 = spec.level_coverage(ATTENUATION_LAYERS - 1, 0).iter().sum();
        assert!((near - 4.0).abs() < 1e-4 && (far - 1.4).abs() < 1e-4);
        let spec = WireTextureSpec {
            attenuation: Attenuation::Intensity,
            ..spec
        };
        let far = spec.level_coverage(ATTENUATION_LAYERS - 1, 0);
        assert!((far[4095] - 0.15).abs() < 1e-4);
    }
}
