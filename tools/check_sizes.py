#!/usr/bin/env python3
"""The size limits of docs/ARCHITECTURE.md, measured: files by lines, functions by ctags.

  - no library or binding file over 800 lines;
  - no file of the wings built in Architecture III (analysis/{estimation,runs,studies,monitor,
    payload}) nor python/bind_*.cpp over 600;
  - no cli/ file over 400;
  - no function over 100 lines and at most 8 of 91-100 (Universal Ctags' end lines; skipped with a
    note when ctags is not installed).
Prints what breaks a limit; exits 1 then.
  python3 tools/check_sizes.py
"""
import glob
import os
import shutil
import subprocess
import sys

LIBRARY = ["core", "identifiability", "search", "data", "analysis", "reports", "cli", "python"]
NEW_WINGS = ["analysis/estimation", "analysis/runs", "analysis/studies", "analysis/monitor",
             "analysis/payload"]


def lines(path):
    with open(path, encoding="utf-8") as f:
        return sum(1 for _ in f)


def limit(path):
    if path.startswith("cli/"):
        return 400
    if any(path.startswith(w + "/") for w in NEW_WINGS) or \
            os.path.basename(path).startswith("bind_"):
        return 600
    return 800


def main():
    os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    errors = []
    for folder in LIBRARY:
        for path in sorted(glob.glob(f"{folder}/**/*.[ch]pp", recursive=True)):
            if lines(path) > limit(path):
                errors.append(f"{path}: {lines(path)} lines (at most {limit(path)})")
    if shutil.which("ctags"):
        out = subprocess.run(["ctags", "--fields=+ne", "--c++-kinds=f", "-x",
                              "--_xformat=%e %n %F %N", "-R"] + LIBRARY,
                             capture_output=True, text=True, check=True).stdout
        long = []
        for row in out.splitlines():
            end, start, path, name = row.split(" ", 3)
            if end.isdigit():
                long.append((int(end) - int(start) + 1, f"{path}:{start} {name}"))
        over = [f for f in long if f[0] > 100]
        near = sorted((f for f in long if 91 <= f[0] <= 100), reverse=True)
        errors += [f"{where}: {n} lines (at most 100)" for n, where in over]
        if len(near) > 8:
            errors.append(f"{len(near)} functions of 91-100 lines (at most 8): " +
                          ", ".join(f"{where} ({n})" for n, where in near))
        print(f"functions: {len(over)} over 100 lines, {len(near)} of 91-100")
    else:
        print("functions: not measured (no ctags: apt-get install universal-ctags)")
    for e in errors:
        print("error:", e, file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
