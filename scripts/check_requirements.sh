#!/usr/bin/env bash
# What the test suite needs besides the build: services, independent judges and
# the shared data beside the checkout. Prints each one missing. In CI (CI set,
# not "false" or "0") a missing one fails the run here, before the build, with
# its name; elsewhere the tests that need it skip and say why.
set -uo pipefail
cd "$(dirname "$0")/.."
shared=../shared
missing=()
need() {  # need WHAT TEST...: WHAT is missing unless the test command succeeds
  local what=$1; shift
  "$@" >/dev/null 2>&1 || missing+=("$what")
}
need "PostgreSQL 15 (postgresql-15)" test -x /usr/lib/postgresql/15/bin/initdb
need "PostGIS 3 (postgresql-15-postgis-3)" test -f /usr/share/postgresql/15/extension/postgis.control
need "Slurm (slurm-wlm)" command -v slurmctld
need "munge" command -v munged
need "root, for the single-node Slurm" test "$(id -u)" -eq 0
need "val3dity ($shared/tools/val3dity/val3dity)" test -x "$shared/tools/val3dity/val3dity"
need "the CityGML/CityJSON schemas ($shared/schemas)" test -d "$shared/schemas"
need "the Cimahi survey ($shared/data/cimahi)" test -d "$shared/data/cimahi"
need "the AHN3 town ($shared/data/ahn3)" test -d "$shared/data/ahn3"
need "the LAS/LAZ pairs ($shared/data/laz)" test -d "$shared/data/laz"
need "xmllint (libxml2-utils)" command -v xmllint
need "ogrinfo (gdal-bin)" command -v ogrinfo
need "GDAL's Python (python3-gdal, python3-numpy)" /usr/bin/python3 -c 'import numpy, osgeo'
need "Chromium (chromium)" command -v chromium
need "node and the npm checks (tests/js/node_modules: ajv, web-ifc, laz-perf, puppeteer-core, cesium)" \
  test -f tests/js/node_modules/ajv-formats/package.json -a -f tests/js/node_modules/web-ifc/package.json \
  -a -f tests/js/node_modules/laz-perf/package.json -a -f tests/js/node_modules/puppeteer-core/package.json \
  -a -f tests/js/node_modules/cesium/package.json
need "IFC++ (libifcplusplus-dev)" test -f /usr/include/ifcpp/reader/ReaderSTEP.h
need "a Vulkan driver (mesa-vulkan-drivers' lavapipe)" test -f /usr/share/vulkan/icd.d/lvp_icd.x86_64.json

[ "${#missing[@]}" -eq 0 ] && { echo "requirements: all present"; exit 0; }
if [ -n "${CI:-}" ] && [ "$CI" != false ] && [ "$CI" != 0 ]; then
  printf 'CI requires it: %s\n' "${missing[@]}" >&2
  exit 1
fi
printf 'requirements: missing, its tests will skip: %s\n' "${missing[@]}" >&2
