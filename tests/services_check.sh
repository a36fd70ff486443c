#!/usr/bin/env bash
# The scale-out services start from the project's own script (issue 37):
# PostGIS answers a spatial query and a Slurm job array runs every task.
# Exit 77 (skipped; in CI a failure) without root or without the Debian packages.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
. "$here/tests/need.sh"
if [ "$(id -u)" -ne 0 ] || ! command -v slurmctld >/dev/null || [ ! -x /usr/lib/postgresql/15/bin/initdb ]; then
  missing "root and scripts/setup.sh's postgresql-15-postgis-3, slurm-wlm, munge"
fi
export C3D_SERVICES_DIR=$(mktemp -d /tmp/c3d-services-test.XXXXXX) C3D_PG_PORT=55499 C3D_SLURM_PORT=56897
chmod 755 "$C3D_SERVICES_DIR"
trap 'bash "$here/scripts/services.sh" stop; rm -rf "$C3D_SERVICES_DIR"' EXIT
eval "$(bash "$here/scripts/services.sh" start)"

area=$(psql "$C3D_PG_URL" -qtAc "SELECT ST_Area(ST_GeomFromText('POLYGON((0 0,3 0,3 2,0 2,0 0))', 32748))")
[ "$area" = 6 ] || { echo "PostGIS area $area, expected 6"; exit 1; }

out="$C3D_SERVICES_DIR/array"
mkdir -p "$out"
job=$(sbatch --parsable --array=0-2 -o "$out/%a.log" --wrap "echo \$SLURM_ARRAY_TASK_ID > $out/task-\$SLURM_ARRAY_TASK_ID")
for _ in $(seq 1 60); do
  [ -z "$(squeue -h -j "$job" 2>/dev/null)" ] && break
  sleep 1
done
for k in 0 1 2; do
  [ "$(cat "$out/task-$k" 2>/dev/null)" = "$k" ] || { echo "Slurm array task $k did not run"; exit 1; }
done
# The scripts `cadastre3d slurm` writes, from a folder named with spaces,
# quotes and '%', submitted and run (tests/slurm_scripts_test.cpp).
if [ -n "${1:-}" ]; then
  "$1/tests/slurm_scripts_test" --gtest_filter=SlurmScripts.ForScript_SubmittedFromAHostileFolder >/dev/null ||
    { echo "a script written in a folder named with spaces, quotes and % did not run on Slurm"; exit 1; }
fi
echo "PostGIS and a 3-task Slurm array ran; so did a script from a hostile folder"
