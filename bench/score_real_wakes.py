"""Score `wakelab detect`'s classic wake search on real images with wakes drawn by eye.

usage: score_real_wakes.py DIR OUT [detect flags...]

DIR holds NAME.png (or NAME.npy, NAME.tif, NAME.tiff) and NAME.geojson (LineStrings of "kind": "wake" in pixel coordinates, as
`wakelab run --real` reads them). Each image runs through `wakelab detect` (the binary in
$WAKELAB, else target/release/wakelab) into OUT/NAME/ unless that holds a result already. A drawn
wake is found when a reported wake's segment comes within TOL_M metres of it (default 300, in
pixels at the drawing's stated spacing: 30 at 10 m, 100 at 3 m; TOL sets it in pixels for every
image instead) and their lines differ by at most 20 degrees; a reported wake that finds none
is false. The CNN's scan in the same run is scored by the transfer issue's rule: a drawn wake is
found when a flagged window's centre lies within 500 m of it (at the drawing's pixel spacing);
a flagged window farther than that from every drawn wake is away; and whether the map's peak
lies within 500 m of one. Prints one line per image, then the totals: images where a wake is
found, where one is found with at most one false wake (the transfer issue's target), wakes found
by how they look (drawn "look": dark, bright, both), the CNN's, and the two together as a user
of `detect` reads them: a wake found by either, with at most one false wake and window away (a
window away on a false wake's line counted once); and, by `detect`'s `cnn_windows` and `on_wake`,
how often a wake seen by both searches, or by one alone, lies on a drawn wake. Item 7's rule of the transfer issue is
printed too: a wake found by the search's wake, a flagged window or the map's peak, with at most
one false alarm (false wakes and windows away). From each scan's `windows.csv`, how well its
windows are ranked: the AUC of a window on a wake (its centre within 500 m of one) against the
others, by the network's probability and by the strongest line's |z| (`--peak line`'s key),
pooled and per image. An image with no wake drawn
(certified wake-free) is scored apart: whether any wake, and any CNN window, is reported there.
Every reported ship's own CNN window (`cnn_probability`) is scored against the line search from
the ship: a ship is a wake's when it lies within 500 m of a drawn wake's line.
The wakes `detect` promoted from a faint line (`promoted`: an image with no other wake, its
best faint line at z 4.5 or more) are listed apart, each on a drawn wake or not.
Where the GeoJSON's "wakelab" member says "ships_drawn": true, its Polygons of "kind": "ship" are
scored too: a drawn ship is found when a reported ship's centre lies within 50 m of its box, and
every other reported ship is false. Where it also says "wakes_drawn": false (bench/ssdd_ships.py),
only its ships are scored.
Pure Python, no packages.
"""
import csv, json, math, os, statistics, subprocess, sys

TOL = os.environ.get("TOL")
TOL_M = float(os.environ.get("TOL_M", "300"))
ANGLE = 20.0
CNN_RADIUS_M = 500.0
SHIP_RADIUS_M = 50.0


def point_segment(p, a, b):
    (px, py), (ax, ay), (bx, by) = p, a, b
    length2 = (bx - ax) ** 2 + (by - ay) ** 2
    t = 0.0 if length2 == 0 else max(0.0, min(1.0, ((px - ax) * (bx - ax) + (py - ay) * (by - ay)) / length2))
    return math.hypot(px - ax - t * (bx - ax), py - ay - t * (by - ay))


def segment_distance(a, b, c, d):
    return min(point_segment(a, c, d), point_segment(b, c, d), point_segment(c, a, b), point_segment(d, a, b))


def line_angle(a, b, c, d):
    e = abs((math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]) - math.atan2(d[1] - c[1], d[0] - c[0])) + 180) % 360 - 180)
    return min(e, 180 - e)


def main():
    if len(sys.argv) < 3 or not os.path.isdir(sys.argv[1]):
        sys.exit("usage: score_real_wakes.py DIR OUT [detect flags...]: DIR must be a folder of NAME.png with NAME.geojson")
    src, out, flags = sys.argv[1], sys.argv[2], sys.argv[3:]
    binary = os.environ.get("WAKELAB", "target/release/wakelab")
    totals = dict(images=0, found=0, target=0, reported=0, false=0,
                  cnn_found=0, cnn_target=0, cnn_peak=0, cnn_windows=0, cnn_away=0,
                  either_found=0, either_target=0, either_false=0,
                  both_true=0, both=0, line_only_true=0, line_only=0, cnn_only_near=0, cnn_only=0,
                  clear=0, clear_quiet=0, clear_cnn_quiet=0,
                  ship_images=0, ships_drawn=0, ships_found=0, ships_false=0)
    by_kind = {}
    ship_records = []
    window_records = []
    faint_records = []
    promoted = []
    for name in sorted(f[:-8] for f in os.listdir(src) if f.endswith(".geojson")):
        drawn_json = json.load(open(os.path.join(src, name + ".geojson")))
        meta = drawn_json.get("wakelab", {})
        run = os.path.join(out, name)
        if not os.path.exists(os.path.join(run, "detections.json")):
            image = next(os.path.join(src, name + e) for e in (".png", ".npy", ".tif", ".tiff") if os.path.exists(os.path.join(src, name + e)))
            cmd = [binary, "--quiet", "detect", image, "--out", run,
                   "--scale", meta.get("scale", "display"),
                   "--pixel-spacing", str(meta.get("pixel_spacing_m", 10))] + flags
            subprocess.run(cmd, check=True, capture_output=True)
        found = json.load(open(os.path.join(run, "detections.json")))
        reported = [((w["product_start"][1], w["product_start"][0]), (w["product_end"][1], w["product_end"][0]))
                    for w in found["wakes"] or []]
        drawn = [(f["geometry"]["coordinates"][0], f["geometry"]["coordinates"][-1], f["properties"])
                 for f in drawn_json["features"] if f["properties"].get("kind") == "wake"]
        tol = float(TOL) if TOL else TOL_M / float(meta.get("pixel_spacing_m", 10))
        match = lambda r, d: segment_distance(r[0], r[1], d[0], d[1]) <= tol and line_angle(r[0], r[1], d[0], d[1]) <= ANGLE
        hits = [any(match(r, d) for r in reported) for d in drawn]
        false = sum(1 for r in reported if not any(match(r, d) for d in drawn))
        for hit, d in zip(hits, drawn):
            k = by_kind.setdefault(d[2].get("look", "?"), [0, 0])
            k[0] += hit
            k[1] += 1
        windows = [(w["product_col"], w["product_row"]) for w in found.get("detections") or []]
        if meta.get("ships_drawn"):
            # ships boxed in the drawing: found when a reported ship's centre lies within 50 m of
            # a box (one scanned 20 m pixel where that is larger); every other one is false
            boxes = [f["geometry"]["coordinates"][0] for f in drawn_json["features"]
                     if f["properties"].get("kind") == "ship"]
            ships = [(s["product_col"], s["product_row"]) for s in found.get("ships") or []]
            reach = max(SHIP_RADIUS_M, 20.0) / float(meta.get("pixel_spacing_m", 10))
            near_box = lambda p, b: math.hypot(
                max(min(q[0] for q in b) - p[0], 0, p[0] - max(q[0] for q in b)),
                max(min(q[1] for q in b) - p[1], 0, p[1] - max(q[1] for q in b))) <= reach
            ships_found = sum(1 for b in boxes if any(near_box(p, b) for p in ships))
            ships_false = sum(1 for p in ships if not any(near_box(p, b) for b in boxes))
            totals["ship_images"] += 1
            totals["ships_drawn"] += len(boxes)
            totals["ships_found"] += ships_found
            totals["ships_false"] += ships_false
            print(f"{name}: ships drawn {len(boxes)}, found {ships_found}, false {ships_false}")
        if meta.get("wakes_drawn") is False:
            # ships alone were drawn (bench/ssdd_ships.py): the image says nothing of its wakes
            continue
        # each reported ship's own CNN window (`cnn_probability`, centred on its return): the
        # ship is a wake's when it lies within 500 m of a drawn wake's line; the line search
        # found its wake when a reported wake starts from it
        near_px = CNN_RADIUS_M / float(meta.get("pixel_spacing_m", 10))
        for k, s in enumerate(found.get("ships") or []):
            p = (s["product_col"], s["product_row"])
            ship_records.append(dict(
                image=name, wake=any(point_segment(p, d[0], d[1]) <= near_px for d in drawn),
                cnn=s.get("cnn_probability"), threshold=found["threshold"],
                line=any(w.get("ship") == k for w in found["wakes"] or [])))
        # the faint lines (`faint_line` of a ship's `no_wake`): best lines refused for their
        # significance alone, for an analyst to look at; on a drawn wake as a reported wake is
        faint = [((f["product_start"][1], f["product_start"][0]), (f["product_end"][1], f["product_end"][0]))
                 for s in found.get("ships") or [] for f in
                 [(s.get("no_wake") or {}).get(k, {}).get("faint_line") for k in ("trough", "bright_arm")] if f]
        faint_records.append(dict(
            image=name, drawn=len(drawn), lines=len(faint),
            on_wake=sum(1 for r in faint if any(match(r, d) for d in drawn)),
            missed_with_faint=sum(1 for h, d in zip(hits, drawn) if not h and any(match(r, d) for r in faint)),
            found=any(hits),
            found_with_faint=any(hits) or any(match(r, d) for r in faint for d in drawn)))
        if not drawn:
            # an image certified wake-free: every wake or window reported there is a false alarm
            totals["clear"] += 1
            totals["clear_quiet"] += not reported
            totals["clear_cnn_quiet"] += not windows
            totals["clear_either_quiet"] = totals.get("clear_either_quiet", 0) + (not windows and not reported)
            print(f"{name}: no wake drawn, reported {len(reported)}; CNN windows {len(windows)}")
            continue
        totals["images"] += 1
        totals["found"] += any(hits)
        totals["target"] += any(hits) and false <= 1
        totals["reported"] += len(reported)
        totals["false"] += false
        # the CNN: flagged windows' centres and the map's peak within 500 m of a drawn wake
        radius = CNN_RADIUS_M / float(meta.get("pixel_spacing_m", 10))
        near = lambda p, d: point_segment(p, d[0], d[1]) <= radius
        cnn_hits = sum(1 for d in drawn if any(near(p, d) for p in windows))
        away = sum(1 for p in windows if not any(near(p, d) for d in drawn))
        peak = found.get("peak")
        on_peak = bool(peak) and any(near((peak["product_col"], peak["product_row"]), d) for d in drawn)
        totals["cnn_found"] += cnn_hits > 0
        totals["cnn_target"] += cnn_hits > 0 and away <= 1
        totals["cnn_peak"] += on_peak
        totals["cnn_windows"] += len(windows)
        totals["cnn_away"] += away
        # either: a wake found by the line search or the CNN; false are the search's false wakes
        # and the windows away, a window away within 500 m of a false wake's line counted once
        on_false = lambda p: any(point_segment(p, r[0], r[1]) <= radius for r in reported if not any(match(r, d) for d in drawn))
        either_false = false + sum(1 for p in windows if not any(near(p, d) for d in drawn) and not on_false(p))
        totals["either_found"] += any(hits) or cnn_hits > 0
        totals["either_target"] += (any(hits) or cnn_hits > 0) and either_false <= 1
        totals["either_false"] += either_false
        # the item 7: a wake found when the search's wake, a flagged window or the map's
        # peak lies on it; its false alarms are the search's false wakes and the windows away
        item7 = any(hits) or cnn_hits > 0 or on_peak
        totals["item7_found"] = totals.get("item7_found", 0) + item7
        totals["item7_target"] = totals.get("item7_target", 0) + (item7 and false + away <= 1)
        # every scored window (`windows.csv`): on a wake when its centre lies within 500 m of one
        window_records.extend(scored_windows(run, name, lambda p: any(near(p, d) for d in drawn)))
        # the searches read together (`detect`'s `cnn_windows` and `on_wake`): how often a wake
        # seen by both, or by the line search alone, is a drawn one; and a window on no
        # reported wake lies within 500 m of a drawn one
        for r, w in zip(reported, found["wakes"] or []):
            if w.get("promoted"):
                # a faint line `detect` promoted to the image's wake, having found no other
                promoted.append(f"{name} {'+' if any(match(r, d) for d in drawn) else '-'}{w['z']:.2f}")
            seen_by_both = bool(w.get("cnn_windows"))
            key = "both" if seen_by_both else "line_only"
            totals[key] += 1
            totals[key + "_true"] += any(match(r, d) for d in drawn)
        for p, w in zip(windows, found.get("detections") or []):
            if w.get("on_wake") is None:
                totals["cnn_only"] += 1
                totals["cnn_only_near"] += any(near(p, d) for d in drawn)
        print(f"{name}: drawn {len(drawn)}, found {sum(hits)}, reported {len(reported)}, false {false}; "
              f"CNN windows {len(windows)}, wakes with a window {cnn_hits}, windows away {away}, "
              f"peak on a wake {'yes' if on_peak else 'no'}")
    t = totals
    print(f"images {t['images']}: a wake found in {t['found']}, with at most one false wake in {t['target']}; "
          f"wakes reported {t['reported']}, false {t['false']}; found by look: "
          + ", ".join(f"{k} {v[0]}/{v[1]}" for k, v in sorted(by_kind.items())))
    print(f"CNN: a window within 500 m of a wake in {t['cnn_found']} images, with at most one window away in "
          f"{t['cnn_target']}; peak on a wake in {t['cnn_peak']}; windows away {t['cnn_away']} of {t['cnn_windows']}")
    print(f"either: a wake found in {t['either_found']} images, with at most one false in {t['either_target']}; "
          f"false {t['either_false']} ({t['either_false'] / max(t['images'], 1):.2f} per wake image)")
    print(f"item 7's rule (the search's wake, a flagged window or the map's peak within 500 m): a wake found in "
          f"{t.get('item7_found', 0)} images, with at most one false (false wakes and windows away) in {t.get('item7_target', 0)}")
    print(f"read together: wakes seen by both {t['both']}, on a drawn wake {t['both_true']}; by the line search "
          f"alone {t['line_only']}, on a drawn wake {t['line_only_true']}; CNN windows on no reported wake "
          f"{t['cnn_only']}, within 500 m of a drawn wake {t['cnn_only_near']} (images with wakes drawn)")
    if promoted:
        print(f"promoted faint lines (`promoted`; + on a drawn wake, - not): {len(promoted)}: {', '.join(promoted)}")
    if t["ship_images"]:
        print(f"ships: {t['ships_found']} of {t['ships_drawn']} found in {t['ship_images']} images, "
              f"{t['ships_false']} false ({t['ships_false'] / t['ship_images']:.2f} per image)")
    if t["clear"]:
        print(f"no-wake images {t['clear']}: without a wake reported {t['clear_quiet']}, "
              f"without a CNN window flagged {t['clear_cnn_quiet']}, without either {t['clear_either_quiet']}")
    if ship_records:
        ship_windows(ship_records)
    if faint_records:
        faint_lines(faint_records)
    if window_records:
        window_ranking(window_records)


def faint_lines(records):
    """The faint lines (a ship's best line refused for its significance alone) per set: how
    many lie on a drawn wake, how many drawn wakes the search missed have one, and in how many
    wake images a wake is reported or lies under a faint line (what an analyst reviewing them
    would see)."""
    def line(label, rows):
        wake_rows = [r for r in rows if r["drawn"]]
        print(f"faint lines, {label}: {sum(r['lines'] for r in rows)} in {len(rows)} images, "
              f"{sum(r['on_wake'] for r in rows)} on a drawn wake; drawn wakes missed with a faint line on them "
              f"{sum(r['missed_with_faint'] for r in rows)}; wake images with a wake found "
              f"{sum(r['found'] for r in wake_rows)}, with a wake found or under a faint line "
              f"{sum(r['found_with_faint'] for r in wake_rows)} of {len(wake_rows)}; "
              f"wake-free images with a faint line {sum(1 for r in rows if not r['drawn'] and r['lines'])}")
    by_set(line, records, "held-out and wake-free images")


def scored_windows(run, name, on_wake):
    """The scan's windows of `windows.csv` in `run` (none where an older `detect` wrote no such
    file), each with its probability, its strongest line's |z| and whether `on_wake` holds at
    its centre (product pixels)."""
    path = os.path.join(run, "windows.csv")
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [dict(image=name, p=float(w["probability"]), z=abs(float(w["line_z"] or 0)),
                     wake=on_wake((float(w["window_col"]), float(w["window_row"]))))
                for w in csv.DictReader(f)]


def window_ranking(records):
    """How well the scan's windows are ranked: the AUC of a window on a wake (its centre within
    500 m of one) against the others, by the network's probability and by the strongest line's
    |z| (the `--peak line` rule's key), pooled over the wake images and per image (its median,
    over images with windows of both kinds)."""
    def line(label, rows):
        pos, neg = [r for r in rows if r["wake"]], [r for r in rows if not r["wake"]]
        per = {}
        for r in rows:
            per.setdefault(r["image"], []).append(r)
        by_image = [(auc([r["p"] for r in v if r["wake"]], [r["p"] for r in v if not r["wake"]]),
                     auc([r["z"] for r in v if r["wake"]], [r["z"] for r in v if not r["wake"]]))
                    for v in per.values() if any(r["wake"] for r in v) and not all(r["wake"] for r in v)]
        median = lambda xs: statistics.median(xs) if xs else float("nan")
        print(f"windows' ranking, {label}: {len(pos)} windows on a wake, {len(neg)} away; AUC by the network's "
              f"probability {auc([r['p'] for r in pos], [r['p'] for r in neg]):.3f}, by the line's |z| "
              f"{auc([r['z'] for r in pos], [r['z'] for r in neg]):.3f}; per image ({len(by_image)}): median "
              f"{median([a for a, _ in by_image]):.3f} and {median([b for _, b in by_image]):.3f}, above 0.5 in "
              f"{sum(a > 0.5 for a, _ in by_image)} and {sum(b > 0.5 for _, b in by_image)}")
    line("all wake images", records)
    by_set(line, records, "held-out")


def by_set(line, records, rest):
    """`line` of the tuning set's records (images named by digits), then of the rest."""
    line("tuning set", [r for r in records if r["image"].isdigit()])
    line(rest, [r for r in records if not r["image"].isdigit()])


def auc(positives, negatives):
    """The probability that a positive scores above a negative (ties count half)."""
    if not positives or not negatives:
        return float("nan")
    wins = sum((p > n) + 0.5 * (p == n) for p in positives for n in negatives)
    return wins / (len(positives) * len(negatives))


def ship_windows(records):
    """The ships' own CNN windows against the line search from each ship, over every image's
    reported ships, split into the tuning set (names of digits), the other wake images and
    ships of wake-free images (no wake drawn: every ship is a wake-free one)."""
    def line(label, rows):
        scored = [r for r in rows if r["cnn"] is not None]
        pos = [r for r in scored if r["wake"]]
        neg = [r for r in scored if not r["wake"]]
        flagged = lambda r: r["cnn"] >= r["threshold"]
        rate = lambda rs, f: f"{sum(map(f, rs))}/{len(rs)}"
        print(f"ships' windows, {label}: {len(rows)} ships, {len(scored)} scored ({len(pos)} with a drawn wake, "
              f"{len(neg)} without); AUC {auc([r['cnn'] for r in pos], [r['cnn'] for r in neg]):.3f}; "
              f"at the threshold: wake ships {rate(pos, flagged)}, others {rate(neg, flagged)}; "
              f"line search from the ship: wake ships {rate(pos, lambda r: r['line'])}, others {rate(neg, lambda r: r['line'])}; "
              f"either: {rate(pos, lambda r: r['line'] or flagged(r))}, {rate(neg, lambda r: r['line'] or flagged(r))}; "
              f"both: {rate(pos, lambda r: r['line'] and flagged(r))}, {rate(neg, lambda r: r['line'] and flagged(r))}")
    line("all", records)
    by_set(line, records, "held-out and wake-free images")


if __name__ == "__main__":
    main()
