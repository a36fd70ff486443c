#!/usr/bin/env bash
# Rebuilds the shipped point classifier (models/classifier.yml.gz) from the
# project's labelled data, with fixed seeds: the sample towns of
# cadastre/classify/training.cpp, the Cimahi survey and IGN's labelled tiles
# beside the checkout. Prints
# the precision and recall on the held-out towns and parcels and writes that table
# to docs/classification_table.md. Usage: scripts/train_classifier.sh [build dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cimahi=../shared/data/cimahi
labelled=../shared/data/labelled
for d in "$cimahi" "$labelled"; do
  [ -d "$d" ] || { echo "train_classifier: $d not found (the model is trained on it)" >&2; exit 1; }
done
cmake --build "$build" --target cadastre3d >/dev/null
"$build/cli/cadastre3d" classify --train --out models/classifier.yml.gz --cimahi "$cimahi" --labelled "$labelled" \
  --table docs/classification_table.md
