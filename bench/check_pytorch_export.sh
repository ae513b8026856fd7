#!/usr/bin/env bash
# Do wakelab's PyTorch exports load into python/wakelab_torch.py with strict=True, and give
# wakelab's own probabilities? Trains "base", "cls" and "unet" (U-Net widths 8 and 16) on a small
# rendered dataset, plus a two-band "base", then for each export: load_state_dict(strict=True)
# and, for the single-band ones, the wake probability of a scene against `wakelab detect --json`
# on the same image (one window). Then the shipped detectors of models/ (line sums, a pooled
# head; file formats 3-4), through their exports there, on three 64 x 64 images against
# `wakelab detect --json`, and once more with their temperature set to 2 in both files (the
# calibrated probability). PyTorch, numpy and safetensors go into a throwaway venv
# ($VENV); they are never a dependency of wakelab. Exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${VENV:-/tmp/wakelab-torch-venv}
if ! "$VENV/bin/python" -c "import torch, numpy, safetensors" 2>/dev/null; then
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install --quiet torch numpy safetensors
fi
cargo build --release --quiet
W=target/release/wakelab
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cat > "$WORK/study.toml" <<'EOF'
[study]
name = "export"
combine = "product"
seeds = 3
test_fraction = 0.34
grouped_split = false
min_visibility = 0.0
mixed_layer_depth = 20.0
bands = ["S", "LWIR"]
[axes]
wind_speed = [5.0, 8.0]
image_size = [32]
pixel_spacing = [20.0]
along_track = [2000.0]
[base]
preset = "quick"
[base.time]
duration = 600.0
EOF
"$W" dataset --study "$WORK/study.toml" --out "$WORK/data" --quiet
M="$WORK/models"
"$W" train "$WORK/data" --bands S --arch base --epochs 2 --out "$M" --quiet >/dev/null
"$W" train "$WORK/data" --bands LWIR --arch cls --epochs 2 --out "$M" --quiet >/dev/null
"$W" train "$WORK/data" --bands S --arch unet --epochs 2 --unet-epochs 1 --unet-width 8 --out "$M" --quiet >/dev/null
"$W" train "$WORK/data" --bands LWIR --arch unet --epochs 2 --unet-epochs 1 --unet-width 16 --out "$M" --quiet >/dev/null
"$W" train "$WORK/data" --bands S+LWIR --arch base --epochs 2 --out "$M" --quiet >/dev/null
SCENE="$WORK/data/scenes/000000-w"
for model in S_base LWIR_cls S_unet LWIR_unet; do
  band=${model%%_*}
  "$W" detect "$SCENE/$band.npy" --model "$M/$model.safetensors" --json --quiet --out "$WORK/detect-$model" \
    > "$WORK/$model.json"
done
PYTHONPATH=python "$VENV/bin/python" - "$M" "$SCENE" "$WORK" <<'PY'
import json, sys
import numpy as np
import torch
from wakelab_torch import detector_input, load_detector

models, scene, work = sys.argv[1:4]
failures = 0
for name in ["S_base", "LWIR_cls", "S_unet", "LWIR_unet", "S+LWIR_base"]:
    model, info = load_detector(f"{models}/{name}.pytorch.safetensors")  # strict=True inside
    params = sum(p.numel() for p in model.parameters())
    line = f"{name}: loaded strictly ({info['architecture']}, bands {info['bands']}, width {info['unet_width']}, {params} parameters)"
    if len(info["bands"]) == 1:
        band = info["bands"][0]
        x = detector_input(np.load(f"{scene}/{band}.npy"), band)
        with torch.no_grad():
            ours = float(model(torch.from_numpy(x)[None, None])[0])
        theirs = json.load(open(f"{work}/{name}.json"))["probability"]
        ok = abs(ours - theirs) < 1e-4
        failures += not ok
        line += f"; probability PyTorch {ours:.6f}, wakelab {theirs:.6f}: {'same' if ok else 'DIFFERENT'}"
    print(line)
sys.exit(1 if failures else 0)
PY
# the shipped detectors: three linear sigma0 images of one window (speckle; a dark line; a
# bright line), each detector at its own spacing, as shipped and with temperature 2
PYTHONPATH=python "$VENV/bin/python" - "$W" "$WORK" <<'PY'
import json, subprocess, sys
import numpy as np
import torch
from safetensors.numpy import load_file, save_file
from safetensors import safe_open
from wakelab_torch import detector_input, load_detector

wakelab, work = sys.argv[1:3]
rng = np.random.default_rng(1)
images = []
for k, gain in enumerate([1.0, 0.3, 4.0]):
    image = rng.exponential(0.02, (64, 64)).astype(np.float32)
    rows = np.arange(64)
    image[rows, (rows * 0.4 + 10 * k).astype(int)] *= gain
    images.append(f"{work}/shipped{k}.npy")
    np.save(images[-1], image)

def with_temperature(path, out, temperature):
    with safe_open(path, framework="np") as f:
        meta = dict(f.metadata())
    meta["wakelab.temperature"] = str(temperature)
    save_file(load_file(path), out, metadata=meta)

failures = 0
for name in ["C_transfer_1280m", "C_transfer_2560m"]:
    for temperature in [None, 2.0]:
        main, export = f"models/{name}.safetensors", f"models/{name}.pytorch.safetensors"
        if temperature is not None:
            main, export = f"{work}/{name}.safetensors", f"{work}/{name}.pytorch.safetensors"
            with_temperature(f"models/{name}.safetensors", main, temperature)
            with_temperature(f"models/{name}.pytorch.safetensors", export, temperature)
        model, info = load_detector(export)
        for image in images:
            x = detector_input(np.load(image), "C", info)
            with torch.no_grad():
                ours = float(model(torch.from_numpy(x)[None, None])[0])
            run = subprocess.run(
                [wakelab, "detect", image, "--model", main, "--pixel-spacing", str(info["pixel_spacing"]),
                 "--scale", "linear", "--json", "--quiet", "--out", f"{work}/detect-shipped"],
                check=True, capture_output=True, text=True)
            theirs = json.loads(run.stdout)["probability"]
            ok = abs(ours - theirs) < 1e-4 and abs(model.window_probability(np.load(image)) - ours) < 1e-7
            failures += not ok
            print(f"{name} ({info['input_form']}, {info['head']}, temperature {info['temperature']:g}) "
                  f"{image.rsplit('/', 1)[1]}: PyTorch {ours:.6f}, wakelab {theirs:.6f}: {'same' if ok else 'DIFFERENT'}")
sys.exit(1 if failures else 0)
PY
echo "every export loads with strict=True and scores as wakelab does"
