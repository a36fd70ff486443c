#!/usr/bin/env bash
# Prepares the optimizer benchmark for a GPU machine that has a driver but no
# Debian packages: builds build/tests/bench/bench_optimizer (linked against the
# optimizer library only, static C++ runtime) and puts it with Debian's Vulkan
# loader (libvulkan1 and glvnd .debs) into .gpubench/, a folder git ignores.
#   bash scripts/bench_gpu.sh [BUILD_DIR]
# On the GPU machine, from the repository root:
#   for f in .gpubench/*.deb; do dpkg -x $f /; done; ldconfig && .gpubench/bench_optimizer
# (where the loader finds no driver: export VK_DRIVER_FILES=<the NVIDIA ICD json>).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR="${1:-build}"
cmake --build "$BUILD_DIR" --target bench_optimizer
mkdir -p .gpubench
cp "$BUILD_DIR/tests/bench/bench_optimizer" .gpubench/
(cd .gpubench && rm -f libvulkan1*.deb && apt-get download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2 >/dev/null)
ldd .gpubench/bench_optimizer
ls -l .gpubench
