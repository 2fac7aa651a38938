#!/usr/bin/python3
"""Penetration checker, independent of xdyna's contact code.

    penetration.py DECK THIST_H5

Reads the shells of a keyword deck (*ELEMENT_SHELL, *SECTION_SHELL
thickness, *PART) and the nodal coordinates of every output state from the
nodout group of thist.h5 (the deck must request all nodes). For every node
and every shell segment that does not contain the node, nor share a
segment with it, it measures the distance from the node to the segment's
mid-surface (the plane through the segment's centre with the normal of its
diagonals, where the node's projection falls inside the segment). Reports:

- the largest overlap of the two half-thicknesses, (t_node + t_seg)/2 - |d|,
  as a fraction of t_seg (0 when the surfaces do not overlap);
- pass-throughs: a node whose signed distance to a segment changes sign
  between two states while its projection lies inside the segment in both
  (it crossed the mid-surface).

Brute force over node-segment pairs near each other, vectorised with numpy:
fine for the test decks (1e3-1e4 shells), not for production models.
"""
import sys

import h5py
import numpy as np

where = None   # (node id, state number, segment's node ids) of the largest overlap


def read_shells(deck):
    """Shell connectivity (ids), part of each shell, and thickness per part."""
    shells, sec_t, part_sec = [], {}, {}
    kw, card = None, 0
    for raw in open(deck):
        line = raw.rstrip("\n")
        if line.startswith("$"):
            continue
        if line.startswith("*"):
            kw, card = line.split()[0].upper(), 0
            continue
        card += 1
        if kw == "*ELEMENT_SHELL":
            v = [int(line[i:i + 8]) for i in range(0, 48, 8)]
            shells.append(v)
        elif kw == "*SECTION_SHELL":
            if card == 1:
                cur = int(line[0:10])
            elif card == 2:
                sec_t[cur] = float(line[0:10])
        elif kw == "*PART" and card % 2 == 0:
            part_sec[int(line[0:10])] = int(line[10:20])
    sh = np.array(shells)
    t = np.array([sec_t[part_sec[p]] for p in sh[:, 1]])
    return sh[:, 2:6], t


def check(deck, h5):
    conn_ids, tseg = read_shells(deck)
    with h5py.File(h5, "r") as f:
        ids = f["nodout/ids"][:]
        X = np.stack([f["nodout/x_coordinate"][:], f["nodout/y_coordinate"][:], f["nodout/z_coordinate"][:]], -1)
    index = {int(n): k for k, n in enumerate(ids)}
    conn = np.vectorize(index.get)(conn_ids)
    nn = len(ids)
    # node thickness: the largest shell thickness at the node
    tnode = np.zeros(nn)
    for k in range(4):
        np.maximum.at(tnode, conn[:, k], tseg)
    # node-segment pairs to skip: the node's own segments and its neighbours'
    near = [set() for _ in range(nn)]
    for s in range(len(conn)):
        for a in conn[s]:
            near[a].update(conn[s])
    skip_seg = [set() for _ in range(nn)]
    seg_of = [set() for _ in range(nn)]
    for s in range(len(conn)):
        for a in conn[s]:
            seg_of[a].add(s)
    for a in range(nn):
        for b in near[a]:
            skip_seg[a].update(seg_of[b])
    worst, crossings, prev = 0.0, 0, None
    global where
    for state, X1 in enumerate(X):
        xs = X1[conn]                                  # (nseg, 4, 3)
        cen = xs.mean(1)
        nrm = np.cross(xs[:, 2] - xs[:, 0], xs[:, 3] - xs[:, 1])
        nrm /= np.linalg.norm(nrm, axis=1)[:, None]
        size = np.max(np.linalg.norm(xs - cen[:, None], axis=2), axis=1)
        # candidate pairs: node within one segment size of the centre
        diff = X1[:, None, :] - cen[None, :, :]        # (nn, nseg, 3)
        close = np.linalg.norm(diff, axis=2) < size[None] + tseg[None]
        a_idx, s_idx = np.nonzero(close)
        keep = np.array([s not in skip_seg[a] for a, s in zip(a_idx, s_idx)], dtype=bool)
        a_idx, s_idx = a_idx[keep], s_idx[keep]
        dist = np.einsum("ij,ij->i", diff[a_idx, s_idx], nrm[s_idx])
        p = X1[a_idx] - dist[:, None] * nrm[s_idx]
        inside = inside_quad(p, xs[s_idx], nrm[s_idx])
        over = 0.5 * (tnode[a_idx] + tseg[s_idx]) - np.abs(dist)
        frac = np.where(inside, np.maximum(over, 0.0) / tseg[s_idx], 0.0)
        if frac.size and float(frac.max()) > worst:
            worst = float(frac.max())
            j = int(np.argmax(frac))
            where = (int(ids[a_idx[j]]), state, conn_ids[s_idx[j]].tolist())
        cur = {(a, s): dv for a, s, dv, ins in zip(a_idx, s_idx, dist, inside) if ins}
        if prev is not None:
            for key, dv in cur.items():
                if key in prev and np.sign(prev[key]) != np.sign(dv) and prev[key] != 0.0:
                    crossings += 1
        prev = cur
    return worst, crossings


def inside_quad(p, xs, nrm):
    """Is p (on the segment's plane) inside the quadrilateral xs (4 corners)?"""
    ok = np.ones(len(p), dtype=bool)
    for k in range(4):
        a, b = xs[:, k], xs[:, (k + 1) % 4]
        c = np.einsum("ij,ij->i", np.cross(b - a, p - a), nrm)
        ok &= c >= 0.0
    return ok


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    worst, crossings = check(sys.argv[1], sys.argv[2])
    print(f"largest overlap {worst:.3f} of the segment thickness; pass-throughs {crossings}")
    if where:
        print(f"  at node {where[0]}, state {where[1]}, segment {where[2]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
