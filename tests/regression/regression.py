#!/usr/bin/env python3
"""The regression tier: global totals of a few short `ejecta run` cases against stored values.

Each case runs the way a user runs it (the ejecta binary, a built-in deck, a few overrides) and
its summary.json is reduced to totals: impulse (in total and by material), peak force, the plate's
motion, the energy books (initial, final, work on the target, boundary flux, gravity's work, each
material kind's internal and kinetic energy), each material's mass, the flow's vertical momentum,
and the step counts. They are compared with tests/regression/totals.json:

  * step counts exactly: the same build, thread count and platform give the same steps, and a
    change of the time-step sequence is a change of the physics' discretisation;
  * every other total within a relative tolerance, RTOL (below), of the larger of its stored value
    and a floor for its kind (1e-3 of the case's scale: the charge's energy for energies, the
    impulse for impulses and momentum, the peak force for forces, ...), so that a total that
    happens to sit near zero is not asked to match digits it does not have.

A physics change that is meant moves the totals: regenerate the file with
`scripts/regression.sh --update` (or this script with --update) and commit it with the change,
saying in the commit why the totals moved.

Python 3 standard library only.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

# Relative tolerance on totals. The release and the sanitizer builds (-O3 -march=native and -O1,
# the same compiler) and every thread count give the same totals bit for bit today; 1e-6 leaves room for a
# compiler or libm that rounds differently (round-off amplified over a few hundred steps of a
# shocked flow stays orders of magnitude below it) while any change to the physics or numerics
# (a constant, a limiter, a mixed-cell rule: 1e-4 and more on these totals) fails.
RTOL = 1e-6

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_FILE = os.path.join(HERE, "totals.json")

# name -> list of runs; each run is the `ejecta run` arguments after the deck; a run may name the
# checkpoint of the run before it ({prev}/checkpoint.bin). The last run's summary is compared.
CASES = {
    "mesh-study-10mm-early": [["mesh-study", "--cell-size", "10", "--set", "end_time_s=0.0003", "--set", "early.cells_per_charge_height=10"]],
    "emi-flat-22-40mm": [["emi-flat-22", "--cell-size", "40", "--set", "end_time_s=0.001"]],
    "emi-flat-22-40mm-bvd": [["emi-flat-22", "--cell-size", "40", "--set", "end_time_s=0.001", "--set", "interface_remap=\"thinc-bvd\""]],
    "emi-v120-7-3d-60mm": [["emi-v120-7", "--cell-size", "60", "--set", "end_time_s=0.0005"]],
    "emi-v120-7-3d-60mm-frozen": [["emi-v120-7", "--cell-size", "60", "--set", "end_time_s=0.0005", "--set", "mixture_stiffness=\"frozen\"", "--set", "cfl=0.45"]],
    "field-cover7-2.5cm-restart": [
        ["field-cover7-2.5cm", "--cell-size", "40", "--set", "end_time_s=0.0005", "--checkpoint-at", "0.00025"],
        ["field-cover7-2.5cm", "--cell-size", "40", "--set", "end_time_s=0.001", "--restart", "{prev}/checkpoint.bin"],
    ],
}

WHAT = {
    "mesh-study-10mm-early": "fixed plate, no gravity, the early-time block (10 cells per charge height) mapped (2D axisymmetric)",
    "emi-flat-22-40mm": "free 300 kg plate, gravity, friction 0.2, wet sand (2D axisymmetric)",
    "emi-flat-22-40mm-bvd": "the same with THINC only where BVD picks it (interface_remap = \"thinc-bvd\")",
    "emi-v120-7-3d-60mm": "120 degree V plate, 3D quarter, free plate, gravity, friction",
    "emi-v120-7-3d-60mm-frozen": "the same with revision 14's frozen mixture stiffness at Courant 0.45 (mixture_stiffness = \"frozen\", cfl = 0.45)",
    "field-cover7-2.5cm-restart": "backfilled cover (5 materials), checkpoint at 0.25 ms, restarted to 1 ms",
}


def totals(summary):
    """The compared quantities of one run's summary.json, flat: name -> number."""
    q = {}
    r = summary["result"]
    q["impulse_Ns"] = r["impulse_Ns"]
    for kind, v in sorted(r["impulse_by_material_Ns"].items()):
        q[f"impulse_{kind}_Ns"] = v
    q["peak_force_N"] = r["peak_force_N"]
    q["plate_velocity_m_s"] = r["final_plate_velocity_m_s"]
    q["plate_displacement_m"] = r["plate_displacement_m"]
    e = summary["energy"]
    for key in ("charge_J", "initial_J", "final_J", "work_on_target_J", "boundary_flux_J", "gravity_work_J"):
        q[f"energy_{key}"] = e[key]
    for kind, v in sorted(e["by_material_J"].items()):
        q[f"energy_{kind}_internal_J"] = v["internal_J"]
        q[f"energy_{kind}_kinetic_J"] = v["kinetic_J"]
    t = summary["totals"]
    for i, m in enumerate(t["materials"]):
        q[f"mass_{i}_{m['name'].replace(' ', '_')}_kg"] = m["mass_kg"]
    q["flow_momentum_vertical_Ns"] = t["flow_momentum_vertical_Ns"]
    q["steps"] = summary["run"]["steps"]
    early = summary.get("early_time", {})
    if early.get("used"):
        q["early_steps"] = early["steps"]
        q["early_mapping_heat_J"] = early["mapping_heat_J"]
    return q


def floor_of(name, q):
    """The smallest scale a quantity is judged against (1e-3 of its kind's scale in the case)."""
    if name.endswith("_J"):
        return 1e-3 * abs(q["energy_charge_J"])
    if name.endswith("_Ns"):
        return 1e-3 * max(abs(q["impulse_Ns"]), abs(q["flow_momentum_vertical_Ns"]), 1.0)
    if name.endswith("_N"):
        return 1e-3 * max(abs(q["peak_force_N"]), 1.0)
    if name.endswith("_kg"):
        return 1e-3 * sum(v for k, v in q.items() if k.startswith("mass_"))
    if name.endswith("_m_s"):
        return 1e-3   # m/s
    if name.endswith("_m"):
        return 1e-6   # m
    return 0.0


def compare(case, stored, now):
    """Messages naming each quantity of `case` that moved beyond its tolerance (empty: none)."""
    bad = []
    for name in sorted(set(stored) | set(now)):
        if name not in now:
            bad.append(f"{case}: {name} is stored but the run no longer reports it")
            continue
        if name not in stored:
            bad.append(f"{case}: {name} = {now[name]!r} is new (not in the stored file)")
            continue
        a, b = stored[name], now[name]
        if name.endswith("steps"):
            if a != b:
                bad.append(f"{case}: {name} moved from {a} to {b} ({b - a:+d}; step counts must match exactly)")
            continue
        scale = max(abs(a), floor_of(name, stored))
        moved = abs(b - a) / scale if scale > 0.0 else (0.0 if a == b else math.inf)
        if not (moved <= RTOL):
            bad.append(f"{case}: {name} moved by {b - a:+.6g} ({moved:.2e} of {scale:.6g}; stored {a:.12g}, now {b:.12g}; "
                       f"tolerance {RTOL:g})")
    return bad


def run_case(ejecta, case, work, threads):
    prev = None
    for i, args in enumerate(CASES[case]):
        out = os.path.join(work, case if i == len(CASES[case]) - 1 else f"{case}.stage{i}")
        shutil.rmtree(out, ignore_errors=True)
        argv = [ejecta, "run"] + [a.replace("{prev}", prev or "") for a in args]
        argv += ["--out", out, "--quiet", "--no-plot", "--threads", str(threads)]
        p = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if p.returncode != 0:
            raise RuntimeError(f"{case}: `{' '.join(argv)}` exited {p.returncode}:\n{p.stdout}")
        prev = out
    return load_totals(os.path.join(prev, "summary.json"))


def load_totals(summary_path):
    with open(summary_path) as f:
        return totals(json.load(f))


def report_failures(headline, messages):
    """Prints a failure's headline and each message to stderr; returns the exit status, 1."""
    print(f"regression: FAILED: {headline}", file=sys.stderr)
    for m in messages:
        print("  " + m, file=sys.stderr)
    return 1


def same_bits(dir_a, dir_b):
    """Every case run in both work folders (two builds' regression runs) gives the same totals to
    the bit. The release build is tuned for its machine (-march=native) and the sanitizer build is
    portable: their equality is what says that the tuning changes no number."""
    compared, bad = 0, []
    for case in CASES:
        paths = [os.path.join(d, case, "summary.json") for d in (dir_a, dir_b)]
        missing = [p for p in paths if not os.path.exists(p)]
        if missing:   # every case must have run in both builds: a skipped case proves nothing
            bad.append(f"{case}: no summary.json in {', '.join(os.path.dirname(p) for p in missing)}")
            continue
        qa, qb = (load_totals(p) for p in paths)
        compared += 1
        for name in sorted(set(qa) | set(qb)):
            a, b = qa.get(name), qb.get(name)
            if a != b:
                bad.append(f"{case}: {name}: {a!r} in {dir_a}, {b!r} in {dir_b}")
    if bad:
        return report_failures("the two builds' totals differ, or a case did not run in both", bad)
    print(f"regression: {compared} case(s) give the same totals to the bit in {dir_a} and {dir_b}")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ejecta", help="the ejecta binary (needed unless --same-bits)")
    ap.add_argument("--same-bits", nargs=2, metavar=("DIR_A", "DIR_B"),
                    help="compare two builds' work folders to the bit instead of running anything")
    ap.add_argument("--file", default=DEFAULT_FILE, help="stored totals (default: tests/regression/totals.json)")
    ap.add_argument("--case", action="append", help="run only this case (repeatable; default: all)")
    ap.add_argument("--work", help="folder for the run folders (default: a temporary one, removed)")
    ap.add_argument("--threads", type=int, default=1, help="OpenMP threads per run (the totals do not depend on it)")
    ap.add_argument("--update", action="store_true", help="store the totals of this build instead of comparing")
    args = ap.parse_args()
    if args.same_bits:
        return same_bits(*args.same_bits)
    if not args.ejecta:
        ap.error("--ejecta is required (unless --same-bits)")
    cases = args.case or list(CASES)
    for c in cases:
        if c not in CASES:
            sys.exit(f"regression: unknown case '{c}'; valid: {', '.join(CASES)}")
    work = args.work or tempfile.mkdtemp(prefix="ejecta-regression-")
    os.makedirs(work, exist_ok=True)
    stored = {"cases": {}}
    if os.path.exists(args.file):
        with open(args.file) as f:
            stored = json.load(f)
    try:
        results = {c: run_case(args.ejecta, c, work, args.threads) for c in cases}
    finally:
        if not args.work:
            shutil.rmtree(work, ignore_errors=True)
    if args.update:
        stored["note"] = ("Global totals of short `ejecta run` cases (tests/regression/regression.py). Regenerate with "
                          "`scripts/regression.sh --update` when a physics change is meant, and say in the commit why they moved.")
        stored["rtol"] = RTOL
        for c in cases:
            stored["cases"][c] = {"what": WHAT[c], "runs": [" ".join(a) for a in CASES[c]], "totals": results[c]}
        with open(args.file, "w") as f:
            json.dump(stored, f, indent=2, sort_keys=True)
            f.write("\n")
        print(f"regression: stored the totals of {len(cases)} case(s) in {args.file}")
        return 0
    failures = []
    for c in cases:
        if c not in stored["cases"]:
            failures.append(f"{c}: no stored totals (run scripts/regression.sh --update)")
            continue
        failures += compare(c, stored["cases"][c]["totals"], results[c])
    for c in cases:
        print(f"regression: {c}: {len(results[c])} totals, {results[c]['steps']} steps")
    sys.stdout.flush()
    if failures:
        return report_failures("totals moved (if the change is meant: scripts/regression.sh --update)", failures)
    print(f"regression: all totals of {len(cases)} case(s) within {RTOL:g} of the stored ones, step counts equal")
    return 0


if __name__ == "__main__":
    sys.exit(main())
