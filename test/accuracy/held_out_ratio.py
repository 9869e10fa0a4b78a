#!/usr/bin/python3
"""Accuracy cannot regress silently: scores an example set with de_evaluate (fine Stable Neo-Hookean solves
of held-out interactions as the truth) and fails when the enriched / coarse RMS ratio exceeds the bound.

Usage: held_out_ratio.py TOOL_DIR SET_DIR MAX_RATIO [de_evaluate options...]
The default slab set scores 0.46 on the slab plan's four held-out interactions (docs/accuracy.md; contacts where
they are on the surface: rho and normals interpolated over the contact's triangle, B continuous, sigma_rho at
least 1 % of |rho|, docs/design.md §8). On these four contacts equivalent descriptions spread over 0.38-0.63 (the
site descriptor is flat on the slab's top, so its noise decides); the bound 0.5 leaves a margin for round-off
differences between machines (BLAS, thread count), not for a worse method.
"""
import json
import subprocess
import sys


def main():
    tool_dir, set_dir, bound = sys.argv[1], sys.argv[2], float(sys.argv[3])
    run = subprocess.run([f"{tool_dir}/de_evaluate", "--examples", set_dir, "--json"] + sys.argv[4:],
                         capture_output=True, text=True)
    if run.returncode != 0:
        print(run.stderr, file=sys.stderr)
        return 1
    result = json.loads(run.stdout)
    ratio = result["ratio"]
    print(f"held-out enriched RMS {result['enriched_rms'] * 1e3:.3f} mm vs coarse {result['coarse_rms'] * 1e3:.3f} mm: "
          f"ratio {ratio:.3f} (bound {bound}) over {result['contacts']} interactions, {result['examples']} examples")
    if not (0.0 < ratio <= bound):
        print(f"FAIL: held-out ratio {ratio} is not in (0, {bound}]", file=sys.stderr)
        return 1
    for contact in result["per_contact"]:
        if not (0.0 < contact["enriched_rms"] < contact["coarse_rms"]):
            print(f"FAIL: a held-out contact is enriched worse than coarse: {contact}", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
