#!/usr/bin/env python3
"""A snapshot written in pieces on MPI ranks (.pvtr and its .vtr pieces) against the same snapshot
written whole by one process (.vtr): the index declares the whole's arrays, its pieces tile the
whole extent along the first axis, each piece opens alone (its own extent), and the pieces' cells
and coordinates, joined, are the whole's value for value.
Usage: vtr_pieces_match.py WHOLE.vtr INDEX.pvtr   (exit 0 when they match)"""
import os
import sys
import xml.etree.ElementTree as ET


def extent(text):
    return [int(v) for v in text.split()]


def read_vtr(path):
    root = ET.parse(path).getroot()
    grid = root.find("RectilinearGrid")
    piece = grid.find("Piece")
    assert grid.get("WholeExtent") == piece.get("Extent"), f"{path}: a piece must open alone"
    ext = extent(piece.get("Extent"))
    coords = [a.text.split() for a in piece.find("Coordinates")]
    read_vtr.coordinate_names = [a.get("Name") for a in piece.find("Coordinates")]
    arrays = [(a.get("Name"), a.get("type"), int(a.get("NumberOfComponents", "1")), a.text.split()) for a in piece.find("CellData")]
    return ext, coords, arrays


def main(whole_path, index_path):
    wext, wcoords, warrays = read_vtr(whole_path)
    idx = ET.parse(index_path).getroot()
    assert idx.get("type") == "PRectilinearGrid"
    pgrid = idx.find("PRectilinearGrid")
    assert extent(pgrid.get("WholeExtent")) == wext, "the index's whole extent is the whole's"
    declared = [(a.get("Name"), a.get("type"), int(a.get("NumberOfComponents", "1"))) for a in pgrid.find("PCellData")]
    assert declared == [a[:3] for a in warrays], f"declared arrays {declared}"
    assert [a.get("Name") for a in pgrid.find("PCoordinates")] == read_vtr.coordinate_names, "the index names the whole's axes"
    pieces = pgrid.findall("Piece")
    assert len(pieces) >= 2, "at least two pieces"
    n1, n2 = wext[3] - wext[2], wext[5] - wext[4]
    ny, nz = max(n1, 1), max(n2, 1)
    at = 0
    cells = {name: [] for name, *_ in warrays}
    xfaces = []
    for p in pieces:
        pext = extent(p.get("Extent"))
        assert pext[0] == at and pext[2:] == wext[2:], f"piece {p.get('Source')} extent {pext} does not follow {at}"
        at = pext[1]
        ext, coords, arrays = read_vtr(os.path.join(os.path.dirname(index_path), p.get("Source")))
        assert ext == pext, f"{p.get('Source')}: extent {ext} against the index's {pext}"
        assert coords[1:] == wcoords[1:], "the other axes' faces are the whole's"
        if xfaces:
            assert coords[0][0] == xfaces[-1], f"{p.get('Source')} starts at face {coords[0][0]}, its neighbour ends at {xfaces[-1]}"
        xfaces += coords[0] if not xfaces else coords[0][1:]
        assert [a[:3] for a in arrays] == [a[:3] for a in warrays]
        for name, _, comp, values in arrays:
            cells[name].append((pext[1] - pext[0], comp, values))
    assert at == wext[1], "the pieces cover the whole"
    assert xfaces == wcoords[0], "the first axis's faces, joined, are the whole's"
    for name, _, comp, values in warrays:
        # x runs fastest in a file: join the pieces row by row (each row of y and z)
        joined = []
        for row in range(ny * nz):
            for n0, c, v in cells[name]:
                joined += v[row * n0 * c:(row + 1) * n0 * c]
        assert joined == values, f"array {name} differs from the whole's"
    print(f"{len(pieces)} pieces match the whole ({len(warrays)} arrays, {wext[1] * ny * nz} cells)")


if __name__ == "__main__":
    try:
        main(sys.argv[1], sys.argv[2])
    except (AssertionError, OSError, ET.ParseError) as e:
        print(f"mismatch: {e}")
        sys.exit(1)
