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

/// The device in words for reports: the backend and, on the CPU, its threads.
pub fn describe_device(device: &Device) -> String {
    let threads = rayon::current_num_threads();
    match format!("{device:?}") {
        d if d.to_lowercase().contains("flex") => format!("cpu (burn flex backend, {threads} threads)"),
        d => d,
    }
}

/// `cpu` (burn's pure-Rust `flex` backend, multi-threaded), `wgpu` (Vulkan/Metal/DX12; built with
/// `--features wgpu`), `cuda` (`--features cuda`, needs the CUDA toolkit), or `auto`: the GPU
/// backend this build has (cuda before wgpu), else the CPU.
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
