#!/usr/bin/python3
"""Independent numpy oracle for the Discrete Shells energies W[reference, deformed].

Written from the papers, not from the C++ code: areas from cross products, tr G and det G from explicit
2x2 first fundamental forms, dihedral angles from arccos of the normals' dot product with the sign from
the edge direction, [Grinspun03]'s bending weight |e| / h_e with h_e a third of the average height of the two triangles.

Input file (whitespace separated): line 1 "model V T k_L k_A mu lambda bending_weight" with model
"classic" or "hyperelastic"; then V lines "x y z" of the reference, V lines of the deformed shape, T lines
"i j k". Prints the energy with 17 significant digits.
"""
import sys

import numpy as np


def areas(x, tri):
    return 0.5 * np.linalg.norm(np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]]), axis=1)


def hinges(tri):
    """Edges with exactly two triangles: (i, j, k, l), i -> j as in the first triangle, l opposite in the second."""
    faces_of_edge = {}
    for t, (a, b, c) in enumerate(tri):
        for u, v in ((a, b), (b, c), (c, a)):
            faces_of_edge.setdefault((min(u, v), max(u, v)), []).append(t)
    out, edges = [], list(faces_of_edge)
    for (u, v), faces in faces_of_edge.items():
        if len(faces) != 2:
            continue
        t1, t2 = (list(tri[f]) for f in faces)
        for a in range(3):
            if {t1[a], t1[(a + 1) % 3]} == {u, v}:
                i, j, k = t1[a], t1[(a + 1) % 3], t1[(a + 2) % 3]
        l = [w for w in t2 if w not in (u, v)][0]
        out.append((i, j, k, l))
    return np.array(out, dtype=int).reshape(-1, 4), np.array(edges, dtype=int)


def dihedral(x, h):
    xi, xj, xk, xl = (x[h[:, c]] for c in range(4))
    e = xj - xi
    n1 = np.cross(e, xk - xi)  # normal of (i, j, k)
    n2 = np.cross(xi - xj, xl - xj)  # normal of (j, i, l)
    n1 /= np.linalg.norm(n1, axis=1)[:, None]
    n2 /= np.linalg.norm(n2, axis=1)[:, None]
    angle = np.arccos(np.clip(np.sum(n1 * n2, axis=1), -1.0, 1.0))
    sign = np.sign(np.sum(np.cross(n1, n2) * e, axis=1))
    return np.where(sign < 0, -angle, angle)


def energy(model, ref, dfm, tri, kL, kA, mu, lam, kB):
    h, edges = hinges(tri)
    a_ref, a_dfm = areas(ref, tri), areas(dfm, tri)
    if model == "classic":
        l_ref = np.linalg.norm(ref[edges[:, 0]] - ref[edges[:, 1]], axis=1)
        l_dfm = np.linalg.norm(dfm[edges[:, 0]] - dfm[edges[:, 1]], axis=1)
        membrane = kL * np.sum((1 - l_dfm / l_ref) ** 2 * l_ref) + kA * np.sum((1 - a_dfm / a_ref) ** 2 * a_ref)
    else:
        membrane = 0.0
        for t, (a, b, c) in enumerate(tri):
            def metric(x):
                basis = np.stack([x[b] - x[a], x[c] - x[a]], axis=1)  # 3 x 2
                return basis.T @ basis
            G = np.linalg.solve(metric(ref), metric(dfm))
            tr, det = np.trace(G), np.linalg.det(G)
            W = mu / 2 * tr + lam / 4 * det - (mu / 2 + lam / 4) * np.log(det) - mu - lam / 4
            membrane += a_ref[t] * W
    if len(h) == 0:
        return membrane
    e_len = np.linalg.norm(ref[h[:, 1]] - ref[h[:, 0]], axis=1)
    a1 = areas(ref, h[:, [0, 1, 2]])
    a2 = areas(ref, h[:, [1, 0, 3]])
    if model == "classic":
        height = (2 * a1 / e_len + 2 * a2 / e_len) / 2.0 / 3.0  # a third of the average triangle height
        weight = e_len / height
    else:
        weight = e_len ** 2 / (a1 + a2)
    bending = np.sum((dihedral(dfm, h) - dihedral(ref, h)) ** 2 * weight)
    return membrane + kB * bending


def main(path):
    tokens = open(path).read().split()
    model, V, T = tokens[0], int(tokens[1]), int(tokens[2])
    kL, kA, mu, lam, kB = (float(t) for t in tokens[3:8])
    numbers = tokens[8:]
    ref = np.array(numbers[: 3 * V], dtype=float).reshape(V, 3)
    dfm = np.array(numbers[3 * V: 6 * V], dtype=float).reshape(V, 3)
    tri = np.array(numbers[6 * V: 6 * V + 3 * T], dtype=int).reshape(T, 3)
    print("%.17g" % energy(model, ref, dfm, tri, kL, kA, mu, lam, kB))


if __name__ == "__main__":
    main(sys.argv[1])
