#!/usr/bin/env python3
"""What lies under a flat plate in a 2D axisymmetric run's fields (fields/field_*.vtr, as `ejecta run`
writes them). Usage: plate_face.py [--r-max M] [--depth M] FIELD.vtr ...

For each field, over the plate's underside at r < --r-max (default 0.4 m), area-weighted by ring:
the products' volume fraction in the cell beside the plate and within --depth (default 0.02 m) of
it, and the sand within that depth as an equivalent thickness (its volume fraction times each cell's
height, summed; mm). The plate is the lowest body cell (`target` > 0.5) of each column. It answers
whether the material at the plate's face converges with the cell size (docs/validate.md, "The mesh
study's split, judged within a fixed depth"). Only the standard library: the fields are ASCII."""
import argparse
import re


def arrays(path):
    text = open(path).read()
    return {m.group(1): [float(x) for x in m.group(2).split()]
            for m in re.finditer(r'<DataArray[^>]*Name="([^"]*)"[^>]*>(.*?)</DataArray>', text, re.S)}


def plate_face(path, r_max, depth):
    a = arrays(path)
    r, z, body = a["r"], a["z"], a["target"]
    nr, nz = len(r) - 1, len(z) - 1
    fractions = [k for k in a if k.startswith("alpha_")]
    soil = [k for k in fractions if "sand" in k.lower() or "soil" in k.lower()]
    products = [k for k in fractions if k != "alpha_air" and k not in soil]
    if len(soil) != 1 or len(products) != 1:
        raise SystemExit(f"{path}: expected one soil and one products fraction, found {fractions}")
    sand, prod = a[soil[0]], a[products[0]]
    area = sand_mm = beside = within = 0.0
    for i in range(nr):
        if 0.5 * (r[i] + r[i + 1]) > r_max:
            break
        jb = next((j for j in range(nz) if body[i + nr * j] > 0.5), None)   # x (r) runs fastest
        if not jb:
            continue
        ring = r[i + 1] ** 2 - r[i] ** 2
        s = p = d = 0.0
        j = jb - 1
        while j >= 0 and z[jb] - z[j + 1] < depth:   # the last cell by the part inside the depth
            dz = min(z[j + 1] - z[j], depth - (z[jb] - z[j + 1]))
            s += sand[i + nr * j] * dz
            p += prod[i + nr * j] * dz
            d += dz
            j -= 1
        area += ring
        sand_mm += ring * 1e3 * s
        within += ring * p / d
        beside += ring * prod[i + nr * (jb - 1)]
    if area == 0.0:
        raise SystemExit(f"{path}: no plate (target) cell with fluid beneath it at r < {r_max} m")
    return beside / area, within / area, sand_mm / area


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("fields", nargs="+")
    ap.add_argument("--r-max", type=float, default=0.4, help="outer radius of the rings read, m")
    ap.add_argument("--depth", type=float, default=0.02, help="depth of the layer beneath the plate, m")
    o = ap.parse_args()
    print("field,products_beside,products_within,sand_within_mm")
    for f in o.fields:
        b, w, s = plate_face(f, o.r_max, o.depth)
        print(f"{f},{b:.3f},{w:.3f},{s:.2f}")


if __name__ == "__main__":
    main()
