#!/usr/bin/env python3
"""Plots the sand model: compaction curves for a family of saturations plus the given soil,
and the yield curves. Usage: plot_soil.py DATA.json OUT.png (data written by `ejecta soil`)."""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(data_path, out_path):
    with open(data_path) as f:
        data = json.load(f)
    fig, (ax_lin, ax_log, ax_y) = plt.subplots(1, 3, figsize=(16, 5.2))
    cmap = plt.get_cmap("viridis")
    family = data["family"]
    for i, c in enumerate(family):
        color = cmap(i / max(len(family) - 1, 1))
        for ax in (ax_lin, ax_log):
            ax.plot(c["natural_strain"], c["pressure_MPa"], color=color, lw=1.2, label=c["label"])
        ax_y.plot(c["yield_pressure_MPa"], c["yield_MPa"], color=color, lw=1.2, label=c["label"])
    soil = data["soil"]
    for ax in (ax_lin, ax_log):
        ax.plot(soil["natural_strain"], soil["pressure_MPa"], "k--", lw=2.2, label=soil["label"])
        ax.set_xlabel("natural volumetric strain -ln(V/V0)")
        ax.set_ylabel("pressure (MPa)")
        ax.grid(True, alpha=0.3)
    ax_lin.set_ylim(0, 1500)
    ax_lin.set_xlim(0, 0.8)
    ax_lin.set_title("Loading compaction curves")
    ax_log.set_yscale("log")
    ax_log.set_ylim(1e-2, 5e4)
    ax_log.set_xlim(0, 0.8)
    ax_log.set_title("Loading compaction curves (log pressure)")
    ax_y.plot(soil["yield_pressure_MPa"], soil["yield_MPa"], "k--", lw=2.2, label=soil["label"])
    ax_y.set_xlabel("pressure (MPa)")
    ax_y.set_ylabel("yield strength (MPa)")
    ax_y.set_title("Yield curves (plateau falls with saturation)")
    ax_y.grid(True, alpha=0.3)
    ax_lin.legend(fontsize=8)
    fig.suptitle(data["title"])
    fig.tight_layout()
    fig.savefig(out_path, dpi=110, format="png")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_soil.py DATA.json OUT.png")
    main(sys.argv[1], sys.argv[2])
