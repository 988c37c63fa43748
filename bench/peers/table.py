#!/usr/bin/env python3
"""Prints the peer comparison table from the figures run.sh gathered.

usage: table.py NAME CAGEWRAP.json PEER.json PEER_SCORE.json [NAME ...]
  CAGEWRAP.json    `cagewrap bench --json` (its first variant)
  PEER.json        what surface_deform.py wrote (times, memory)
  PEER_SCORE.json  `cagewrap bench --score-deformed --json` on the peer's deformed skin
Ratios are Surface Deform / cagewrap: above 1 means cagewrap is faster, smaller or more faithful.
cagewrap's bind counts its kernel table too (bind_s + table_s: what it takes before the first deform).
Below each table: cagewrap's kernel table per vertex and its achieved bandwidth as a share of the
bandwidth probe measured in the same run (issue 24: the ratio is the figure of record).
"""
import json
import sys


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"table.py: {path}: {e}")


def need(d, key, path):
    if key not in d:
        sys.exit(f"table.py: {path} has no '{key}'")
    return d[key]


def rows(name, cw_path, sd_path, score_path):
    cw_all, sd, score = load(cw_path), load(sd_path), load(score_path)
    cw = need(cw_all, "variants", cw_path)[0]
    points = need(cw_all, "points", cw_path)
    for other, path in ((sd, sd_path), (score, score_path)):
        if need(other, "points", path) != points:
            sys.exit(f"table.py: {path} has {other['points']} points but {cw_path} has {points}: not the same skin")
    cw_twist, sd_twist = cw.get("twist"), need(score, "twist", score_path)
    if cw_twist is None:
        sys.exit(f"table.py: {cw_path} has no twist figures (run the bench with --twist)")
    out = [
        ("bind s", need(cw, "bind_s", cw_path) + cw.get("table_s", 0.0), need(sd, "bind_s", sd_path), "%.3f"),
        ("ms per cage change", need(cw, "deform_median_ms", cw_path), need(sd, "deform_median_ms", sd_path), "%.2f"),
        ("peak memory MB", need(cw_all, "peak_rss_mb", cw_path), need(sd, "peak_rss_mb", sd_path), "%.0f"),
        ("twist rms", cw_twist["rms"], sd_twist["rms"], "%.3e"),
        ("twist max", cw_twist["max"], sd_twist["max"], "%.3e"),
    ]
    header = f"{name}: {points} skin points, {cw_all.get('elements', '?')} cage elements ({cw['variant']} variant; {sd.get('tool', 'Surface Deform')})"
    footer = ""
    probe = cw_all.get("bandwidth_probe")
    if probe and "table_bytes_per_vertex" in cw:
        footer = (f"cagewrap's kernel: {cw.get('table', '?')} table {cw['table_bytes_per_vertex']:.1f} B/vertex "
                  f"(binding {cw['binding_bytes_per_vertex']:.1f}), {cw['effective_gbps']:.1f} GB/s = "
                  f"{100 * cw['effective_gbps'] / probe['triad_gbps']:.0f}% of the bandwidth probe's triad "
                  f"({probe['triad_gbps']:.1f} GB/s, same run); bind {cw['bind_s']:.3f} s + table {cw.get('table_s', 0):.3f} s")
    return header, out, footer


def main(argv):
    if not argv or len(argv) % 4:
        sys.exit(__doc__)
    for i in range(0, len(argv), 4):
        header, out, footer = rows(*argv[i:i + 4])
        print(header)
        print(f"| {'figure':<20} | {'cagewrap':>12} | {'Surface Deform':>14} | {'ratio SD/cw':>11} |")
        print(f"|{'-' * 22}|{'-' * 13}:|{'-' * 15}:|{'-' * 12}:|")
        for label, cw, sd, fmt in out:
            ratio = sd / cw if cw > 0 else float("inf")
            print(f"| {label:<20} | {fmt % cw:>12} | {fmt % sd:>14} | {ratio:>11.2f} |")
        if footer:
            print()
            print(footer)
        print()


if __name__ == "__main__":
    main(sys.argv[1:])
