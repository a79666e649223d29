#!/usr/bin/env python3
"""Plots deploy/soak.sh's samples (one SVG, no dependencies beyond the standard library) and
judges them: after the warm-up samples, resident memory may grow by at most --rss-growth
percent over its warm-up maximum, threads and open file descriptors by at most 10%, and the
floor of GPU bytes (their minimum) in the last third of the run by at most 10% over the floor
before it. Prints a table of
first / warm-up max / last / max (and floors) per series and exits 1 when one is not flat.

    deploy/soak_plot.py SAMPLES.csv OUT.svg [--warmup N] [--rss-growth PERCENT]
"""
import argparse
import csv
import sys

# column, title, allowed growth (None: --rss-growth), what grows: "max" compares maxima,
# "floor" minima. Threads and descriptors get 10%: a churn RPC in flight when a sample is taken
# holds a thread and a socket. GPU memory is the churn's state (grid sizes, views) when the
# sample is taken, so its maximum says which state a sample caught (a 61-minute run whose slow
# warm-up never met the largest grid "grew" 7.9 -> 9.0 MiB); a leak shows as a rising floor,
# the level the churn returns to in its base state: the last third's minimum against the
# minimum before it.
SERIES = [
    ("rss_mib", "resident memory (MiB)", None, "max"),
    ("threads", "threads", 0.1, "max"),
    ("fds", "open file descriptors", 0.1, "max"),
    ("gpu_mib", "GPU memory held (MiB)", 0.1, "floor"),
]
PANEL_W, PANEL_H, MARGIN = 420, 200, 48


def read_samples(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{path}: no samples")
    return [{k: float(v) for k, v in row.items()} for row in rows]


def panel(rows, column, title, warmup, x0, y0):
    """One line chart as SVG elements: the warm-up shaded, the samples as a polyline."""
    xs = [r["minute"] for r in rows]
    ys = [r[column] for r in rows]
    x_lo, x_hi = min(xs), max(max(xs), min(xs) + 1e-9)
    y_lo, y_hi = 0.0, max(max(ys) * 1.15, 1.0)

    def px(x):
        return x0 + MARGIN + (x - x_lo) / (x_hi - x_lo) * (PANEL_W - 1.5 * MARGIN)

    def py(y):
        return y0 + PANEL_H - MARGIN + -(y - y_lo) / (y_hi - y_lo) * (PANEL_H - 1.7 * MARGIN)

    out = [f'<text x="{x0 + MARGIN}" y="{y0 + 20}" font-size="14">{title}</text>']
    if warmup > 0 and len(rows) > warmup:
        w = px(xs[warmup - 1]) - px(x_lo)
        out.append(f'<rect x="{px(x_lo):.1f}" y="{py(y_hi):.1f}" width="{w:.1f}" '
                   f'height="{py(y_lo) - py(y_hi):.1f}" fill="#eee"/>')
    out.append(f'<line x1="{px(x_lo):.1f}" y1="{py(0):.1f}" x2="{px(x_hi):.1f}" y2="{py(0):.1f}" '
               'stroke="#888"/>')
    out.append(f'<line x1="{px(x_lo):.1f}" y1="{py(0):.1f}" x2="{px(x_lo):.1f}" '
               f'y2="{py(y_hi):.1f}" stroke="#888"/>')
    for frac in (0.0, 0.5, 1.0):
        y = y_lo + frac * (y_hi - y_lo)
        out.append(f'<text x="{px(x_lo) - 6:.1f}" y="{py(y) + 4:.1f}" font-size="11" '
                   f'text-anchor="end">{y:.0f}</text>')
    out.append(f'<text x="{px(x_hi):.1f}" y="{py(0) + 16:.1f}" font-size="11" '
               f'text-anchor="end">{x_hi:.0f} min</text>')
    points = " ".join(f"{px(x):.1f},{py(y):.1f}" for x, y in zip(xs, ys))
    out.append(f'<polyline points="{points}" fill="none" stroke="#1565c0" stroke-width="2"/>')
    return out


def judge(rows, warmup, rss_growth):
    """(table lines, failures): each series' first, warm-up max, last and max."""
    lines = ["| series | first | warm-up max (floor before the last third) | last "
             "| max after warm-up (floor of the last third) | judged by "
             "| flat |", "|---|---|---|---|---|---|---|"]
    failures = []
    warm = rows[:warmup] if len(rows) > warmup else rows[:1]
    after = rows[len(warm):] or rows[-1:]
    for column, title, allowed, rule in SERIES:
        warm_max, after_max = (max(r[column] for r in part) for part in (warm, after))
        third = max(1, len(rows) // 3)
        warm_min, after_min = (min(r[column] for r in part) for part in (rows[:-third],
                                                                         rows[-third:]))
        growth = rss_growth / 100.0 if allowed is None else allowed
        before, now = (warm_max, after_max) if rule == "max" else (warm_min, after_min)
        flat = now <= before * (1.0 + growth) + 1e-9
        lines.append(f"| {title} | {rows[0][column]:.1f} | {warm_max:.1f} ({warm_min:.1f}) "
                     f"| {rows[-1][column]:.1f} | {after_max:.1f} ({after_min:.1f}) | {rule} "
                     f"| {'yes' if flat else 'NO'} |")
        if not flat:
            failures.append(f"{title}: max {now:.1f} after warm-up, {before:.1f} in it"
                            if rule == "max" else
                            f"{title}: floor {now:.1f} in the last third, {before:.1f} before")
    return lines, failures


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("samples")
    parser.add_argument("svg")
    parser.add_argument("--warmup", type=int, default=3)
    parser.add_argument("--rss-growth", type=float, default=10.0)
    args = parser.parse_args()
    rows = read_samples(args.samples)
    elements = []
    for i, (column, title, _, _) in enumerate(SERIES):
        elements += panel(rows, column, title, args.warmup, (i % 2) * PANEL_W,
                          (i // 2) * PANEL_H)
    width, height = 2 * PANEL_W, 2 * PANEL_H
    with open(args.svg, "w") as f:
        f.write(f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
                f'font-family="sans-serif"><rect width="100%" height="100%" fill="white"/>\n')
        f.write("\n".join(elements))
        f.write("\n</svg>\n")
    lines, failures = judge(rows, args.warmup, args.rss_growth)
    print("\n".join(lines))
    print(f"frames sent: {rows[-1]['frames_sent']:.0f} in {rows[-1]['minute']:.1f} min; "
          f"plot: {args.svg}")
    for failure in failures:
        print(f"not flat: {failure}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
