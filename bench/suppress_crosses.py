#!/usr/bin/env python3
"""Take the sidelobe crosses out of a display-stretched SAR chip, offline, to see how much of a
detector's alarm they make (docs/results.md, "Sidelobe crosses as look-alikes, and a seed
ensemble"). An exploration, not part of wakelab.

usage: suppress_crosses.py IN.png OUT.png [--seed N]

Targets are the connected pixels at or above the larger of the chip's median + 8 MAD and its
99.9th percentile (two pixels at least). Along the rows through each target (its extent, 2
pixels either side) a pixel brighter than the 95th percentile of the same column in the 10 rows
beyond the band is replaced by one of those rows' pixels in that column, drawn at random; the
columns through it likewise. The target itself is kept. Replacing by the neighbours' speckle,
not clipping to their median, matters: a clipped band is a smooth dark line, which a wake
detector reads as a wake. numpy, scipy and Pillow.
"""
import argparse

import numpy as np
from PIL import Image
from scipy import ndimage

BAND = 2
REFERENCE = 10


def suppress(grey, rng):
    a = grey.astype(np.float32)
    median = np.median(a)
    mad = 1.4826 * np.median(np.abs(a - median)) + 1e-6
    level = max(median + 8 * mad, np.percentile(a, 99.9))
    labels, _ = ndimage.label(a >= level)
    out = a.copy()
    for rows, cols in ndimage.find_objects(labels):
        if (rows.stop - rows.start) * (cols.stop - cols.start) < 2:
            continue
        _replace_band(out, a, rows, cols, rng)
        _replace_band(out.T, a.T, cols, rows, rng)
    return out


def _replace_band(out, a, rows, cols, rng):
    """The rows through a target (rows x cols): bright pixels off the target replaced by the speckle
    of the rows just beyond the band, column by column."""
    h, w = a.shape
    r0, r1 = max(0, rows.start - BAND), min(h, rows.stop + BAND)
    reference = np.r_[max(0, r0 - REFERENCE):r0, r1:min(h, r1 + REFERENCE)]
    if len(reference) == 0:
        return
    values = a[reference]
    ceiling = np.percentile(values, 95, axis=0)
    band = out[r0:r1]
    off_target = np.ones(w, bool)
    off_target[max(0, cols.start - BAND):cols.stop + BAND] = False
    drawn = values[rng.integers(0, len(reference), size=band.shape), np.arange(w)[None, :]]
    replace = (band > ceiling[None, :]) & off_target[None, :]
    band[replace] = drawn[replace]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('source')
    ap.add_argument('out')
    ap.add_argument('--seed', type=int, default=0)
    a = ap.parse_args()
    grey = np.asarray(Image.open(a.source).convert('L'))
    cleaned = suppress(grey, np.random.default_rng(a.seed))
    Image.fromarray(np.clip(cleaned, 0, 255).astype(np.uint8)).save(a.out)


if __name__ == '__main__':
    main()
