#!/usr/bin/env bash
# Renders the figures a dynid command draws as PNG pictures, to look at them where no browser is
# (scripts/report-screenshot.sh needs chromium): the command runs with DYNID_GNUPLOT pointing at a
# wrapper that keeps each gnuplot script it is given, and each script is drawn again with gnuplot's
# pngcairo terminal at the SVG's size.
#   scripts/figure-png.sh OUT_DIR DYNID ARGS...
#   e.g. scripts/figure-png.sh pictures build/bin/dynid study --robot panda ... --front --out s
# Writes OUT_DIR/figure-1.png, figure-2.png, ... in the order the command drew them. Exit 0 when
# every figure rendered, 1 when one did not or the command failed, 2 on a usage error.
set -euo pipefail
if [[ $# -lt 2 ]]; then
  echo "usage: scripts/figure-png.sh OUT_DIR DYNID ARGS..." >&2
  exit 2
fi
out=$1
shift
gnuplot=$(command -v gnuplot || true)
[[ -n "$gnuplot" ]] || { echo "figure-png: no gnuplot (apt-get install gnuplot)" >&2; exit 2; }
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The wrapper: each script to a new numbered file (mktemp: exclusive), then to gnuplot as usual.
cat >"$work/gnuplot" <<EOF
#!/bin/sh
keep=\$(mktemp "$work/script.\$(date +%s%N).XXXX")
tee "\$keep" | "$gnuplot"
EOF
chmod +x "$work/gnuplot"
DYNID_GNUPLOT="$work/gnuplot" "$@" >/dev/null
status=0
count=0
# In the order they were started (the names begin with the time), drawn in the work directory
# under a fixed name: no path of the caller's reaches gnuplot's code.
shopt -s nullglob
for script in "$work"/script.*; do
  count=$((count + 1))
  sed -E "s/^set terminal svg size ([0-9]+),([0-9]+) .*/set terminal pngcairo size \1,\2 font 'sans,9' background rgb 'white'\nset output 'figure.png'/" \
    "$script" >"$work/png.gp"
  if (cd "$work" && "$gnuplot" png.gp 2>/dev/null) && [[ -s "$work/figure.png" ]]; then
    mv "$work/figure.png" "$out/figure-$count.png"
    echo "figure-png: $out/figure-$count.png"
  else
    echo "figure-png: figure $count did not render" >&2
    status=1
  fi
done
[[ $count -gt 0 ]] || { echo "figure-png: the command drew no figure" >&2; status=1; }
exit $status
