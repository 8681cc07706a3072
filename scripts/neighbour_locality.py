#!/usr/bin/env python3
"""How local the particles' neighbours are in memory: what the order the particles are stored in
buys a GPU warp.

A gather loads each neighbour's data through the neighbour list, so a warp of 32 consecutive
particles touches as many 128-byte lines as its neighbours' indices span. This reads the
particle positions of `penetrate run` target frames (binary VTU, points (r, 0, z)), finds every
pair within the support 2h, and gives, per frame, the lines a warp touches loading a 4-byte
field (32 to a line) and a 16-byte packed record (8 to a line) of all its neighbours: with the
particles as stored; kept from the first frame in the lattice's row-by-row order, or in its
Z-order (what `mesh::target::lattice` lays); and sorted by cell of side h at that frame (rows
of z, then r, then index), as a list build could sort them. Needs numpy.

    python3 scripts/neighbour_locality.py H FIRST_FRAME.vtu [LATER_FRAME.vtu...]

H is the smoothing length in m (the Forrestal scenes: 1.5 x 4 mm = 0.006); the first frame
must be a run's first (the lattice as laid).
"""
import re
import sys
from collections import defaultdict

import numpy as np

WARP = 32
LINE = 32  # f32 per 128-byte line


def positions(path):
    """(r, z) of the frame's points, from the first appended array (UInt64 byte count)."""
    data = open(path, "rb").read()
    head = data[: data.index(b"<AppendedData")]
    n = int(re.search(rb'NumberOfPoints="(\d+)"', head).group(1))
    start = data.index(b"_", data.index(b"<AppendedData")) + 1
    count = int(np.frombuffer(data[start : start + 8], dtype="<u8")[0])
    xyz = np.frombuffer(data[start + 8 : start + 8 + count], dtype="<f4").reshape(n, 3)
    return xyz[:, [0, 2]].astype(np.float64)


def pairs(p, support):
    """Every (i, j) closer than `support`, i itself included, by a cell search."""
    key = np.floor(p / support).astype(np.int64)
    cells = defaultdict(list)
    for i, (a, b) in enumerate(key):
        cells[(a, b)].append(i)
    out_i, out_j = [], []
    for (a, b), members in cells.items():
        members = np.array(members)
        near = np.concatenate(
            [np.array(cells.get((a + da, b + db), []), dtype=np.int64)
             for da in (-1, 0, 1) for db in (-1, 0, 1)]
        )
        d = p[members][:, None, :] - p[near][None, :, :]
        ii, jj = np.nonzero((d ** 2).sum(-1) < support ** 2)
        out_i.append(members[ii])
        out_j.append(near[jj])
    return np.concatenate(out_i), np.concatenate(out_j)


def lines_per_warp(i, j, place, per_line):
    """Distinct (warp, line) pairs over warps, `per_line` neighbour records to a 128-byte line:
    `place[x]` is where particle x is stored (and so its warp and where it is read)."""
    warp = place[i] // WARP
    line = place[j] // per_line
    return len(np.unique(warp * (len(place) // per_line + 1) + line)) / len(np.unique(warp))


def z_order(col, row):
    """Key of lattice site (col, row) on the Z-order curve, as `mesh::target::lattice` sorts."""
    key = np.zeros(len(col), dtype=np.int64)
    for b in range(24):
        key |= ((col >> b) & 1) << (2 * b) | ((row >> b) & 1) << (2 * b + 1)
    return key


def places(order):
    place = np.empty(len(order), dtype=np.int64)
    place[order] = np.arange(len(order))
    return place


def main():
    h = float(sys.argv[1])
    kept = None
    for frame in sys.argv[2:]:
        p = positions(frame)
        n = len(p)
        if kept is None:
            # The orders a run keeps, laid from its first frame's lattice (first column at Δ/2).
            spacing = 2 * p[:, 0].min()
            col = np.rint(p[:, 0] / spacing - 0.5).astype(np.int64)
            row = np.rint(-p[:, 1] / spacing - 0.5).astype(np.int64)
            kept = {
                "as stored": np.arange(n),
                "row by row": places(np.lexsort((col, row))),
                "Z-order": places(np.argsort(z_order(col, row), kind="stable")),
            }
        i, j = pairs(p, 2 * h)
        cell = np.floor(p / h).astype(np.int64)
        orders = dict(kept)
        orders["sorted by cell now"] = places(np.lexsort((np.arange(n), cell[:, 0], cell[:, 1])))
        figures = ", ".join(
            f"{name} {lines_per_warp(i, j, place, LINE):.1f} / "
            f"{lines_per_warp(i, j, place, LINE // 4):.1f}"
            for name, place in orders.items()
        )
        print(
            f"{frame}: {n} particles, {len(i) / n:.1f} neighbours each; 128-byte lines a warp "
            f"touches loading a 4-byte / 16-byte record of every neighbour: {figures}"
        )


if __name__ == "__main__":
    main()
