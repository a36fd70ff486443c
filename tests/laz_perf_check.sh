#!/usr/bin/env bash
# The LAZ files our writer makes, decoded by an independent decoder: laz-perf
# (tests/js, installed by scripts/setup.sh) must give the SHA-256 of the
# records that ../shared/data/laz/README.md lists for the originals.
# Usage: tests/laz_perf_check.sh BUILD_DIR     (exit 77: skipped; in CI a failure)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "$1" && pwd)"
. "$root/tests/need.sh"
[ -d "$root/../shared/data/laz" ] || missing "../shared/data/laz not found"
command -v node >/dev/null && [ -f "$root/tests/js/node_modules/laz-perf/package.json" ] ||
  missing "node or laz-perf (scripts/setup.sh installs them)"
# Each shared LAZ written again by our encoder (chunks of 50,000 and 1,000 points).
dir="$build/tests/tmp/laz_perf_check"
rm -rf "$dir"
C3D_LAZ_OUT="$dir" "$build/tests/laz_write_test" --gtest_filter=LazWrite.ForScript_RewriteSharedFiles >/dev/null
readme="$root/../shared/data/laz/README.md"
fail=0
for f in "$dir"/*.laz; do
  name="${f##*/}"; original="${name#*_}"
  want=$(grep -E "^    " "$readme" | grep -F "$original" | awk '{print $NF}')
  got=$(cd "$root/tests/js" && node laz_reference.js "$f" | sed 's/.*sha256 //')
  if [ -n "$want" ] && [ "$got" = "$want" ]; then echo "ok   $name $got"
  else echo "FAIL $name: laz-perf gives $got, README $want"; fail=1; fi
done
exit $fail
