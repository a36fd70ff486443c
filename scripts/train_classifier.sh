#!/usr/bin/env bash
# Rebuilds the shipped point classifier (models/classifier.yml.gz) from the
# project's labelled data, with fixed seeds: the sample towns of
# cadastre/classify/training.cpp and the Cimahi survey beside the checkout. Prints
# the precision and recall on the held-out towns and parcels and writes that table
# to docs/classification_table.md. Usage: scripts/train_classifier.sh [build dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cimahi=../shared/data/cimahi
[ -d "$cimahi" ] || { echo "train_classifier: $cimahi not found (the model needs Cimahi's walls)" >&2; exit 1; }
cmake --build "$build" --target cadastre3d >/dev/null
"$build/cli/cadastre3d" classify --train --out models/classifier.yml.gz --cimahi "$cimahi" \
  --table docs/classification_table.md
