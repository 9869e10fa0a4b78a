#!/usr/bin/env bash
# ctest fixture: acquires a slab example set into SET_DIR (de_make_examples --scene slab, by default the
# demo's set; extra options such as --examples 16 pass through), resuming or re-checking a set that is
# already there. Usage: slab_example_set.sh TOOL_DIR SET_DIR [de_make_examples options...]
set -eo pipefail
"$1/de_make_examples" --scene slab --output "$2" "${@:3}"
