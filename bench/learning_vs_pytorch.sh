#!/usr/bin/env bash
# Training throughput of wakelab's networks beside PyTorch's, measured in one run on this machine:
# "base" at 256 x 256 (batch 8) and the U-Net at 128 x 128 (batch 4), 2 CPU threads each; and
# `wakelab detect` with a "base" detector over an 8192 x 8192 image (windows of 32, stride 32)
# beside the same model and tiling in PyTorch.
# PyTorch is installed from PyPI into a throwaway venv (never a dependency of wakelab).
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${VENV:-/tmp/wakelab-torch-venv}
if [ ! -x "$VENV/bin/python" ] || ! "$VENV/bin/python" -c "import torch" 2>/dev/null; then
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install --quiet torch numpy
fi
echo "== PyTorch (CPU, 2 threads)"
"$VENV/bin/python" bench/pytorch_reference.py 2 | tee /tmp/wakelab-torch-bench.json
echo "== wakelab (burn flex, 2 cores)"
RAYON_NUM_THREADS=2 cargo bench -p wakelab-learn --bench training -- --noplot 2>&1 | tee /tmp/wakelab-burn-bench.txt
python3 - <<'PY'
import json, re
torch = json.load(open("/tmp/wakelab-torch-bench.json"))
text = open("/tmp/wakelab-burn-bench.txt").read()
def seconds(name):
    m = re.search(name + r"\s+time:\s+\[\S+ \S+ (\S+) (\S+)", text)
    value, unit = float(m.group(1)), m.group(2)
    return value * {"s": 1.0, "ms": 1e-3, "µs": 1e-6, "us": 1e-6}[unit]
for name, key, batch in [("base_256_batch8", "base_256_batch8", 8), ("unet_128_batch4", "unet_128_batch4", 4)]:
    ours, theirs = seconds("train_step/" + name), torch[key]["seconds_per_step"]
    print(f"{name}: wakelab {ours*1e3:.1f} ms/step ({batch/ours:.1f} img/s), PyTorch {theirs*1e3:.1f} ms/step "
          f"({batch/theirs:.1f} img/s): wakelab/PyTorch time ratio {ours/theirs:.2f}")
PY

echo "== wakelab detect, 8192 x 8192, \"base\" (32 x 32 windows, stride 32)"
WORK=${WORK:-/tmp/wakelab-scan-bench}
W=target/release/wakelab
cargo build --release --quiet -p wakelab
mkdir -p "$WORK"
python3 - "$WORK/tiny.toml" <<'PY'
import re, sys
s = open("configs/study/default.toml").read()
for a, b in [(r"^seeds = .*", "seeds = 1"), (r"^bands = .*", 'bands = ["LWIR"]'), (r"^fused_inputs = .*", "fused_inputs = []")]:
    s = re.sub(a, b, s, flags=re.M)
open(sys.argv[1], "w").write(s)
PY
$W dataset --study "$WORK/tiny.toml" --out "$WORK/data" --quiet
$W train "$WORK/data" --arch base --bands LWIR --epochs 1 --out "$WORK/learn" --quiet >/dev/null
"$VENV/bin/python" -c "import numpy as np, sys; np.save(sys.argv[1], (290 + np.random.default_rng(0).standard_normal((8192, 8192))).astype(np.float32))" "$WORK/scene.npy"
RAYON_NUM_THREADS=2 /usr/bin/time -f "%e %M" -o "$WORK/time.txt" $W detect "$WORK/scene.npy" \
  --model "$WORK/learn/LWIR_base.safetensors" --stride 32 --out "$WORK/scan" --quiet >/dev/null
python3 - "$WORK/time.txt" <<'PY'
import json, sys
seconds, kb = open(sys.argv[1]).read().split()
ours = 8192 * 8192 / float(seconds) / 1e6
theirs = json.load(open("/tmp/wakelab-torch-bench.json"))["scan_8192_base"]["megapixels_per_second"]
print(f"scan_8192_base: wakelab detect {ours:.1f} MP/s ({float(seconds):.1f} s, {int(kb) // 1024} MiB peak, reading the "
      f"image and writing the map included), PyTorch {theirs:.1f} MP/s (scoring only): wakelab/PyTorch throughput {ours / theirs:.2f}")
PY
