//! Work refused before it starts when it would not fit the memory there is: past it,
//! the allocator aborts or the system's OOM killer ends the run long after it began.

use crate::{Error, Result};

/// Refuses work that needs about `needed` bytes when the system has less available
/// (Linux's MemAvailable; elsewhere nothing is known and nothing is refused). `what`
/// and `doing` name the work in the message.
pub fn check_memory(needed: f64, what: &str, doing: &str) -> Result<()> {
    if let Some(available) = available_memory()
        && needed > available
    {
        return Err(Error::scene(format!(
            "{what} need about {:.1} GB {doing}, and {:.1} GB of memory is available",
            needed / 1e9,
            available / 1e9
        )));
    }
    Ok(())
}

/// Memory the system can still give this process without swapping, in bytes
/// (Linux's MemAvailable; `None` where it is not known).
pub fn available_memory() -> Option<f64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kb = info
        .lines()
        .find_map(|l| l.strip_prefix("MemAvailable:"))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse::<f64>()
        .ok()?;
    Some(1024.0 * kb)
}

/// Peak resident memory of this process (VmHWM), kB.
pub fn peak_memory_kb() -> Option<u64> {
    std::fs::read_to_string("/proc/self/status")
        .ok()?
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()
}
