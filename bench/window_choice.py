#!/usr/bin/env python3
"""Which window should a scan's peak be? The rules below each pick one window of a scan from
its windows.csv (every window's probability and strongest line, `wakelab detect`), and are
scored on real images by the transfer issue's rule: the peak is on a wake when the place the
window gives (on its strongest line) lies within 500 m of a drawn wake; a wake image is found
when the peak or a detection is on a wake, with at most one false alarm (a detection farther
than 500 m from every drawn wake; the detections are the scan's, whatever the rule).

usage: window_choice.py DIR RUN [RUN ...]      (a RUN may be RUN+RUN+...: their mean probability)

DIR holds the drawings (NAME.geojson, wakes as LineStrings in pixel coordinates with
"pixel_spacing_m"); RUN/real/FOOTPRINT/NAME/ the scan (`wakelab run --study transfer --real DIR`),
scored for each footprint there (1280m, 2560m).
Rules:
  probability   the window of largest wake probability (`detect`'s peak)
  line          the window of largest |line_z| (its strongest line's contrast)
  p*|z|         the largest probability times |line_z|
  top3 line     of the three most probable windows, the one of largest |line_z|
  rank sum      the least sum of the window's ranks by probability and by |line_z|
  topK z p      of the K windows of largest |line_z| (K = 2, 3, 5, 8), the most probable
  z>=qQ p       of the windows whose |line_z| is at least its Q quantile in the image, the most
                probable (Q = 0.5, 0.8, 0.9)
  p>=qQ z       of the windows whose probability is at least its Q quantile, the one of
                largest |line_z|
  logit+A z     the largest logit(p) + A |line_z| / (the image's median |line_z|), A = 0.5, 1, 2
Every rule's peak by chance is the same: the share of the image's windows on a wake, summed.
Per rule: peaks on a wake and images found (of the wake images; tuning set, held-out), the same
less chance; first, the images where the network's peak and the line's disagree. Images whose drawing is in longitude and latitude are left out.
Pure Python, no packages.
"""
import csv
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peak_direction import segments, WITHIN_M  # noqa: E402
from score_real_wakes import point_segment  # noqa: E402
from threshold_cv import set_of  # noqa: E402


def rank(values):
    """Each value's rank, 0 for the largest."""
    order = sorted(range(len(values)), key=lambda i: -values[i])
    ranks = [0] * len(values)
    for r, i in enumerate(order):
        ranks[i] = r
    return ranks


def choose(rule, windows):
    p = [w['probability'] for w in windows]
    z = [abs(w['line_z']) if w['line_z'] == w['line_z'] else 0.0 for w in windows]
    best = lambda key: max(range(len(windows)), key=key)  # noqa: E731
    if rule == 'probability':
        return best(lambda i: p[i])
    if rule == 'line':
        return best(lambda i: z[i])
    if rule == 'p*|z|':
        return best(lambda i: p[i] * z[i])
    if rule == 'top3 line':
        top = sorted(range(len(windows)), key=lambda i: -p[i])[:3]
        return max(top, key=lambda i: z[i])
    if rule == 'rank sum':
        rp, rz = rank(p), rank(z)
        return min(range(len(windows)), key=lambda i: (rp[i] + rz[i], -p[i]))
    kind, value = rule.split(' ', 1)[0], rule.split(' ', 1)[-1]
    if kind.startswith('top'):
        top = sorted(range(len(windows)), key=lambda i: -z[i])[:int(kind[3:])]
        return max(top, key=lambda i: p[i])
    if kind.startswith('z>=q') or kind.startswith('p>=q'):
        first, second = (z, p) if kind[0] == 'z' else (p, z)
        ordered = sorted(first)
        cut = ordered[int(float(kind[4:]) * (len(ordered) - 1))]
        return max((i for i in range(len(windows)) if first[i] >= cut), key=lambda i: second[i])
    if kind.startswith('logit+'):
        weight, median = float(kind[6:]), sorted(z)[len(z) // 2] or 1.0
        logit = [math.log(max(q, 1e-9) / max(1 - q, 1e-9)) for q in p]
        return best(lambda i: logit[i] + weight * z[i] / median)
    raise ValueError(rule)


RULES = ['probability', 'line', 'p*|z|', 'top3 line', 'rank sum',
         'top2 z p', 'top3 z p', 'top5 z p', 'top8 z p',
         'z>=q0.5 p', 'z>=q0.8 p', 'z>=q0.9 p', 'p>=q0.5 z', 'p>=q0.8 z', 'p>=q0.9 z',
         'logit+0.5 z', 'logit+1 z', 'logit+2 z']


def number(v):
    return float(v) if v != '' else float('nan')


def windows_of(scan):
    with open(os.path.join(scan, 'windows.csv')) as f:
        return [{k: number(v) for k, v in r.items()} for r in csv.DictReader(f)]


def scored(src, run, footprint='1280m'):
    """Per wake image: (name, set, its windows, on_wake(row, col), detections' on-wake flags).
    RUN+RUN+...: the runs' probabilities averaged window by window (the same detector grid,
    checked), without detections (the mean has no threshold)."""
    parts = run.split('+')
    for name in sorted(f[:-8] for f in os.listdir(src) if f.endswith('.geojson')):
        drawing = json.load(open(os.path.join(src, name + '.geojson')))
        meta = drawing.get('wakelab', {})
        if meta.get('coordinates', 'pixel') != 'pixel':
            continue
        scans = [os.path.join(part, 'real', footprint, name) for part in parts]
        if not all(os.path.exists(os.path.join(scan, 'windows.csv')) for scan in scans):
            continue
        wakes = list(segments(drawing))
        if not wakes:
            continue
        spacing = float(meta.get('pixel_spacing_m', 10))

        def on_wake(row, col, wakes=wakes, spacing=spacing):
            return min(point_segment((col, row), a, b) for a, b in wakes) * spacing <= WITHIN_M

        windows = windows_of(scans[0])
        if not windows:
            continue
        for scan in scans[1:]:
            more = windows_of(scan)
            if [(w['window_row'], w['window_col']) for w in more] != [(w['window_row'], w['window_col']) for w in windows]:
                sys.exit(f"{scan}: its windows are not {scans[0]}'s; a mean needs runs of one window grid")
            for w, m in zip(windows, more):
                w['probability'] += m['probability']
        for w in windows:
            w['probability'] /= len(scans)
        if len(scans) > 1:
            detections = []
        else:
            result = json.load(open(os.path.join(scans[0], 'detections.json')))
            detections = [on_wake(d['product_row'], d['product_col']) for d in result['detections']]
        yield name, set_of(name), windows, on_wake, detections


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    src = sys.argv[1]
    for run in sys.argv[2:]:
        for part in run.split('+'):
            if not os.path.isdir(os.path.join(part, 'real')):
                sys.exit(f"{part}/real: missing; run `wakelab run --study transfer --out {part} --real {src}` first")
    first = lambda run: os.path.join(run.split('+')[0], 'real')  # noqa: E731
    for run, footprint in ((r, f) for r in sys.argv[2:] for f in sorted(os.listdir(first(r)))):
        images = list(scored(src, run, footprint))
        print(f"{run}, {footprint}: {len(images)} wake images")
        chance = {}
        for name, group, windows, on_wake, _ in images:
            share = sum(on_wake(w['place_row'], w['place_col']) for w in windows) / len(windows)
            chance[group] = chance.get(group, 0.0) + share
        tuning = 'tuning'
        print(f"  by chance: peaks on a wake {sum(chance.values()):.1f}, tuning {chance.get(tuning, 0):.1f}, "
              f"held-out {sum(v for k, v in chance.items() if k != tuning):.1f}")
        hits = {rule: {name for name, _, windows, on_wake, _ in images
                       if on_wake(*(lambda w: (w['place_row'], w['place_col']))(windows[choose(rule, windows)]))}
                for rule in ('probability', 'line')}
        print(f"  the network's peak and the line's on a wake: both {len(hits['probability'] & hits['line'])}, "
              f"the network's alone {sorted(hits['probability'] - hits['line'])}, "
              f"the line's alone {sorted(hits['line'] - hits['probability'])}")
        for rule in RULES:
            peak, found = {}, {}
            for name, group, windows, on_wake, detections in images:
                w = windows[choose(rule, windows)]
                hit = on_wake(w['place_row'], w['place_col'])
                peak[group] = peak.get(group, 0) + hit
                ok = (hit or any(detections)) and sum(not d for d in detections) <= 1
                found[group] = found.get(group, 0) + ok
            total = sum(chance.values())
            held = lambda d: sum(v for k, v in d.items() if k != tuning)  # noqa: E731
            print(f"  {rule:<12} peak on a wake {sum(peak.values()):>2} (tuning {peak.get(tuning, 0):>2}, "
                  f"held-out {held(peak):>2}); found <= 1 false {sum(found.values()):>2} "
                  f"(tuning {found.get(tuning, 0):>2}, held-out {held(found):>2}); "
                  f"peak over chance {sum(peak.values()) - total:5.1f} "
                  f"(tuning {peak.get(tuning, 0) - chance.get(tuning, 0):5.1f}, held-out {held(peak) - held(chance):5.1f})")


if __name__ == '__main__':
    main()
