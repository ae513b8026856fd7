#!/usr/bin/env python3
"""How `detect`'s averaging to the detector's 20 m treats a display image, and a copy averaged the
other way, for the fine-chip trials of docs/results.md ("Three knobs for the fine chips").

usage:
    display_averaging.py spread DIR
    display_averaging.py geometric DIR OUT

DIR holds NAME.png (or .npy) with NAME.geojson, as bench/score_real_wakes.py reads them; only the
drawings with "scale": "display" (the default) are taken.

spread: per image, the sea's robust deviation (1.4826 MAD, in the image's dB) about its 2 km
local mean, at the image's own pixels and once averaged to 20 m as `detect` averages a display
image (grey levels read as dB, the area mean taken of 10^(g/10), then 10 log10 again), and
their ratio. For independent N-look speckle the mean of k pixels shrinks the deviation by about
sqrt(k); the ratio says how far it shrinks here.

geometric: OUT gets NAME.npy, the image averaged to 20 m by the mean of its grey levels (the
geometric mean of 10^(g/10): the one average that does not depend on the display's unknown gain
in dB per grey level), and NAME.geojson with its drawn coordinates scaled alike and
"pixel_spacing_m": 20. Images at 20 m or coarser are copied as they are.

Needs numpy, Pillow and scipy.
"""
import json
import os
import sys

import numpy as np
from PIL import Image
from scipy.ndimage import uniform_filter

TARGET_M = 20.0
LOCAL_M = 2000.0


def drawings(src):
    """(name, drawing, spacing) of each display drawing in `src`."""
    for f in sorted(os.listdir(src)):
        if not f.endswith('.geojson'):
            continue
        with open(os.path.join(src, f)) as g:
            drawing = json.load(g)
        meta = drawing.get('wakelab', {})
        if meta.get('scale', 'display') == 'display':
            yield f[:-len('.geojson')], drawing, float(meta.get('pixel_spacing_m', 10))


def grey(src, name):
    for ext in ('.png', '.npy'):
        path = os.path.join(src, name + ext)
        if os.path.exists(path):
            if ext == '.npy':
                return np.load(path).astype(np.float64)
            return np.asarray(Image.open(path).convert('L')).astype(np.float64)
    sys.exit(f'{name}: no .png or .npy beside its drawing')


def box_mean(image, factor):
    """The area mean of `image` over blocks of `factor` pixels a side (fractional edges weighed)."""
    rows, cols = image.shape
    size = (max(1, round(cols / factor)), max(1, round(rows / factor)))
    return np.asarray(Image.fromarray(image.astype(np.float32), mode='F').resize(size, Image.BOX), dtype=np.float64)


def robust_local_spread(db, spacing):
    side = max(3, int(round(LOCAL_M / spacing)) | 1)
    residual = db - uniform_filter(db, size=min(side, min(db.shape)))
    return 1.4826 * np.median(np.abs(residual - np.median(residual)))


def spread(src):
    print('name spacing_m pixels_per_20m_pixel deviation_own deviation_20m ratio')
    for name, _, spacing in drawings(src):
        db = grey(src, name)
        factor = max(TARGET_M / spacing, 1.0)
        averaged = 10 * np.log10(np.maximum(box_mean(10 ** (db / 10), factor), 1e-30))
        own, coarse = robust_local_spread(db, spacing), robust_local_spread(averaged, TARGET_M)
        print(f'{name} {spacing:g} {factor * factor:.1f} {own:.2f} {coarse:.2f} {own / coarse:.2f}')


def scaled(coordinates, by):
    if coordinates and isinstance(coordinates[0], (int, float)):
        return [v / by for v in coordinates]
    return [scaled(c, by) for c in coordinates]


def geometric(src, out):
    os.makedirs(out, exist_ok=True)
    for name, drawing, spacing in drawings(src):
        image = grey(src, name)
        if spacing < TARGET_M:
            rows, cols = image.shape
            image = box_mean(image, TARGET_M / spacing)
            by = cols / image.shape[1]
            for feature in drawing['features']:
                feature['geometry']['coordinates'] = scaled(feature['geometry']['coordinates'], by)
            drawing['wakelab']['pixel_spacing_m'] = TARGET_M
        np.save(os.path.join(out, name + '.npy'), image.astype(np.float32))
        with open(os.path.join(out, name + '.geojson'), 'w') as g:
            json.dump(drawing, g)


def main():
    if len(sys.argv) == 3 and sys.argv[1] == 'spread':
        spread(sys.argv[2])
    elif len(sys.argv) == 4 and sys.argv[1] == 'geometric':
        geometric(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__.split('\n\n')[1])


if __name__ == '__main__':
    main()
