#!/usr/bin/env python3
"""Whether `detect`'s peak points along the wake it lands on: for each real image a `wakelab run
--study transfer --real DIR` scored, the peak's `orientation` (its strongest window's line,
degrees anticlockwise from the image's rows, 0-180) against the direction of the drawn wake
segment nearest to it, where that lies within 500 m (the peak is on a wake).

usage: peak_direction.py DIR RUN [RUN ...]

DIR holds the drawings (NAME.geojson, wakes as LineStrings in pixel coordinates with
"pixel_spacing_m"); each RUN/real/1280m/NAME/detections.json holds the peak. A peak's direction
agrees when it lies within 20 degrees of the segment's, modulo 180 (a drawn line has no
heading; the line search's rule for a reported wake). Prints per run: the peaks on a wake, how
many agree, and the share a direction drawn uniformly would give (20 / 90 of them); the peak's
distance to the nearest drawn wake over every wake image (quartiles, metres: how closely the
peak is placed, whether or not it lands within 500 m); then each image's angle difference. Images whose drawing is in longitude and latitude are left out.
Pure Python, no packages.
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from score_real_wakes import point_segment  # noqa: E402

WITHIN_M = 500.0
AGREE_DEG = 20.0


def segments(drawing):
    for f in drawing.get('features', []):
        if f.get('properties', {}).get('kind', 'wake') != 'wake':
            continue
        g = f['geometry']
        lines = [g['coordinates']] if g['type'] == 'LineString' else g['coordinates']
        for line in lines:
            for a, b in zip(line, line[1:]):
                yield tuple(a), tuple(b)


def segment_angle(a, b):
    # [column, row] with rows down: anticlockwise from the rows with y up, as `orientation`
    return math.degrees(math.atan2(-(b[1] - a[1]), b[0] - a[0])) % 180.0


def difference(x, y):
    d = abs(x - y) % 180.0
    return min(d, 180.0 - d)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    drawings, runs = sys.argv[1], sys.argv[2:]
    for run in runs:
        scans = os.path.join(run, 'real', '1280m')
        rows, distances = [], []
        for name in sorted(os.listdir(scans)):
            path = os.path.join(scans, name, 'detections.json')
            geojson = os.path.join(drawings, name + '.geojson')
            if not (os.path.exists(path) and os.path.exists(geojson)):
                continue
            drawing = json.load(open(geojson))
            how = drawing.get('wakelab', {})
            if how.get('coordinates') != 'pixel':
                continue
            spacing = float(how.get('pixel_spacing_m', 10))
            peak = json.load(open(path))['peak']
            p = (peak['product_col'], peak['product_row'])
            near = [(point_segment(p, a, b) * spacing, a, b) for a, b in segments(drawing)]
            if not near:
                continue
            metres, a, b = min(near)
            distances.append(metres)
            if peak.get('orientation') is None:
                continue
            if metres <= WITHIN_M:
                rows.append((name, difference(peak['orientation'], segment_angle(a, b)), metres))
        agree = sum(d <= AGREE_DEG for _, d, _ in rows)
        print(f'{run}: peaks on a wake {len(rows)}, direction within {AGREE_DEG:.0f} deg {agree} '
              f'(a uniform direction: {len(rows) * AGREE_DEG / 90.0:.1f})')
        distances.sort()
        quartile = lambda q: distances[min(len(distances) - 1, int(q * len(distances)))] if distances else float('nan')
        print(f'  peak to the nearest drawn wake, {len(distances)} wake images: quartiles '
              f'{quartile(0.25):.0f} / {quartile(0.5):.0f} / {quartile(0.75):.0f} m')
        print('  ' + ', '.join(f'{n} {d:.0f}' for n, d, _ in rows))


if __name__ == '__main__':
    main()
