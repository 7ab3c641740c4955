#!/usr/bin/env python3
"""Opens a run's fields.pvd and its .vti files with VTK's own XML readers (what ParaView
uses) and the .npy files with NumPy, and checks names, sizes, spacing, origin and times.
Usage: check_fields_vtk.py RUN_DIR NX NY ORIGIN_X ORIGIN_Y ORIGIN_Z SPACING_X SPACING_Y SPACING_Z [2|3]
Exit 0 when everything matches; prints what it read."""
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
from vtkmodules.vtkIOXML import vtkXMLImageDataReader
from vtkmodules.util.numpy_support import vtk_to_numpy

run, nx, ny = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
origin = [float(v) for v in sys.argv[4:7]]
spacing = [float(v) for v in sys.argv[7:10]]
dim = int(sys.argv[10]) if len(sys.argv) > 10 else 2
temperature = "kT" if dim == 2 else "granular_temperature"
fraction = "area_fraction" if dim == 2 else "solid_fraction"
expected = ["number_density", fraction, temperature, "mean_velocity", "speed_of_mean_velocity", "mean_speed",
            "vorticity", "open_fraction", "sample_count", "mask"]

def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)

# The collection: what ParaView's PVD reader opens (a list of DataSet files with times).
root = ET.parse(os.path.join(run, "fields.pvd")).getroot()
if root.get("type") != "Collection":
    fail("fields.pvd is not a VTK collection")
sets = root.findall("./Collection/DataSet")
if len(sets) < 2:
    fail(f"fields.pvd lists {len(sets)} frames, expected at least 2")
times = [float(s.get("timestep")) for s in sets]
files = [s.get("file") for s in sets]
if times != sorted(times) or len(set(times)) != len(times) or len(set(files)) != len(files):
    fail(f"times not strictly increasing or duplicated: {times}")
for name in os.listdir(os.path.join(run, "fields")):
    if name.endswith(".vti") and "fields/" + name not in files:
        fail(f"fields/{name} exists but fields.pvd does not list it")
print(f"fields.pvd: {len(sets)} frames, t = {times[0]} … {times[-1]}")

for f, t in zip(files, times):
    r = vtkXMLImageDataReader()
    r.SetFileName(os.path.join(run, f))
    r.Update()
    img = r.GetOutput()
    if img is None or img.GetNumberOfCells() != nx * ny:
        fail(f"{f}: {img.GetNumberOfCells() if img else None} cells, expected {nx * ny}")
    if not np.allclose(img.GetOrigin(), origin, rtol=1e-12, atol=1e-12):
        fail(f"{f}: origin {img.GetOrigin()}, expected {origin}")
    if not np.allclose(img.GetSpacing(), spacing, rtol=1e-12):
        fail(f"{f}: spacing {img.GetSpacing()}, expected {spacing}")
    cd = img.GetCellData()
    names = [cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays())]
    if names != expected:
        fail(f"{f}: arrays {names}, expected {expected}")
    for name in names:
        a = cd.GetArray(name)
        comps = 3 if name == "mean_velocity" else 1
        if a.GetNumberOfTuples() != nx * ny or a.GetNumberOfComponents() != comps:
            fail(f"{f}: {name} has {a.GetNumberOfTuples()} × {a.GetNumberOfComponents()}")
    tv = vtk_to_numpy(img.GetFieldData().GetArray("TimeValue"))[0]
    if tv != t:
        fail(f"{f}: TimeValue {tv}, fields.pvd says {t}")
    n = vtk_to_numpy(cd.GetArray("number_density"))
    counts = vtk_to_numpy(cd.GetArray("sample_count"))
    mask = vtk_to_numpy(cd.GetArray("mask"))
    if counts.sum() == 0 or not np.all(np.isfinite(n[mask == 1])):
        fail(f"{f}: no samples, or non-finite density in open bins")
    # The same frame as NumPy: the README's three lines.
    g = np.load(os.path.join(run, f[:-4] + ".npy"))
    if g.shape != (ny, nx) or list(g.dtype.names) != ["x", "y", "z"] + expected:
        fail(f"{f[:-4]}.npy: shape {g.shape}, fields {g.dtype.names}")
    if not np.array_equal(g["number_density"].ravel(), n, equal_nan=True) or not np.array_equal(
            g["sample_count"].ravel(), counts):
        fail(f"{f[:-4]}.npy differs from the .vti")
    if not np.allclose(g["mean_velocity"].reshape(-1, 3), vtk_to_numpy(cd.GetArray("mean_velocity")), equal_nan=True):
        fail(f"{f[:-4]}.npy mean_velocity differs from the .vti")
print(f"every frame: {nx}×{ny} cells, origin {origin}, spacing {spacing}, arrays {expected}; .npy equal")
