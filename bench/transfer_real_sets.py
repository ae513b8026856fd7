#!/usr/bin/env python3
"""The transfer study's CNN detectors on real images, set by set (docs/results.md, "Simulated
wakes on real sea").

usage: transfer_real_sets.py RUN [RUN ...]

Each RUN is a `wakelab run --study transfer --out RUN --real DIR` directory; its
RUN/transfer/real.json holds every image's score per detector (a wake found when a detection
or the map's peak lies within 500 m of a drawn wake; every other detection a false alarm).
For each run and footprint, per set that `bench/` draws its images in (the tuning set, the held-out sets,
the fourth, other wake-free images; as bench/threshold_cv.py names them): wake images with a
wake found, with at most one false alarm (the transfer issue's target), with the map's peak on
a wake, with the strongest detection on one, false alarms per wake image, and wake-free images
without an alarm; then the line search's wakes seen by the CNN too, and how many of those lie on
a drawn wake. Pure Python, no packages.
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
    false = sum(s['false_alarms'] for s in wake) / max(1, len(wake))
    return (f"  {label:<16} found {len(found):>2}/{len(wake):<2} with <= 1 false {one:>2}  "
            f"peak on a wake {sum(s['peak_on_wake'] for s in wake):>2}  "
            f"strongest on a wake {sum(s['strongest_on_wake'] for s in wake):>2}  "
            f"false per wake image {false:.2f}  wake-free clean {sum(s['detections'] == 0 for s in free)}/{len(free)}")


def main():
    runs = sys.argv[1:]
    if not runs:
        sys.exit(__doc__.split('\n\n')[1])
    for run in runs:
        path = os.path.join(run, 'transfer', 'real.json')
        if not os.path.exists(path):
            sys.exit(f'{path}: missing; run `wakelab run --study transfer --out {run} --real DIR` first')
        with open(path) as f:
            real = json.load(f)
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
