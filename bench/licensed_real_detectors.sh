#!/usr/bin/env bash
# Candidate detectors for shipping (models/README.md): the embedded transfer study trained on real
# sea and real wakes too, from images whose repositories carry a licence:
#
# - real wakes (`--wake-images`): the 12 OpenSARWake samples (osw_*, libzzluo/OpenSARWake, MIT),
#   the Sentinel-1 tiles s1lf_01 and eob_01 (MIT repositories, Copernicus data) and the 33 SSDD
#   chips of the fourth set (Lemon-L7/efficient-pytorch-ship, MIT; SSDD itself asks for research
#   use and citation, and holds RadarSat-2 and TerraSAR-X imagery): 47 images, 69 wakes drawn;
# - real sea (`--sea-images`): the 705 other SSDD chips of bench/ssdd_ships.py --sea.
#
# No image of the tuning set (no licence), of HRSID (GPL-3.0 data) or of a repository without a
# licence is trained on: those are what the detectors are scored on (SCORE, optional: `--real`,
# e.g. a folder of bench/real_wakes.sh's images less the ones above; docs/results.md, "Real wakes
# from licensed images", says which 61 were used).
#
#   MIRRORS=/work/.mirror bench/licensed_real_detectors.sh OUT [SCORE]
#
# MIRRORS holds the repositories bench/held_out_wakes.py names (its docstring; default
# /work/.mirror). OUT gets images/ (the four held-out sets, cut), wakes/ (links to the 47),
# sea/ (the SSDD chips) and run/ (the study's output, run/detectors/C_transfer_*.safetensors).
# SEED (default 0, the embedded study's) sets every draw; another seed writes run_seedSEED/.
# STUDY (default: the embedded configs/study/transfer.toml) trains another study file instead,
# its `seed = 0` line set to SEED, and writes run_NAME_seedSEED/ (NAME: the file's stem).
# OFFSHORE=1 takes the real sea without the SSDD chips that hold land (bench/ssdd_ships.py
# --sea --offshore, into sea_offshore/) and adds _offshore to the run's folder. DISTINCT=1 keeps
# one chip of each set of SSDD's copies and leaves out the sets where a faint wake was seen
# (--distinct, into sea[_offshore]_distinct/; bench/held_out_wakes_4/sea_wakes.txt) and adds
# _distinct.
# About 10-17 min on 2 cores with 61 images scored (machines differ twofold), once the images are
# cut (20 s).
set -euo pipefail
out=${1:?usage: bench/licensed_real_detectors.sh OUT [SCORE]}
score=${2:-}
here=$(cd "$(dirname "$0")" && pwd)
wakelab=${WAKELAB:-$here/../target/release/wakelab}
mirrors=${MIRRORS:-/work/.mirror}
seed=${SEED:-0}
mkdir -p "$out/images" "$out/wakes"
out=$(realpath "$out")

[ -f "$out/images/osw_01.png" ] || python3 "$here/held_out_wakes.py" "$out/images" --mirrors "$mirrors" >/dev/null
[ -f "$out/images/s1lf_01.png" ] || python3 "$here/held_out_wakes.py" "$out/images" --second --mirrors "$mirrors" >/dev/null
[ -f "$out/images/eob_01.png" ] || python3 "$here/held_out_wakes.py" "$out/images" --third --mirrors "$mirrors" >/dev/null
[ -f "$out/images/ssdd_000028.png" ] || python3 "$here/held_out_wakes.py" "$out/images" --fourth --mirrors "$mirrors" >/dev/null
sea=sea
sea_flags=()
if [ "${OFFSHORE:-0}" = 1 ]; then
  sea=sea_offshore
  sea_flags=(--offshore)
fi
if [ "${DISTINCT:-0}" = 1 ]; then
  sea=${sea}_distinct
  sea_flags+=(--distinct)
  # a new list of chips seen with a wake asks for the set to be written again
  [ "$out/$sea/.written" -nt "$here/held_out_wakes_4/sea_wakes.txt" ] || rm -f "$out/$sea/.written"
fi
[ -f "$out/$sea/.written" ] || {
  rm -rf "${out:?}/$sea"
  python3 "$here/ssdd_ships.py" "$out/$sea" --sea "${sea_flags[@]}" --mirrors "$mirrors"
  touch "$out/$sea/.written"
}

licensed=$(
  for g in "$here"/held_out_wakes/osw_*.geojson "$here"/held_out_wakes_2/s1lf_*.geojson \
    "$here"/held_out_wakes_3/eob_*.geojson "$here"/held_out_wakes_4/ssdd_*.geojson; do
    basename "$g" .geojson
  done
)
for name in $licensed; do
  ln -sf "$out/images/$name.png" "$out/wakes/"
  # the fourth set's drawings are written with the images (SSDD's ship boxes added)
  case $name in
    ssdd_*) ln -sf "$out/images/$name.geojson" "$out/wakes/" ;;
    *) ln -sf "$(ls "$here"/held_out_wakes*/"$name.geojson")" "$out/wakes/$name.geojson" ;;
  esac
done

study=transfer
run="$out/run"
if [ -n "${STUDY:-}" ]; then
  name=$(basename "$STUDY" .toml)
  run="$out/run_${name}_seed$seed"
  study="$out/${name}_seed$seed.toml"
  sed "s/^seed = 0$/seed = $seed/" "$STUDY" >"$study"
elif [ "$seed" != 0 ]; then
  run="$out/run_seed$seed"
  study="$out/transfer_seed$seed.toml"
  sed "s/^seed = 0$/seed = $seed/" "$here/../configs/study/transfer.toml" >"$study"
fi
if [ "${OFFSHORE:-0}" = 1 ]; then run="${run}_offshore"; fi
if [ "${DISTINCT:-0}" = 1 ]; then run="${run}_distinct"; fi
real=()
[ -z "$score" ] || real=(--real "$score")
"$wakelab" run --study "$study" --sea-images "$out/$sea" --wake-images "$out/wakes" "${real[@]}" \
  --out "$run" --quiet
sha256sum "$run"/detectors/C_transfer_*.safetensors
