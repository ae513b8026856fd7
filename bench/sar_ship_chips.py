#!/usr/bin/env python3
"""Four real SAR chips of ships at sea with no visible wake, with the dataset's own ship boxes:
a wake-free set no rule of `wakelab detect` was set on, where ships without a wake are the
look-alike (the transfer issue's "ships without a visible wake").

usage: sar_ship_chips.py OUT [--mirrors DIR]

The chips are the SAR-Ship-Dataset samples (Wang et al. 2019, Remote Sensing 11(7), 765:
Gaofen-3 and Sentinel-1 chips of 256 x 256 pixels) that Rc-W024/SAR_Ship_detection_CFAR holds
at commit f2e4a779 in "Raw images/" (the repository is MIT), read with `git show` from
DIR/Rc-W024+SAR_Ship_detection_CFAR (default /work/.mirror). Of its twelve chips, the four
kept are those of open sea whose sea the display stretch kept. Five hold land, a harbour or a
river bank (looked at by eye, 2026-12-07: Gao_ship_hh_0201611139301040015,
Gao_ship_hh_02017012977040807, Gao_ship_hh_02017110638010408, Sen_ship_hh_0201610150202506,
Sen_ship_hv_02017102202012015) and are not read. Of the seven open-sea chips (OPEN_SEA), those
whose median grey is below CLIPPED (10 of 255) are left out, each printed with its median and
its share of 0s: the stretch clipped their sea to black, leaving no texture to judge a
detector on (one, 84 % zeros, `detect` reads as a no-data border and refuses).
Gao_ship_vh_020170115650701803 is kept with the sea-ice-like texture in its top-left corner. No chip shows a wake to the eye; several
show a ship's azimuth sidelobes as bright streaks.

Writes OUT/sd_NAME.png (the chip's first band; the JPEGs are grey, R = G = B) and
OUT/sd_NAME.geojson: no wake drawn (so bench/score_real_wakes.py counts it wake-free), each box
a Polygon of "kind": "ship" with "ships_drawn": true. The dataset states a chip's product
(Gaofen-3 at 3-10 m, Sentinel-1 SM or IW) but not its spacing: every chip is taken at 5 m, the
size that makes its ships 60-200 m long; the display scale, as the JPEGs are display-stretched.
Needs GDAL's Python bindings (python3-gdal) and numpy; reads the mirror with
bench/wake_free_images.py's helpers. Prints each output's name and sha256.
"""
import argparse
import hashlib
import json
import os
import re

import numpy as np
from osgeo import gdal

from wake_free_images import git_show, read_band

REPO, COMMIT = 'Rc-W024+SAR_Ship_detection_CFAR', 'f2e4a779'
OPEN_SEA = ['Gao_ship_hh_02017010717010109', 'Gao_ship_hh_0201802133701016010', 'Gao_ship_vh_020170115650701803',
            'Sen_ship_hh_0201705190105404', 'Sen_ship_vv_02017091501054029', 'ship010902', 'ship050304']
CLIPPED = 10
SPACING_M = 5


def boxes(xml):
    """The VOC annotation's ship boxes as closed pixel-coordinate rings."""
    rings = []
    for obj in re.findall(r'<object>(.*?)</object>', xml, re.S):
        x0, y0, x1, y1 = (float(re.search(f'<{k}>([0-9.]+)</{k}>', obj).group(1)) for k in ('xmin', 'ymin', 'xmax', 'ymax'))
        rings.append([[x0, y0], [x1, y0], [x1, y1], [x0, y1], [x0, y0]])
    return rings


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('out')
    parser.add_argument('--mirrors', default='/work/.mirror')
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    for chip in OPEN_SEA:
        grey = read_band(git_show(args.mirrors, REPO, COMMIT, f'Raw images/{chip}.jpg'), '.jpg')
        grey = (grey[0] if grey.ndim == 3 else grey).astype(np.uint8)
        if np.median(grey) < CLIPPED:
            print(f'left out {chip}: sea clipped to black (median grey {np.median(grey):.0f}, '
                  f'{np.mean(grey == 0):.0%} of pixels 0)')
            continue
        name = 'sd_' + chip
        png = os.path.join(args.out, name + '.png')
        mem = gdal.GetDriverByName('MEM').Create('', grey.shape[1], grey.shape[0], 1, gdal.GDT_Byte)
        mem.GetRasterBand(1).WriteArray(grey)
        gdal.GetDriverByName('PNG').CreateCopy(png + '.part', mem)
        os.replace(png + '.part', png)
        rings = boxes(git_show(args.mirrors, REPO, COMMIT, f'Raw images/{chip}.xml').decode())
        meta = {'type': 'FeatureCollection',
                'wakelab': {'coordinates': 'pixel', 'pixel_spacing_m': SPACING_M, 'scale': 'display', 'ships_drawn': True},
                'notes': f"SOURCE {REPO.replace('+', '/')}@{COMMIT}:Raw images/{chip}.jpg; no_wake",
                'features': [{'type': 'Feature', 'geometry': {'type': 'Polygon', 'coordinates': [r]},
                              'properties': {'kind': 'ship'}} for r in rings]}
        with open(os.path.join(args.out, name + '.geojson'), 'w') as f:
            json.dump(meta, f, indent=1)
        with open(png, 'rb') as f:
            print(name + '.png', hashlib.sha256(f.read()).hexdigest(), f'{len(rings)} ships')


if __name__ == '__main__':
    main()
