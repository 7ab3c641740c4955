#!/usr/bin/env python3
"""The static "dune" in front of an obstacle (seed 003 §5, Fig. 5.9) measured from a run's
field files (output.fields = true): bins whose mean velocity |<v>| is below a fraction of U
(0.2 by default) among the gas bins within R + D of the obstacle's centre upstream of it,
and the stream's profile along x (density, <vx>, kT averaged over y) that shows a jam.
Reads only the standard library (the .npy structured arrays are parsed here).
Usage: dune_metrics.py RUN_DIR [--frames K] [--frac 0.2] [--profile] [--every N]
  RUN_DIR: a run folder with fields/ and run.json (or scene.toml) giving U and the obstacle.
  --frames K: average the static count over the last K frames (default 4); --profile: print
  the y-averaged profile along x of the last frame; --every N: the static count of every
  Nth frame (time series)."""
import argparse
import ast
import glob
import json
import math
import os
import re
import struct
import sys


def read_npy(path):
    """A structured .npy (version 1/2/3, little endian) as (names, shape, rows): rows[i] is a
    dict name -> value (a tuple for sub-arrays), in C order (iy major)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:6] != b"\x93NUMPY":
        raise ValueError(f"{path}: not a .npy file")
    major = data[6]
    if major == 1:
        hlen = struct.unpack("<H", data[8:10])[0]
        start = 10
    else:
        hlen = struct.unpack("<I", data[8:12])[0]
        start = 12
    header = ast.literal_eval(data[start:start + hlen].decode("latin1"))
    body = data[start + hlen:]
    if header["fortran_order"]:
        raise ValueError(f"{path}: Fortran order not supported")
    fmt = "<"
    fields = []
    for entry in header["descr"]:
        name, typ = entry[0], entry[1]
        sub = entry[2] if len(entry) > 2 else ()
        count = 1
        for s in sub:
            count *= s
        code = {"<f8": "d", "<f4": "f", "<i4": "i", "<u4": "I", "<i8": "q", "<u8": "Q", "|u1": "B", "|i1": "b",
                "<u2": "H", "<i2": "h"}[typ]
        fmt += code * count
        fields.append((name, count))
    size = struct.calcsize(fmt)
    n = 1
    for s in header["shape"]:
        n *= s
    rows = []
    for k in range(n):
        vals = struct.unpack_from(fmt, body, k * size)
        row, p = {}, 0
        for name, count in fields:
            row[name] = vals[p] if count == 1 else vals[p:p + count]
            p += count
        rows.append(row)
    return [f[0] for f in fields], header["shape"], rows


def scene_params(run):
    """U, the obstacle (x, y, D) and the bins from the effective scene the run wrote."""
    text = None
    for name in ("scene.toml", "effective_scene.toml"):
        p = os.path.join(run, name)
        if os.path.exists(p):
            text = open(p).read()
            break
    if text is None:
        raise SystemExit(f"{run}: no scene.toml")
    section, vals = "", {}
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        m = re.match(r"^\[+([^\]]+)\]+$", line)
        if m:
            section = m.group(1).strip()
            continue
        m = re.match(r"^([A-Za-z0-9_]+)\s*=\s*(.+)$", line)
        if m and section in ("system", "boundary.obstacle"):
            vals[section + "." + m.group(1)] = m.group(2).strip()
    def num(key):
        if key not in vals:
            raise SystemExit(f"{run}: scene has no {key}")
        return float(vals[key])
    return num("system.U"), num("boundary.obstacle.x"), num("boundary.obstacle.y"), num("boundary.obstacle.D")


def frame_files(run):
    files = sorted(glob.glob(os.path.join(run, "fields", "frame_*.npy")))
    if not files:
        raise SystemExit(f"{run}: no fields/frame_*.npy (run with --set output.fields=true)")
    return files


def frame_time(run, npy):
    vti = npy[:-4] + ".vti"
    if os.path.exists(vti):
        with open(vti, "rb") as f:
            head = f.read(4096).decode("latin1")
        m = re.search(r'Name="TimeValue"[^>]*>\s*([-0-9.eE+]+)', head)
        if m:
            return float(m.group(1))
    return float("nan")


def static_bins(rows, U, ox, oy, D, frac):
    """(static, annulus): gas bins (centre outside the obstacle) of the front half disk
    |c − o| ≤ R + D, x < ox, and those of them with |<v>| < frac·U."""
    R = 0.5 * D
    static = annulus = 0
    for r in rows:
        dx, dy = r["x"] - ox, r["y"] - oy
        dist = math.hypot(dx, dy)
        if not (dist <= R + D and dx < 0.0):
            continue
        if not r["mask"]:
            continue
        s = r["speed_of_mean_velocity"]
        if s != s:  # NaN: no samples
            continue
        annulus += 1
        if s < frac * U:
            static += 1
    return static, annulus


def profile(rows, shape):
    ny, nx = shape
    out = []
    for ix in range(nx):
        n = vx = kT = 0.0
        cnt = 0
        for iy in range(ny):
            r = rows[iy * nx + ix]
            if not r["mask"] or r["number_density"] != r["number_density"]:
                continue
            n += r["number_density"]
            vx += r["mean_velocity"][0]
            if r["kT"] == r["kT"]:
                kT += r["kT"]
            cnt += 1
        x = rows[ix]["x"]
        out.append((x, n / cnt if cnt else float("nan"), vx / cnt if cnt else float("nan"),
                    kT / cnt if cnt else float("nan"), cnt))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run")
    ap.add_argument("--frames", type=int, default=4)
    ap.add_argument("--frac", type=float, default=0.2)
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--every", type=int, default=0)
    a = ap.parse_args()
    U, ox, oy, D = scene_params(a.run)
    files = frame_files(a.run)
    if a.every:
        for k in range(a.every - 1, len(files), a.every):
            _, shape, rows = read_npy(files[k])
            s, n = static_bins(rows, U, ox, oy, D, a.frac)
            print(f"{os.path.basename(files[k])} t = {frame_time(a.run, files[k]):.0f}: static {s} of {n}")
    last = files[-a.frames:]
    counts = []
    for f in last:
        names, shape, rows = read_npy(f)
        counts.append(static_bins(rows, U, ox, oy, D, a.frac))
    ny, nx = shape
    bin_area = (rows[1]["x"] - rows[0]["x"]) * (rows[nx]["y"] - rows[0]["y"])
    mean_static = sum(c[0] for c in counts) / len(counts)
    print(f"static bins (|<v>| < {a.frac} U, gas bins within R + D of the centre, upstream), last {len(last)} frames: "
          + ", ".join(f"{s}/{n}" for s, n in counts)
          + f"; mean {mean_static:.1f} bins = {mean_static * bin_area / (D * D):.3f} D^2")
    if a.profile:
        print("x  n  <vx>  kT  (y-averaged, last frame)")
        for x, n, vx, kT, cnt in profile(rows, shape):
            print(f"{x:8.1f} {n:6.3f} {vx:8.4f} {kT:9.5f}")


if __name__ == "__main__":
    sys.exit(main())
