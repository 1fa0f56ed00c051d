//! Device setup: headless by default. The adapter is chosen from those of the
//! backends `WGPU_BACKEND` allows (all by default), by `WGPU_ADAPTER_NAME` when set,
//! else the most capable kind (discrete, integrated, virtual, then CPU), leaving out
//! OpenGL contexts too old for strata's shaders.

use crate::{Error, Result};

/// An open device and what it can do.
pub struct Gpu {
    /// The adapter the device was opened on (a window asks it for surface formats).
    pub adapter: wgpu::Adapter,
    /// Creates every buffer, texture and pipeline.
    pub device: wgpu::Device,
    /// Takes uploads and command buffers.
    pub queue: wgpu::Queue,
    /// Which adapter and backend draw, for reports and for choosing CPU paths.
    pub info: wgpu::AdapterInfo,
    /// The optional features strata asked for and got.
    pub features: wgpu::Features,
    /// The adapter's limits strata sizes its buffers and textures by.
    pub limits: wgpu::Limits,
}

/// Features strata uses when the adapter has them; everything works without them.
const WANTED_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::POLYGON_MODE_LINE);

fn kind_rank(t: wgpu::DeviceType) -> u8 {
    match t {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    }
}

/// Why strata cannot draw through an OpenGL adapter whose `GL_VERSION` is
/// `driver_info`, or `None` when it can (and for every other backend).
///
/// Where EGL offers desktop OpenGL, wgpu asks for a 3.3 core context. Mesa answers
/// with its newest version (4.5 on llvmpipe); NVIDIA's driver answers with 3.3, for
/// which naga writes GLSL 3.30: it has no storage buffers, so the pulled wireframes
/// and the isoline pass cannot be built, and on an NVIDIA H200 the surfaces drew
/// nothing at all. strata's shaders need OpenGL 4.3 or OpenGL ES 3.1.
fn opengl_shortfall(backend: wgpu::Backend, driver_info: &str) -> Option<String> {
    if backend != wgpu::Backend::Gl {
        return None;
    }
    let (es, version) = match driver_info.strip_prefix("OpenGL ES ") {
        Some(rest) => (true, rest),
        None => (false, driver_info),
    };
    let mut numbers = version
        .split(|c: char| !c.is_ascii_digit())
        .map(|n| n.parse::<u32>().ok());
    let (Some(Some(major)), Some(Some(minor))) = (numbers.next(), numbers.next()) else {
        return None;
    };
    let (api, needed) = if es {
        ("OpenGL ES", (3, 1))
    } else {
        ("OpenGL", (4, 3))
    };
    ((major, minor) < needed).then(|| {
        format!(
            "opens {api} {major}.{minor}, and strata's shaders need {api} {}.{} \
             (storage buffers); use the device's Vulkan adapter (WGPU_BACKEND=vulkan)",
            needed.0, needed.1
        )
    })
}

impl Gpu {
    /// Opens the best adapter the environment allows.
    pub fn new() -> Result<Self> {
        Self::with_backends(wgpu::Backends::from_env().unwrap_or(wgpu::Backends::all()))
    }

    /// Opens the best adapter among `backends` (`WGPU_ADAPTER_NAME` still applies).
    pub fn with_backends(backends: wgpu::Backends) -> Result<Self> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        desc.backends = backends;
        let instance = wgpu::Instance::new(desc);
        Self::open(&instance, backends, None)
    }

    /// Opens the best adapter of `instance` that can present to `surface` (a
    /// window's): the instance must know the window's display for OpenGL to present.
    pub fn for_surface(instance: &wgpu::Instance, surface: &wgpu::Surface<'_>) -> Result<Self> {
        let backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::all());
        Self::open(instance, backends, Some(surface))
    }

    /// The best adapter among `backends` of `instance` (presenting to `surface` when
    /// given), opened with the features and limits strata asks for.
    fn open(
        instance: &wgpu::Instance,
        backends: wgpu::Backends,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self> {
        let mut adapters = pollster::block_on(instance.enumerate_adapters(backends));
        if let Some(surface) = surface {
            adapters.retain(|a| a.is_surface_supported(surface));
        }
        let wanted_name = std::env::var("WGPU_ADAPTER_NAME")
            .ok()
            .map(|n| n.to_lowercase());
        if let Some(name) = &wanted_name {
            adapters.retain(|a| a.get_info().name.to_lowercase().contains(name));
        }
        let mut unsuitable = Vec::new();
        adapters.retain(|a| {
            let info = a.get_info();
            let shortfall = opengl_shortfall(info.backend, &info.driver_info);
            if let Some(why) = &shortfall {
                unsuitable.push(format!("{} ({:?}) {why}", info.name, info.backend));
            }
            shortfall.is_none()
        });
        adapters.sort_by_key(|a| {
            let info = a.get_info();
            // Prefer Vulkan over GL for the same kind: it has the fuller feature set.
            (
                kind_rank(info.device_type),
                info.backend != wgpu::Backend::Vulkan,
            )
        });
        if adapters.is_empty() && !unsuitable.is_empty() {
            return Err(Error::Unsuitable(unsuitable.join("; ")));
        }
        let adapter = adapters.into_iter().next().ok_or_else(|| {
            let presenting = if surface.is_some() {
                ", presenting to the window"
            } else {
                ""
            };
            Error::NoAdapter(match &wanted_name {
                Some(n) => format!("backends {backends:?}{presenting}, name containing {n:?}"),
                None => format!("backends {backends:?}{presenting}"),
            })
        })?;
        let info = adapter.get_info();
        let features = adapter.features() & WANTED_FEATURES;
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: adapter.limits().max_storage_buffer_binding_size,
            max_buffer_size: adapter.limits().max_buffer_size,
            max_texture_dimension_2d: adapter.limits().max_texture_dimension_2d,
            ..wgpu::Limits::downlevel_defaults()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("strata"),
            required_features: features,
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| Error::Device {
            adapter: format!("{} ({:?})", info.name, info.backend),
            message: e.to_string(),
        })?;
        Ok(Gpu {
            adapter,
            device,
            queue,
            info,
            features,
            limits,
        })
    }

    /// One line naming the adapter and backend, for logs and benchmark JSON.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.info.name, self.info.backend, self.info.device_type
        )
    }

    /// Blocks until the GPU has finished all submitted work.
    pub fn wait(&self) -> Result<()> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| Error::Gpu(e.to_string()))
    }

    /// Maps all of `buffer` (a `MAP_READ` readback buffer) for reading, waiting for
    /// the GPU; read it with `get_mapped_range` and `unmap` it afterwards.
    pub fn map_read(&self, buffer: &wgpu::Buffer) -> Result<()> {
        let (tx, rx) = std::sync::mpsc::channel();
        buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv()
            .map_err(|e| Error::Gpu(e.to_string()))?
            .map_err(|e| Error::Gpu(e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::opengl_shortfall;
    use wgpu::Backend;

    #[test]
    fn opengl_below_4_3_or_es_3_1_is_refused_with_its_version() {
        // GL_VERSION strings as wgpu reports them: NVIDIA's 3.3 context (H200,
        // driver 580), llvmpipe's desktop and ES contexts.
        let nvidia = opengl_shortfall(Backend::Gl, "3.3.0 NVIDIA 580.159.04");
        assert!(
            nvidia
                .as_deref()
                .is_some_and(|why| why.contains("OpenGL 3.3") && why.contains("4.3")),
            "{nvidia:?}"
        );
        assert_eq!(
            opengl_shortfall(Backend::Gl, "4.5 (Core Profile) Mesa 22.3.6"),
            None
        );
        assert_eq!(opengl_shortfall(Backend::Gl, "4.3.0 NVIDIA 580"), None);
        assert_eq!(
            opengl_shortfall(Backend::Gl, "OpenGL ES 3.2 Mesa 22.3.6"),
            None
        );
        let es30 = opengl_shortfall(Backend::Gl, "OpenGL ES 3.0 Mesa");
        assert!(
            es30.as_deref()
                .is_some_and(|why| why.contains("OpenGL ES 3.0") && why.contains("3.1")),
            "{es30:?}"
        );
        // Other backends, and versions that cannot be read, are left to wgpu.
        assert_eq!(opengl_shortfall(Backend::Vulkan, "3.3.0 NVIDIA"), None);
        assert_eq!(opengl_shortfall(Backend::Gl, "unknown"), None);
    }
}
