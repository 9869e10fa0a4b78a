#!/usr/bin/python3
"""More examples must make the enrichment better, and accuracy cannot regress silently: scores the prefixes of
a nested example set with de_evaluate --learning-curve on random held-out contacts and fails when a size's
mean enriched / coarse ratio exceeds its bound, when a contact is enriched worse than coarse by more than 5 %,
or when a larger prefix scores worse than a smaller one.

Usage: learning_curve.py TOOL_DIR SET_DIR SIZES BOUNDS [de_evaluate options...]
  SIZES, BOUNDS: comma-separated, one bound per size.
The bounds of the slab test (cmake/core.cmake) come from the measured curve on its seed (docs/accuracy.md,
"Tests"), with a margin of about 0.1 for round-off between machines (BLAS, thread count), not for a worse
method; that seed was used for no setting.
"""
import json
import subprocess
import sys

WORST_ALLOWED = 1.05


def main():
    tool_dir, set_dir = sys.argv[1], sys.argv[2]
    sizes = sys.argv[3]
    bounds = [float(b) for b in sys.argv[4].split(",")]
    run = subprocess.run([f"{tool_dir}/de_evaluate", "--examples", set_dir, "--learning-curve", sizes] + sys.argv[5:],
                         capture_output=True, text=True)
    if run.returncode != 0:
        print(run.stderr, file=sys.stderr)
        return 1
    curve = json.loads(run.stdout)["learning_curve"]
    if len(curve) != len(bounds):
        print(f"FAIL: {len(curve)} sizes scored for {len(bounds)} bounds", file=sys.stderr)
        return 1
    failed = False
    for point, bound in zip(curve, bounds):
        print(f"{point['examples']:4d} examples: mean ratio {point['mean_ratio']:.3f} (bound {bound}), worst "
              f"{point['worst_ratio']:.3f}, oracle {point['oracle_mean_ratio']:.3f}, own stamp {point['own_stamp_mean_ratio']:.3f}")
        if not (0.0 < point["mean_ratio"] <= bound):
            print(f"FAIL: mean ratio {point['mean_ratio']} with {point['examples']} examples is not in (0, {bound}]",
                  file=sys.stderr)
            failed = True
        if point["worst_ratio"] > WORST_ALLOWED:
            print(f"FAIL: a contact is enriched worse than coarse (ratio {point['worst_ratio']} > {WORST_ALLOWED})",
                  file=sys.stderr)
            failed = True
    for smaller, larger in zip(curve, curve[1:]):
        if larger["mean_ratio"] > smaller["mean_ratio"]:
            print(f"FAIL: {larger['examples']} examples score worse than {smaller['examples']} "
                  f"({larger['mean_ratio']} > {smaller['mean_ratio']})", file=sys.stderr)
            failed = True
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
