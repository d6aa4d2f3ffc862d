#!/usr/bin/env python3
"""Plots one `ejecta run`: target impulse (total and by material) and force vs time, and the soil
surface (bubble) profiles. Usage: plot_run.py DATA.json OUT.png (data written by ejecta)."""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(data_path, out_path):
    with open(data_path) as f:
        d = json.load(f)
    h = d["history"]
    t = [r[0] * 1e3 for r in h]
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(16, 4.8))
    a1.plot(t, [r[1] for r in h], "k", lw=2, label="total")
    # by the materials within 20 mm of the target (columns 8-10; it converges with the cell size),
    # and thin and dashed by the cell beside it (columns 5-7; it does not: docs/validate.md)
    for col, name, c in ((5, "air", "tab:blue"), (6, "products", "tab:red"), (7, "soil", "tab:brown")):
        if len(h[0]) > col + 3:
            a1.plot(t, [r[col + 3] for r in h], color=c, lw=1.2, label=f"{name}, within 20 mm")
            a1.plot(t, [r[col] for r in h], color=c, lw=0.8, ls="--", label=f"{name}, cell beside")
        else:
            a1.plot(t, [r[col] for r in h], color=c, lw=1.2, label=name)
    a1.set_xlabel("time (ms)")
    a1.set_ylabel("impulse on the target (N s)")
    a1.legend(fontsize=8)
    a1.grid(True, alpha=0.3)
    a2.plot(t, [r[2] / 1e6 for r in h], "k", lw=1)
    a2.set_xlabel("time (ms)")
    a2.set_ylabel("force on the target (MN)")
    a2.grid(True, alpha=0.3)
    r = d["r"]
    cmap = plt.get_cmap("viridis")
    n = max(len(d["profiles"]), 1)
    for i, (tp, prof) in enumerate(zip(d["profile_times"], d["profiles"])):
        z = [v if v is not None else float("nan") for v in prof]
        a3.plot(r, z, color=cmap(i / n), label=f"{tp * 1e3:.2f} ms")
    a3.set_xlabel("r (m)")
    a3.set_ylabel("soil surface z (m)")
    a3.set_xlim(0, max(r) if r else 1)
    a3.legend(fontsize=8)
    a3.grid(True, alpha=0.3)
    a3.set_title("soil bubble profile")
    fig.suptitle(d.get("title", "ejecta run"))
    fig.tight_layout()
    fig.savefig(out_path, dpi=100, format="png")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_run.py DATA.json OUT.png")
    main(sys.argv[1], sys.argv[2])
