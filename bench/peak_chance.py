#!/usr/bin/env python3
"""How often a detector's map would peak on a drawn wake by chance (docs/results.md, "Real wakes
in training, scored across folds").

usage: peak_chance.py DIR [FOOTPRINT_M]

A wake is found when a detection or the map's peak lies within 500 m of it (issue 38, item 7).
A detector that flags nothing still has a peak, so on a small image with a long wake its peak
lands on the wake often by chance. For each wake image of DIR (images with NAME.geojson in
pixel coordinates, as `--real` reads them) this takes the window centres a scan of FOOTPRINT_M
(default 1280) can have (the image less half a window each side; its middle where the image is
smaller than a window) on a 60 x 60 grid, and the share of them within 500 m of a drawn wake:
the chance that a peak placed at random is counted as found. Their sum per set (as
bench/threshold_cv.py names the sets) is the number of images a detector with a random peak
and no alarm would find. numpy and Pillow.

Superseded since 2026-12-02 by the transfer report's own `peak_by_chance` (and
bench/transfer_real_sets.py's "by chance"), which scores each image's very windows at random and
places the peak by `detect`'s rule. This uniform model is not that: on the 23 held-out images it
gives 9.4, where random windows give 4.6 through the rule `detect` had until then (the map's
largest cell, which favours the image's corners) and 8.1 through today's (the strongest window's place); docs/results.md, "The map's peak placed by
its strongest window". Kept so that the earlier sections' figures can be reproduced.
"""
import glob
import json
import os
import sys

import numpy as np
from PIL import Image

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from threshold_cv import set_of  # noqa: E402

Image.MAX_IMAGE_PIXELS = None
WITHIN_M = 500.0


def to_segment(x, y, a, b):
    (ax, ay), (bx, by) = a, b
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    t = np.clip(((x - ax) * dx + (y - ay) * dy) / length2, 0, 1) if length2 > 0 else 0
    return np.hypot(x - ax - t * dx, y - ay - t * dy)


def chance(geojson, footprint):
    drawing = json.load(open(geojson))
    how = drawing.get('wakelab', {})
    wakes = [f['geometry']['coordinates'] for f in drawing['features']
             if f['geometry']['type'] == 'LineString' and f.get('properties', {}).get('kind', 'wake') == 'wake']
    if not wakes or how.get('coordinates') != 'pixel':
        return None
    stem = geojson[:-len('.geojson')]
    image = next(p for p in glob.glob(glob.escape(stem) + '.*') if not p.endswith('.geojson'))
    width, height = Image.open(image).size
    spacing = how['pixel_spacing_m']
    half = 0.5 * footprint / spacing
    axis = lambda n: np.linspace(half, n - half, 60) if n > 2 * half else np.array([0.5 * n])
    x, y = np.meshgrid(axis(width), axis(height))
    nearest = np.full(x.shape, np.inf)
    for wake in wakes:
        for a, b in zip(wake[:-1], wake[1:]):
            nearest = np.minimum(nearest, to_segment(x, y, a, b))
    return float((nearest * spacing <= WITHIN_M).mean())


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    footprint = float(sys.argv[2]) if len(sys.argv) > 2 else 1280.0
    per_set = {}
    for geojson in sorted(glob.glob(os.path.join(sys.argv[1], '*.geojson'))):
        p = chance(geojson, footprint)
        if p is not None:
            name = os.path.basename(geojson)[:-len('.geojson')]
            per_set.setdefault(set_of(name), []).append(p)
    for label, shares in sorted(per_set.items()):
        print(f"  {label:<16} {len(shares):>3} wake images: a random peak on a wake in {sum(shares):.1f}")
    everything = [p for shares in per_set.values() for p in shares]
    print(f"  {'all':<16} {len(everything):>3} wake images: a random peak on a wake in {sum(everything):.1f}")


if __name__ == '__main__':
    main()
