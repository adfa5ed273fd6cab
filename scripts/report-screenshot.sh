#!/usr/bin/env bash
# Renders the demo's and identify's HTML reports in headless Chromium (Debian's `chromium`) at a
# laptop's window (1280 x 800) and checks that the verdict box is above the fold: its border
# colour (#22aa66) must be in the screenshot's pixels. Writes the screenshots into OUT.
#   scripts/report-screenshot.sh [BUILD_DIR] [OUT]      (defaults: build, build/screenshots)
# Exit 0 when both verdicts show, 1 when one does not, 2 when chromium or dynid is missing.
set -euo pipefail
build=${1:-build}
out=${2:-$build/screenshots}
dynid="$build/bin/dynid"
chromium=$(command -v chromium || command -v chromium-browser || true)
if [[ -z "$chromium" ]]; then
  echo "report-screenshot: no chromium (apt-get install chromium)" >&2
  exit 2
fi
[[ -x "$dynid" ]] || { echo "report-screenshot: no $dynid (build first)" >&2; exit 2; }
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$dynid" demo --quick --out "$work/demo" >/dev/null
"$dynid" simulate --robot puma560 --drives --duration 10 --noise-tau 0.05 --seed 1 \
  --out "$work/train.csv" >/dev/null
"$dynid" identify --method pc --robot puma560 --drives --data "$work/train.csv" \
  --out "$work/identify" >/dev/null

status=0
for report in demo identify; do
  png="$out/$report.png"
  # --no-sandbox: root in a container has no user namespace for Chromium's sandbox.
  "$chromium" --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1280,800 \
    --screenshot="$png" "file://$work/$report/report.html" >/dev/null 2>&1
  if python3 - "$png" <<'EOF'; then
import struct, sys, zlib
# A minimal PNG reader (8-bit RGB or RGBA, non-interlaced: what Chromium writes).
data = open(sys.argv[1], "rb").read()
pos, chunks = 8, {}
width = height = 0
idat = b""
while pos < len(data):
    length, kind = struct.unpack(">I4s", data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + length]
    if kind == b"IHDR":
        width, height, depth, colour = struct.unpack(">IIBB", body[:10])
        channels = {2: 3, 6: 4}[colour]
    elif kind == b"IDAT":
        idat += body
    pos += 12 + length
raw = zlib.decompress(idat)
stride = width * channels
previous = bytearray(stride)
found = 0
for y in range(height):
    filter_type = raw[y * (stride + 1)]
    line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for x in range(stride):
        left = line[x - channels] if x >= channels else 0
        up = previous[x]
        upper_left = previous[x - channels] if x >= channels else 0
        if filter_type == 1:
            line[x] = (line[x] + left) & 255
        elif filter_type == 2:
            line[x] = (line[x] + up) & 255
        elif filter_type == 3:
            line[x] = (line[x] + (left + up) // 2) & 255
        elif filter_type == 4:
            p = left + up - upper_left
            pa, pb, pc = abs(p - left), abs(p - up), abs(p - upper_left)
            predictor = left if pa <= pb and pa <= pc else up if pb <= pc else upper_left
            line[x] = (line[x] + predictor) & 255
    for x in range(0, stride, channels):
        if abs(line[x] - 0x22) < 8 and abs(line[x + 1] - 0xaa) < 8 and abs(line[x + 2] - 0x66) < 8:
            found += 1
    previous = line
sys.exit(0 if found > 100 else 1)
EOF
    echo "report-screenshot: $report: the verdict is above the fold ($png)"
  else
    echo "report-screenshot: $report: no verdict box in the first 1280 x 800 pixels ($png)" >&2
    status=1
  fi
done
exit $status
