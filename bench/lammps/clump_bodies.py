#!/usr/bin/env python3
"""Clump helper for the LAMMPS clump bed (in.clump_bed, run by ../run_clump_bed_lammps.sh).
Standard library only.

  clump_bodies.py molecule SHAPE.yaml SCALE DENSITY OUT.mol
      LAMMPS molecule file of a grainscale shape (studies/shapes/*.yaml): centres and radii times
      SCALE (file length unit -> m, times the scenario's scale_factor, as run_clump_bed.sh scales
      them for LIGGGHTS). Mass properties are those of the union of the spheres (overlaps counted
      once), as grainscale computes them: written as the file's 'mass', 'com' and 'inertia' header
      lines and used by 'infile'. Per-atom masses (the Masses section) split the union among the
      spheres (each slice of the solid of revolution goes to the sphere that spans it), so they sum to
      the clump mass and keep the centre of mass: fix gravity on the atoms then pulls the body with
      m g at its centre. Prints "mass_kg M volume_m3 V i_axial I1 i_transverse I2 rmin R rmax R
      half_length L".
      Only coaxial shapes (all centres on one line, as studies/shapes/wheat.yaml) are handled: their
      union is a solid of revolution, whose volume and inertia are exact 1-D integrals.

  clump_bodies.py insert OUT.mol N SEED LX LY FILLZ DATA RIGID
      N clumps at random positions and orientations in the region [0,LX]x[0,LY]x[0,FILLZ] (m), their
      bounding spheres inside it and not overlapping each other (what LIGGGHTS' fix insert/pack does
      with overlapcheck yes, all_in yes), at rest. DATA: LAMMPS data file (atom style sphere, with a
      Molecules section for fix property/atom mol; box 10 mm around the region, 20 mm above it).
      RIGID: fix rigid/small 'infile' with each clump's union mass, centre of mass and inertia tensor
      in the box frame, zero velocity and angular momentum.

  clump_bodies.py check OUT.mol DUMP
      rigidity of the clumps in DUMP: largest change of a sphere-sphere distance within a clump
      against the template; prints "clumps N max_distance_error_m E".
"""
import math
import random
import re
import sys

N_SLICES = 200000


def read_shape(path):
    t = open(path).read()
    code = "\n".join(l.split("#")[0] for l in t.split("\n"))
    rows = []
    for m in re.finditer(r"center:\s*\[([^\]]*)\],\s*radius:\s*([0-9.eE+-]+)", code):
        c = [float(v) for v in m.group(1).split(",")]
        rows.append((c, float(m.group(2))))
    if len(rows) < 2:
        sys.exit(f"{path}: fewer than 2 spheres")
    return rows


def axis_of(centres):
    """unit vector of the line through all centres, or exit if they are not on one line"""
    a, b = centres[0], centres[-1]
    d = [b[k] - a[k] for k in range(3)]
    n = math.sqrt(sum(x * x for x in d))
    if n == 0:
        sys.exit("first and last sphere centres coincide")
    u = [x / n for x in d]
    for c in centres:
        w = [c[k] - a[k] for k in range(3)]
        s = sum(w[k] * u[k] for k in range(3))
        off = math.sqrt(max(0.0, sum(x * x for x in w) - s * s))
        if off > 1e-12 * n:
            sys.exit("the shape's centres are not on one line; only coaxial clumps are handled")
    return u


def molecule(shape, scale, rho, out):
    rows = read_shape(shape)
    cen = [[x * scale for x in c] for c, _ in rows]
    rad = [r * scale for _, r in rows]
    u = axis_of(cen)
    o = cen[0]
    s = [sum((c[k] - o[k]) * u[k] for k in range(3)) for c in cen]  # positions along the axis
    lo = min(si - ri for si, ri in zip(s, rad))
    hi = max(si + ri for si, ri in zip(s, rad))
    h = (hi - lo) / N_SLICES
    n = len(rad)
    vol = [0.0] * n
    m0 = m1 = m2 = 0.0  # zeroth..second axial moments of the volume
    ia = 0.0            # axial moment of inertia / density
    r4 = 0.0            # integral of pi r^4 / 4 (disc moment about a diameter)
    for k in range(N_SLICES):
        x = lo + (k + 0.5) * h
        best, r2 = -1, 0.0
        for i in range(n):
            q = rad[i] ** 2 - (x - s[i]) ** 2
            if q > r2:
                best, r2 = i, q
        if best < 0:
            continue
        dv = math.pi * r2 * h
        vol[best] += dv
        m0 += dv; m1 += dv * x; m2 += dv * x * x
        ia += 0.5 * math.pi * r2 * r2 * h
        r4 += 0.25 * math.pi * r2 * r2 * h
    V = m0
    M = rho * V
    xc = m1 / m0
    i_ax = rho * ia
    i_tr = rho * (m2 - m0 * xc * xc + r4)
    com = [o[k] + xc * u[k] for k in range(3)]
    # inertia tensor of the template in its own (file) frame: I = It 1 + (Ia - It) u u^T
    I = [[(i_tr if a == b else 0.0) + (i_ax - i_tr) * u[a] * u[b] for b in range(3)] for a in range(3)]
    half = max(math.dist(com, c) + r for c, r in zip(cen, rad))
    with open(out, "w") as f:
        f.write(f"# {shape} x {scale:g} m, density {rho:g} kg/m3: union of {n} spheres, exact mass properties\n\n")
        f.write(f"{n} atoms\n")
        f.write(f"{M:.12g} mass\n")
        f.write(f"{com[0]:.12g} {com[1]:.12g} {com[2]:.12g} com\n")
        f.write(f"{I[0][0]:.12g} {I[1][1]:.12g} {I[2][2]:.12g} {I[0][1]:.12g} {I[0][2]:.12g} {I[1][2]:.12g} inertia\n")
        f.write("\nCoords\n\n")
        for i, c in enumerate(cen):
            f.write(f"{i + 1} {c[0]:.12g} {c[1]:.12g} {c[2]:.12g}\n")
        f.write("\nTypes\n\n")
        for i in range(n):
            f.write(f"{i + 1} 1\n")
        f.write("\nDiameters\n\n")
        for i, r in enumerate(rad):
            f.write(f"{i + 1} {2 * r:.12g}\n")
        f.write("\nMasses\n\n")
        for i, v in enumerate(vol):
            f.write(f"{i + 1} {rho * v:.12g}\n")
    print(f"mass_kg {M:.10g} volume_m3 {V:.10g} i_axial {i_ax:.10g} i_transverse {i_tr:.10g} "
          f"rmin {min(rad):.10g} rmax {max(rad):.10g} half_length {half:.10g}")


def read_molecule(path):
    t = open(path).read()
    M = float(re.search(r"^(\S+)\s+mass\s*$", t, re.M).group(1))
    com = [float(v) for v in re.search(r"^(\S+)\s+(\S+)\s+(\S+)\s+com\s*$", t, re.M).groups()]
    ii = [float(v) for v in re.search(r"^(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+inertia\s*$", t, re.M).groups()]
    sec = t.split("Coords", 1)[1].split("Types", 1)[0]
    cen = [[float(v) for v in l.split()[1:4]] for l in sec.strip().split("\n") if l.strip()]
    u = axis_of(cen)
    # back out the axial and transverse moments from the stored tensor: I_ax = u.I.u, trace = I_ax + 2 I_tr
    T = [[ii[0], ii[3], ii[4]], [ii[3], ii[1], ii[5]], [ii[4], ii[5], ii[2]]]
    i_ax = sum(u[a] * T[a][b] * u[b] for a in range(3) for b in range(3))
    i_tr = (ii[0] + ii[1] + ii[2] - i_ax) / 2
    return M, com, cen, i_ax, i_tr


def read_dump(path):
    """{mol: [(id, [x, y, z]), ...]} from a write_dump custom file with columns id mol x y z ..."""
    lines = open(path).read().split("\n")
    i = next(k for k, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    cols = lines[i].split()[2:]
    ci, cm, cx = cols.index("id"), cols.index("mol"), cols.index("x")
    bodies = {}
    for l in lines[i + 1:]:
        w = l.split()
        if not w:
            continue
        bodies.setdefault(int(w[cm]), []).append((int(w[ci]), [float(w[cx]), float(w[cx + 1]), float(w[cx + 2])]))
    for b in bodies.values():
        b.sort()
    return bodies


def random_axis(rng):
    z = rng.uniform(-1.0, 1.0)
    phi = rng.uniform(0.0, 2.0 * math.pi)
    s = math.sqrt(1.0 - z * z)
    return [s * math.cos(phi), s * math.sin(phi), z]


def insert(mol, n, seed, lx, ly, fillz, data, out):
    """n clumps at random positions and orientations in [0,lx]x[0,ly]x[0,fillz], bounding spheres
    inside the region and not overlapping (LIGGGHTS insert/pack: overlapcheck yes, all_in yes)"""
    M, com, cen, i_ax, i_tr = read_molecule(mol)
    t = open(mol).read()
    diam = [float(l.split()[1]) for l in t.split("Diameters", 1)[1].split("Masses", 1)[0].strip().split("\n")]
    mass = [float(l.split()[1]) for l in t.split("Masses", 1)[1].strip().split("\n")]
    u0 = axis_of(cen)
    s = [sum((c[k] - com[k]) * u0[k] for k in range(3)) for c in cen]  # along the axis, from the COM
    hb = max(abs(si) + d / 2 for si, d in zip(s, diam))                 # bounding-sphere radius
    lo, hi = [hb, hb, hb], [lx - hb, ly - hb, fillz - hb]
    if any(h <= l for l, h in zip(lo, hi)):
        sys.exit("the insertion region is smaller than one clump")
    rng = random.Random(seed)
    cell = 2 * hb
    grid = {}
    placed = []
    tries = 0
    while len(placed) < n:
        tries += 1
        if tries > 1000 * n + 100000:
            sys.exit(f"placed only {len(placed)} of {n} clumps")
        x = [rng.uniform(lo[k], hi[k]) for k in range(3)]
        key = tuple(int(x[k] // cell) for k in range(3))
        if any(math.dist(x, placed[j][0]) < 2 * hb
               for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
               for j in grid.get((key[0] + dx, key[1] + dy, key[2] + dz), ())):
            continue
        grid.setdefault(key, []).append(len(placed))
        placed.append((x, random_axis(rng)))
    na = len(cen)
    with open(data, "w") as f:
        f.write(f"LAMMPS data file: {n} clumps of {mol} (clump_bodies.py insert, seed {seed})\n\n")
        f.write(f"{n * na} atoms\n1 atom types\n\n")
        f.write(f"-0.01 {lx + 0.01:.12g} xlo xhi\n-0.01 {ly + 0.01:.12g} ylo yhi\n-0.01 {fillz + 0.02:.12g} zlo zhi\n")
        f.write("\nAtoms # sphere\n\n")
        for b, (x, u) in enumerate(placed):
            for i in range(na):
                p = [x[k] + s[i] * u[k] for k in range(3)]
                rho = mass[i] / (math.pi / 6 * diam[i] ** 3)   # atom style sphere takes a density
                f.write(f"{b * na + i + 1} 1 {diam[i]:.12g} {rho:.12g} {p[0]:.15g} {p[1]:.15g} {p[2]:.15g}\n")
        f.write("\nMolecules\n\n")
        for b in range(n):
            for i in range(na):
                f.write(f"{b * na + i + 1} {b + 1}\n")
    with open(out, "w") as f:
        f.write(f"# fix rigid/small infile: {n} clumps, mass properties of {mol} (union of the spheres)\n")
        f.write(f"{n}\n")
        for b, (x, u) in enumerate(placed):
            I = [[(i_tr if a == c else 0.0) + (i_ax - i_tr) * u[a] * u[c] for c in range(3)] for a in range(3)]
            f.write(f"{b + 1} {M:.12g} {x[0]:.15g} {x[1]:.15g} {x[2]:.15g} "
                    f"{I[0][0]:.12g} {I[1][1]:.12g} {I[2][2]:.12g} {I[0][1]:.12g} {I[0][2]:.12g} {I[1][2]:.12g} "
                    f"0 0 0 0 0 0 0 0 0\n")
    print(f"inserted {n} clumps ({n * na} spheres) in {tries} tries, bounding radius {hb:.6g} m")


def check(mol, dump):
    _, _, cen, _, _ = read_molecule(mol)
    bodies = read_dump(dump)
    worst = 0.0
    for atoms in bodies.values():
        pos = [p for _, p in atoms]
        for i in range(len(pos)):
            for j in range(i + 1, len(pos)):
                worst = max(worst, abs(math.dist(pos[i], pos[j]) - math.dist(cen[i], cen[j])))
    print(f"clumps {len(bodies)} max_distance_error_m {worst:.3g}")


if __name__ == "__main__":
    a = sys.argv[1:]
    if a[:1] == ["molecule"] and len(a) == 5:
        molecule(a[1], float(a[2]), float(a[3]), a[4])
    elif a[:1] == ["insert"] and len(a) == 9:
        insert(a[1], int(a[2]), int(a[3]), float(a[4]), float(a[5]), float(a[6]), a[7], a[8])
    elif a[:1] == ["check"] and len(a) == 3:
        check(a[1], a[2])
    else:
        sys.exit(__doc__)
