#!/usr/bin/env bash
# A whole Sentinel-1 IW GRD product (16854 x 25931 pixels; ESA's SAFE layout, written by the
# products crate's synthetic_product example: a -20 dB sea with 4-look speckle, thermal noise near
# -22 dB and no-data borders) read, calibrated, denoised and written as a COG by `wakelab
# calibrate`, and scanned by `wakelab detect` with the default run's C-band "base" detector
# (windows of 32 px, stride 16); wall time and peak memory of each, and the same scan (same
# model, windows, stride and normalisation) in PyTorch on this machine, 2 threads.
# Usage: bench/product_scan.sh [RUN_DIR] [LINES SAMPLES]   (RUN_DIR: a finished `wakelab run`)
set -euo pipefail
cd "$(dirname "$0")/.."
RUN=${1:-runs/default}
LINES=${2:-16854}
SAMPLES=${3:-25931}
WORK=${WORK:-/tmp/wakelab-product-bench}
VENV=${VENV:-/tmp/wakelab-torch-venv}
W=target/release/wakelab
cargo build --release --quiet -p wakelab
cargo build --release --quiet -p wakelab-products --example synthetic_product
mkdir -p "$WORK"
SAFE=$(target/release/examples/synthetic_product "$WORK" "$LINES" "$SAMPLES")
echo "== $SAFE ($LINES x $SAMPLES)"
RAYON_NUM_THREADS=2 /usr/bin/time -f "%e %M" -o "$WORK/calibrate.time" $W calibrate "$SAFE" --out "$WORK/sigma0.tif"
RAYON_NUM_THREADS=2 /usr/bin/time -f "%e %M" -o "$WORK/detect.time" $W detect "$SAFE" \
  --model "$RUN/learn/C/models/C_base.safetensors" --out "$WORK/scan" --quiet
if [ ! -x "$VENV/bin/python" ] || ! "$VENV/bin/python" -c "import torch" 2>/dev/null; then
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install --quiet torch numpy
fi
"$VENV/bin/python" bench/pytorch_reference.py 2 product "$LINES" "$SAMPLES" > "$WORK/torch.json"
python3 - "$WORK" "$LINES" "$SAMPLES" <<'PY'
import json, sys
work, lines, samples = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
mp = lines * samples / 1e6
for step in ["calibrate", "detect"]:
    seconds, kb = open(f"{work}/{step}.time").read().split()
    print(f"wakelab {step}: {float(seconds):.1f} s ({mp / float(seconds):.2f} MP/s), peak {int(kb) / 1024 / 1024:.2f} GiB")
seconds = float(open(f"{work}/detect.time").read().split()[0])
torch = json.load(open(f"{work}/torch.json"))
print(f"PyTorch {torch['torch']} scan (scoring only, 2 threads): {torch['seconds']:.1f} s ({torch['megapixels_per_second']:.2f} MP/s)")
print(f"wakelab detect (reading, calibration, scan and outputs included) / PyTorch scan: throughput ratio {torch['seconds'] / seconds:.2f}")
PY
