#!/usr/bin/env bash
# The transfer study trained on real wakes (`--wake-images`) and scored on real wake images it
# never saw, in two folds by set (docs/results.md, "Real wakes in training, scored across folds"):
#
# - fold A trains on the tuning set (30) and the fourth set (33 SSDD chips) and scores the three
#   held-out sets (37 wake images, 5 wake-free) and the other 3 wake-free images;
# - fold B trains on the held-out sets' 37 wake images and the fourth set and scores the tuning
#   set and the 8 wake-free images.
#
# Every wake image is so scored once, by detectors that never saw it; the wake-free images are
# trained on by neither fold. Both folds draw the simulated wakes onto the real sea SEA too
# (`--sea-images`, bench/ssdd_ships.py SEA --sea), whose detectors' thresholds then also hold
# the stated alarm rate on that sea.
#
#   bench/transfer_folds.sh DIR DIR4 SEA OUT [SEED]
#
# DIR: the 75 images of bench/real_wakes.sh (the tuning set and held-out sets 1-3, with the
# other wake-free images); DIR4: the fourth set (bench/real_wakes.sh --held-out-4); OUT gets the
# fold folders (links) and the two runs, OUT/A_SEED and OUT/B_SEED. WAKELAB names the binary
# (default target/release/wakelab). About 10 min a fold on 2 cores. Then
# `python3 bench/transfer_real_sets.py OUT/A_SEED OUT/B_SEED` gives each fold's figures.
set -euo pipefail
dir=$(realpath "${1:?usage: bench/transfer_folds.sh DIR DIR4 SEA OUT [SEED]}")
dir4=$(realpath "${2:?DIR4}")
sea=$(realpath "${3:?SEA}")
out=${4:?OUT}
seed=${5:-0}
here=$(cd "$(dirname "$0")" && pwd)
wakelab=${WAKELAB:-$here/../target/release/wakelab}
mkdir -p "$out"
out=$(realpath "$out")

# link NAME FROM INTO...: the image NAME of FROM and its drawing into each folder
link() {
  local name=$1 from=$2
  shift 2
  for into in "$@"; do
    mkdir -p "$into"
    for f in "$from/$name".*; do ln -sf "$f" "$into/"; done
  done
}
for g in "$here"/real_wakes/*.geojson; do link "$(basename "$g" .geojson)" "$dir" "$out/A_train" "$out/B_score"; done
for g in "$here"/held_out_wakes_4/*.geojson; do link "$(basename "$g" .geojson)" "$dir4" "$out/A_train" "$out/B_train"; done
for g in "$here"/held_out_wakes/*.geojson "$here"/held_out_wakes_2/*.geojson "$here"/held_out_wakes_3/*.geojson; do
  name=$(basename "$g" .geojson)
  case $name in
    hrsid_n*) link "$name" "$dir" "$out/A_score" "$out/B_score" ;;
    *) link "$name" "$dir" "$out/A_score" "$out/B_train" ;;
  esac
done
for name in hs je24 kp; do link "$name" "$dir" "$out/A_score" "$out/B_score"; done

study="$out/transfer_seed$seed.toml"
sed "s/^seed = 0$/seed = $seed/" "$here/../configs/study/transfer.toml" > "$study"
for fold in A B; do
  "$wakelab" run --study "$study" --sea-images "$sea" --wake-images "$out/${fold}_train" \
    --real "$out/${fold}_score" --out "$out/${fold}_$seed" --quiet
done
