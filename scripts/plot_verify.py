#!/usr/bin/env python3
"""Plots `ejecta verify` profiles: for each problem, the finest numerical solution against the
exact (or published) one. Usage: plot_verify.py DATA.json OUT.png (data written by ejecta)."""
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(data_path, out_path):
    with open(data_path) as f:
        panels = json.load(f)
    n = max(len(panels), 1)
    cols = min(4, n)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.6 * rows), squeeze=False)
    for ax, p in zip(axes.flat, panels):
        x = p["x"]
        num = [v if v is not None else float("nan") for v in p["numeric"]]
        ex = [v if v is not None else float("nan") for v in p["exact"]]
        marker = "o" if len(x) <= 12 else None
        ax.plot(x, num, color="tab:blue", lw=1.2, marker=marker, ms=4, label=f"ejecta ({p['resolution']})")
        ax.plot(x, ex, color="k", lw=1.0, ls="--", marker="s" if marker else None, ms=4, label="exact / reference")
        ax.set_title(p["problem"], fontsize=10)
        ax.set_xlabel(p["x_label"], fontsize=8)
        ax.set_ylabel(p["y_label"], fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[len(panels):]:
        ax.axis("off")
    fig.suptitle("ejecta verify: finest resolution against exact solutions", fontsize=12)
    fig.tight_layout()
    fig.savefig(out_path, dpi=110, format="png")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_verify.py DATA.json OUT.png")
    main(sys.argv[1], sys.argv[2])
