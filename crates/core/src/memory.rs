//! The process's resident memory as Linux reports it (`/proc/self/status`), for measurements that
//! state what a step needs. Elsewhere every function answers `None`.

/// A field of `/proc/self/status` in bytes (`VmRSS`, `VmHWM`: given in kB).
fn status_bytes(field: &str) -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(field))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

/// Resident memory now (bytes).
pub fn resident() -> Option<f64> {
    status_bytes("VmRSS:")
}

/// Reset the peak resident memory to the current one (Linux's `clear_refs` value 5) and return
/// the current resident memory, the start that [`peak_since`] measures from.
pub fn reset_peak() -> Option<f64> {
    std::fs::write("/proc/self/clear_refs", "5").ok()?;
    resident()
}

/// Peak resident memory since [`reset_peak`] above `start` (bytes).
pub fn peak_since(start: f64) -> Option<f64> {
    Some((status_bytes("VmHWM:")? - start).max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_touched_allocation_shows_in_the_peak() {
        let start = reset_peak();
        if !cfg!(target_os = "linux") {
            return;
        }
        let start = start.expect("Linux reports resident memory");
        let bytes = 64 << 20;
        let block = vec![1u8; bytes];
        std::hint::black_box(&block);
        let peak = peak_since(start).expect("a peak after a reset");
        drop(block);
        assert!(peak >= 0.9 * bytes as f64, "peak {peak} for a {bytes}-byte block");
    }
}
