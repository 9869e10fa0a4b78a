#!/usr/bin/python3
"""Checks the layering of docs/design.md §2 on the built binaries: none may depend (ELF NEEDED) on a layer
above it. Usage: check_layers.py FILE=FORBIDDEN[,FORBIDDEN...] ...  (FORBIDDEN: a library name part, e.g.
'simulation' for libdeformation_enrichment_simulation.so). Exit 1 naming every violation."""
import subprocess
import sys


def needed(path):
    out = subprocess.run(["readelf", "-d", path], check=True, capture_output=True, text=True).stdout
    return [line.split("[", 1)[1].rstrip("]") for line in out.splitlines() if "(NEEDED)" in line]


def main():
    violations = []
    for spec in sys.argv[1:]:
        path, forbidden = spec.split("=", 1)
        libraries = needed(path)
        ours = [lib for lib in libraries if lib.startswith("libdeformation_enrichment_")]
        print(f"{path}: {' '.join(ours) or '(no package libraries)'}")
        for layer in forbidden.split(","):
            for lib in ours:
                if lib.startswith(f"libdeformation_enrichment_{layer}."):
                    violations.append(f"{path} links {lib}, a layer above it")
    for v in violations:
        print("layering violation:", v, file=sys.stderr)
    return 1 if violations else 0


if __name__ == "__main__":
    sys.exit(main())
