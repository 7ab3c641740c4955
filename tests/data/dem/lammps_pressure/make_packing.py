# Writes packing.data: 216 spheres (d = 1 mm, 2500 kg/m3) on a simple cubic lattice of
# spacing 1.001 d filling a periodic cube, velocities 0.1 sin(c·id) m/s per axis with the
# mean removed (zero total momentum, so LAMMPS's lab-frame kinetic tensor and grainflow's
# one about the mass-averaged velocity agree), no spin. Every number at 17 digits.
n, d, a = 6, 1e-3, 1.001e-3
L = n * a
ids = range(1, n ** 3 + 1)
v = [(0.1 * __import__('math').sin(12.9898 * i), 0.1 * __import__('math').sin(78.2330 * i),
      0.1 * __import__('math').sin(37.7190 * i)) for i in ids]
mean = [sum(c[k] for c in v) / len(v) for k in range(3)]
v = [tuple(c[k] - mean[k] for k in range(3)) for c in v]
with open('packing.data', 'w') as f:
    f.write('216 spheres on a simple cubic lattice of spacing 1.001 d in a periodic cube (make_packing.py)\n\n')
    f.write(f'{n ** 3} atoms\n1 atom types\n\n')
    for ax in 'xyz':
        f.write(f'0 {L!r} {ax}lo {ax}hi\n')
    f.write('\nAtoms # sphere\n\n')
    i = 0
    for kz in range(n):
        for ky in range(n):
            for kx in range(n):
                i += 1
                f.write(f'{i} 1 {d!r} 2500 {(kx + 0.5) * a!r} {(ky + 0.5) * a!r} {(kz + 0.5) * a!r} 0 0 0\n')
    f.write('\nVelocities\n\n')
    for i, c in zip(ids, v):
        f.write(f'{i} {c[0]!r} {c[1]!r} {c[2]!r} 0 0 0\n')
