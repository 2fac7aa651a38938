#!/usr/bin/python3
"""Penetration checker, independent of xdyna's contact code.

    penetration.py RUN [--json] [--parts=1,2] [--growth]
                                       states of RUN/d3plot.h5 (shells and solids);
                                       --parts: only nodes and segments of those
                                       parts (a deck's contact set); --growth: an
                                       overlap counts only beyond what the pair had
                                       in the first state (overlaps the deck's
                                       geometry starts with)
    penetration.py DECK THIST_H5       shells of DECK, nodes of thist.h5's nodout

Surfaces: every shell is a two-sided segment of its thickness t (from the
states' shell_thickness, or the deck's section); every hexahedron face that
belongs to one hexahedron only is an outward segment of a solid, whose
local thickness is the element's depth behind it (twice the distance from
the face's centre to the element's centre).

For every node and every segment near it, skipping segments that contain
the node or a node of an element sharing one with it, the node is projected
on the segment: a shell segment's bilinear surface (the closest point), a
solid face's plane (through its centre, normal to its diagonals); where the
projection falls inside the segment:

- shell segment: the overlap is (t_node + t)/2 - |d|, where t_node is the
  largest thickness of the node's own shells (0 for a solid's node);
- solid face: where the node (inflated by t_node/2) lies inside the
  hexahedron, its depth t_node/2 - d below the nearest of that element's
  exterior faces. Faces of the node's own solid part are skipped: a solid
  part is not checked against itself.

Reported: the largest overlap as a fraction of the segment's local
thickness, with node, state and segment, and the pass-throughs: a node
whose signed distance to a shell segment changes sign between two states
while its projection lies inside the segment in both (it crossed the
mid-surface), and by no more than 1.5 times the node's motion against the
segment's nodes (a larger change is the closest point leaping from one
side to the other, not a crossing). With a few dozen states,
pass-throughs between two states that come back are not seen; the
overlap check is the stricter of the two. Nodes under prescribed motion:
in the DECK THIST_H5 form, the figures are given again for the pairs
free of them (no contact force stops such a node, nor a segment it
drives).

Candidate pairs come from a uniform grid of cells one segment size plus
one thickness wide, so the cost is linear in the model size.
"""
import json
import os
import sys

import h5py
import numpy as np

HEX_FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]

where = None   # (node id, state number, segment's node ids) of the largest overlap


class Surfaces:
    """Segments of one model: conn (nseg, 4) node indices, kind (0 shell,
    1 solid face), part, elem_nodes (the nodes of the segment's element, for
    the skip rule), solid face's opposite-centre data for the depth."""

    def __init__(self, nn, shells, shell_part, hexes=None, hex_part=None):
        conn, kind, part, elem = [], [], [], []
        for s, p in zip(shells, shell_part):
            conn.append(s)
            kind.append(0)
            part.append(p)
            elem.append(tuple(s))
        self.nshell = len(conn)
        self.face_elem = []
        if hexes is not None and len(hexes):
            count = {}
            for e, h in enumerate(hexes):
                for f in HEX_FACES:
                    key = tuple(sorted(h[i] for i in f))
                    count[key] = count.get(key, 0) + 1
            for e, h in enumerate(hexes):
                for f in HEX_FACES:
                    if count[tuple(sorted(h[i] for i in f))] == 1:
                        conn.append([h[i] for i in f])
                        kind.append(1)
                        part.append(hex_part[e])
                        elem.append(tuple(h))
                        self.face_elem.append(e)
        self.conn = np.array(conn, dtype=np.int64).reshape(-1, 4)
        self.kind = np.array(kind)
        self.part = np.array(part)
        self.hexes = np.array(hexes, dtype=np.int64) if hexes is not None and len(hexes) else None
        self.face_elem = np.array(self.face_elem, dtype=np.int64)
        # nodes to skip per node: all nodes of elements that contain it
        near = [set() for _ in range(nn)]
        for ns in elem:
            for a in ns:
                near[a].update(ns)
        self.elem_nodes = elem
        self.near = near
        self.node_part = -np.ones(nn, dtype=np.int64)      # solid part of each node (-1: none)
        if self.hexes is not None:
            for e, h in enumerate(self.hexes):
                self.node_part[h] = hex_part[e]

    def skip(self, a, s):
        """Does segment s contain node a or a node of an element touching a?"""
        if self.kind[s] == 1 and self.node_part[a] == self.part[s]:
            return True
        return not self.near[a].isdisjoint(self.elem_nodes[s])


def candidate_pairs(X, cen, reach):
    """(node, segment) pairs with the node within reach[s] of segment s's
    centre, from a uniform grid of cells max(reach) wide."""
    h = float(reach.max())
    cell_n = np.floor(X / h).astype(np.int64)
    cell_s = np.floor(cen / h).astype(np.int64)
    bucket = {}
    for a, c in enumerate(map(tuple, cell_n)):
        bucket.setdefault(c, []).append(a)
    A, S = [], []
    offs = [(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)]
    for s, (ci, cj, ck) in enumerate(map(tuple, cell_s)):
        for di, dj, dk in offs:
            lst = bucket.get((ci + di, cj + dj, ck + dk))
            if lst:
                A.extend(lst)
                S.extend([s] * len(lst))
    A, S = np.array(A, dtype=np.int64), np.array(S, dtype=np.int64)
    if len(A):
        d = np.linalg.norm(X[A] - cen[S], axis=1)
        ok = d < reach[S]
        A, S = A[ok], S[ok]
    return A, S


def inside_quad(p, xs, nrm):
    """Is p (on the segment's plane) inside the quadrilateral xs (4 corners;
    a triangle repeats its third corner)?"""
    ok = np.ones(len(p), dtype=bool)
    for k in range(4):
        a, b = xs[:, k], xs[:, (k + 1) % 4]
        c = np.einsum("ij,ij->i", np.cross(b - a, p - a), nrm)
        ok &= c >= -1e-12 * np.einsum("ij,ij->i", b - a, b - a)
    return ok


def bilinear_distance(P, Q, iters=8):
    """Signed distance of points P (n, 3) to the bilinear patches Q (n, 4, 3)
    at the closest point (Newton on (x(xi, eta) - p) . x_xi = (x - p) . x_eta
    = 0 from the patch centre), sign by the normal x_xi x x_eta there, and
    whether that point lies inside the patch (|xi|, |eta| <= 1). Triangles
    (fourth corner = third) are bilinear patches too, degenerate at one
    corner."""
    n = len(P)
    if n == 0:
        return np.zeros(0), np.zeros(0, dtype=bool)
    xi = np.zeros(n)
    eta = np.zeros(n)
    sx = np.array([-1.0, 1.0, 1.0, -1.0])
    se = np.array([-1.0, -1.0, 1.0, 1.0])
    a = 0.25 * np.einsum("k,nkj->nj", sx, Q)                 # x = c + a xi + b eta + h xi eta
    b = 0.25 * np.einsum("k,nkj->nj", se, Q)
    h = 0.25 * np.einsum("k,nkj->nj", sx * se, Q)
    c = Q.mean(1)
    for _ in range(iters):
        x = c + a * xi[:, None] + b * eta[:, None] + h * (xi * eta)[:, None]
        r = x - P
        tx = a + h * eta[:, None]
        te = b + h * xi[:, None]
        g1 = np.einsum("ij,ij->i", r, tx)
        g2 = np.einsum("ij,ij->i", r, te)
        h11 = np.einsum("ij,ij->i", tx, tx)
        h22 = np.einsum("ij,ij->i", te, te)
        h12 = np.einsum("ij,ij->i", tx, te) + np.einsum("ij,ij->i", r, h)
        det = h11 * h22 - h12 * h12
        det = np.where(np.abs(det) < 1e-30, 1e-30, det)
        xi = np.clip(xi - (h22 * g1 - h12 * g2) / det, -1.5, 1.5)
        eta = np.clip(eta - (h11 * g2 - h12 * g1) / det, -1.5, 1.5)
    x = c + a * xi[:, None] + b * eta[:, None] + h * (xi * eta)[:, None]
    nrm = np.cross(a + h * eta[:, None], b + h * xi[:, None])
    nrm /= np.maximum(np.linalg.norm(nrm, axis=1), 1e-30)[:, None]
    d = np.linalg.norm(P - x, axis=1) * np.sign(np.einsum("ij,ij->i", P - x, nrm))
    tol = 1e-9
    ins = (np.abs(xi) <= 1 + tol) & (np.abs(eta) <= 1 + tol)
    # triangles (fourth corner = third): the patch's normal vanishes on the
    # collapsed edge, where Newton may stop; the flat triangle is exact:
    # signed distance to its plane, inside by barycentric coordinates
    tri = np.all(Q[:, 2] == Q[:, 3], axis=1)
    if tri.any():
        q0, q1, q2 = Q[tri, 0], Q[tri, 1], Q[tri, 2]
        nt = np.cross(q1 - q0, q2 - q0)
        nt /= np.maximum(np.linalg.norm(nt, axis=1), 1e-30)[:, None]
        dt = np.einsum("ij,ij->i", P[tri] - q0, nt)
        pp = P[tri] - dt[:, None] * nt
        okt = np.ones(int(tri.sum()), dtype=bool)
        for u, v in ((q0, q1), (q1, q2), (q2, q0)):
            okt &= np.einsum("ij,ij->i", np.cross(v - u, pp - u), nt) >= -1e-12 * np.einsum("ij,ij->i", v - u, v - u)
        d[tri] = dt
        ins[tri] = okt
    return d, ins


def solid_depth(surf, X, A, S, dist, tnode):
    """Depths of nodes A in the elements of solid faces S: where the node
    (inflated by half its shell thickness) is inside the hexahedron, its
    depth below the nearest exterior face of that element, given to that
    face's pair only (the other pairs of the node and element get 0)."""
    E = surf.face_elem[S - surf.nshell]
    hx = X[surf.hexes[E]]                                    # (P, 8, 3)
    half = 0.5 * tnode[A]
    inside = np.ones(len(A), dtype=bool)
    for f in HEX_FACES:
        q = hx[:, f]
        c = q.mean(1)
        n = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
        n /= np.linalg.norm(n, axis=1)[:, None]
        inside &= np.einsum("ij,ij->i", X[A] - c, n) <= half
    depth = np.where(inside, half - dist, 0.0)
    key = A * (len(surf.hexes) + 1) + E
    order = np.lexsort((depth, key))
    first = np.ones(len(order), dtype=bool)
    first[1:] = key[order][1:] != key[order][:-1]
    out = np.zeros(len(A))
    out[order[first]] = depth[order[first]]
    return out


crossed = []          # the first pass-throughs: (node, state, segment)


def check_states(surf, states, tshell_states, node_ids, parts=None, growth=False, seg_part=None, alive_states=None):
    """Largest overlap fraction and pass-throughs over the states; sets
    `where`. states: (nstate, nn, 3) coordinates; tshell_states: (nstate,
    nshell) thicknesses; alive_states: (nstate, nshell), 0 for a shell
    eroded by then (its segment is gone: no overlap with it, and a node
    crossing where it was is no pass-through)."""
    global where
    where = None
    crossed.clear()
    conn = surf.conn
    nn = states.shape[1]
    worst, crossings, prev = 0.0, 0, None
    skip_cache = {}
    base = {}
    coplanar = set()
    seg_ok = node_ok = None
    if parts is not None:
        seg_ok = np.isin(np.asarray(seg_part), parts)
        node_ok = np.zeros(nn, dtype=bool)
        node_ok[np.unique(conn[seg_ok].ravel())] = True
    for state, X in enumerate(states):
        tsh = np.asarray(tshell_states[state], dtype=float)
        xs = X[conn]                                           # (nseg, 4, 3)
        cen = xs.mean(1)
        nrm = np.cross(xs[:, 2] - xs[:, 0], xs[:, 3] - xs[:, 1])
        nrm /= np.linalg.norm(nrm, axis=1)[:, None]
        size = np.max(np.linalg.norm(xs - cen[:, None], axis=2), axis=1)
        tseg = np.zeros(len(conn))
        tseg[:surf.nshell] = tsh
        tnode = np.zeros(nn)
        for k in range(4):
            np.maximum.at(tnode, conn[:surf.nshell, k], tsh)
        if surf.hexes is not None and len(surf.face_elem):
            ecen = X[surf.hexes[surf.face_elem]].mean(1)      # element centres of the faces
            tseg[surf.nshell:] = 2.0 * np.abs(np.einsum("ij,ij->i", cen[surf.nshell:] - ecen,
                                                        nrm[surf.nshell:]))
        reach = size + tseg + tnode.max()
        A, S = candidate_pairs(X, cen, reach)
        keep = np.empty(len(A), dtype=bool)
        for i, (a, s) in enumerate(zip(A.tolist(), S.tolist())):
            k = (a, s)
            v = skip_cache.get(k)
            if v is None:
                v = skip_cache[k] = surf.skip(a, s)
            keep[i] = not v
        if seg_ok is not None:
            keep &= seg_ok[S] & node_ok[A]
        if alive_states is not None:
            alive = np.ones(len(conn), dtype=bool)
            alive[:surf.nshell] = np.asarray(alive_states[state]) > 0.5
            keep &= alive[S]
        A, S = A[keep], S[keep]
        dist = np.einsum("ij,ij->i", X[A] - cen[S], nrm[S])
        p = X[A] - dist[:, None] * nrm[S]
        inside = inside_quad(p, xs[S], nrm[S])
        shell = surf.kind[S] == 0
        # shells: the distance to the segment's bilinear surface (a crushed
        # segment warps by a good part of its thickness: its mean plane would
        # show overlaps that are not there)
        bd, bin_ = bilinear_distance(X[A[shell]], xs[S[shell]])
        dist[shell] = bd
        inside[shell] = bin_
        over = np.where(shell & inside, 0.5 * (tnode[A] + tseg[S]) - np.abs(dist), 0.0)
        if not shell.all():
            over[~shell] = solid_depth(surf, X, A[~shell], S[~shell], dist[~shell], tnode)
        if growth:
            pairs = list(zip(A.tolist(), S.tolist()))
            if state == 0:
                base = {k: max(o, 0.0) for k, o in zip(pairs, over.tolist())}
                # pairs that start within each other's thickness band (coplanar
                # flanges, a part meeting another in its plane): their side is
                # not defined, so their sign changes are no pass-throughs
                band = 0.5 * (tnode[A] + tseg[S]) - np.abs(dist)
                coplanar = {k for k, b in zip(pairs, band.tolist()) if b > 0.0}
            over = over - np.array([base.get(k, 0.0) for k in pairs])
        frac = np.maximum(over, 0.0) / np.maximum(tseg[S], 1e-30)
        if frac.size and float(frac.max()) > worst:
            worst = float(frac.max())
            j = int(np.argmax(frac))
            where = (int(node_ids[A[j]]), state, [int(node_ids[v]) for v in conn[S[j]]])
        cur = {(a, s): dv for a, s, dv, ins, sh in zip(A.tolist(), S.tolist(), dist.tolist(), inside, shell)
               if ins and sh}
        if prev is not None:
            for key, dv in cur.items():
                pv = prev.get(key)
                if growth and (base.get(key, 0.0) > 0.0 or key in coplanar):
                    continue          # the pair overlapped from the start: no crossing to speak of
                if pv is not None and pv != 0.0 and (pv > 0.0) != (dv > 0.0):
                    # a node that went through the surface changed its distance
                    # by no more than it moved against the segment's nodes (a
                    # point of the patch moves as a convex sum of its nodes:
                    # the distance changes by at most max_j |dx - dx_j|, and
                    # the way through passes d = 0); a larger jump is the
                    # closest point leaping across (a node in the plane of a
                    # free edge beside the segment, or beyond a fold's crease
                    # in the same sheet; 3.3 mm against 1.3 mm of relative
                    # motion in the front frame): no crossing. The bound is
                    # taken 1.5 times over: the way between two states may be
                    # a curve up to that much longer than its chord
                    a, sg = key
                    rel = (X[a] - Xprev[a]) - (X[conn[sg]] - Xprev[conn[sg]])
                    if abs(pv) + abs(dv) > 1.5 * np.linalg.norm(rel, axis=1).max() + 1e-12:
                        continue
                    crossings += 1
                    if len(crossed) < 20:
                        crossed.append((int(node_ids[key[0]]), state, [int(node_ids[v]) for v in conn[key[1]]]))
        prev = cur
        Xprev = X
    return worst, crossings


def check_run(run, parts=None, growth=False):
    """Shells and solids of RUN/d3plot.h5: (worst fraction, pass-throughs,
    number of states, time of the worst state)."""
    with h5py.File(os.path.join(run, "d3plot.h5"), "r") as f:
        ids = f["mesh/node_ids"][:]
        nn = len(ids)
        m = f["mesh"]
        shells = m["shell_connectivity"][:] if "shell_connectivity" in m else np.zeros((0, 4), np.int64)
        spart = m["shell_part"][:] if "shell_part" in m else np.zeros(0, np.int64)
        hexes = m["solid_connectivity"][:] if "solid_connectivity" in m else None
        hpart = m["solid_part"][:] if "solid_part" in m else None
        names = sorted(k for k in f["states"] if k != "time")
        times = f["states/time"][:]
        X = np.array([f[f"states/{k}/coordinates"][:] for k in names], dtype=float)
        if len(shells):
            T = np.array([f[f"states/{k}/shell_thickness"][:] for k in names], dtype=float)
        else:
            T = np.zeros((len(names), 0))
        # eroded shells (written where a material can fail)
        alive = None
        if len(shells) and all("shell_alive" in f[f"states/{k}"] for k in names):
            alive = np.array([f[f"states/{k}/shell_alive"][:] for k in names], dtype=float)
    surf = Surfaces(nn, shells.tolist(), spart.tolist(), None if hexes is None else hexes.tolist(),
                    None if hpart is None else hpart.tolist())
    seg_part = list(spart.tolist()) + ([] if hpart is None else [hpart[e] for e in surf.face_elem])
    worst, crossings = check_states(surf, X, T, ids, parts, growth, seg_part, alive)
    t_worst = float(times[where[1]]) if where else 0.0
    return worst, crossings, len(names), t_worst


def deck_cards(deck):
    """The data lines of DECK (comments left out), each as (keyword, its
    card number under that keyword from 1, line)."""
    kw, card = None, 0
    for raw in open(deck):
        line = raw.rstrip("\n")
        if line.startswith("$"):
            continue
        if line.startswith("*"):
            kw, card = line.split()[0].upper(), 0
            continue
        card += 1
        yield kw, card, line


def read_shells(deck):
    """Shell connectivity (ids), part of each shell, and thickness per part."""
    shells, sec_t, part_sec = [], {}, {}
    for kw, card, line in deck_cards(deck):
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
    return sh[:, 2:6], sh[:, 1], t


def prescribed_nodes(deck):
    """Ids of the nodes under *BOUNDARY_PRESCRIBED_MOTION_NODE or _SET
    (through *SET_NODE_LIST) in DECK."""
    sets, driven, set_ids, cur = {}, set(), [], None
    for kw, card, line in deck_cards(deck):
        if kw == "*SET_NODE_LIST":
            if card == 1:
                cur = int(line[0:10])
                sets[cur] = []
            else:
                sets[cur] += [int(line[i:i + 10]) for i in range(0, len(line), 10) if line[i:i + 10].strip()]
        elif kw == "*BOUNDARY_PRESCRIBED_MOTION_NODE":
            driven.add(int(line[0:10]))
        elif kw == "*BOUNDARY_PRESCRIBED_MOTION_SET":
            set_ids.append(int(line[0:10]))
    for k in set_ids:
        driven.update(v for v in sets.get(k, []) if v > 0)
    return driven


def check(deck, h5, leave_out=()):
    """Shells of DECK against the nodout states of THIST_H5 (every node
    must be a history node): (worst fraction, pass-throughs). leave_out:
    node ids whose pairs are not checked, as slave or as a segment's node
    (nodes under prescribed motion: no contact force can stop them, nor a
    segment they drive)."""
    conn_ids, parts, tseg = read_shells(deck)
    with h5py.File(h5, "r") as f:
        ids = f["nodout/ids"][:]
        X = np.stack([f["nodout/x_coordinate"][:], f["nodout/y_coordinate"][:], f["nodout/z_coordinate"][:]], -1)
    index = {int(n): k for k, n in enumerate(ids)}
    conn = np.vectorize(index.get)(conn_ids)
    surf = Surfaces(len(ids), conn.tolist(), parts.tolist())
    if leave_out:
        out = np.isin(ids, list(leave_out))
        plain = surf.skip
        surf.skip = lambda a, s: plain(a, s) or bool(out[a]) or bool(out[conn[s]].any())
    return check_states(surf, X, np.broadcast_to(tseg, (len(X), len(tseg))), ids)


def main(argv):
    global where
    as_json = "--json" in argv
    growth = "--growth" in argv
    parts = None
    for a in argv:
        if a.startswith("--parts="):
            parts = [int(v) for v in a[8:].split(",") if v]
    args = [a for a in argv if not a.startswith("--")]
    if len(args) == 1:
        worst, crossings, nstate, t_worst = check_run(args[0], parts, growth)
        res = {"largest_overlap": worst, "pass_throughs": crossings, "states": nstate, "time": t_worst,
               "node": where[0] if where else None, "segment": where[2] if where else None,
               "first_pass_throughs": crossed[:20]}
    elif len(args) == 2:
        worst, crossings = check(args[0], args[1])
        res = {"largest_overlap": worst, "pass_throughs": crossings,
               "node": where[0] if where else None, "segment": where[2] if where else None}
        driven = prescribed_nodes(args[0])
        if driven:
            at = where
            w2, c2 = check(args[0], args[1], driven)
            where = at
            res["free"] = {"largest_overlap": w2, "pass_throughs": c2, "prescribed_nodes": len(driven)}
    else:
        print(__doc__)
        return 2
    if as_json:
        print(json.dumps(res))
    else:
        print(f"largest overlap {worst:.3f} of the local thickness; pass-throughs {crossings}")
        if where:
            extra = f" (t = {res['time'] * 1e3:.3f} ms)" if "time" in res else ""
            print(f"  at node {where[0]}, state {where[1]}{extra}, segment {where[2]}")
        if "free" in res:
            fr = res["free"]
            print(f"pairs free of the {fr['prescribed_nodes']} nodes under prescribed motion: largest overlap "
                  f"{fr['largest_overlap']:.3f}; pass-throughs {fr['pass_throughs']}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
