#!/usr/bin/env bash
# The 30 real SAR wake images of Ultraaaman/yolo3_ship_wake_detection (its test/ folder, commit
# fb66d81; the repository states no licence, so the images are not in this one), each with its
# wakes drawn by eye in bench/real_wakes/NAME.geojson (98 wakes, 71 of them "sure"; pixel
# coordinates, apex first). Fetches the images into DIR as single-band PNGs beside their GeoJSON
# (`wakelab detect` refuses colour images), then scores `wakelab detect`'s classic wake search on
# them (bench/score_real_wakes.py). The same DIR serves `wakelab run --study transfer --real DIR`.
#
#   bench/real_wakes.sh DIR [detect flags...]     # e.g. bench/real_wakes.sh /tmp/real_wakes
set -euo pipefail
dir=${1:?usage: bench/real_wakes.sh DIR [detect flags...]}
shift
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$dir"
if [ ! -f "$dir/0002.png" ]; then
  src=$(mktemp -d)
  git clone --quiet https://github.com/Ultraaaman/yolo3_ship_wake_detection "$src"
  git -C "$src" checkout --quiet fb66d81
  for g in "$here"/real_wakes/*.geojson; do
    name=$(basename "$g" .geojson)
    gdal_translate -q -b 1 -of PNG "$src/test/$name.jpg" "$dir/$name.png"
  done
  rm -rf "$src"
fi
cp "$here"/real_wakes/*.geojson "$dir/"
python3 "$here/score_real_wakes.py" "$dir" "$dir/out" "$@"
