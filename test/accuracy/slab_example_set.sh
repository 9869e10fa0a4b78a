#!/usr/bin/env bash
# ctest fixture: acquires the default slab example set (de_make_examples --scene slab, the demo's set) into
# SET_DIR, resuming or re-checking a set that is already there. Usage: slab_example_set.sh TOOL_DIR SET_DIR
set -eo pipefail
"$1/de_make_examples" --scene slab --output "$2"
