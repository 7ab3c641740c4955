#!/usr/bin/env python3
"""The particle files of real runs, read by the tools they are for (issue 15):

  * ASE: ase.io.read(particles.xyz, index=':') loads every frame with ids, types,
    radii, velocities and spins, the cell and the periodic axes; in disks_box the median
    displacement per id between frames 0.5 apart is below 1 sigma; in the obstacle stream
    (disks leaving and entering) ids are unique and never come back;
  * LAMMPS (the Debian `lmp`): read_dump of one frame of particles.lammpstrj gives back its
    ids, positions and velocities exactly, and `rerun` goes through every frame (2D ED box,
    3D DEM box).

usage: particle_files_check.py GRAINFLOW SCENES_DIR OUT_DIR
"""
import math
import os
import re
import shutil
import subprocess
import sys

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL: " + what)
    return ok


def run(grainflow, scene, out, *sets):
    cmd = [grainflow, "run", scene, "-o", out, "--force", "--threads", "1",
           "--set", "output.png=false", "--set", "output.mp4=false", "--set", "render.size=[64,64]"]
    for s in sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit("grainflow failed (%d): %s\n%s" % (r.returncode, " ".join(cmd), r.stdout + r.stderr))


def own_frames(path):
    """Frames of an extended XYZ file as (count, header, rows of floats), read plainly."""
    frames = []
    with open(path) as f:
        while True:
            line = f.readline()
            if not line:
                return frames
            n = int(line)
            header = f.readline()
            rows = [[float(t) for t in f.readline().split()] for _ in range(n)]
            frames.append((n, header, rows))


def median(v):
    v = sorted(v)
    return v[len(v) // 2]


def check_ase(path, box=None):
    import numpy as np
    import ase.io
    frames = ase.io.read(path, index=":")
    own = own_frames(path)
    check(len(frames) == len(own) and len(frames) > 1, "%s: ASE read %d of %d frames" % (path, len(frames), len(own)))
    for k, (a, (n, header, rows)) in enumerate(zip(frames, own)):
        where = "%s frame %d" % (path, k)
        check(len(a) == n, where + ": %d atoms, the file says %d" % (len(a), n))
        for name, shape in (("id", (n,)), ("type", (n,)), ("radius", (n,)), ("velo", (n, 3)), ("omega", (n, 3)),
                            ("mass", (n,))):
            check(name in a.arrays and a.arrays[name].shape == shape,
                  where + ": array %s %s" % (name, a.arrays[name].shape if name in a.arrays else "missing"))
        ids = a.arrays["id"]
        check(len(set(ids.tolist())) == n and ids.min() > 0, where + ": ids not unique and positive")
        check(np.all(a.arrays["radius"] > 0), where + ": radii")
        rows = np.array(rows)
        # Properties=id:I:1:type:I:1:pos:R:3:radius:R:1:velo:R:3:omega:R:3:mass:R:1
        check(np.array_equal(ids, rows[:, 0].astype(int)), where + ": ids differ from the file's")
        check(np.array_equal(a.positions, rows[:, 2:5]), where + ": positions differ from the file's")
        check(np.array_equal(a.arrays["velo"], rows[:, 6:9]), where + ": velocities differ from the file's")
        check("Time" in a.info, where + ": no Time")
        if box is not None:
            check(np.allclose(np.diag(a.cell.array)[:2], box[:2]) and list(a.pbc[:2]) == [True, True],
                  where + ": cell %s pbc %s" % (a.cell.array.tolist(), a.pbc))
    return frames


def displacements(a, b):
    """|r_b - r_a| per id of the disks in both frames, nearest image along periodic axes."""
    pos = {int(i): p for i, p in zip(a.arrays["id"], a.positions)}
    period = [a.cell.array[k][k] if a.pbc[k] else None for k in range(2)]
    d = []
    for i, q in zip(b.arrays["id"], b.positions):
        p = pos.get(int(i))
        if p is None:
            continue
        dr = [q[k] - p[k] for k in range(2)]
        for k in range(2):
            if period[k]:
                dr[k] -= period[k] * round(dr[k] / period[k])
        d.append(math.hypot(*dr))
    return d


def lammps(workdir, script):
    lmp = shutil.which("lmp") or shutil.which("lmp_serial")
    if not check(lmp is not None, "LAMMPS (lmp) not found: install the Debian package lammps (.ci/install-deps)"):
        return None
    with open(os.path.join(workdir, "in.check"), "w") as f:
        f.write(script)
    r = subprocess.run([lmp, "-in", "in.check", "-log", "log.lammps", "-echo", "none", "-screen", "none"],
                       cwd=workdir, capture_output=True, text=True)
    log = open(os.path.join(workdir, "log.lammps")).read() if os.path.exists(os.path.join(workdir, "log.lammps")) else ""
    if not check(r.returncode == 0, "lmp failed in %s:\n%s%s" % (workdir, r.stdout, log[-2000:])):
        return None
    return log


def dump_frames(path):
    """Frames of our dump as dicts: step, time, ATOMS columns -> lists."""
    frames = []
    with open(path) as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines) and lines[i]:
        fr = {}
        while not lines[i].startswith("ITEM: ATOMS"):
            if lines[i] == "ITEM: TIME":
                fr["time"] = float(lines[i + 1])
            if lines[i] == "ITEM: TIMESTEP":
                fr["step"] = int(lines[i + 1])
            if lines[i] == "ITEM: NUMBER OF ATOMS":
                n = int(lines[i + 1])
            i += 1
        cols = lines[i].split()[2:]
        rows = [lines[i + 1 + k].split() for k in range(n)]
        fr["cols"] = {c: [float(r[j]) for r in rows] for j, c in enumerate(cols)}
        frames.append(fr)
        i += 1 + n
    return frames


def check_lammps(dump, workdir, dim, box_lines):
    """read_dump of the third frame (exact ids, positions, velocities) and a rerun of all."""
    os.makedirs(workdir, exist_ok=True)
    frames = dump_frames(dump)
    target = frames[2]
    fields = "x y vx vy" if dim == 2 else "x y z vx vy vz"  # LAMMPS refuses z and vz in 2D
    script = """units lj
dimension {dim}
atom_style sphere
{box}
create_box 1 box
read_dump {dump} {step} {fields} box yes add yes
pair_style zero 1.0
pair_coeff * *
compute svx all reduce sum vx
compute sx all reduce sum x
thermo_style custom step atoms c_svx c_sx
thermo_modify norm no format float %.17g
thermo 1
write_dump all custom read_back.dump id x y z vx vy vz modify sort id format float %.17g
rerun {dump} dump {fields} box yes
""".format(dim=dim, box=box_lines, dump=os.path.abspath(dump), step=target["step"], fields=fields)
    log = lammps(workdir, script)
    if log is None:
        return
    # read_dump: the frame back, sorted by id, to the last bit.
    back = own_dump(os.path.join(workdir, "read_back.dump"))
    want = sorted(zip(*[target["cols"][c] for c in ("id", "x", "y", "z", "vx", "vy", "vz")]))
    check(len(back) == len(want), "%s: read_dump gave %d atoms of %d" % (dump, len(back), len(want)))
    check(back == [tuple(r) for r in want], "%s: read_dump did not give the frame back exactly" % dump)
    # rerun: one thermo line per frame, with that frame's step, atom count and sums.
    rows = re.findall(r"^\s*(\d+)\s+(\d+)\s+(\S+)\s+(\S+)\s*$", log, re.M)
    check(len(rows) == len(frames), "%s: rerun printed %d rows for %d frames" % (dump, len(rows), len(frames)))
    for fr, (step, atoms, svx, sx) in zip(frames, rows):
        c = fr["cols"]
        ok = (int(step) == fr["step"] and int(atoms) == len(c["id"]) and
              math.isclose(float(sx), math.fsum(c["x"]), rel_tol=1e-12) and
              math.isclose(float(svx), math.fsum(c["vx"]), rel_tol=1e-9, abs_tol=1e-12 * math.fsum(map(abs, c["vx"]))))
        check(ok, "%s: rerun at step %s: %s atoms, sum x %s, sum vx %s; the frame: step %d, %d atoms, %r, %r" % (
            dump, step, atoms, sx, svx, fr["step"], len(c["id"]), math.fsum(c["x"]), math.fsum(c["vx"])))
    print("LAMMPS: read_dump of step %d (%d atoms) exact, rerun of %d frames: %s" % (
        target["step"], len(want), len(frames), dump))


def own_dump(path):
    rows = []
    with open(path) as f:
        lines = f.read().split("\n")
    k = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    for l in lines[k + 1:]:
        if l.strip():
            t = l.split()
            rows.append(tuple([float(t[0])] + [float(x) for x in t[1:]]))
    return sorted(rows)


def main():
    grainflow, scenes, out = sys.argv[1:4]
    os.makedirs(out, exist_ok=True)
    try:
        import ase.io  # noqa: F401
    except ImportError:
        sys.exit("ASE is missing for %s: install the Debian package python3-ase (.ci/install-deps)" % sys.executable)

    # 1. The equilibrium box: every frame, and ids that follow the disks.
    box = os.path.join(out, "box")
    run(grainflow, os.path.join(scenes, "disks_box.toml"), box, "run.until=2", "sample.exposure=0.5",
        "output.particles=true", "output.lammps_dump=true")
    frames = check_ase(os.path.join(box, "particles.xyz"), box=(100.0, 100.0))
    for k in range(len(frames) - 1):
        d = displacements(frames[k], frames[k + 1])
        check(len(d) == len(frames[k]), "box: ids of frame %d missing in frame %d" % (k, k + 1))
        m = median(d)
        print("disks_box frames %d-%d (0.5 apart): median displacement per id %.4f sigma" % (k, k + 1, m))
        check(m < 1.0, "disks_box: median displacement per id %.3g sigma, not below 1" % m)

    # 2. The obstacle stream: disks leave and newcomers take their slots.
    stream = os.path.join(out, "stream")
    run(grainflow, os.path.join(scenes, "obstacle_quick.toml"), stream, "run.until=16", "sample.exposure=8",
        "output.particles=true")
    frames = check_ase(os.path.join(stream, "particles.xyz"))
    seen, gone = set(), set()
    for k, a in enumerate(frames):
        ids = set(a.arrays["id"].tolist())
        check(not (ids & gone), "stream frame %d: an id that left came back" % k)
        if k > 0:
            d = displacements(frames[k - 1], a)
            print("obstacle_quick frames %d-%d (8 apart, U = 0.2): %d disks in both, median displacement per id "
                  "%.3f sigma, largest %.3f" % (k - 1, k, len(d), median(d), max(d)))
            check(median(d) < 2.5 and max(d) < 10, "stream: ids do not follow the disks")
            gone |= seen - ids
        seen |= ids
    check(frames[-1].arrays["id"].max() > len(frames[0]), "stream: no newcomer got a new id")

    # 3. LAMMPS reads the dumps: the 2D box and a 3D DEM box.
    check_lammps(os.path.join(box, "particles.lammpstrj"), os.path.join(out, "lmp_box"), 2,
                 "boundary p p p\nregion box block 0 100 0 100 -0.5 0.5")
    dem = os.path.join(out, "dem")
    run(grainflow, os.path.join(scenes, "dem_freefall_box.toml"), dem, "system.group[0].N=300",
        "system.box=[0.01,0.01,0.02]", "sample.slab=[0.0,0.01]", "run.until=0.004", "sample.exposure=0.001", "output.lammps_dump=true",
        "output.particles=true")
    check_ase(os.path.join(dem, "particles.xyz"))
    check_lammps(os.path.join(dem, "particles.lammpstrj"), os.path.join(out, "lmp_dem"), 3,
                 "boundary f f f\nregion box block 0 0.01 0 0.01 0 0.02")

    if failures:
        sys.exit("%d check(s) failed" % len(failures))
    print("all particle-file checks passed")


if __name__ == "__main__":
    main()
