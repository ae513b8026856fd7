#!/usr/bin/env python3
"""How much room a display stretch leaves the ship search's CFAR (docs/results.md, "A second
held-out set, and the ship search's target window").

usage: display_headroom.py IMAGE.png [...] [--spacing M] [--at ROW0:ROW1,COL0:COL1]

Each 8-bit image is read as `wakelab detect --scale display` reads it (grey levels as dB) and
area-averaged, in linear units, to the search's 20 m (from --spacing, default 10 m: 2 x 2
pixels). At every pixel the CFAR's ring (guard 500 m, background 800 m, as `CfarOptions`) gives
the sea's mean and spread; the script prints, per image, the median spread (grey levels), the
median headroom (the brightest grey in the image minus the ring's mean, in spreads: a pixel can
pass a test of t spreads only where this exceeds t; P_fa 1e-9 asks 6), the share of pixels with
less than 6, and the median spread of the ring on the image averaged over SNAP's 50 m target
window (3 x 3 pixels at 20 m). With --at (rows and columns of the image's own pixels, a box
around a ship) it also prints the most any window mean in that box stands over its averaged
ring, in that ring's spreads: what the target window's test sees there. Needs numpy, Pillow and
scipy.
"""
import sys
try:
    import numpy as np
    from PIL import Image
    from scipy.ndimage import uniform_filter
except ImportError as missing:
    sys.exit(f"display_headroom.py needs numpy, Pillow and scipy ({missing}): pip install numpy pillow scipy")

SEARCH_M, GUARD_M, BACKGROUND_M, T = 20.0, 500.0, 800.0, 6.0


def ring(db, guard, back):
    """The ring's mean and spread at every pixel (zero-padded box sums over the image)."""
    box = lambda a, n: uniform_filter(a, n, mode='constant') * n * n
    ones = np.ones_like(db)
    n = box(ones, back) - box(ones, guard)
    mean = (box(db, back) - box(db, guard)) / n
    var = (box(db * db, back) - box(db * db, guard)) / n - mean * mean
    return mean, np.sqrt(np.maximum(var, 0.0))


def main():
    args = sys.argv[1:]
    spacing = 10.0
    if '--spacing' in args:
        i = args.index('--spacing')
        spacing = float(args[i + 1])
        del args[i:i + 2]
    if not args:
        sys.exit(__doc__.split('\n\n')[1])
    at = None
    if '--at' in args:
        i = args.index('--at')
        at = [tuple(int(v) for v in part.split(':')) for part in args[i + 1].split(',')]
        del args[i:i + 2]
    k = max(1, round(SEARCH_M / spacing))
    odd = lambda m: 2 * round((m / SEARCH_M) / 2) + 1
    guard, back = odd(GUARD_M), odd(BACKGROUND_M)
    print('image | spread (grey) | headroom (spreads) | share under 6 | spread over 50 m windows')
    for path in args:
        grey = np.asarray(Image.open(path).convert('L'), dtype=np.float64)
        h, w = (grey.shape[0] // k) * k, (grey.shape[1] // k) * k
        linear = (10.0 ** (grey[:h, :w] / 10.0)).reshape(h // k, k, w // k, k).mean(axis=(1, 3))
        db = 10.0 * np.log10(linear)
        mean, spread = ring(db, guard, back)
        headroom = (db.max() - mean) / spread
        averaged = uniform_filter(db, 3, mode='nearest')
        averaged_mean, averaged_spread = ring(averaged, guard, back)
        print(f'{path} | {np.median(spread):.1f} | {np.median(headroom):.1f} | '
              f'{(headroom < T).mean():.2f} | {np.median(averaged_spread):.1f}')
        if at:
            (r0, r1), (c0, c1) = at
            box = (slice(r0 // k, r1 // k + 1), slice(c0 // k, c1 // k + 1))
            z = (averaged[box] - averaged_mean[box]) / averaged_spread[box]
            print(f'  in rows {r0}:{r1}, columns {c0}:{c1}: a window mean stands at most {np.nanmax(z):.1f} spreads up')


if __name__ == '__main__':
    main()
