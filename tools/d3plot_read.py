"""Read the binary d3plot family xdyna writes (numpy only), for the tools.

The layout is LSTC's "LS-DYNA Database Binary Output Files" as xdyna
writes it (src/output/d3plot.f90): 64 control words; the initial
coordinates, hexahedra (8 nodes and a material) and shells (4 and a
material); the user ids (NARBS); in the first member, an end-of-file
marker and the part titles; the states in the members after it (or,
in a family without titles, right after the ids). A state: time, the
NGLBV global values, coordinates and velocities of every node, NV3D words
per hexahedron, NV2D per shell, a deletion flag per element.

    d = D3plot(run_dir)
    d.mesh: node_ids, solid_connectivity and shell_connectivity (0-based
            node rows), solid_part and shell_part (the deck's part ids),
            part_titles {part id: title}
    d.times: the states' times
    d.state(k): coordinates, displacement, velocity, solid_stress (6),
            solid_plastic_strain, solid_von_mises, shell_thickness,
            shell_plastic_strain and shell_von_mises (the largest over the
            points through the thickness)
"""
import os
import re

import numpy as np

EOF = np.float32(-999999.0)


def _members(run):
    names = [x for x in os.listdir(run) if re.fullmatch(r"d3plot(\d\d+)?", x)]
    return [os.path.join(run, x) for x in sorted(names, key=lambda x: int(x[6:] or -1))]


class D3plot:
    def __init__(self, run):
        self.files = _members(run)
        if not self.files:
            raise FileNotFoundError(os.path.join(run, "d3plot"))
        root = np.fromfile(self.files[0], dtype=np.int32)
        rf = root.view(np.float32)
        c = root[:64]
        self.nnode, self.nel8, self.nv3d = int(c[16]), int(c[23]), int(c[27])
        self.nel4, self.nv2d, self.nglbv = int(c[31]), int(c[33]), int(c[18])
        self.maxint = abs(int(c[36])) % 10000 if c[36] < 0 else int(c[36])
        narbs, nmmat = int(c[39]), int(c[51])
        k = 64
        x0 = rf[k:k + 3 * self.nnode].reshape(-1, 3).astype(float)
        k += 3 * self.nnode
        sol = root[k:k + 9 * self.nel8].reshape(-1, 9)
        k += 9 * self.nel8
        shl = root[k:k + 5 * self.nel4].reshape(-1, 5)
        k += 5 * self.nel4
        ids = root[k:k + narbs]
        k += narbs
        part_of_mat = ids[16 + self.nnode + self.nel8 + self.nel4:][:nmmat] if narbs else np.arange(1, nmmat + 1)
        self.mesh = {
            "node_ids": ids[16:16 + self.nnode] if narbs else np.arange(1, self.nnode + 1),
            "solid_connectivity": sol[:, :8] - 1, "shell_connectivity": shl[:, :4] - 1,
            "solid_part": part_of_mat[sol[:, 8] - 1] if len(sol) else np.zeros(0, int),
            "shell_part": part_of_mat[shl[:, 4] - 1] if len(shl) else np.zeros(0, int),
            "part_titles": {},
        }
        self.x0 = x0
        self.state_words = 1 + self.nglbv + 6 * self.nnode + self.nv3d * self.nel8 + self.nv2d * self.nel4 \
            + self.nel8 + self.nel4
        # the titles after the marker; the states in the later members
        starts = []
        if k < len(root) and rf[k] == EOF:
            if k + 3 <= len(root) and root[k + 1] == 90001:
                n = int(root[k + 2])
                q = k + 3
                for _ in range(n):
                    self.mesh["part_titles"][int(root[q])] = root[q + 1:q + 19].tobytes().decode(
                        "ascii", "replace").strip()
                    q += 19
            first = 1
        else:
            starts += self._scan(0, k)
            first = 1
        for m in range(first, len(self.files)):
            starts += self._scan(m, 0)
        self._starts = starts
        self.times = np.array([self._word(m, p) for m, p in starts], dtype=float)

    def _scan(self, m, p):
        size = os.path.getsize(self.files[m]) // 4
        out = []
        while p + self.state_words <= size:
            if self._word(m, p) == EOF:
                break
            out.append((m, p))
            p += self.state_words
        return out

    def _word(self, m, p):
        with open(self.files[m], "rb") as f:
            f.seek(4 * p)
            return np.frombuffer(f.read(4), dtype=np.float32)[0]

    def state(self, i):
        m, p = self._starts[i]
        with open(self.files[m], "rb") as f:
            f.seek(4 * p)
            w = np.frombuffer(f.read(4 * self.state_words), dtype=np.float32).astype(float)
        k = 1 + self.nglbv
        x = w[k:k + 3 * self.nnode].reshape(-1, 3)
        k += 3 * self.nnode
        v = w[k:k + 3 * self.nnode].reshape(-1, 3)
        k += 3 * self.nnode
        sol = w[k:k + self.nv3d * self.nel8].reshape(-1, self.nv3d)
        k += self.nv3d * self.nel8
        shl = w[k:k + self.nv2d * self.nel4].reshape(-1, self.nv2d)
        out = {"time": w[0], "coordinates": x, "displacement": x - self.x0, "velocity": v,
               "solid_stress": sol[:, :6], "solid_plastic_strain": sol[:, 6] if self.nv3d > 6 else 0 * sol[:, 0],
               "solid_von_mises": von_mises(sol[:, :6])}
        if self.nel4:
            lay = shl[:, :7 * self.maxint].reshape(-1, self.maxint, 7)
            out["shell_plastic_strain"] = lay[:, :, 6].max(axis=1)
            out["shell_von_mises"] = np.max([von_mises(lay[:, j, :6]) for j in range(self.maxint)], axis=0)
            out["shell_thickness"] = shl[:, 7 * self.maxint + 8]
        return out


def von_mises(s):
    """Von Mises stress of (n, 6) stresses xx yy zz xy yz zx."""
    if len(s) == 0:
        return np.zeros(0)
    xx, yy, zz, xy, yz, zx = (s[:, j] for j in range(6))
    return np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2) + 3 * (xy ** 2 + yz ** 2 + zx ** 2))
