#!/usr/bin/env python3
"""SSDD chips with SSDD's own ship boxes, to score `wakelab detect`'s ship search on chips no
rule was set on.

usage: ssdd_ships.py OUT_DIR [--every N] [--test-split | --sea [--offshore] [--distinct]] [--mirrors DIR]

Writes OUT_DIR/ssdd_ID.png (the chip's R channel; the JPEGs are grey, R = G = B, but for a few
whose differing pixels are listed) and
OUT_DIR/ssdd_ID.geojson (each box a Polygon of "kind": "ship", "ships_drawn": true and
"wakes_drawn": false, so that bench/score_real_wakes.py scores the ships alone) for every Nth
chip (default 3), in ID order, of SSDD's train split (IDs ending in neither 1 nor 9: the test
split's chips set the display ship search's false-alarm probability and the bright arm's cap),
leaving out the fourth held-out wake set's chips and 000006 (docs/results.md). The chips are
those of Lemon-L7/efficient-pytorch-ship at commit 05b50517 (VOCdevkit/VOC2007; the
repository is MIT, SSDD is released for research with citation), read with `git show` from
DIR/Lemon-L7+efficient-pytorch-ship (or DIR/efficient-pytorch-ship; default /work/.mirror), as
bench/held_out_wakes.py reads them (its functions are used here).

SSDD states no pixel spacing per chip. A chip is taken at 3 m where its longest box is over 40
pixels, else at 10 m: the fourth set's rule. Chips that would fill under half of the shipped
detector's 64-pixel window once averaged to 20 m (`detect` refuses them) are left out and
counted. With --test-split, every chip of the test split instead (IDs ending in 1 or 9), all
taken at 10 m as the 2026-11-28 ship study took them. With --sea, every chip of the train
split less also the 210 chips the fourth set's screeners looked at closely for wakes
(bench/held_out_wakes_4/screened.txt: every candidate among them): real sea for
`wakelab run --study transfer --sea-images DIR`, which refuses an image with a wake drawn. `wakelab run --study transfer --real DIR` does not read "wakes_drawn" and would take
these chips for wake-free images: score them with bench/score_real_wakes.py. With --offshore
too, the chips that hold land are left out (`land_share` over LAND_SHARE: harbours, river
banks, coasts; docs/results.md, "Sidelobe crosses as look-alikes, and a seed ensemble", where
the rule was set by eye on the chips either side of it). With --distinct too, one chip of each
set of copies (SSDD cut most scenes into several overlapping chips: `copies`), the largest, is
kept, and the chips listed in bench/held_out_wakes_4/sea_wakes.txt (a faint wake seen on a
second look, or a copy of one) are left out. Needs what bench/held_out_wakes.py
needs (numpy, Pillow, scipy).
"""
import argparse
import io
import json
import os
import subprocess
import sys

import numpy as np
from PIL import Image

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from held_out_wakes import SSDD, blob, git_dir, ssdd_ship_boxes  # noqa: E402

WINDOW = 64
SCANNED_M = 20.0
# land: cells of CELL x CELL pixels off the ships whose median stands LAND_GREY grey levels over
# the chip's median off the ships, in more than LAND_SHARE of the cells
CELL, LAND_GREY, LAND_SHARE, SHIP_MARGIN = 8, 40, 0.01, 15
# copies: ship boxes alike in size (within SIZE_SHARE) whose patches, 16 x 16, correlate over
# SHIP_CORR, confirmed by the sea around the ship (3 boxes wide, the box itself out) correlating
# over SEA_CORR at the best shift within SHIFT pixels
SIZE_SHARE, SHIP_CORR, SEA_CORR, SHIFT = 0.25, 0.9, 0.5, 4


def land_share(grey, boxes):
    """The share of a chip's CELL-pixel cells, away from its ship boxes (grown by SHIP_MARGIN
    pixels), that are bright texture: a cell's median LAND_GREY levels over the sea's. Open sea
    with ships scored 0-0.016 in the chips looked at; harbours, river banks and coasts 0.02-0.25.
    Not `wakelab detect`'s own land mask (crates/ships/src/land.rs): it asks for land holding a
    400 m disc, which a chip of 1-1.5 km rarely has (it found land on 2 of the 22 chips with the
    strongest alarms, 6 of them harbours or river banks), and this screen leans on SSDD's ship
    boxes, which a user's image lacks."""
    h, w = grey.shape
    ships = np.zeros((h, w), bool)
    for x0, y0, x1, y1 in boxes:
        ships[max(0, int(y0) - SHIP_MARGIN):int(y1) + SHIP_MARGIN, max(0, int(x0) - SHIP_MARGIN):int(x1) + SHIP_MARGIN] = True
    sea = np.median(grey[~ships]) if (~ships).any() else np.median(grey)
    hh, ww = h // CELL * CELL, w // CELL * CELL
    cells = grey[:hh, :ww].astype(np.float32).reshape(hh // CELL, CELL, ww // CELL, CELL)
    medians = np.median(cells.transpose(0, 2, 1, 3).reshape(hh // CELL, ww // CELL, -1), axis=2)
    on_ship = ships[:hh, :ww].reshape(hh // CELL, CELL, ww // CELL, CELL).any(axis=(1, 3))
    return float(((medians > sea + LAND_GREY) & ~on_ship).mean())


def unit(v):
    """`v` flattened, less its mean, over its norm: dot products of two are correlations."""
    v = v.ravel().astype(np.float64) - v.mean()
    return v / (np.linalg.norm(v) + 1e-9)


def sea_around(grey, box, half, hole, shift):
    """The sea around `box` (x0, y0, x1, y1): a crop of half-size `half` (columns, rows) centred
    on the box moved by `shift` (columns, rows), less a centred hole of `hole` (columns, rows)
    grown by 3 pixels (the ship); None where the crop leaves the chip."""
    (x0, y0, x1, y1), (hw, hh), (dx, dy), (w, h) = box, half, shift, hole
    cx, cy = (x0 + x1) / 2 + dx, (y0 + y1) / 2 + dy
    r0, c0 = int(cy - hh), int(cx - hw)
    if r0 < 0 or c0 < 0 or r0 + 2 * int(hh) > grey.shape[0] or c0 + 2 * int(hw) > grey.shape[1]:
        return None
    crop = grey[r0:r0 + 2 * int(hh), c0:c0 + 2 * int(hw)].astype(np.float32)
    keep = np.ones(crop.shape, bool)
    br, bc = int(hh - h / 2) - 3, int(hw - w / 2) - 3
    keep[max(br, 0):br + int(h) + 6, max(bc, 0):bc + int(w) + 6] = False
    return crop[keep]


def copies(chips):
    """The sets of chips (names) that show the same sea: SSDD cut one scene into overlapping
    chips around the same ships. Two chips are copies when a ship box of each matches in size and
    look (SHIP_CORR) and the sea around the two ships matches too (SEA_CORR): a ship alone is a
    bright blob much like any other, speckle and swell around it are not. In an exploratory pass
    over the offshore set's 2,465 candidate pairs the sea correlated under 0.25 in 1,764 (other
    scenes), 0.55-1.0 in 526 (copies, resampled ones lower) and in between in 175, which the
    0.5 line splits unchecked.
    Checked on a synthetic scene of gamma speckle: two overlapping crops are one set, the same
    ship pasted into another sea is not; a box drawn 3 pixels off on a 20-pixel ship escapes
    (its patch correlates 0.80), so copies whose boxes SSDD drew apart may remain.
    `chips`: name -> (grey, boxes). Sets, each in name order, singletons included."""
    patches = []
    for name, (grey, boxes) in chips.items():
        for x0, y0, x1, y1 in boxes:
            if x1 - x0 < 6 or y1 - y0 < 6:
                continue
            patch = Image.fromarray(grey[int(y0):int(y1), int(x0):int(x1)]).resize((16, 16), Image.BILINEAR)
            patches.append((name, (x0, y0, x1, y1), unit(np.asarray(patch, np.float32))))
    if not patches:
        return [[n] for n in sorted(chips)]
    looks = np.array([p[2] for p in patches])
    alike = looks @ looks.T
    parent = {n: n for n in chips}

    def root(n):
        while parent[n] != n:
            parent[n] = parent[parent[n]]
            n = parent[n]
        return n

    for i, (a, box_a, _) in enumerate(patches):
        for j in np.nonzero(alike[i, i + 1:] > SHIP_CORR)[0] + i + 1:
            b, box_b, _ = patches[j]
            if root(a) == root(b):
                continue
            (wa, ha), (wb, hb) = ((x1 - x0, y1 - y0) for x0, y0, x1, y1 in (box_a, box_b))
            if abs(wa - wb) > SIZE_SHARE * max(wa, wb) or abs(ha - hb) > SIZE_SHARE * max(ha, hb):
                continue
            hole = (max(wa, wb), max(ha, hb))
            # the widest ring of sea that both chips hold around their ship
            for half in ((1.5 * hole[0], 1.5 * hole[1]), hole):
                sea = sea_around(chips[a][0], box_a, half, hole, (0, 0))
                if sea is not None and sea_around(chips[b][0], box_b, half, hole, (0, 0)) is not None:
                    break
            else:
                continue
            sea = unit(sea)
            best = max((float(sea @ unit(other)) for dy in range(-SHIFT, SHIFT + 1) for dx in range(-SHIFT, SHIFT + 1)
                        for other in [sea_around(chips[b][0], box_b, half, hole, (dx, dy))]
                        if other is not None and other.size == sea.size), default=-1.0)
            if best > SEA_CORR:
                parent[root(a)] = root(b)
    sets = {}
    for n in sorted(chips):
        sets.setdefault(root(n), []).append(n)
    return sorted(sets.values())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('out_dir')
    ap.add_argument('--every', type=int, default=3)
    split = ap.add_mutually_exclusive_group()
    split.add_argument('--test-split', action='store_true')
    split.add_argument('--sea', action='store_true')
    ap.add_argument('--offshore', action='store_true')
    ap.add_argument('--distinct', action='store_true')
    ap.add_argument('--mirrors', default='/work/.mirror')
    a = ap.parse_args()
    if a.offshore and not a.sea:
        sys.exit('--offshore: only with --sea (real sea without land)')
    if a.distinct and not a.sea:
        sys.exit('--distinct: only with --sea (one chip of each set of copies)')
    if a.every < 1:
        sys.exit(f'--every {a.every}: a whole number of at least 1 (every Nth chip)')
    git = git_dir(a.mirrors, SSDD[0])
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'held_out_wakes_4')
    fourth = {f[len('ssdd_'):-len('.geojson')] for f in os.listdir(here) if f.endswith('.geojson')}
    listing = subprocess.run(['git', '--git-dir', git, 'ls-tree', '--name-only', SSDD[1],
                              'VOCdevkit/VOC2007/Annotations/'], check=True, capture_output=True, text=True)
    ids = sorted(os.path.basename(p)[:-len('.xml')] for p in listing.stdout.split() if p.endswith('.xml'))
    train = [i for i in ids if i[-1] not in '19' and i not in fourth and i != '000006']
    if a.test_split:
        train, a.every = [i for i in ids if i[-1] in '19'], 1
    if a.sea:
        with open(os.path.join(here, 'screened.txt')) as f:
            screened = set(f.read().split())
        train, a.every = [i for i in train if i not in screened], 1
    os.makedirs(a.out_dir, exist_ok=True)
    small, empty, land, coloured, chosen = 0, 0, 0, [], {}
    for chip in train[::a.every]:
        boxes = ssdd_ship_boxes(a.mirrors, chip)
        if not boxes:
            empty += 1
            continue
        rgb = np.asarray(Image.open(io.BytesIO(blob(a.mirrors, SSDD, f'VOCdevkit/VOC2007/JPEGImages/{chip}.jpg'))).convert('RGB'))
        if not ((rgb[..., 0] == rgb[..., 1]).all() and (rgb[..., 0] == rgb[..., 2]).all()):
            coloured.append(f'{chip} ({(rgb[..., 0] != rgb[..., 2]).mean():.1%})')
        spacing = 3 if max(max(x1 - x0, y1 - y0) for x0, y0, x1, y1 in boxes) > 40 and not a.test_split else 10
        # detect's area average to 20 m keeps floor(n / factor) pixels a side
        rows, cols = (int(n * spacing // SCANNED_M) for n in rgb.shape[:2])
        if 2 * min(rows, WINDOW) * min(cols, WINDOW) < WINDOW * WINDOW:
            small += 1
            continue
        if a.offshore and land_share(rgb[..., 0], boxes) > LAND_SHARE:
            land += 1
            continue
        chosen[chip] = (np.ascontiguousarray(rgb[..., 0]), boxes, spacing)
    distinct = ''
    if a.distinct:
        with open(os.path.join(here, 'sea_wakes.txt')) as f:
            seen = {line.split()[0] for line in f if line.strip() and not line.startswith('#')}
        sets = copies({c: (grey, boxes) for c, (grey, boxes, _) in chosen.items()})
        clean = [s for s in sets if not seen & set(s)]
        largest = {max(s, key=lambda c: (chosen[c][0].size, -int(c))) for s in clean}
        distinct = (f'; {len(sets)} sets of copies, {len(sets) - len(clean)} with a wake seen '
                    f'({sum(len(s) for s in sets if seen & set(s))} chips) left out, the largest of each other set kept')
        chosen = {c: v for c, v in chosen.items() if c in largest}
    for chip, (grey, boxes, spacing) in chosen.items():
        Image.fromarray(grey, 'L').save(os.path.join(a.out_dir, f'ssdd_{chip}.png'))
        drawing = {
            'type': 'FeatureCollection',
            'wakelab': {'coordinates': 'pixel', 'pixel_spacing_m': spacing, 'scale': 'display',
                        'ships_drawn': True, 'wakes_drawn': False},
            'notes': f'SOURCE {SSDD[0]}@{SSDD[1]}:VOCdevkit/VOC2007/JPEGImages/{chip}.jpg; boxes from its annotation',
            'features': [{'type': 'Feature', 'properties': {'kind': 'ship', 'source': 'SSDD annotation'},
                          'geometry': {'type': 'Polygon',
                                       'coordinates': [[[x0, y0], [x1, y0], [x1, y1], [x0, y1], [x0, y0]]]}}
                         for x0, y0, x1, y1 in boxes],
        }
        with open(os.path.join(a.out_dir, f'ssdd_{chip}.geojson'), 'w') as g:
            json.dump(drawing, g)
    split = ('test split' if a.test_split else 'train split less the fourth set, 000006'
             + (' and the screened chips' if a.sea else ''))
    with_land = f', {land} with land' if a.offshore else ''
    print(f'{len(chosen)} chips written of {len(train[::a.every])} taken ({len(train)} in the {split}); left out: {small} under half a window at 20 m, {empty} without a box{with_land}{distinct}')
    if coloured:
        print(f'{len(coloured)} of them hold pixels whose R, G and B differ (their R channel taken as for the '
              f'others): ' + ', '.join(coloured))


if __name__ == '__main__':
    main()
