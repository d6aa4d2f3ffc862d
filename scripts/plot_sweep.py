#!/usr/bin/env python3
"""Plots an `ejecta sweep`: impulse against the first varied key, one line per combination of the
others. Usage: plot_sweep.py DATA.json OUT.png (data written by ejecta)."""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(v):
    try:
        return float(v)
    except ValueError:
        return v


def main(data_path, out_path):
    with open(data_path) as f:
        d = json.load(f)
    keys = [a["key"] for a in d["vary"]]
    first = keys[0]
    groups = {}
    for r in d["rows"]:
        if "impulse_Ns" not in r:  # a case that failed or has not run yet
            continue
        rest = ", ".join(f"{k}={r['values'][k]}" for k in keys[1:])
        groups.setdefault(rest, []).append((number(r["values"][first]), r["impulse_Ns"]))
    fig, ax = plt.subplots(figsize=(7, 4.8))
    if not groups:
        sys.exit("no case has a result to plot")
    for label, pts in groups.items():
        xs = [p[0] for p in pts]
        ys = [p[1] for p in pts]
        ax.plot(range(len(xs)) if isinstance(xs[0], str) else xs, ys, marker="o", label=label or "impulse")
        if isinstance(xs[0], str):
            ax.set_xticks(range(len(xs)), xs)
    ax.set_xlabel(first)
    ax.set_ylabel("impulse on the target (N s)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"ejecta sweep: {d['deck'].split('/')[-1]}")
    fig.tight_layout()
    fig.savefig(out_path, dpi=100, format="png")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_sweep.py DATA.json OUT.png")
    main(sys.argv[1], sys.argv[2])
