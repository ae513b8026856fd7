#!/usr/bin/env bash
# `wakelab detect` on a whole scene: a 1024 x 1024 scene rendered by the default study's physics
# (one wake at 3 m/s, slicks, speckle) scanned by the default run's LWIR detectors, the map's peak
# and the strongest detections measured against the wake's mask; then the same scene tiled to
# 4096 x 4096 and 8192 x 8192 for speed (megapixels per second) and peak memory.
# Usage: bench/detect_scene.sh [RUN_DIR]   (RUN_DIR: a finished `wakelab run`, default runs/default)
set -euo pipefail
cd "$(dirname "$0")/.."
RUN=${1:-runs/default}
W=target/release/wakelab
WORK=${WORK:-/tmp/wakelab-detect-scene}
cargo build --release --quiet -p wakelab
mkdir -p "$WORK"
python3 - "$WORK/large.toml" <<'PY'
import sys, re
s = open("configs/study/default.toml").read()
for a, b in [(r"^seeds = .*", "seeds = 1"), (r"^wind_speed = .*", "wind_speed = [3.0]"),
             (r"^swell_direction = .*", 'swell_direction = ["calm"]'),
             (r"^stratification = .*", 'stratification = ["linear"]'),
             (r"^image_size = .*", "image_size = [1024]"), (r"^bands = .*", 'bands = ["S", "LWIR"]'),
             (r"^cross_track = .*", "cross_track = [-2000.0, 2000.0]"), (r"^fused_inputs = .*", "fused_inputs = []")]:
    s = re.sub(a, b, s, flags=re.M)
open(sys.argv[1], "w").write(s)
PY
$W dataset --study "$WORK/large.toml" --out "$WORK/scene" --quiet
SCENE="$WORK/scene/scenes/000000-w"
for arch in base cls; do
  $W detect "$SCENE/LWIR.npy" --model "$RUN/learn/LWIR/models/LWIR_$arch.safetensors" --stride 16 \
    --out "$WORK/lwir_$arch" --quiet
done
python3 - "$WORK" <<'PY'
import json, struct, sys
work = sys.argv[1]
b = open(work + "/scene/scenes/000000-w/mask_LWIR.npy", "rb").read()
hl = struct.unpack("<H", b[8:10])[0]
mask = b[10 + hl:]
n = int(b[10:10 + hl].decode().split("(")[1].split(",")[0])
points = [(i // n, i % n) for i, v in enumerate(mask) if v > 0]
dist = lambda r, c: min(((pr + 0.5 - r) ** 2 + (pc + 0.5 - c) ** 2) ** 0.5 for pr, pc in points)
for arch in ["base", "cls"]:
    d = json.load(open(f"{work}/lwir_{arch}/detections.json"))
    p = d["peak"]
    top = [round(dist(x["row"], x["col"])) for x in d["detections"][:10]]
    print(f"LWIR {arch}: peak {dist(p['row'], p['col']):.0f} px from the wake mask; "
          f"{len(d['detections'])} detections at threshold {d['threshold']}; "
          f"the 10 strongest lie {top} px from it")
PY
for k in 4 8; do
  python3 bench/tile_scene.py "$SCENE/LWIR.npy" $k "$WORK/tiled_$k.npy"
  /usr/bin/time -f "tiled x$k: %e s, %M KB peak RSS" $W detect "$WORK/tiled_$k.npy" \
    --model "$RUN/learn/LWIR/models/LWIR_base.safetensors" --stride 32 --out "$WORK/tiled_$k" --quiet
done
