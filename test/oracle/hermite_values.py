#!/usr/bin/python3
"""Independent oracle for the Hermite basis: prints H_alpha(r) = He_ax(rx) He_ay(ry) He_az(rz) / sqrt(n!)
using scipy.special.eval_hermitenorm, for every multi-index of order <= 4 (lexicographic order of the
sorted index tuples), one line per point: the 35 values separated by spaces.
Usage: hermite_values.py x1 y1 z1 [x2 y2 z2 ...]"""
import itertools
import math
import sys

from scipy.special import eval_hermitenorm


def multi_indices(n):
    for tup in itertools.combinations_with_replacement(range(3), n):
        yield [tup.count(axis) for axis in range(3)]


def main():
    coords = [float(v) for v in sys.argv[1:]]
    for start in range(0, len(coords), 3):
        r = coords[start:start + 3]
        values = []
        for n in range(5):
            for alpha in multi_indices(n):
                he = 1.0
                for axis in range(3):
                    he *= eval_hermitenorm(alpha[axis], r[axis])
                values.append(he / math.sqrt(math.factorial(n)))
        print(" ".join(repr(float(v)) for v in values))


if __name__ == "__main__":
    main()
