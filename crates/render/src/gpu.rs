//! Device setup: headless by default. The adapter is chosen from those of the
//! backends `WGPU_BACKEND` allows (all by default), by `WGPU_ADAPTER_NAME` when set,
//! else the most capable kind (discrete, integrated, virtual, then CPU).

use crate::{Error, Result};

/// An open device and what it can do.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    /// The optional features strata asked for and got.
    pub features: wgpu::Features,
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
        let mut adapters = pollster::block_on(instance.enumerate_adapters(backends));
        let wanted_name = std::env::var("WGPU_ADAPTER_NAME")
            .ok()
            .map(|n| n.to_lowercase());
        if let Some(name) = &wanted_name {
            adapters.retain(|a| a.get_info().name.to_lowercase().contains(name));
        }
        adapters.sort_by_key(|a| {
            let info = a.get_info();
            // Prefer Vulkan over GL for the same kind: it has the fuller feature set.
            (
                kind_rank(info.device_type),
                info.backend != wgpu::Backend::Vulkan,
            )
        });
        let adapter = adapters.into_iter().next().ok_or_else(|| {
            Error::NoAdapter(match &wanted_name {
                Some(n) => format!("backends {backends:?}, name containing {n:?}"),
                None => format!("backends {backends:?}"),
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
