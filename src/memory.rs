//! What this process can still have of the machine's memory, and what it has used (Linux's
//! /proc files): renders are refused before they start rather than aborted midway.

const MIB: u64 = 1 << 20;

/// Bytes of address space a render maps besides its buffers, generously: Embree's (256 MiB)
/// and, for each of `threads` render threads, a stack and an allocator arena (80 MiB).
pub fn reserve(threads: u64) -> u64 {
    256 * MIB + threads * 80 * MIB
}

/// Bytes of address space a command that starts neither Embree nor threads maps besides its
/// buffers (`timbre generate-mesh`: its output's buffer, formatting), generously.
pub const PLAIN_RESERVE: u64 = 64 * MIB;

/// Bytes a render's buffers can still have (Linux), whichever is less: the address-space limit
/// less what is mapped now and `reserve` (what the render will map besides its buffers and has
/// not mapped yet, e.g. [`reserve`]'s), and the memory the system has available (MemAvailable
/// and free swap) less 128 MiB for the rest of the program; `None` where neither is known.
pub fn available(reserve: u64) -> Option<u64> {
    let address_space = proc_number("/proc/self/limits", "Max address space").and_then(|limit| {
        let mapped = proc_number("/proc/self/status", "VmSize:")? * 1024;
        Some(limit.saturating_sub(mapped + reserve))
    });
    let system = proc_number("/proc/meminfo", "MemAvailable:").map(|available| {
        let swap = proc_number("/proc/meminfo", "SwapFree:").unwrap_or(0);
        ((available + swap) * 1024).saturating_sub(128 * MIB)
    });
    address_space.into_iter().chain(system).min()
}

/// The first number after `name` on the line of `file` (a Linux /proc file) that starts with
/// it; `None` if the file, the line or a number is missing ("unlimited").
fn proc_number(file: &str, name: &str) -> Option<u64> {
    let text = std::fs::read_to_string(file).ok()?;
    let line = text.lines().find(|l| l.starts_with(name))?;
    line[name.len()..].split_whitespace().next()?.parse().ok()
}

/// Peak resident memory of this process (Linux), e.g. "231 MiB".
pub fn peak() -> Option<String> {
    let kib = proc_number("/proc/self/status", "VmHWM:")?;
    Some(format!("{} MiB", kib.div_ceil(1024)))
}
