#!/usr/bin/python3
"""Independent oracle for the stamp unit tests: bilinear look-up with SciPy, rasterisation with matplotlib.

Usage: stamp_oracle.py IN.json OUT.json
IN:  {"lookup": {"rows": r, "cols": c, "radius": R, "values": [r*c*3, row-major, channel fastest],
                 "phi": [n], "varphi": [n]},
      "raster": {"phi": [m], "varphi": [m], "triangles": [3t, vertex ids], "values": [3m, vertex-major],
                 "radius": R, "resolution": N}}
OUT: {"lookup": [3n, point-major], "raster": [N*N*3, row-major, channel fastest]}
Look-up: scipy.interpolate.RegularGridInterpolator (linear, zero outside) over nodes spanning [-R, R]^2.
Raster: matplotlib.tri.LinearTriInterpolator on the given triangulation, evaluated at the grid nodes;
nodes outside every triangle are 0.
"""
import json
import sys

import numpy as np
from matplotlib.tri import LinearTriInterpolator, Triangulation
from scipy.interpolate import RegularGridInterpolator


def lookup(req):
    rows, cols, radius = req["rows"], req["cols"], req["radius"]
    values = np.asarray(req["values"], dtype=float).reshape(rows, cols, 3)
    axis_y = np.linspace(-radius, radius, rows)
    axis_x = np.linspace(-radius, radius, cols)
    interp = RegularGridInterpolator((axis_y, axis_x), values, method="linear", bounds_error=False, fill_value=0.0)
    points = np.column_stack([req["varphi"], req["phi"]])
    return interp(points).reshape(-1).tolist()


def raster(req):
    tri = Triangulation(np.asarray(req["phi"]), np.asarray(req["varphi"]),
                        np.asarray(req["triangles"], dtype=int).reshape(-1, 3))
    values = np.asarray(req["values"], dtype=float).reshape(-1, 3)
    n, radius = req["resolution"], req["radius"]
    axis = np.linspace(-radius, radius, n)
    gx, gy = np.meshgrid(axis, axis)  # gx varies along columns (phi), gy along rows (varphi)
    out = np.zeros((n, n, 3))
    for c in range(3):
        field = LinearTriInterpolator(tri, values[:, c])(gx, gy)
        out[:, :, c] = np.ma.filled(field, 0.0)
    return out.reshape(-1).tolist()


def main():
    with open(sys.argv[1]) as f:
        request = json.load(f)
    answer = {}
    if "lookup" in request:
        answer["lookup"] = lookup(request["lookup"])
    if "raster" in request:
        answer["raster"] = raster(request["raster"])
    with open(sys.argv[2], "w") as f:
        json.dump(answer, f)


if __name__ == "__main__":
    main()
