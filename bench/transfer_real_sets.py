#!/usr/bin/env python3
"""The transfer study's CNN detectors on real images, set by set (docs/results.md, "Simulated
wakes on real sea").

usage: transfer_real_sets.py RUN [RUN ...]
       transfer_real_sets.py --majority RUN,RUN,... RUN,RUN,...

A RUN may be RUN+RUN+...: the runs' images merged, each taken from the first run that scored it
(the two folds of bench/transfer_folds.sh, OUT/A_SEED+OUT/B_SEED, score every image once).

Each RUN is a `wakelab run --study transfer --out RUN --real DIR` directory; its
RUN/transfer/real.json holds every image's score per detector (a wake found when a detection
or the map's peak lies within 500 m of a drawn wake; every other detection a false alarm).
For each run and footprint, per set that `bench/` draws its images in (the tuning set, the held-out sets,
the fourth, other wake-free images; as bench/threshold_cv.py names them): wake images with a
wake found, with at most one false alarm (the transfer issue's target), with the map's peak on
a wake, with the strongest detection on one, false alarms per wake image, and wake-free images
without an alarm; then the line search's wakes seen by the CNN too, and how many of those lie on
a drawn wake. Where the run wrote it, the peaks a detector scoring the same windows at random
would place on a wake (the sum of `peak_by_chance`), and a detector of lines alone (`peak_by_line`). With --majority, two groups of runs (the same study at several seeds, with and
without a change): the images whose verdict (a wake image: a wake found with at most one false
alarm; a wake-free one: no alarm) the 1.28 km detector gets in most runs of one group and not
of the other, each with its count per group. Pure Python, no packages.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from threshold_cv import set_of  # noqa: E402


def row(label, scores):
    wake = [s for s in scores if s['wakes'] > 0]
    free = [s for s in scores if s['wakes'] == 0]
    found = [s for s in wake if s['peak_on_wake'] or s['detections'] > s['false_alarms']]
    one = sum(s['false_alarms'] <= 1 for s in found)
    peak_alone = sum(s['peak_on_wake'] and s['detections'] <= s['false_alarms'] for s in wake)
    false = sum(s['false_alarms'] for s in wake) / max(1, len(wake))
    # what the peak finds were the same windows scored at random (the report's `peak_by_chance`,
    # written since 2026-12-02; runs before have none)
    chances = [s['peak_by_chance'] for s in wake if s.get('peak_by_chance') is not None]
    chance = f", by chance {sum(chances):4.1f}" if chances else ""
    # and what a detector of lines alone would (`peak_by_line`, written since 2026-12-07)
    lines = [s['peak_by_line'] for s in wake if s.get('peak_by_line') is not None]
    chance += f", by the line {sum(lines):>2}" if lines else ""
    return (f"  {label:<16} found {len(found):>2}/{len(wake):<2} with <= 1 false {one:>2}  "
            f"peak on a wake {sum(s['peak_on_wake'] for s in wake):>2}{chance} (found by it alone {peak_alone:>2})  "
            f"strongest on a wake {sum(s['strongest_on_wake'] for s in wake):>2}  "
            f"false per wake image {false:.2f}  wake-free clean {sum(s['detections'] == 0 for s in free)}/{len(free)}")


def load(run):
    """A run's real.json; for RUN+RUN+..., the runs' scores merged, an image (per footprint)
    taken from the first run that scored it (bench/transfer_folds.sh's folds, A_SEED+B_SEED)."""
    merged = {'scores': []}
    for part in run.split('+'):
        path = os.path.join(part, 'transfer', 'real.json')
        if not os.path.exists(path):
            sys.exit(f'{path}: missing; run `wakelab run --study transfer --out {part} --real DIR` first')
        with open(path) as f:
            real = json.load(f)
        if '+' not in run:
            return real
        seen = {(s['image'], s['footprint']) for s in merged['scores']}
        merged['scores'] += [s for s in real['scores'] if (s['image'], s['footprint']) not in seen]
    return merged


def verdicts(run, footprint=1280.0):
    out = {}
    for s in load(run)['scores']:
        if s['footprint'] != footprint or s.get('skipped'):
            continue
        if s['wakes'] > 0:
            ok = (s['peak_on_wake'] or s['detections'] > s['false_alarms']) and s['false_alarms'] <= 1
        else:
            ok = s['detections'] == 0
        out[os.path.splitext(s['image'])[0]] = ok
    return out


def majority(first, second):
    groups = [[verdicts(r) for r in g.split(',')] for g in (first, second)]
    names = sorted(set.intersection(*(set(v) for g in groups for v in g)))
    counts = [{n: sum(v[n] for v in g) for n in names} for g in groups]
    most = [{n for n in names if 2 * c[n] > len(g)} for c, g in zip(counts, groups)]
    for label, names_ in (('the second group only', most[1] - most[0]), ('the first group only', most[0] - most[1])):
        print(f'right in most runs of {label}: {len(names_)}')
        for n in sorted(names_):
            print(f'  {n:<12} {set_of(n):<16} {counts[0][n]} of {len(groups[0])}, {counts[1][n]} of {len(groups[1])}')
    print(f'right in most runs: {len(most[0])} and {len(most[1])} of {len(names)} images')


def main():
    runs = sys.argv[1:]
    if not runs:
        sys.exit(__doc__.split('\n\n')[1])
    if runs[0] == '--majority':
        if len(runs) != 3:
            sys.exit('--majority takes two groups of runs, each a comma-separated list')
        return majority(runs[1], runs[2])
    for run in runs:
        real = load(run)
        for footprint in sorted({s['footprint'] for s in real['scores']}):
            scores = [s for s in real['scores'] if s['footprint'] == footprint and not s.get('skipped')]
            print(f'{run}, {footprint / 1000:.2f} km:')
            sets = {}
            for s in scores:
                sets.setdefault(set_of(os.path.splitext(s['image'])[0]), []).append(s)
            held = [s for label, group in sets.items() if label.startswith('held-out') for s in group]
            for label in sorted(sets):
                print(row(label, sets[label]))
            print(row('held-out, all', held))
            print(row('all', scores))
        search = real.get('search_summary') or {}
        if search:
            print(f"  line search's wakes seen by the CNN too: {search['seen_by_both']}, "
                  f"{search['seen_by_both_found']} on a drawn wake")


if __name__ == '__main__':
    main()
