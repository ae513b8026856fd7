#!/usr/bin/env python3
"""The image's best line (docs/results.md, "The image's best line, a rule stated before a
fourth held-out set"): where `wakelab detect` reports no wake in an image, its faint line of the
largest z (a ship's best trough or arm refused for its significance alone) taken as the image's
wake when z >= THRESHOLD. Scored on `bench/score_real_wakes.py`'s outputs, by its rule (a line
within TOL_M metres, default 300, of a drawn wake and within 20 degrees of it).

usage: best_line_rule.py DIR OUT [THRESHOLD...]   (default thresholds 4.0 4.5 4.75)

DIR holds NAME.geojson (the drawn wakes), OUT the NAME/detections.json of score_real_wakes.py.
Images named with digits first are the tuning set (Ultraaaman's), the others with wakes drawn
the held-out sets, those with none the wake-free images. Prints, per threshold and set: images
with a wake found / with at most one false wake / false wakes, and where the rule fires (+ on a
drawn wake, - not); then, on the tuning set, the ships with no drawn wake whose best line (a
reported wake off any drawn one, or a faint line) reaches each z: the strict search's own rate.
Since 2026-11-30 (fifteenth session) `detect` applies the rule at 4.5 itself (`promoted` in
its wakes): on its outputs the "shipped" line holds the rule, lower thresholds add to it, and
higher ones cannot take its promoted wakes back (replay them on an older binary's outputs).
Pure Python, no packages.
"""
import os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from score_real_wakes import segment_distance, line_angle  # noqa: E402
from threshold_cv import drawing_and_result, ends  # noqa: E402

TOL_M = float(os.environ.get("TOL_M", "300"))


def image(src, out, name):
    meta, drawn, found, on = drawing_and_result(src, out, name)
    tol = TOL_M / float(meta.get("pixel_spacing_m", 10))
    wakes = found["wakes"] or []
    reported = [ends(w) for w in wakes]
    by_ship = {w["ship"]: w for w in wakes if w.get("ship") is not None}
    ships = []  # per ship: (z of its best line, on a drawn wake, reported as a wake)
    for k, ship in enumerate(found["ships"] or []):
        if k in by_ship:
            ships.append((by_ship[k]["z"], on(*ends(by_ship[k])), True))
            continue
        best = (0.0, False, False)
        for kind in ("trough", "bright_arm"):
            refused = (ship.get("no_wake") or {}).get(kind) or {}
            if refused.get("faint_line") and refused["z"] > best[0]:
                best = (refused["z"], on(*ends(refused["faint_line"])), False)
        ships.append(best)
    group = "wake-free" if not drawn else ("tuning" if name[0].isdigit() else "held-out")
    return dict(group=group, drawn=drawn, ships=ships, reported=len(reported),
                found=sum(any(segment_distance(r[0], r[1], c, d) <= tol and line_angle(r[0], r[1], c, d) <= 20
                              for r in reported) for c, d in drawn),
                false=sum(not on(*r) for r in reported))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    src, out = sys.argv[1], sys.argv[2]
    thresholds = [float(t) for t in sys.argv[3:]] or [4.0, 4.5, 4.75]
    names = sorted(f[:-8] for f in os.listdir(src) if f.endswith(".geojson") and os.path.isdir(os.path.join(out, f[:-8])))
    images = {n: image(src, out, n) for n in names}
    for threshold in [None] + thresholds:
        totals, fired = {}, []
        for name, r in images.items():
            found, false = r["found"] > 0, r["false"]
            faint = [s for s in r["ships"] if not s[2] and s[0] > 0]
            if threshold is not None and r["reported"] == 0 and faint:
                z, on_wake, _ = max(faint)
                if z >= threshold:
                    fired.append(f"{name} {'+' if on_wake else '-'}{z:.2f}")
                    found, false = found or on_wake, false + (not on_wake)
            t = totals.setdefault(r["group"], [0, 0, 0, 0])
            t[0] += 1; t[1] += found; t[2] += found and false <= 1; t[3] += false
        label = "shipped" if threshold is None else f"z >= {threshold}"
        print(f"{label}: " + "; ".join(f"{g} ({t[0]}) {t[1]} / {t[2]} / {t[3]} false" for g, t in sorted(totals.items()))
              + (f"; fires: {', '.join(fired)}" if fired else ""))
    null = [s[0] for r in images.values() if r["group"] == "tuning" for s in r["ships"] if not s[1]]
    print(f"tuning ships with no drawn wake behind them: {len(null)}; their best line reaches "
          + ", ".join(f"z {z}: {sum(v >= z for v in null)}" for z in [4.5, 4.75, 5.0]))


if __name__ == "__main__":
    main()
