#!/usr/bin/env python3
"""Builds of `wakelab detect` that differ in one setting, compared set by set on the real images
and chosen by leave-one-set-out cross-validation (docs/results.md, "The bright arm's cap, chosen
across the sets").

usage: compare_variants.py --sets DIR... --variant LABEL OUT... [--variant LABEL OUT...]

Each DIR holds NAME.geojson drawings (bench/score_real_wakes.py's input); each variant gives one
OUT per DIR, in the same order, holding the NAME/detections.json that score_real_wakes.py wrote
with that build. An image counts when a wake is found in it with at most one false wake (300 m
and 20 degrees, score_real_wakes.py's rule); an image with no wake drawn, or whose drawing says
"wakes_drawn": false (SSDD's ship chips, bench/ssdd_ships.py, which hold few wakes), when no wake
is reported there. The sets are those bench/ draws the images in (threshold_cv.py), and each
DIR of ship chips is a set of its own. For each set left out, the variant that does best on
the others is chosen (ties to the first given: the shipped one) and scored on the set left out.
Pure Python, no packages.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from threshold_cv import drawing_and_result, ends, leave_one_set_out, set_of  # noqa: E402


def counts(src, out, name):
    """(the image's set, whether it counts) for the drawing `name` of `src` and its result in `out`."""
    meta, drawn, found, on = drawing_and_result(src, out, name)
    reported = [ends(w) for w in found['wakes'] or []]
    if meta.get('wakes_drawn') is False:
        return f'ship chips {os.path.basename(os.path.normpath(src))}', not reported
    if not drawn:
        return set_of(name), not reported
    false = sum(not on(*r) for r in reported)
    return set_of(name), any(on(*r) for r in reported) and false <= 1


def main():
    args = sys.argv[1:]
    if not args or args[0] != '--sets' or '--variant' not in args:
        sys.exit(__doc__.split('\n\n')[1])
    first = args.index('--variant')
    dirs = args[1:first]
    variants = []
    rest = args[first:]
    while rest:
        nxt = rest.index('--variant', 1) if '--variant' in rest[1:] else len(rest)
        label, outs = rest[1], rest[2:nxt]
        if len(outs) != len(dirs):
            sys.exit(f'variant {label}: {len(outs)} outputs for {len(dirs)} sets of drawings')
        variants.append((label, outs))
        rest = rest[nxt:]
    score, sizes = {}, {}
    for label, outs in variants:
        for src, out in zip(dirs, outs):
            for f in sorted(os.listdir(src)):
                if f.endswith('.geojson'):
                    group, counted = counts(src, out, f[:-len('.geojson')])
                    score[label, group] = score.get((label, group), 0) + counted
                    if label == variants[0][0]:
                        sizes[group] = sizes.get(group, 0) + 1
    labels = [v[0] for v in variants]
    # ties go to the one given first: the shipped one
    leave_one_set_out(score, sizes, labels, str, 'variants', rank=lambda v: -labels.index(v))

if __name__ == '__main__':
    main()
