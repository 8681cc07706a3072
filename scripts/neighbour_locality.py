#!/usr/bin/env python3
"""How local the particles' neighbours are in memory: what reordering them by cell would buy.

A gather loads each neighbour's data through the neighbour list, so a warp of 32 consecutive
particles touches as many 128-byte lines of a field as its neighbours' indices span. This reads
the particle positions of `penetrate run` target frames (binary VTU, points (r, 0, z)), finds
every pair within the support 2h, and gives, per frame, the 128-byte lines (32 f32) a warp
touches loading one field of all its neighbours: in the order the particles are stored; if
they were sorted by cell of side h (rows of z, then r, then index), as a list build could sort
them; and if only the data the gathers read of a neighbour were kept in that order, the
particles (and so the warps) staying as stored. Needs numpy.

    python3 scripts/neighbour_locality.py H FRAME.vtu...

H is the smoothing length in m (the Forrestal scenes: 1.5 x 4 mm = 0.006).
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


def lines_per_warp(i, j, place, nbr_place=None):
    """Distinct (warp, line) pairs over warps: `place[x]` is where particle x is stored, and
    `nbr_place[x]` where its data are read as a neighbour (`place` if None)."""
    nbr_place = place if nbr_place is None else nbr_place
    warp = place[i] // WARP
    line = nbr_place[j] // LINE
    return len(np.unique(warp * (len(place) // LINE + 1) + line)) / len(np.unique(warp))


def main():
    h = float(sys.argv[1])
    for frame in sys.argv[2:]:
        p = positions(frame)
        i, j = pairs(p, 2 * h)
        n = len(p)
        index = np.arange(n)
        cell = np.floor(p / h).astype(np.int64)
        order = np.lexsort((index, cell[:, 0], cell[:, 1]))
        sorted_place = np.empty(n, dtype=np.int64)
        sorted_place[order] = index
        print(
            f"{frame}: {n} particles, {len(i) / n:.1f} neighbours each; lines a warp touches "
            f"per field: {lines_per_warp(i, j, index):.1f} as stored, "
            f"{lines_per_warp(i, j, sorted_place):.1f} sorted by cell, "
            f"{lines_per_warp(i, j, index, sorted_place):.1f} with only the neighbour data sorted"
        )


if __name__ == "__main__":
    main()
