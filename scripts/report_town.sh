#!/usr/bin/env bash
# The report of a large sample town, checked as an officer would open it:
# generates the town, runs the batch (with its 3D Tiles), then with headless
# Chromium takes a screenshot of the summary, of its 3D view and of the 3D
# view of the parcel of the most elements (clicking its largest roof), prints
# parcel pages to PDF (page count, A4), and lists the page sizes
# (docs/report.md). The 3D views need tests/js/node_modules (scripts/setup.sh).
#
#   bash scripts/report_town.sh [PARCELS [DIR]]   # default 800 parcels in out/report_town
#
# Environment: C3D (default build/cli/cadastre3d).
set -euo pipefail
cd "$(dirname "$0")/.."
N="${1:-800}"
DIR="$(realpath -m "${2:-out/report_town}")"
C3D="${C3D:-build/cli/cadastre3d}"
rm -rf "$DIR"
"$C3D" sample --out "$DIR/town" --parcels "$N" --seed 1 >/dev/null
rc=0
"$C3D" batch --quiet --cloud "$DIR/town/cloud.las" --parcels "$DIR/town/parcels.gpkg" \
  --dtm "$DIR/town/dtm.tif" --out "$DIR/out" --formats obj,3dtiles || rc=$?
[ "$rc" -eq 0 ] || [ "$rc" -eq 3 ] || { echo "report_town: batch failed ($rc)" >&2; exit 1; }

chrome=(chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run
        --user-data-dir="$DIR/chrome")
"${chrome[@]}" --screenshot="$DIR/summary.png" --window-size=1400,2400 \
  "file://$DIR/out/report.html" 2>/dev/null
view() { node tests/js/report_view.js "$@"; }
echo "3D view:  $(view "$DIR/out/report.html" "$DIR/summary_3d.png")"
largest=$(ls -S "$DIR"/out/report/parcel/*.html | head -1 || true)
echo "3D view:  $(view "$largest" "$DIR/parcel_3d.png" --click largest 0)"
echo "summary:  $(stat -c %s "$DIR/out/report.html") bytes, screenshot $DIR/summary.png"
echo "detail:   $(ls "$DIR"/out/report/parcels-*.html | wc -l) pages, largest $(ls -S "$DIR"/out/report/parcels-*.html | head -1 | xargs stat -c %s) bytes"
echo "parcels:  $(ls "$DIR"/out/report/parcel | wc -l) pages, largest $(ls -S "$DIR"/out/report/parcel/* | head -1 | xargs stat -c %s) bytes"
# Print the largest parcel pages and a few others: one A4 sheet each.
for page in $(ls -S "$DIR"/out/report/parcel/*.html | head -3) $(ls "$DIR"/out/report/parcel/*.html | head -3); do
  pdf="$DIR/$(basename "$page" .html).pdf"
  "${chrome[@]}" --no-pdf-header-footer --print-to-pdf="$pdf" "file://$page" 2>/dev/null
  python3 - "$pdf" <<'PY'
import re, sys
b = open(sys.argv[1], 'rb').read()
box = re.search(rb'/MediaBox \[0 0 ([\d.]+) ([\d.]+)\]', b)
pages = len(re.findall(rb'/Type\s*/Page[^s]', b))
print(f"print:    {sys.argv[1]}: {pages} page(s), {float(box[1]):.0f} x {float(box[2]):.0f} pt")
PY
done
