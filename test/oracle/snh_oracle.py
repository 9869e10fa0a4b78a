#!/usr/bin/python3
"""Independent oracle for the Stable Neo-Hookean material (docs/design.md §4, [Masanti19 eq. 3.1]).

Only the energy density is taken from the design; everything else is derived here independently of the
C++ code: PK1 by complex-step differentiation of psi, the Hessian by complex-step differentiation of the
literal PK1 formula (both exact to rounding, no finite-difference truncation), the PSD projection by
numpy/LAPACK eigh and clamping.

usage: snh_oracle.py INPUT OUTPUT
INPUT:  line 1 "mu lambda variant" (variant: paper | production), then one F per line, 9 numbers,
        column-major vec(F).
OUTPUT: one line per F: psi, P (9, column-major), H (81, column-major 9x9), projected H (81).
"""
import sys

import numpy as np


def constants(mu, lam, variant):
    if variant == "paper":
        mu_p, lam_p = 4.0 / 3.0 * mu, lam + 5.0 / 6.0 * mu
        alpha = 1.0 + mu_p / lam_p - mu_p / (4.0 * lam_p)
    else:
        mu_p, lam_p = mu, lam + mu
        alpha = 1.0 + mu_p / lam_p
    return mu_p, lam_p, alpha


def det3(F):
    # Written out so that it is analytic in complex arguments (no pivoting, no conjugation).
    return (F[0, 0] * (F[1, 1] * F[2, 2] - F[1, 2] * F[2, 1])
            - F[0, 1] * (F[1, 0] * F[2, 2] - F[1, 2] * F[2, 0])
            + F[0, 2] * (F[1, 0] * F[2, 1] - F[1, 1] * F[2, 0]))


def psi(F, mu_p, lam_p, alpha, variant):
    ic = np.sum(F * F)
    value = mu_p / 2.0 * (ic - 3.0) + lam_p / 2.0 * (det3(F) - alpha) ** 2
    if variant == "paper":
        value = value - mu_p / 2.0 * np.log(ic + 1.0)
    return value


def pk1_literal(F, mu_p, lam_p, alpha, variant):
    ic = np.sum(F * F)
    cof = np.column_stack([np.cross(F[:, 1], F[:, 2]), np.cross(F[:, 2], F[:, 0]), np.cross(F[:, 0], F[:, 1])])
    tikhonov = mu_p * (1.0 - 1.0 / (ic + 1.0)) if variant == "paper" else mu_p
    return tikhonov * F + lam_p * (det3(F) - alpha) * cof


def unvec(f):
    return np.asarray(f).reshape(3, 3, order="F")


def main():
    src, dst = sys.argv[1], sys.argv[2]
    with open(src) as handle:
        header = handle.readline().split()
        mu, lam, variant = float(header[0]), float(header[1]), header[2]
        rows = [np.array([float(x) for x in line.split()]) for line in handle if line.strip()]
    mu_p, lam_p, alpha = constants(mu, lam, variant)
    psi_rest = psi(np.eye(3), mu_p, lam_p, alpha, variant)
    h = 1e-30  # complex step: derivative = Im f(x + i h) / h, exact to rounding
    with open(dst, "w") as out:
        for f in rows:
            F = unvec(f)
            value = psi(F, mu_p, lam_p, alpha, variant) - psi_rest
            P = np.zeros(9)
            H = np.zeros((9, 9))
            for k in range(9):
                step = np.zeros(9, dtype=complex)
                step[k] = 1j * h
                Fc = unvec(f.astype(complex) + step)
                P[k] = psi(Fc, mu_p, lam_p, alpha, variant).imag / h
                H[:, k] = pk1_literal(Fc, mu_p, lam_p, alpha, variant).reshape(9, order="F").imag / h
            H = 0.5 * (H + H.T)
            w, V = np.linalg.eigh(H)
            projected = (V * np.maximum(w, 0.0)) @ V.T
            numbers = [value] + list(P) + list(H.reshape(81, order="F")) + list(projected.reshape(81, order="F"))
            out.write(" ".join(repr(float(x)) for x in numbers) + "\n")


if __name__ == "__main__":
    main()
