#!/usr/bin/env python3
"""Plots ridge's archive against the strongest anchor over several `ridge codec-bench` runs.

    ridge codec-bench DEM --json-file DEM.json -q      # once per DEM
    bench/codec_ratio_plot.py A.json B.json ... -o docs/images/codec_v4_vs_jxl.png

One line per DEM: JPEG XL effort 9's bytes (finest level) over ridge's (whole pyramid
archive) at each bound, with issue 31's targets (1.0 at every bound, 1.1 on the median).
Repeat --anchor for one panel per anchor, e.g. --anchor "JPEG XL e9" --anchor "JPEG XL e9
progressive" (JPEG XL's own pyramid). Prints the same numbers as Markdown tables. Needs
python3-matplotlib (Debian).
"""
import argparse
import json
import os
import statistics

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def ratios(path, anchor):
    with open(path) as f:
        bench = json.load(f)
    points = []
    for bound in bench["bounds"]:
        rows = {r["codec"]: r for r in bound["rows"]}
        ridge = next(r for name, r in rows.items() if name.startswith("ridge"))
        points.append((bound["max_error_metres"], rows[anchor]["bytes"] / ridge["bytes"]))
    return points


def panel(ax, runs, anchor, legend_loc):
    every = []
    print("\n%s ÷ ridge\n" % anchor)
    print("| DEM | " + " | ".join("%g m" % b for b, _ in ratios(runs[0], anchor)) + " |")
    for path in runs:
        name = os.path.splitext(os.path.basename(path))[0]
        points = ratios(path, anchor)
        every += [r for _, r in points]
        ax.plot([b for b, _ in points], [r for _, r in points], marker="o", label=name)
        print("| %s | %s |" % (name, " | ".join("%.3f" % r for _, r in points)))
    print("median %.3f, min %.3f, max %.3f" % (statistics.median(every), min(every), max(every)))
    ax.axhline(1.0, color="black", linewidth=1)
    ax.axhline(1.1, color="black", linewidth=1, linestyle="--")
    ax.text(0.52, 1.005, "target: every bound", fontsize=8)
    ax.text(0.52, 1.105, "target: the median", fontsize=8)
    ax.set_xscale("log", base=2)
    ax.set_xticks([0.5, 1, 2, 4, 8, 16])
    ax.set_xticklabels(["0.5", "1", "2", "4", "8", "16"])
    ax.set_xlabel("L-inf bound (m, log2 scale)")
    ax.set_ylabel(anchor + " bytes / ridge bytes")
    ax.set_title("ridge's archive against %s" % anchor, fontsize=10)
    ax.grid(True, alpha=0.3)
    if legend_loc:
        ax.legend(fontsize=8, loc=legend_loc)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", help="codec-bench --json-file outputs")
    parser.add_argument("-o", "--output", required=True, help="PNG to write")
    parser.add_argument("--anchor", action="append", help="anchor row(s), default JPEG XL e9")
    args = parser.parse_args()
    anchors = args.anchor or ["JPEG XL e9"]

    fig, axes = plt.subplots(1, len(anchors), figsize=(8 * len(anchors), 5), squeeze=False,
                             sharey=True)
    # One legend, in the last panel: beside a second panel its lines sit highest, so lower right.
    loc = "lower right" if len(anchors) > 1 else "lower left"
    for k, (ax, anchor) in enumerate(zip(axes[0], anchors)):
        panel(ax, args.runs, anchor, loc if k == len(anchors) - 1 else None)
    fig.tight_layout()
    fig.savefig(args.output, dpi=100)


if __name__ == "__main__":
    main()
