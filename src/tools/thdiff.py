#!/usr/bin/python3
"""thdiff: compare the time histories of two runs.

usage: thdiff A B [--rtol R] [--atol A] [--only NAMES] [--common] [--pointwise] [--overlap] [--top N]

A and B are run directories (thist.h5 if both have one, else the ASCII
files glstat, matsum, nodout, rcforc, rwforc found in both), thist.h5
files, or single ASCII files in LS-DYNA's layout (from xdyna or LS-DYNA).

A point fails when |a - b| > atol + rtol * peak, where peak is the largest
|b| of that series (so values crossing zero are judged against the size of
the signal); with --pointwise, peak is |b| at that point. B's series are
interpolated linearly onto A's times when the time lists differ.

The two runs must span the same times: one that ends earlier than the other
(a run killed halfway) fails, with the last common time and each run's end,
unless --overlap asks for the common times only.

Exit status: 0 all within tolerance, 1 some series differ (or are missing
from one run without --common), 2 unreadable input.
"""
import argparse
import os
import re
import sys

import numpy as np

ASCII_NAMES = ("glstat", "matsum", "nodout", "rcforc", "rwforc")
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+|[-+]\d+)?")


def to_float(text):
    """A Fortran number, also with an E-less exponent (1.00000+100)."""
    t = text.strip().replace("D", "E").replace("d", "e")
    m = re.fullmatch(r"([-+]?(?:\d+\.?\d*|\.\d+))([-+]\d+)", t)
    if m:
        t = m.group(1) + "e" + m.group(2)
    return float(t)


class Series(dict):
    """name -> (times, values) arrays."""

    def add(self, name, t, v):
        ts, vs = self.setdefault(name, ([], []))
        ts.append(t)
        vs.append(v)

    def finish(self):
        for k, (t, v) in list(self.items()):
            self[k] = (np.asarray(t, float), np.asarray(v, float))
        return self


def read_glstat(path, out):
    t = None
    skip = ("time per zone cycle", "time....")
    with open(path) as f:
        for line in f:
            if len(line) < 33 or line[1:2] == " " or "." not in line[1:32]:
                continue
            label = line[1:32].rstrip(".").strip()
            try:
                val = to_float(line[32:])
            except ValueError:
                continue
            if line.startswith(" time...."):
                t = val
                continue
            if t is None or any(label.startswith(s) for s in skip):
                continue
            out.add("glstat/" + canon(label), t, val)


def read_matsum(path, out):
    t, part = None, None
    pair = re.compile(r"([A-Za-z_#.+\-]+)=\s*(\S+)")
    with open(path) as f:
        for line in f:
            s = line.strip()
            if s.startswith("time ="):
                t = to_float(s.split("=")[1])
                continue
            if t is None:
                continue
            for key, val in pair.findall(line):
                if key == "mat.#":
                    part = int(val)
                    continue
                out.add(f"matsum/{canon(key)}[{part}]", t, to_float(val))


def read_nodout(path, out):
    t = None
    trans = ("x-disp", "y-disp", "z-disp", "x-vel", "y-vel", "z-vel", "x-accl", "y-accl", "z-accl",
             "x-coor", "y-coor", "z-coor")
    # with shells, a second block of each step: the rotations
    rots = ("x-rot", "y-rot", "z-rot", "x-rot-vel", "y-rot-vel", "z-rot-vel", "x-rot-acc", "y-rot-acc", "z-rot-acc")
    cols = trans
    with open(path) as f:
        for line in f:
            if "( at time" in line:
                t = to_float(line.split("( at time")[1].split(")")[0])
                continue
            if line.startswith(" nodal point"):
                cols = rots if "x-rot" in line else trans
                continue
            if t is None or len(line) < 20:
                continue
            parts = NUMBER.findall(line)
            if len(parts) == len(cols) + 1 and parts[0].lstrip("+-").isdigit():
                nid = int(parts[0])
                for name, val in zip(cols, parts[1:]):
                    out.add(f"nodout/{canon(name)}[{nid}]", t, to_float(val))


def read_rcforc(path, out):
    rx = re.compile(r"^\s*(\S+)\s+(\d+)\s+time\s+(\S+)(.*)$")
    with open(path) as f:
        for line in f:
            m = rx.match(line)
            if not m:
                continue
            side, ident, t = m.group(1), m.group(2), to_float(m.group(3))
            # LS-DYNA R14 names the sides SURFA (slave) and SURFB (master);
            # older files (and xdyna's before it) slave and master
            side = {"SURFA": "slave", "SURFB": "master"}.get(side, side)
            rest = m.group(4).split()
            for k in range(0, len(rest) - 1, 2):
                out.add(f"rcforc/{side}-{rest[k]}[{ident}]", t, to_float(rest[k + 1]))


def read_rwforc(path, out):
    with open(path) as f:
        for line in f:
            parts = line.split()
            if len(parts) < 6:
                continue
            try:
                t, wall = to_float(parts[0]), int(parts[1])
                vals = [to_float(p) for p in parts[2:6]]
            except ValueError:
                continue
            for name, val in zip(("normal-force", "x-force", "y-force", "z-force"), vals):
                out.add(f"rwforc/{canon(name)}[{wall}]", t, val)


# ASCII labels -> the column names of thist.h5, so the two compare directly
CANONICAL = {
    "time step": "time_step", "kinetic energy": "kinetic_energy", "internal energy": "internal_energy",
    "hourglass energy": "hourglass_energy", "external work": "external_work", "total energy": "total_energy",
    "total energy / initial energy": "energy_ratio", "energy ratio w/o eroded energy": "energy_ratio_wo_eroded",
    "global x velocity": "x_velocity", "global y velocity": "y_velocity", "global z velocity": "z_velocity",
    "inten": "internal_energy", "kinen": "kinetic_energy", "hgeng": "hourglass_energy",
    "x-mom": "x_momentum", "y-mom": "y_momentum", "z-mom": "z_momentum",
    "x-rbv": "x_rigid_body_velocity", "y-rbv": "y_rigid_body_velocity", "z-rbv": "z_rigid_body_velocity",
    "+mass": "added_mass",
    "x-disp": "x_displacement", "y-disp": "y_displacement", "z-disp": "z_displacement",
    "x-vel": "x_velocity", "y-vel": "y_velocity", "z-vel": "z_velocity",
    "x-accl": "x_acceleration", "y-accl": "y_acceleration", "z-accl": "z_acceleration",
    "x-coor": "x_coordinate", "y-coor": "y_coordinate", "z-coor": "z_coordinate",
    "normal-force": "normal_force", "x-force": "x_force", "y-force": "y_force", "z-force": "z_force",
}


def canon(label):
    label = label.strip()
    return CANONICAL.get(label, re.sub(r"[^A-Za-z0-9+]+", "_", label).strip("_"))


READERS = {"glstat": read_glstat, "matsum": read_matsum, "nodout": read_nodout, "rcforc": read_rcforc,
           "rwforc": read_rwforc}


def read_h5(path, out):
    import h5py
    with h5py.File(path, "r") as f:
        for gname, g in f.items():
            t = g["time"][:]
            ids = g["ids"][:] if "ids" in g else None
            for dname, ds in g.items():
                if dname in ("time", "ids"):
                    continue
                data = ds[:]
                if data.ndim == 1:
                    out[f"{gname}/{dname}"] = (t, data.astype(float))
                else:
                    for j in range(data.shape[1]):
                        out[f"{gname}/{dname}[{ids[j]}]"] = (t, data[:, j].astype(float))


def load(path, kinds):
    """Series of a run directory, a thist.h5 or one ASCII file."""
    out = Series()
    if os.path.isdir(path):
        h5 = os.path.join(path, "thist.h5")
        if kinds == "h5":
            read_h5(h5, out)
            return out
        for name in ASCII_NAMES:
            p = os.path.join(path, name)
            if os.path.exists(p) and name in kinds:
                READERS[name](p, out)
        return out.finish()
    if path.endswith(".h5"):
        read_h5(path, out)
        return out
    base = os.path.basename(path)
    reader = next((READERS[n] for n in ASCII_NAMES if base.startswith(n)), None)
    if reader is None:
        raise ValueError(f"{path}: not a run directory, thist.h5 or {'/'.join(ASCII_NAMES)} file")
    reader(path, out)
    return out.finish()


def choose_kinds(a, b):
    if os.path.isdir(a) and os.path.isdir(b):
        if all(os.path.exists(os.path.join(p, "thist.h5")) for p in (a, b)):
            return "h5"
        # every file either run has: one the other lacks shows as series in
        # one run only (a difference, unless --common), never skipped
        return [n for n in ASCII_NAMES if any(os.path.exists(os.path.join(p, n)) for p in (a, b))]
    return ASCII_NAMES


def compare(sa, sb, rtol, atol, pointwise):
    """Per series: (excess ratio, time, a, b, allowed)."""
    rows = {}
    for name in sorted(set(sa) & set(sb)):
        ta, va = sa[name]
        tb, vb = sb[name]
        if len(ta) == 0 or len(tb) == 0:
            continue
        if len(ta) == len(tb) and np.allclose(ta, tb, rtol=1e-9, atol=1e-30):
            vbi = vb
            tt, vv = ta, va
        else:
            keep = (ta >= tb[0] - 1e-12 * abs(tb[0])) & (ta <= tb[-1] + 1e-12 * abs(tb[-1]))
            tt, vv = ta[keep], va[keep]
            if len(tt) == 0:
                rows[name] = (np.inf, np.nan, np.nan, np.nan, 0.0)
                continue
            vbi = np.interp(tt, tb, vb)
        scale = np.abs(vbi) if pointwise else np.full(len(vbi), np.max(np.abs(vbi)))
        allowed = atol + rtol * scale
        diff = np.abs(vv - vbi)
        diff = np.where(np.isnan(diff), np.inf, diff)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(allowed > 0, diff / allowed, np.where(diff > 0, np.inf, 0.0))
        k = int(np.argmax(ratio))
        rows[name] = (float(ratio[k]), float(tt[k]), float(vv[k]), float(vbi[k]), float(allowed[k]))
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(prog="thdiff", description=__doc__.split("\n")[0])
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--rtol", type=float, default=1e-6)
    ap.add_argument("--atol", type=float, default=0.0)
    ap.add_argument("--only", default="", help="comma-separated prefixes of series names (glstat,matsum/...)")
    ap.add_argument("--common", action="store_true", help="compare only the series both runs have")
    ap.add_argument("--pointwise", action="store_true", help="tolerance relative to each point, not the peak")
    ap.add_argument("--overlap", action="store_true",
                    help="compare only the times both runs reached (a shorter run is no failure)")
    ap.add_argument("--top", type=int, default=10, help="how many of the worst series to print")
    args = ap.parse_args(argv)
    try:
        kinds = choose_kinds(args.a, args.b)
        sa, sb = load(args.a, kinds), load(args.b, kinds)
    except (OSError, ValueError, KeyError) as exc:
        print(f"thdiff: {exc}", file=sys.stderr)
        return 2
    if args.only:
        prefixes = tuple(p.strip() for p in args.only.split(",") if p.strip())
        sa = {k: v for k, v in sa.items() if k.startswith(prefixes)}
        sb = {k: v for k, v in sb.items() if k.startswith(prefixes)}
    missing = sorted(set(sa) ^ set(sb))
    rows = compare(sa, sb, args.rtol, args.atol, args.pointwise)
    if not rows:
        print("thdiff: no series in common", file=sys.stderr)
        return 1
    bad = {k: r for k, r in rows.items() if r[0] > 1.0}
    # the time spans: a run that stops early is not the same run
    short = []
    for name in sorted(set(sa) & set(sb)):
        ta, tb = sa[name][0], sb[name][0]
        if len(ta) == 0 or len(tb) == 0:
            continue
        span = max(abs(ta[-1]), abs(tb[-1]), 1e-300)
        if abs(ta[-1] - tb[-1]) > 1e-6 * span or abs(ta[0] - tb[0]) > 1e-6 * span:
            short.append((name, ta[0], ta[-1], tb[0], tb[-1]))
    worst = sorted(rows.items(), key=lambda kv: -kv[1][0])[: args.top]
    print(f"thdiff: {len(rows)} series compared (rtol {args.rtol:g}, atol {args.atol:g}"
          f"{', pointwise' if args.pointwise else ', relative to each series peak'})")
    print(f"  {'series':44s} {'time':>12s} {'A':>13s} {'B':>13s} {'|A-B|':>11s} {'allowed':>11s}")
    for name, (ratio, t, va, vb, allowed) in worst:
        flag = "FAIL" if ratio > 1.0 else "ok"
        print(f"  {name:44s} {t:12.5e} {va:13.5e} {vb:13.5e} {abs(va - vb):11.3e} {allowed:11.3e} {flag}")
    if missing:
        print(f"thdiff: {len(missing)} series in only one run, e.g. {', '.join(missing[:5])}")
    if short:
        name, a0, a1, b0, b1 = short[0]
        common = min(a1, b1)
        print(f"thdiff: {len(short)} series span different times, e.g. {name}: A {a0:.6e} to {a1:.6e}, "
              f"B {b0:.6e} to {b1:.6e}; last common time {common:.6e}"
              + (" (--overlap: compared over the common times)" if args.overlap else ""))
    if bad or (missing and not args.common) or (short and not args.overlap):
        if short and not args.overlap and not bad:
            print("thdiff: the runs end at different times (use --overlap to compare the common times only)")
            return 1
        print(f"thdiff: {len(bad)} series over tolerance" + ("" if args.common or not missing else
                                                              f", {len(missing)} missing"))
        return 1
    print("thdiff: all series within tolerance")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except BrokenPipeError:
        sys.exit(0)
