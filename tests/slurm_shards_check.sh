#!/usr/bin/env bash
# A sharded batch through Slurm equals the unsharded one (issue 37): a sample
# town run whole into a GeoPackage, then as 3 shards by `cadastre3d slurm
# --submit`; shard 2's task is killed (SIGKILL) with parcels stored and
# others pending, rerun with OUT/slurm/rerun.sh 2, and the finish job merges.
# scripts/compare_stores.py: same parcels, statuses, element areas, NJOP and
# tax, no row twice. Then the same through one PostGIS store that every
# task writes at once (--store postgresql://): no merge, the finish job
# (`merge --store`) writes the summary, report and exports from the database.
# Both finish jobs get the batch's inputs: the summaries' whole-run fit
# equals the unsharded run's. Exit 77 (skipped; in CI a failure) without root, Slurm or GDAL's Python.
#   tests/slurm_shards_check.sh path/to/cadastre3d_test_hooks   (the program built with its test hooks)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
. "$here/tests/need.sh"
c3d=$(realpath "${1:?usage: $0 path/to/cadastre3d}")
if [ "$(id -u)" -ne 0 ] || ! command -v slurmctld >/dev/null || [ ! -x /usr/lib/postgresql/15/bin/initdb ] ||
   ! /usr/bin/python3 -c 'from osgeo import ogr' 2>/dev/null; then
  missing "root, scripts/setup.sh's slurm-wlm, munge, postgresql-15-postgis-3 and python3-gdal"
fi
export C3D_SERVICES_DIR=$(mktemp -d /tmp/c3d-slurm-shards.XXXXXX) C3D_PG_PORT=55497 C3D_SLURM_PORT=56893
chmod 755 "$C3D_SERVICES_DIR"
trap 'scancel --name=c3d-shards,c3d-finish 2>/dev/null || true; bash "$here/scripts/services.sh" stop; rm -rf "$C3D_SERVICES_DIR"' EXIT
eval "$(bash "$here/scripts/services.sh" start)"
cd "$C3D_SERVICES_DIR"

fail() { echo "FAIL: $*"; for f in out/slurm/*.log; do echo "== $f"; tail -5 "$f"; done; exit 1; }
jobs_left() { squeue -h -n c3d-shards,c3d-finish 2>/dev/null; }
wait_jobs() {  # until no job of ours is queued or running (a finish whose dependency failed is left pending)
  for _ in $(seq 1 "$1"); do
    [ -z "$(jobs_left | grep -v DependencyNeverSatisfied)" ] && return 0
    sleep 1
  done
  fail "jobs still queued after $1 s: $(jobs_left)"
}
# The whole-run fit of summary $2 equals the unsharded summary $1's: counts,
# ruler medians and p95 (0.1 mm bins) exactly, pooled figures to 1e-9.
same_fit() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert b["any_model_fit"] == "computed", b["any_model_fit"]
for k in ("any_model_roof_deviation", "any_model_wall_deviation", "roof_ruler", "wall_ruler"):
    for f, v in a[k].items():
        exact = f in ("n", "median", "p95")
        assert (b[k][f] == v) if exact else abs(b[k][f] - v) <= 1e-9, (k, f, v, b[k][f])
assert a["roof_ruler"]["n"] > 1000 and b["wall_points_measured_share"] == a["wall_points_measured_share"]
PY
}
done_parcels() { sqlite3 "$1" "SELECT count(*) FROM parcel_job WHERE status <> 'pending'" 2>/dev/null || echo 0; }

"$c3d" sample --out town --parcels 24 --seed 5 >/dev/null
inputs=(--cloud town/cloud.las --parcels town/parcels.gpkg --dtm town/dtm.tif --formats cityjson)
"$c3d" batch "${inputs[@]}" --out whole --quiet || [ $? -eq 3 ]

# Shard 2 stops for a minute after its 3rd parcel (the test hook), and is killed then.
C3D_TEST_PAUSE_SHARD=2/3:3 "$c3d" slurm --shards 3 --out out --submit "${inputs[@]}" | tee submit.txt
array=$(awk '/^shards: job/ {print $3}' submit.txt)
store2=out/shards/2/cadastre.gpkg
for _ in $(seq 1 60); do [ "$(done_parcels $store2)" -ge 3 ] && break; sleep 0.5; done
[ "$(done_parcels $store2)" -eq 3 ] || fail "shard 2 did not stop at 3 parcels"
scancel --signal=KILL --full "${array}_2"
wait_jobs 60
pending=$(sqlite3 $store2 "SELECT count(*) FROM parcel_job WHERE status = 'pending'")
[ "$pending" -gt 0 ] || fail "shard 2 was not killed midway"
[ ! -f out/cadastre.gpkg ] || fail "the finish step ran after a killed task"
echo "shard 2 killed with 3 parcels stored and $pending pending"

out/slurm/rerun.sh 2
wait_jobs 90
[ -f out/summary.json ] || fail "the finish step wrote no summary"
[ "$(sqlite3 $store2 "SELECT count(*) FROM parcel_job WHERE status = 'pending'")" -eq 0 ] || fail "shard 2 not complete"
[ -n "$(sqlite3 out/cadastre.gpkg "SELECT finished FROM run")" ] || fail "the merged run is not finished"
/usr/bin/python3 "$here/scripts/compare_stores.py" whole/cadastre.gpkg out/cadastre.gpkg || fail "the stores differ"
grep -q -- "--cloud=town/cloud.las" out/slurm/finish.sbatch || fail "the finish job lacks the batch's inputs"
same_fit whole/summary.json out/summary.json || fail "the merged whole-run fit differs from the unsharded run's"
"$c3d" merge --out nofit --quiet out/shards/*/cadastre.gpkg
grep -q '"any_model_fit": "not computed: ' nofit/summary.json || fail "a merge without inputs does not say the fit is missing"
echo "3 shards on Slurm, one killed and rerun, equal the unsharded run, whole-run fit included"

# The same on one shared PostGIS store: the shards write it at once; shard 2
# is killed midway and rerun; no merge, and no parcel twice.
db=c3d_shards_$$
createdb -h 127.0.0.1 -p "$C3D_PG_PORT" -U postgres "$db"
url="${C3D_PG_URL%/*}/$db"
pg_count() { psql -h 127.0.0.1 -p "$C3D_PG_PORT" -U postgres -d "$db" -Atc "$1" 2>/dev/null || echo 0; }
C3D_TEST_PAUSE_SHARD=2/3:3 "$c3d" slurm --shards 3 --out pg --store "$url" --submit "${inputs[@]}" | tee submit_pg.txt
array=$(awk '/^shards: job/ {print $3}' submit_pg.txt)
# Shard 2 pauses after its 3rd parcel; the others finish: 8 + 8 + 3 parcels stored.
for _ in $(seq 1 120); do [ "$(pg_count "SELECT count(*) FROM parcel_job WHERE status <> 'pending'")" -ge 19 ] && break; sleep 0.5; done
scancel --signal=KILL --full "${array}_2"
wait_jobs 60
pending=$(pg_count "SELECT count(*) FROM parcel_job WHERE status = 'pending'")
[ "$pending" -gt 0 ] || fail "shard 2 was not killed midway on PostGIS"
[ ! -f pg/summary.json ] || fail "the finish step ran after a killed task (PostGIS)"
echo "PostGIS: shard 2 killed with $pending parcels pending"
pg/slurm/rerun.sh 2
wait_jobs 90
[ -f pg/report.html ] || fail "the finish step wrote no report from PostGIS"
same_fit whole/summary.json pg/summary.json || fail "the PostGIS whole-run fit differs from the unsharded run's"
[ "$(pg_count "SELECT count(*) FROM parcel_job WHERE status = 'pending'")" -eq 0 ] || fail "PostGIS store not complete"
[ "$(pg_count "SELECT count(*) - count(DISTINCT parcel_id) FROM la_spatialunit")" -eq 0 ] || fail "a parcel stored twice"
/usr/bin/python3 "$here/scripts/compare_stores.py" whole/cadastre.gpkg "$url" || fail "the PostGIS store differs"
dropdb -h 127.0.0.1 -p "$C3D_PG_PORT" -U postgres "$db"
echo "3 shards on Slurm into one PostGIS store, one killed and rerun, equal the unsharded run"
