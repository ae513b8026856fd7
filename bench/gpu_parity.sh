#!/usr/bin/env bash
# The GPU path, executed: the wgpu backend against the CPU backend for every network (forward,
# loss, gradients, one optimiser step) and for a detector's scan
# (`crates/learn/tests/gpu_parity.rs`). On a machine without a GPU it runs on Mesa's software
# Vulkan driver, lavapipe, installed here from the system packages (as root, like `.ci/run`).
# `.ci/run` only checks that the wgpu build compiles: on the 2-core machine this script's build took
# 28 minutes and its run 23 (2026-11-27), too long for CI's 45. Run it when you touch the models,
# the training step or burn's version (CONTRIBUTING.md). On a machine with a GPU, `GPU_PARITY_ADAPTER=any bench/gpu_parity.sh`
# lets wgpu pick the card instead of pinning lavapipe.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
cd "$(dirname "$0")/.."
adapter=${GPU_PARITY_ADAPTER:-lavapipe}
case "$adapter" in
  lavapipe | any) ;;
  *)
    echo "GPU_PARITY_ADAPTER=$adapter: allowed are lavapipe (the default) and any" >&2
    exit 2
    ;;
esac

packages="mesa-vulkan-drivers vulkan-tools"
if ! dpkg -s $packages >/dev/null 2>&1; then
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends $packages >/dev/null
fi

# Which Vulkan devices the test can see; with no adapter at all the test fails, never skips.
if [ "$adapter" = lavapipe ]; then
  # only Mesa's lavapipe ICD, so a GPU elsewhere cannot stand in for it
  icd=$(ls /usr/share/vulkan/icd.d/lvp_icd*.json 2>/dev/null | head -n 1)
  if [ -z "$icd" ]; then
    echo "lavapipe's Vulkan ICD (lvp_icd*.json, package mesa-vulkan-drivers) is missing" >&2
    exit 1
  fi
  export VK_DRIVER_FILES="$icd" VK_ICD_FILENAMES="$icd"
fi
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
vulkaninfo --summary 2>/dev/null | grep -E "deviceName|driverName|apiVersion" || {
  echo "no Vulkan device: vulkaninfo found none" >&2
  exit 1
}

cargo test -p wakelab-learn --features wgpu --locked --test gpu_parity -- --nocapture --test-threads 1
