#!/usr/bin/env python3
"""The settled state in a grainscale checkpoint (`grainscale bench --settled FILE`, `grainscale dem`'s
checkpoint.h5; layout: docs/checkpoint_layout.md), read through libhdf5 with ctypes (no h5py needed).

Usage: h5_state.py CHECKPOINT.h5 [--area A_m2] [--density RHO]
Prints one line of `key value` pairs:
  time_s dt_s skin_m rmax_m (largest sphere radius) spheres bodies mass_kg ekin_J (translational + rotational) zmax_m (highest sphere centre) zmean_m (mean body centre)
  pours_done D/P (if the scenario pours: pours finished / pours)
and, with --area (floor area of the box) and --density (particle material):
  height_m = 2 x zmean (bed height of a level bed whose centres fill it evenly)
  phi = (mass / density) / (area x height_m), the bulk solid fraction.
Both codes' beds are measured this way in the benchmark scripts, so the figures compare."""
import ctypes, ctypes.util, sys


def lib():
    for name in ("hdf5_serial", "hdf5"):
        path = ctypes.util.find_library(name)
        if path:
            return ctypes.CDLL(path)
    sys.exit("libhdf5 not found")


h5 = lib()
h5.H5open()
hid = ctypes.c_int64
h5.H5Fopen.restype = hid
h5.H5Fopen.argtypes = [ctypes.c_char_p, ctypes.c_uint, hid]
h5.H5Dopen2.restype = hid
h5.H5Dopen2.argtypes = [hid, ctypes.c_char_p, hid]
h5.H5Dget_space.restype = hid
h5.H5Dget_space.argtypes = [hid]
h5.H5Sget_simple_extent_npoints.restype = ctypes.c_int64
h5.H5Sget_simple_extent_npoints.argtypes = [hid]
h5.H5Dread.argtypes = [hid, hid, hid, hid, hid, ctypes.c_void_p]
h5.H5Aopen.restype = hid
h5.H5Aopen.argtypes = [hid, ctypes.c_char_p, hid]
h5.H5Aread.argtypes = [hid, hid, ctypes.c_void_p]
h5.H5Eset_auto2.argtypes = [hid, ctypes.c_void_p, ctypes.c_void_p]
h5.H5Eset_auto2(0, None, None)  # errors are reported here, not printed by the library
native_double = hid.in_dll(h5, "H5T_NATIVE_DOUBLE_g").value


def die(msg):
    sys.exit(f"h5_state.py: {msg}")


def dataset(f, name):
    d = h5.H5Dopen2(f, name.encode(), 0)
    if d < 0:
        die(f"no {name} in {sys.argv[1]} (is it a grainscale checkpoint?)")
    n = h5.H5Sget_simple_extent_npoints(h5.H5Dget_space(d))
    buf = (ctypes.c_double * n)()
    if h5.H5Dread(d, native_double, 0, 0, 0, buf) < 0:
        die(f"cannot read {name}")
    return list(buf)


def dataset_if(f, name):
    h5.H5Lexists.argtypes = [hid, ctypes.c_char_p, hid]
    group = name.rsplit("/", 1)[0]
    if group and h5.H5Lexists(f, group.encode(), 0) <= 0:
        return None
    return dataset(f, name) if h5.H5Lexists(f, name.encode(), 0) > 0 else None


def attribute(f, name):
    a = h5.H5Aopen(f, name.encode(), 0)
    if a < 0:
        die(f"no attribute {name} in {sys.argv[1]}")
    v = ctypes.c_double()
    if h5.H5Aread(a, native_double, ctypes.byref(v)) < 0:
        die(f"cannot read attribute {name}")
    return v.value


def main():
    args = sys.argv[1:]
    if not args or args[0].startswith("-"):
        sys.exit(__doc__)
    opts = {}
    for i in range(1, len(args) - 1, 2):
        opts[args[i].lstrip("-")] = float(args[i + 1])
    f = h5.H5Fopen(args[0].encode(), 0, 0)  # H5F_ACC_RDONLY, H5P_DEFAULT
    if f < 0:
        die("cannot open " + args[0])
    mass = dataset(f, "/bodies/mass")
    bz = dataset(f, "/bodies/position")[2::3]
    sz = dataset(f, "/particles/position")[2::3]
    v = dataset(f, "/bodies/velocity")
    am, w = dataset(f, "/bodies/angular_momentum"), dataset(f, "/bodies/angular_velocity")
    ekin = 0.5 * sum(m * (v[3 * b] ** 2 + v[3 * b + 1] ** 2 + v[3 * b + 2] ** 2) for b, m in enumerate(mass))
    ekin += 0.5 * sum(am[i] * w[i] for i in range(len(w)))
    out = {
        "time_s": f"{attribute(f, 'time'):.6g}",
        "dt_s": f"{attribute(f, 'dt'):.6g}",
        "skin_m": f"{attribute(f, 'skin'):.6g}",
        "rmax_m": f"{max(dataset(f, '/particles/radius')):.6g}",
        "spheres": len(sz),
        "bodies": len(mass),
        "mass_kg": f"{sum(mass):.6g}",
        "ekin_J": f"{ekin:.4g}",
        "zmax_m": f"{max(sz):.6g}" if sz else "nan",
        "zmean_m": f"{sum(bz) / len(bz):.6g}" if bz else "nan",
    }
    done = dataset_if(f, "/scenario/pour_done")
    if done:
        out["pours_done"] = f"{int(sum(done))}/{len(done)}"
    if "area" in opts and "density" in opts and bz:
        height = 2 * sum(bz) / len(bz)
        out["height_m"] = f"{height:.6g}"
        out["phi"] = f"{sum(mass) / opts['density'] / (opts['area'] * height):.4f}"
    print(" ".join(f"{k} {v}" for k, v in out.items()))


main()
