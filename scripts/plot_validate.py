#!/usr/bin/env python3
"""Draws one figure of the `ejecta validate` report. Usage: plot_validate.py DATA.json OUT.png, where
DATA.json is {"figure": study, "title": ..., "plot": {...}} as written by ejecta. SI units, with
impulses in N s, times in ms and heights in mm on the axes."""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def histories(ax, hs):
    for h in hs:
        t = [v * 1e3 for v in h["t_s"]]
        ax.plot(t, h["impulse_Ns"], lw=1.3, label=h["label"])
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("impulse (N s)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)


def mesh(p):
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(15, 4.2))
    histories(a1, p["histories"])
    a2.plot(p["cell_mm"], p["impulse_Ns"], "o-", color="tab:blue")
    m = p["mean_Ns"]
    a2.axhline(m, color="k", lw=0.8, label="mean of the finest three")
    a2.axhspan(0.98 * m, 1.02 * m, color="tab:green", alpha=0.15, label="mean +/- 2%")
    a2.set_xlabel("cell size (mm)")
    a2.set_ylabel("total impulse at 10 ms (N s)")
    a2.invert_xaxis()
    a2.grid(alpha=0.3)
    a2.legend(fontsize=8)
    # each material's share must converge too, not only the sum
    # by the cell beside the plate (dashed) and by the materials within 20 mm of it (solid, banded)
    for key, label, colour, style, band in (("impulse_products_Ns", "products, cell beside the plate (shown)", "tab:red", "o--", False),
                                            ("impulse_soil_Ns", "soil, cell beside the plate (shown)", "tab:olive", "o--", False),
                                            ("within_products", "products, within 20 mm (judged)", "tab:red", "s-", True),
                                            ("within_soil", "soil, within 20 mm (judged)", "tab:olive", "s-", True)):
        if key in p:
            v = p[key]
            a3.plot(p["cell_mm"], v, style, color=colour, label=label)
            if band or "within_products" not in p:
                fine = v[-3:] if len(v) >= 3 else v
                mean = sum(fine) / len(fine)
                a3.axhspan(0.95 * mean, 1.05 * mean, color=colour, alpha=0.12)
    a3.set_xlabel("cell size (mm)")
    a3.set_ylabel("impulse by material at 10 ms (N s)")
    a3.set_title("bands: mean of the finest three +/- 5%", fontsize=9)
    a3.invert_xaxis()
    a3.grid(alpha=0.3)
    a3.legend(fontsize=8)
    return fig


def moisture(p):
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    histories(a1, p["histories"])
    a2.plot(p["moisture_pct"], p["impulse_Ns"], "o-", color="tab:brown")
    a2.set_xlabel("moisture (%)")
    a2.set_ylabel("impulse at 10 ms (N s)")
    a2.grid(alpha=0.3)
    return fig


def field(p):
    fig, axes = plt.subplots(1, len(p["groups"]), figsize=(11, 4.2), sharey=True)
    if len(p["groups"]) == 1:
        axes = [axes]
    for ax, g in zip(axes, p["groups"]):
        bars = ax.bar(range(len(g["labels"])), g["impulse_Ns"], color=["tab:blue", "tab:orange", "tab:red"][: len(g["labels"])])
        for b, c in zip(bars, g["change_pct"]):
            ax.annotate(f"{c:+.1f}%", (b.get_x() + b.get_width() / 2, b.get_height()), ha="center", va="bottom", fontsize=8)
        ax.set_xticks(range(len(g["labels"])))
        ax.set_xticklabels([lab.replace(", ", "\n") for lab in g["labels"]], fontsize=8)
        ax.set_title(f"cover {g['thickness_cm']:g} cm", fontsize=10)
        ax.grid(alpha=0.3, axis="y")
    axes[0].set_ylabel("impulse at 10 ms (N s)")
    return fig


def split_bars(ax, p, **ticks):
    """Each case's impulse by material: soil, products stacked on it, and beside them air (net of
    ambient, so it can be negative), in a bar of its own rather than over the soil's."""
    x = range(len(p["labels"]))
    w = 0.38
    ax.bar([i - w / 2 for i in x], p["soil"], width=w, color="tab:brown", label="soil")
    ax.bar([i - w / 2 for i in x], p["products"], width=w, bottom=p["soil"], color="tab:red", label="products (on the soil)")
    ax.bar([i + w / 2 for i in x], p["air"], width=w, color="tab:blue", label="air (net of ambient)")
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xticks(list(x))
    ax.set_xticklabels(p["labels"], fontsize=8, **ticks)
    ax.set_ylabel("impulse (N s)")
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8)


def share(p):
    fig, ax = plt.subplots(figsize=(11, 4.6))
    split_bars(ax, p, rotation=30, ha="right")
    fig.tight_layout()
    return fig


def sensitivity(p):
    fig, ax = plt.subplots(figsize=(9, 0.6 * len(p["labels"]) + 1.5))
    y = range(len(p["labels"]))
    ax.barh(y, p["change_pct"], color=["tab:red" if v < 0 else "tab:green" for v in p["change_pct"]])
    ax.set_yticks(list(y))
    ax.set_yticklabels(p["labels"], fontsize=8)
    ax.axvline(0.0, color="k", lw=0.6)
    ax.set_xlabel(f"change of impulse (%) from {p['baseline_Ns']:.0f} N s")
    ax.grid(alpha=0.3, axis="x")
    fig.tight_layout()
    return fig


def dres(p):
    n = len(p["cases"])
    fig, axes = plt.subplots(1, 1 + n, figsize=(5 * (1 + n), 4.2))
    for c in p["cases"]:
        h = c["history"]
        t = [v * 1e3 for v in h["t_s"]]
        top = [None if v is None else v * 1e3 for v in h["soil_top_m"]]
        axis = [None if v is None else v * 1e3 for v in h["bubble_height_on_axis_m"]]
        (line,) = axes[0].plot(t, top, lw=1.4, label=f"{c['label']}: top of soil")
        axes[0].plot(t, axis, lw=1.0, ls="--", color=line.get_color(), label=f"{c['label']}: on the axis")
    axes[0].set_xlabel("time (ms)")
    axes[0].set_ylabel("height over the surface (mm)")
    axes[0].grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    for ax, c in zip(axes[1:], p["cases"]):
        pr = c["profiles"]
        r = [v * 1e3 for v in pr["r_m"]]
        cmap = plt.get_cmap("viridis")
        for i, (tp, z) in enumerate(zip(pr["times_s"], pr["z_m"])):
            pts = [(ri, zi * 1e3) for ri, zi in zip(r, z) if zi is not None and ri <= 400]
            ax.plot([q[0] for q in pts], [q[1] for q in pts], color=cmap(i / max(1, len(pr["times_s"]) - 1)), label=f"{tp * 1e3:.2f} ms")
        ax.set_title(c["label"], fontsize=10)
        ax.set_xlabel("r (mm)")
        ax.set_ylabel("soil surface (mm)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    return fig


def vplates(p):
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    histories(a1, p["histories"])
    split_bars(a2, p, rotation=15)
    return fig


def main(data_path, out_path):
    with open(data_path) as f:
        d = json.load(f)
    fig = {"mesh": mesh, "moisture": moisture, "field": field, "share": share, "sensitivity": sensitivity, "dres": dres, "vplates": vplates}[d["figure"]](d["plot"])
    fig.suptitle(d["title"], fontsize=11)
    fig.tight_layout()
    fig.savefig(out_path, dpi=110, format="png")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
