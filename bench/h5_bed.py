#!/usr/bin/env python3
"""Bed height of a grainscale snapshot, read through libhdf5 with ctypes (no h5py needed).
Usage: h5_bed.py SNAPSHOT.h5  ->  prints "zmax_m Z zmean_m Z n N" (sphere centres)."""
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
native_double = hid.in_dll(h5, "H5T_NATIVE_DOUBLE_g").value
f = h5.H5Fopen(sys.argv[1].encode(), 0, 0)  # H5F_ACC_RDONLY, H5P_DEFAULT
if f < 0: sys.exit("cannot open " + sys.argv[1])
d = h5.H5Dopen2(f, b"/particles/position", 0)
if d < 0: sys.exit("no /particles/position in " + sys.argv[1])
n = h5.H5Sget_simple_extent_npoints(h5.H5Dget_space(d))
buf = (ctypes.c_double * n)()
if h5.H5Dread(d, native_double, 0, 0, 0, buf) < 0: sys.exit("cannot read /particles/position")
z = buf[2::3]
print(f"zmax_m {max(z):.6g} zmean_m {sum(z) / len(z):.6g} n {len(z)}")
