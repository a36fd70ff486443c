#!/usr/bin/env bash
# The README's test command: set up (idempotent), build, run every test.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# CI also fuzzes every reader under ASan + UBSan, a fixed count of inputs each (docs/testing.md).
C3D_FUZZ_SANITIZE=ON bash scripts/test.sh
