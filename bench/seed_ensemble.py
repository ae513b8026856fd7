#!/usr/bin/env python3
"""Whether averaging the probability maps of several runs (seeds) puts the peak on real wakes more
often than each run alone (docs/results.md, "Sidelobe crosses as look-alikes, and a seed
ensemble").

usage: seed_ensemble.py DIR RUN [RUN...] [--footprint 1280m]

DIR holds the real images with their NAME.geojson (wakes as LineStrings in pixel coordinates, as
`--real` reads them); each RUN is a `wakelab run --study ... --real DIR` output, whose
RUN/real/FOOTPRINT/NAME/ holds the scan's probability.tif and detections.json. For each wake
image the runs' maps are averaged cell by cell and the mean's peak is scored as the study scores
one run's (src: crates/study/src/transfer/real.rs): found when it lies within 500 m of a drawn
wake. Each run's own peak is first checked against the one its detections.json states, so the
cells are placed as the scan placed them. Prints per image and per set (bench/threshold_cv.py's
sets). GDAL's Python bindings (python3-gdal, the system's python3) and numpy.
"""
import argparse
import json
import math
import os
import sys
import warnings

import numpy as np
from osgeo import gdal

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from score_real_wakes import CNN_RADIUS_M as WITHIN_M, point_segment  # noqa: E402
from threshold_cv import set_of  # noqa: E402


def wakes_of(geojson):
    return [f['geometry']['coordinates'] for f in geojson['features']
            if f['properties'].get('kind') != 'ship' and f['geometry']['type'] == 'LineString']


def to_wakes(row, col, wakes, spacing):
    """Metres from the product pixel (row, col) to the nearest drawn wake ([column, row] points)."""
    metres = lambda q: (q[0] * spacing[1], q[1] * spacing[0])
    p = (col * spacing[1], row * spacing[0])
    return min((point_segment(p, metres(a), metres(b)) for w in wakes for a, b in zip(w, w[1:])),
               default=math.inf)


def peak_place(probability, scan):
    """The product pixel of the map's largest cell, where the scan puts a cell's centre."""
    i, k = np.unravel_index(np.nanargmax(probability), probability.shape)
    stride, factor = scan['stride'], scan['resampled']
    return (i + 0.5) * stride * factor[0], (k + 0.5) * stride * factor[1]


def score(directory, runs, footprint):
    rows = []
    for name in sorted(os.listdir(os.path.join(runs[0], 'real', footprint))):
        path = os.path.join(directory, name + '.geojson')
        if not os.path.exists(path):
            continue
        wakes = wakes_of(json.load(open(path)))
        if not wakes:
            continue
        maps, scans = [], []
        for run in runs:
            folder = os.path.join(run, 'real', footprint, name)
            maps.append(gdal.Open(os.path.join(folder, 'probability.tif')).ReadAsArray().astype(float))
            scans.append(json.load(open(os.path.join(folder, 'detections.json'))))
        for probability, scan in zip(maps, scans):
            row, col = peak_place(probability, scan)
            stated = scan['peak']
            if abs(row - stated['product_row']) > 1e-3 or abs(col - stated['product_col']) > 1e-3:
                sys.exit(f'{name}: peak placed at ({row}, {col}), the scan says {stated}')
        spacing = (scans[0]['product']['pixel_spacing']['rows'], scans[0]['product']['pixel_spacing']['columns'])
        each = [to_wakes(*peak_place(m, s), wakes, spacing) <= WITHIN_M for m, s in zip(maps, scans)]
        with warnings.catch_warnings():
            # a cell no run scored (no data) stays NaN and is never the peak
            warnings.simplefilter('ignore', RuntimeWarning)
            mean = np.nanmean(np.stack(maps), axis=0)
        rows.append((name, len(wakes), each, to_wakes(*peak_place(mean, scans[0]), wakes, spacing) <= WITHIN_M))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('dir')
    ap.add_argument('runs', nargs='+')
    ap.add_argument('--footprint', default='1280m')
    a = ap.parse_args()
    rows = score(a.dir, a.runs, a.footprint)
    for name, wakes, each, mean in rows:
        print(f'{name:14s} wakes {wakes}  each run {"".join(str(int(x)) for x in each)}  mean {int(mean)}')
    sets = sorted({set_of(r[0]) for r in rows})
    for label in sets + ['held-out, all', 'all']:
        chosen = [r for r in rows if label == 'all' or set_of(r[0]) == label
                  or (label == 'held-out, all' and set_of(r[0]).startswith('held-out'))]
        each = [sum(r[2][k] for r in chosen) for k in range(len(a.runs))]
        print(f'{label:14s} {len(chosen):2d} wake images: peak on a wake, each run {each}, their mean map {sum(r[3] for r in chosen)}')


if __name__ == '__main__':
    main()
