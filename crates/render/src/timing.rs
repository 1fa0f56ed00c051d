//! Frame timing for the benchmarks: GPU timestamps written before and after a frame's
//! command buffer where the adapter has timestamp queries, and the wall clock around
//! submit and wait in every case (the only clock without them, and the one that
//! includes what the CPU does for the GPU, such as uploads).

use std::cell::RefCell;
use std::time::Instant;

use crate::{Error, Gpu, Result};

/// How long one frame took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTime {
    /// Between the timestamps around the frame's commands, when the adapter has them.
    pub gpu_ms: Option<f64>,
    /// From submit to the end of the wait.
    pub wall_ms: f64,
}

impl FrameTime {
    /// The GPU time where there is one, else the wall clock.
    pub fn best_ms(&self) -> f64 {
        self.gpu_ms.unwrap_or(self.wall_ms)
    }
}

/// Timestamp queries: a pair per frame, resolved and read back after the wait.
struct Queries {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    /// Timestamps can be written between passes; else empty compute passes write them.
    inside_encoders: bool,
    /// Nanoseconds per tick.
    period: f64,
}

/// Times frames on one device.
pub struct FrameTimer {
    queries: Option<Queries>,
    /// Where immediate mode's uploads land (grown as needed).
    scratch: RefCell<Option<wgpu::Buffer>>,
}

impl FrameTimer {
    /// A timer with timestamps when `gpu` was given TIMESTAMP_QUERY (see gpu.rs).
    pub fn new(gpu: &Gpu) -> Self {
        let queries = gpu
            .features
            .contains(wgpu::Features::TIMESTAMP_QUERY)
            .then(|| {
                let size = 2 * wgpu::QUERY_SIZE as u64;
                let buffer = |label, usage| {
                    gpu.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(label),
                        size,
                        usage,
                        mapped_at_creation: false,
                    })
                };
                Queries {
                    set: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                        label: Some("frame timestamps"),
                        ty: wgpu::QueryType::Timestamp,
                        count: 2,
                    }),
                    resolve: buffer(
                        "timestamp resolve",
                        wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    ),
                    readback: buffer(
                        "timestamp readback",
                        wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                    ),
                    inside_encoders: gpu
                        .features
                        .contains(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS),
                    period: f64::from(gpu.queue.get_timestamp_period()),
                }
            });
        FrameTimer {
            queries,
            scratch: RefCell::new(None),
        }
    }

    /// Whether frames get GPU timestamps.
    pub fn has_timestamps(&self) -> bool {
        self.queries.is_some()
    }

    /// Sends `bytes` to the GPU through the queue, as immediate mode sends a mesh's
    /// vertex data before every frame; they land in a scratch buffer, which costs the
    /// same transfer as the mesh's own buffers and leaves what is drawn unchanged.
    pub fn upload(&self, gpu: &Gpu, bytes: &[u8]) {
        let size = (bytes.len() as u64).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        let mut scratch = self.scratch.borrow_mut();
        if scratch.as_ref().is_none_or(|b| b.size() < size) {
            *scratch = Some(gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("immediate-mode scratch"),
                size: size.max(wgpu::COPY_BUFFER_ALIGNMENT),
                usage: wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        let whole = bytes.len() - bytes.len() % wgpu::COPY_BUFFER_ALIGNMENT as usize;
        if let Some(buffer) = scratch.as_ref() {
            gpu.queue.write_buffer(buffer, 0, &bytes[..whole]);
        }
    }

    /// Writes timestamp `index` into `encoder`.
    fn stamp(q: &Queries, encoder: &mut wgpu::CommandEncoder, index: u32) {
        if q.inside_encoders {
            encoder.write_timestamp(&q.set, index);
            return;
        }
        let writes = wgpu::ComputePassTimestampWrites {
            query_set: &q.set,
            beginning_of_pass_write_index: (index == 0).then_some(0),
            end_of_pass_write_index: (index == 1).then_some(1),
        };
        encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("timestamp"),
            timestamp_writes: Some(writes),
        });
    }

    /// Submits `frame` between two timestamps and waits for it.
    pub fn submit(&self, gpu: &Gpu, frame: wgpu::CommandEncoder) -> Result<FrameTime> {
        let device = &gpu.device;
        let Some(q) = &self.queries else {
            let start = Instant::now();
            gpu.queue.submit([frame.finish()]);
            gpu.wait()?;
            return Ok(FrameTime {
                gpu_ms: None,
                wall_ms: start.elapsed().as_secs_f64() * 1e3,
            });
        };
        let mut before = device.create_command_encoder(&Default::default());
        Self::stamp(q, &mut before, 0);
        let mut after = device.create_command_encoder(&Default::default());
        Self::stamp(q, &mut after, 1);
        after.resolve_query_set(&q.set, 0..2, &q.resolve, 0);
        after.copy_buffer_to_buffer(&q.resolve, 0, &q.readback, 0, q.resolve.size());
        let start = Instant::now();
        gpu.queue
            .submit([before.finish(), frame.finish(), after.finish()]);
        gpu.wait()?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;
        gpu.map_read(&q.readback)?;
        let slice = q.readback.slice(..);
        let ticks: [u64; 2] = {
            let data = slice
                .get_mapped_range()
                .map_err(|e| Error::Gpu(e.to_string()))?;
            bytemuck::pod_read_unaligned(&data[..16])
        };
        q.readback.unmap();
        Ok(FrameTime {
            gpu_ms: Some(ticks[1].saturating_sub(ticks[0]) as f64 * q.period / 1e6),
            wall_ms,
        })
    }
}
