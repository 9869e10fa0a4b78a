#!/usr/bin/python3
"""A transfer calibrated on a few fine solves of the target scene helps and never hurts: scores an example set
of one scene on another with de_evaluate --calibrate and fails when the stamp scale is not the smallest of the
calibration contacts' limits (transfer_calibration.hpp), when the calibration does not raise detail the
material similarity fades (the slab's stamps on the softer liver), when the mean enriched / coarse ratio
exceeds the bound, when a held-out contact is enriched worse than coarse by more than 5 %, or when a bad
calibration option does not exit 1.

Usage: transfer_calibration.py TOOL_DIR SET_DIR MAX_MEAN_RATIO [de_evaluate options...]
The bound of the slab -> liver test (cmake/core.cmake) comes from its measured value on seeds used for no
setting (docs/accuracy.md, "Transfer calibration"), with a margin for round-off between machines.
"""
import json
import subprocess
import sys

WORST_ALLOWED = 1.05


def refused(tool_dir, set_dir, arguments, message):
    """A bad calibration setting exits 1, naming the problem, before any solve."""
    run = subprocess.run([f"{tool_dir}/de_evaluate", "--examples", set_dir] + arguments, capture_output=True, text=True)
    if run.returncode == 1 and message in run.stderr and not run.stdout:
        return True
    print(f"FAIL: de_evaluate {' '.join(arguments)} exited {run.returncode} with {run.stderr!r}", file=sys.stderr)
    return False


def main():
    tool_dir, set_dir, bound = sys.argv[1], sys.argv[2], float(sys.argv[3])
    if not (refused(tool_dir, set_dir, ["--calibrate", "2", "--seed", "5", "--calibration-seed", "5"], "--calibration-seed")
            and refused(tool_dir, set_dir, ["--calibrate", "-1"], "--calibrate")):
        return 1
    run = subprocess.run([f"{tool_dir}/de_evaluate", "--examples", set_dir] + sys.argv[4:], capture_output=True, text=True)
    if run.returncode != 0:
        print(run.stderr, file=sys.stderr)
        return 1
    result = json.loads(run.stdout)
    calibration = result["transfer_calibration"]
    if calibration is None:
        print("FAIL: no transfer calibration in the report (pass --calibrate K)", file=sys.stderr)
        return 1
    limits = calibration["limits"]
    scale, similarity = result["stamp_scale"], result["material_similarity"]
    worst = max(c["ratio"] for c in result["per_contact"])
    print(f"calibration on {calibration['contacts']} contacts: limits {[round(g, 3) for g in limits]}, stamp scale "
          f"{scale:.3f} (material similarity {similarity:.3f}); held-out mean ratio {result['mean_ratio']:.3f} "
          f"(bound {bound}), worst {worst:.3f} (bound {WORST_ALLOWED}) over {result['contacts']} contacts")
    if not limits or scale != min(limits) or calibration["transfer_gain"] != scale:
        print("FAIL: the stamp scale is not the smallest limit of the calibration contacts", file=sys.stderr)
        return 1
    if not scale > similarity:
        print("FAIL: the calibration does not raise the detail the material similarity fades", file=sys.stderr)
        return 1
    if not (0.0 < result["mean_ratio"] <= bound):
        print(f"FAIL: mean held-out ratio {result['mean_ratio']} is not in (0, {bound}]", file=sys.stderr)
        return 1
    if worst > WORST_ALLOWED:
        print(f"FAIL: a held-out contact is enriched worse than coarse by more than 5 %: {worst}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
