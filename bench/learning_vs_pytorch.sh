#!/usr/bin/env bash
# Training throughput of wakelab's networks beside PyTorch's, measured in one run on this machine:
# "base" at 256 x 256 (batch 8) and the U-Net at 128 x 128 (batch 4), 2 CPU threads each.
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
