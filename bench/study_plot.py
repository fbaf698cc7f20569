#!/usr/bin/env python3
"""Pareto plot of bench/study's CSV: the wall time to produce each point's image (its frame,
plus the environment bake where it needs one) against mean CIEDE2000 after tonemapping, one
colour per knob, the Pareto front (no other point both faster and more accurate) drawn
through. Usage: study_plot.py study.csv docs/images/tradeoffs.png"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")  # no display: write the PNG only
import matplotlib.pyplot as plt  # noqa: E402


def pareto_front(points):
    """The points no other point beats on both time and error, by increasing time."""
    front, best = [], float("inf")
    for p in sorted(points, key=lambda p: (p["cost_ms"], p["de2000_mean"])):
        if p["de2000_mean"] < best:
            front.append(p)
            best = p["de2000_mean"]
    return front


def main(csv_path, png_path):
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{csv_path}: no points")
    for r in rows:
        for k in ("wall_ms", "gpu_ms", "bake_ms", "rmse_hdr", "max_hdr", "de2000_mean", "de2000_max"):
            r[k] = float(r.get(k) or 0.0)
        r["cost_ms"] = r["wall_ms"] + r["bake_ms"]
    fig, ax = plt.subplots(figsize=(8, 5), dpi=110)
    for knob in dict.fromkeys(r["knob"] for r in rows):
        pts = [r for r in rows if r["knob"] == knob]
        ax.scatter([p["cost_ms"] for p in pts], [max(p["de2000_mean"], 1e-3) for p in pts], label=knob, s=28)
        for p in pts:
            ax.annotate(p["setting"], (p["cost_ms"], max(p["de2000_mean"], 1e-3)), fontsize=6,
                        xytext=(3, 3), textcoords="offset points")
    front = pareto_front(rows)
    ax.plot([p["cost_ms"] for p in front], [max(p["de2000_mean"], 1e-3) for p in front], "k--", lw=0.8,
            label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("lavapipe wall time, ms (frame + environment bake; cumulative for the path tracer)")
    ax.set_ylabel("mean CIEDE2000 vs reference")
    ax.set_title("skygraph study: speed against accuracy")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png_path)
    print(f"wrote {png_path}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
