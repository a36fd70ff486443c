#!/usr/bin/env bash
# Installs every Debian package Cadastre3D needs to build, test and run its demo.
# Idempotent; works as root or through sudo. Only apt and npm are used.
set -euo pipefail
cd "$(dirname "$0")/.."

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

PACKAGES=(
  build-essential cmake ninja-build pkg-config ccache lld git
  libpcl-dev libeigen3-dev libopencv-dev libgeos-dev libgeos++-dev libgdal-dev gdal-bin python3-gdal
  python3-numpy python3-lxml libcgal-dev libopen3d-dev libocct-foundation-dev libocct-modeling-data-dev
  libocct-modeling-algorithms-dev libocct-data-exchange-dev
  libvulkan-dev mesa-vulkan-drivers glslc vulkan-tools
  libsqlite3-dev sqlite3 libgtest-dev libgmock-dev
  nlohmann-json3-dev libtomlplusplus-dev libcli11-dev
  libxml2-utils libifcplusplus-dev chromium
  postgresql-15 postgresql-15-postgis-3 libpq-dev slurm-wlm munge
)
# Node.js may already come from elsewhere (e.g. nodesource); Debian's npm conflicts with it.
if ! command -v npm >/dev/null; then PACKAGES+=(nodejs npm); fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  if ! command -v eatmydata >/dev/null; then $SUDO apt-get install -y -qq eatmydata >/dev/null || true; fi
  EMD=""; command -v eatmydata >/dev/null && EMD="eatmydata"
  $SUDO env DEBIAN_FRONTEND=noninteractive $EMD apt-get install -y -qq --no-install-recommends \
    -o Dpkg::Options::=--force-unsafe-io "${missing[@]}"
else
  echo "setup: all Debian packages present"
fi

# The web views (the report's 3D view, the 3D Tiles page) are bundled at
# build time from npm's three.js and 3d-tiles-renderer (esbuild): the build
# needs these, so a failure here stops the set-up.
if [ ! -f web/node_modules/three/package.json ] ||
   [ ! -f web/node_modules/3d-tiles-renderer/package.json ] ||
   [ ! -e web/node_modules/.bin/esbuild ]; then
  echo "setup: installing the web views' npm packages into web/node_modules"
  (cd web && npm ci --no-audit --no-fund --loglevel=error)
fi

# npm tools for independent validation of exports (CityJSON schema, IFC reader, glTF, 3D Tiles),
# installed into tests/js/node_modules (the path the tests look in) from the
# lock file. Without them (no network to the npm registry) those checks skip.
js_ok() {
  [ -e tests/js/node_modules/.bin/ajv ] && [ -f tests/js/node_modules/ajv-formats/package.json ] &&
    [ -f tests/js/node_modules/web-ifc/package.json ] && [ -f tests/js/node_modules/laz-perf/package.json ] &&
    [ -f tests/js/node_modules/gltf-validator/package.json ] && [ -f tests/js/node_modules/3d-tiles-tools/package.json ] &&
    [ -f tests/js/node_modules/cesium/package.json ] && [ -f tests/js/node_modules/puppeteer-core/package.json ]
}
if [ -f tests/js/package.json ] && ! js_ok; then
  echo "setup: installing npm packages for the export checks into tests/js/node_modules"
  npm_cmd=install
  [ -f tests/js/package-lock.json ] && npm_cmd=ci
  if ! (cd tests/js && npm "$npm_cmd" --no-audit --no-fund --loglevel=error) || ! js_ok; then
    echo "setup: warning: npm packages not installed; the CityJSON schema, web-ifc, glTF and 3D Tiles checks will skip" >&2
  fi
fi
echo "setup: done"
