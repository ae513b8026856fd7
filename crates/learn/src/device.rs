//! The backend, chosen at run time (`--device`): the model code is the same on every one.

pub use burn::tensor::Device;
use wakelab_core::{ConfigError, WakelabError};

/// Device names this build accepts, the CPU first and the preferred GPU backend last.
pub fn available_devices() -> Vec<&'static str> {
    let mut names = vec!["cpu"];
    if cfg!(feature = "wgpu") {
        names.push("wgpu");
    }
    if cfg!(feature = "cuda") {
        names.push("cuda");
    }
    names
}

/// Whether `device` is the CPU backend (burn's `flex`).
pub fn is_cpu(device: &Device) -> bool {
    format!("{device:?}").to_lowercase().contains("flex")
}

/// The device in words for reports: the backend and, on the CPU, its threads.
pub fn describe_device(device: &Device) -> String {
    let threads = rayon::current_num_threads();
    match format!("{device:?}") {
        _ if is_cpu(device) => format!("cpu (burn flex backend, {threads} threads)"),
        d if d.contains("Wgpu") => "wgpu (default adapter)".into(),
        d if d.contains("Cuda") => "cuda".into(),
        d => d,
    }
}

/// `cpu` (burn's pure-Rust `flex` backend, multi-threaded), `wgpu` (Vulkan/Metal/DX12; built with
/// `--features wgpu`), `cuda` (`--features cuda`: the NVIDIA driver and `libdevice.10.bc` at run
/// time, no CUDA toolkit; docs/guide/train.md), or `auto`: the GPU backend this build has (cuda
/// before wgpu), else the CPU.
pub fn parse_device(name: &str) -> Result<Device, WakelabError> {
    match name {
        "auto" => parse_device(available_devices().last().expect("cpu is always there")),
        "cpu" | "flex" => Ok(Device::flex()),
        #[cfg(feature = "wgpu")]
        "wgpu" => Ok(Device::wgpu(Default::default())),
        #[cfg(feature = "cuda")]
        "cuda" => Ok(Device::cuda(0)),
        other => Err(ConfigError::new(
            "--device",
            other,
            format!(
                "auto or one of {:?} (wgpu and cuda need wakelab built with `--features wgpu` or `--features cuda`)",
                available_devices()
            ),
        )
        .into()),
    }
}

/// mimalloc's `mi_option_purge_delay` (index 15 of the option enum in mimalloc 2 and 3, `mimalloc.h`), which
/// `libmimalloc-sys` does not name.
const MIMALLOC_PURGE_DELAY: libmimalloc_sys::mi_option_t = 15;

/// Tells mimalloc, where it is the global allocator (the `wakelab` binary, the training benchmark),
/// to keep freed pages instead of returning them to the kernel a second later (its default in
/// the bundled mimalloc 3, `src/options.c`). A
/// training step frees and reallocates activation buffers of tens of MB; returned pages come back
/// as page faults on fresh, kernel-zeroed memory (6-10 % of a U-Net step in `perf`). Measured with
/// `bench/learning_vs_pytorch.sh`'s benchmark: 12-13 % less time per step for "base" and the
/// U-Net. The process keeps its peak footprint instead of shrinking between steps. Without
/// mimalloc as the allocator this sets an unused option and changes nothing.
pub fn keep_freed_pages() {
    // SAFETY: sets one integer option; mimalloc reads options atomically and this one only
    // delays purging.
    unsafe { libmimalloc_sys::mi_option_set(MIMALLOC_PURGE_DELAY, -1) }
}

/// Hand the pages mimalloc keeps back to the kernel now (purge delay 0, a forced collection,
/// then the delay as it was), so that the next measurement of resident memory starts from what
/// is in use. Without mimalloc as the allocator this changes nothing.
pub fn release_freed_pages() {
    // SAFETY: integer options and a collection, which mimalloc allows at any time.
    unsafe {
        let delay = libmimalloc_sys::mi_option_get(MIMALLOC_PURGE_DELAY);
        libmimalloc_sys::mi_option_set(MIMALLOC_PURGE_DELAY, 0);
        libmimalloc_sys::mi_collect(true);
        libmimalloc_sys::mi_option_set(MIMALLOC_PURGE_DELAY, delay);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Option 15 is the purge delay: its default in the bundled mimalloc 3 (`src/options.c`'s
    /// table; `mimalloc.h`'s comment still says 10) is 1000 ms, which none of its neighbours
    /// (14: 1, 16: 0) has; after `keep_freed_pages` it reads -1 (never purge).
    #[test]
    fn the_option_set_is_mimallocs_purge_delay() {
        // SAFETY: reads of integer options.
        let get = |o| unsafe { libmimalloc_sys::mi_option_get(o) };
        assert_eq!(get(MIMALLOC_PURGE_DELAY), 1000, "mimalloc's default purge delay");
        keep_freed_pages();
        assert_eq!(get(MIMALLOC_PURGE_DELAY), -1);
    }
}
