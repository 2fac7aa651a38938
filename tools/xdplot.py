#!/usr/bin/python3
"""Pictures of xdyna runs (matplotlib and h5py from Debian's packages).

    xdplot.py history RUN [RUN2 ...] [--out PNG] [--nodes ID ...]
        Time histories from RUN/thist.h5: energies (glstat), contact forces
        (rcforc), rigid-wall forces (rwforc) and, with --nodes, the
        displacement of those history nodes. Several runs are overlaid
        (solid line the first, dashed the others).

    xdplot.py mesh RUN [--times T ...] [--color part|von_mises|plastic_strain|thickness|displacement]
                       [--view ELEV AZIM] [--out PNG]
        Deformed meshes from RUN/d3plot.h5 (h5plot=1), else from the binary
        d3plot family every run writes, at the states nearest the given
        times (default: four states spread over the run), side by side in
        one figure like the paper's Figs. 9-11, coloured by part or a field
        (von Mises and plastic strain of a shell: d3plot.h5's values, or the
        d3plot's largest over the points through the thickness).

Exit 0 with the PNG written; 2 on bad arguments or missing files.
"""
import argparse
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

HEX_FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def history(runs, out, nodes):
    groups = []
    for r in runs:
        f = h5py.File(os.path.join(r, "thist.h5"), "r")
        groups.append(f)
    panels = [("glstat", "energies")]
    if any("rcforc" in f for f in groups):
        panels.append(("rcforc", "contact force"))
    if any("rwforc" in f for f in groups):
        panels.append(("rwforc", "rigid-wall force"))
    if nodes:
        panels.append(("nodout", "nodal displacement"))
    fig, axes = plt.subplots(len(panels), 1, figsize=(8, 3.2 * len(panels)), squeeze=False)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for (name, title), ax in zip(panels, axes[:, 0]):
        for k, (run, f) in enumerate(zip(runs, groups)):
            if name not in f:
                continue
            g = f[name]
            t = g["time"][:] * 1e3
            ls = "-" if k == 0 else "--"
            tag = os.path.basename(os.path.normpath(run))
            if name == "glstat":
                keys = [c for c in ("kinetic_energy", "internal_energy", "hourglass_energy",
                                    "sliding_interface_energy", "stonewall_energy", "total_energy",
                                    "external_work") if c in g]
                for j, c in enumerate(keys):
                    ax.plot(t, g[c][:], ls, color=colours[j % len(colours)],
                            label=f"{c.replace('_', ' ')} ({tag})")
                ax.set_ylabel("energy")
            elif name in ("rcforc", "rwforc"):
                ids = g["ids"][:]
                col = "slave_z_force" if name == "rcforc" else "normal_force"
                if name == "rcforc":
                    mag = np.sqrt(g["slave_x_force"][:] ** 2 + g["slave_y_force"][:] ** 2
                                  + g["slave_z_force"][:] ** 2)
                else:
                    mag = g[col][:]
                for j, i in enumerate(ids):
                    ax.plot(t, mag[:, j], ls, color=colours[j % len(colours)], label=f"{name} {i} ({tag})")
                ax.set_ylabel("|force|" if name == "rcforc" else "normal force")
            else:
                ids = list(g["ids"][:])
                for j, n in enumerate(nodes):
                    if n not in ids:
                        continue
                    c = ids.index(n)
                    u = np.sqrt(sum(g[a + "_displacement"][:, c] ** 2 for a in "xyz"))
                    ax.plot(t, u, ls, color=colours[j % len(colours)], label=f"node {n} ({tag})")
                ax.set_ylabel("|displacement|")
        ax.set_title(title)
        ax.set_xlabel("time (ms)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    return 0


def faces_of(m):
    """Polygons (node index lists) and their element (kind, index)."""
    polys, owner = [], []
    if "shell_connectivity" in m:
        for e, c in enumerate(m["shell_connectivity"][:]):
            polys.append(list(c[:3]) if c[2] == c[3] else list(c))
            owner.append(("shell", e))
    if "solid_connectivity" in m:
        conn = m["solid_connectivity"][:]
        # exterior faces only: a face seen once
        seen = {}
        for e, c in enumerate(conn):
            for fc in HEX_FACES:
                nodes = [c[i] for i in fc]
                key = tuple(sorted(set(nodes)))
                if len(key) < 3:
                    continue
                seen.setdefault(key, []).append((nodes, e))
        for key, lst in seen.items():
            if len(lst) == 1:
                nodes, e = lst[0]
                uniq = [n for i, n in enumerate(nodes) if n not in nodes[:i]]
                polys.append(uniq)
                owner.append(("solid", e))
    return polys, owner


def open_states(run):
    """(times, mesh, state): the states' times, the mesh (connectivity and
    parts) and state(k), the fields of state k, from RUN/d3plot.h5 if the
    run wrote it, else from the d3plot family."""
    h5 = os.path.join(run, "d3plot.h5")
    if os.path.exists(h5):
        f = h5py.File(h5, "r")
        return f["states/time"][:], f["mesh"], lambda k: f[f"states/{k + 1:06d}"]
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from d3plot_read import D3plot
    d = D3plot(run)
    return d.times, d.mesh, d.state


def mesh(run, times, colour, view, out):
    st_times, m, state = open_states(run)
    if len(st_times) == 0:
        print(f"xdplot: no states in {run}", file=sys.stderr)
        return 2
    if not times:
        picks = sorted(set(np.linspace(0, len(st_times) - 1, min(4, len(st_times))).round().astype(int)))
    else:
        picks = [int(np.argmin(abs(st_times - t))) for t in times]
    polys, owner = faces_of(m)
    fig = plt.figure(figsize=(4.2 * len(picks), 4.6))
    cmap = plt.get_cmap("tab20" if colour == "part" else "viridis")
    vals_all = []
    for s in picks:
        g = state(s)
        if colour == "part":
            v = [m[f"{k}_part"][e] for k, e in owner]
        elif colour == "displacement":
            d = np.linalg.norm(g["displacement"][:], axis=1)
            v = [d[p].mean() for p in polys]
        else:
            v = [g[f"{k}_{colour}"][e] if f"{k}_{colour}" in g else 0.0 for k, e in owner]
        vals_all.append(np.asarray(v, dtype=float))
    lo = min(v.min() for v in vals_all)
    hi = max(v.max() for v in vals_all)
    if hi <= lo:
        hi = lo + 1.0
    x0 = state(0)["coordinates"][:]
    span = (x0.max(0) - x0.min(0)).max()
    for j, s in enumerate(picks):
        x = state(s)["coordinates"][:]
        ax = fig.add_subplot(1, len(picks), j + 1, projection="3d")
        v = vals_all[j]
        if colour == "part":
            parts = sorted(set(v))
            # tab20's strong colours first, then its light ones: 20 parts apart
            cols = [cmap((2 * parts.index(p)) % 20 + (parts.index(p) // 10) % 2) for p in v]
        else:
            cols = [cmap((a - lo) / (hi - lo)) for a in v]
        pc = Poly3DCollection([x[p] for p in polys], facecolors=cols, edgecolors="k", linewidths=0.1)
        ax.add_collection3d(pc)
        c = 0.5 * (x0.max(0) + x0.min(0))
        for set_lim, k in ((ax.set_xlim, 0), (ax.set_ylim, 1), (ax.set_zlim, 2)):
            set_lim(c[k] - span / 2, c[k] + span / 2)
        ax.view_init(elev=view[0], azim=view[1])
        try:
            ax.set_box_aspect((1, 1, 1), zoom=1.5)
        except TypeError:  # matplotlib before 3.6 has no zoom
            pass
        ax.set_title(f"t = {st_times[s] * 1e3:.3g} ms", fontsize=10)
        ax.set_axis_off()
    fig.subplots_adjust(left=0.0, right=0.9 if colour != "part" else 1.0, bottom=0.0, top=0.92, wspace=0.0)
    if colour != "part":
        sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(lo, hi))
        fig.colorbar(sm, ax=fig.axes, shrink=0.6, label=colour.replace("_", " "))
    fig.savefig(out, dpi=110)
    return 0


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("what", choices=["history", "mesh"])
    p.add_argument("runs", nargs="+", help="output directories")
    p.add_argument("--out", default=None, help="PNG to write")
    p.add_argument("--nodes", type=int, nargs="*", default=[])
    p.add_argument("--times", type=float, nargs="*", default=[])
    p.add_argument("--color", default="part",
                   choices=["part", "von_mises", "plastic_strain", "thickness", "displacement"])
    p.add_argument("--view", type=float, nargs=2, default=[25.0, -60.0])
    a = p.parse_args()
    for r in a.runs:
        need = "thist.h5" if a.what == "history" else "d3plot"
        if not (os.path.exists(os.path.join(r, need)) or os.path.exists(os.path.join(r, "d3plot.h5"))):
            print(f"xdplot: {os.path.join(r, need)} not found", file=sys.stderr)
            return 2
    out = a.out or os.path.join(a.runs[0], f"{a.what}.png")
    if a.what == "history":
        rc = history(a.runs, out, a.nodes)
    else:
        rc = mesh(a.runs[0], a.times, a.color, a.view, out)
    if rc == 0:
        print(f"xdplot: wrote {out}")
    return rc


if __name__ == "__main__":
    sys.exit(main())
