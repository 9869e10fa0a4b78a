#!/usr/bin/python3
"""Independent oracle for the kinematics unit tests: polar decomposition and Kabsch via SciPy.

Usage: kinematics_oracle.py IN.json OUT.json
IN:  {"polar": [[9 numbers, F column-major], ...],
      "kabsch": [{"x": [3M, column-major], "y": [3M], "w": [M]}, ...]}
OUT: {"polar": [{"U": [9], "P": [9], "R": [9], "S": [9]}, ...],
      "kabsch": [{"R": [9], "t": [3]}, ...]}
Matrices column-major. U, P are scipy.linalg.polar's factors (U orthogonal, possibly improper; P PSD).
R, S are the proper-rotation form F = R S: when det U < 0 the reflection is moved into S across the
eigenvector of P with the smallest eigenvalue (H = I - 2 v v^T, R = U H, S = H P).
Kabsch uses scipy.spatial.transform.Rotation.align_vectors on the centred, weighted point sets.
"""
import json
import sys

import numpy as np
from scipy.linalg import polar
from scipy.spatial.transform import Rotation


def col_major(a):
    return np.asarray(a, dtype=float).flatten(order="F").tolist()


def from_col_major(values, rows):
    return np.asarray(values, dtype=float).reshape((rows, -1), order="F")


def polar_case(values):
    F = from_col_major(values, 3)
    U, P = polar(F, side="right")  # F = U P
    R, S = U, P
    if np.linalg.det(U) < 0:
        _, vecs = np.linalg.eigh(P)  # ascending eigenvalues
        v = vecs[:, 0]
        H = np.eye(3) - 2.0 * np.outer(v, v)
        R, S = U @ H, H @ P
    return {"U": col_major(U), "P": col_major(P), "R": col_major(R), "S": col_major(S)}


def kabsch_case(case):
    x = from_col_major(case["x"], 3)
    y = from_col_major(case["y"], 3)
    w = np.asarray(case["w"], dtype=float)
    x_bar = x @ w / w.sum()
    y_bar = y @ w / w.sum()
    # align_vectors(a, b, weights) minimises sum w |a_i - C b_i|^2: a = deformed, b = rest.
    rotation, _ = Rotation.align_vectors((y - y_bar[:, None]).T, (x - x_bar[:, None]).T, weights=w)
    R = rotation.as_matrix()
    return {"R": col_major(R), "t": (y_bar - R @ x_bar).tolist()}


def main():
    with open(sys.argv[1]) as f:
        request = json.load(f)
    answer = {
        "polar": [polar_case(F) for F in request.get("polar", [])],
        "kabsch": [kabsch_case(c) for c in request.get("kabsch", [])],
    }
    with open(sys.argv[2], "w") as f:
        json.dump(answer, f)


if __name__ == "__main__":
    main()
