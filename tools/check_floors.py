#!/usr/bin/env python3
"""The include graph between the wings of analysis/ against their floors (docs/ARCHITECTURE.md).

Prints each wing's floor and the wings it includes; exits 1 when a wing includes one on a higher
floor, two wings include each other, or a source file sits at the root of analysis/.
  python3 tools/check_floors.py
"""
import os
import re
import sys

FLOORS = {"records": 1, "logs": 1, "excitation": 1, "estimation": 2, "runs": 3, "floating": 3,
          "studies": 4, "monitor": 4, "payload": 4, "fleet": 4}
INCLUDE = re.compile(r'#include "analysis/([a-z_]+)/')


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "analysis")
    errors = []
    loose = [f for f in os.listdir(root) if f.endswith((".cpp", ".hpp"))]
    if loose:
        errors.append(f"files at the root of analysis/: {', '.join(sorted(loose))}")
    edges = {}
    for wing in sorted(os.listdir(root)):
        path = os.path.join(root, wing)
        if not os.path.isdir(path):
            continue
        if wing not in FLOORS:
            errors.append(f"analysis/{wing}/ is no wing of the floor table (tools/check_floors.py)")
            continue
        for name in sorted(os.listdir(path)):
            if not name.endswith((".cpp", ".hpp")):
                continue
            with open(os.path.join(path, name), encoding="utf-8") as f:
                for target in INCLUDE.findall(f.read()):
                    if target != wing:
                        edges.setdefault(wing, set()).add(target)
                        if FLOORS.get(target, 0) > FLOORS[wing]:
                            errors.append(f"analysis/{wing}/{name} includes analysis/{target}/ "
                                          f"(floor {FLOORS[target]} above {FLOORS[wing]})")
    for a, targets in edges.items():
        for b in targets:
            if a < b and a in edges.get(b, set()):
                errors.append(f"analysis/{a}/ and analysis/{b}/ include each other")
    for wing in sorted(FLOORS, key=lambda w: (FLOORS[w], w)):
        below = ", ".join(sorted(edges.get(wing, set()))) or "-"
        print(f"floor {FLOORS[wing]}  {wing:<11} includes {below}")
    for e in errors:
        print("error:", e, file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
