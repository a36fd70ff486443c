#!/usr/bin/env bash
# The scale benchmark of issue 37 (a script, not a timed test): sample towns
# of growing size written as LAZ tiles, the batch on them, and what it costs.
# For each size: `sample --laz --tiles` (generation time and memory), the
# batch on the tiles (given as a list of --cloud files, which every version
# reads), and, with -b, the same town's LAS through an older binary on the
# same machine in the same session (today's baseline, which reads LAS only).
# With scripts/services.sh and a `cadastre3d slurm` sub-command it adds the
# sharded run on 1, 2 and 4 Slurm tasks; without them it says so and skips.
# Each run: wall time, CPU time (user+sys), peak RSS (/usr/bin/time -v) and
# the batch's own timing line. Parcels per CPU-second is the per-core
# throughput, robust to other load on a shared machine; the load average is
# recorded beside it.
#   scripts/bench_scale.sh [-b OLD_BIN] [-s "1000 10000"] [-t TILE_M] [-j JOBS] [-o OUT] [-k]
#   env C3D=build/cli/cadastre3d, WORK=DIR (the towns; default OUT/work, removed unless -k)
# Writes OUT/scale.jsonl (one record a run) and OUT/scale.md (the table).
set -euo pipefail
cd "$(dirname "$0")/.."
C3D="${C3D:-build/cli/cadastre3d}"
BASE=""; SIZES="1000 10000"; TILE=250; JOBS=$(nproc); OUT=""; KEEP=0
while getopts "b:s:t:j:o:k" opt; do
  case $opt in
    b) BASE="$OPTARG" ;; s) SIZES="$OPTARG" ;; t) TILE="$OPTARG" ;; j) JOBS="$OPTARG" ;;
    o) OUT="$OPTARG" ;; k) KEEP=1 ;; *) sed -n 2,17p "$0"; exit 2 ;;
  esac
done
[ -x "$C3D" ] || { echo "bench_scale: build $C3D first (cmake --build build --target cadastre3d)" >&2; exit 1; }
[ -z "$BASE" ] || [ -x "$BASE" ] || { echo "bench_scale: $BASE is not an executable" >&2; exit 1; }
OUT="${OUT:-$(mktemp -d /tmp/bench_scale.XXXXXX)}"; mkdir -p "$OUT"
WORK="${WORK:-$OUT/work}"; mkdir -p "$WORK"
[ "$KEEP" = 1 ] || trap 'rm -rf "$WORK"' EXIT
RESULTS="$OUT/scale.jsonl"; : > "$RESULTS"
PY=/usr/bin/python3; [ -x "$PY" ] || PY=python3

# measure LABEL PARCELS INPUT_DESC TILES INPUT_BYTES -- command...
measure() {
  local label="$1" parcels="$2" input="$3" tiles="$4" bytes="$5"; shift 6
  local load; load=$(cut -d' ' -f1 /proc/loadavg)
  echo "[$(date -u +%H:%M:%S)] $label: $*" >&2
  local rc=0
  /usr/bin/time -v -o "$WORK/$label.time" "$@" > "$WORK/$label.log" 2>&1 || rc=$?
  "$PY" - "$label" "$parcels" "$input" "$tiles" "$bytes" "$JOBS" "$rc" "$load" "$WORK/$label.time" \
    "$WORK/$label.log" >> "$RESULTS" <<'PYEOF'
import json, re, sys
label, parcels, inp, tiles, nbytes, jobs, rc, load, tfile, lfile = sys.argv[1:]
t = open(tfile).read(); log = open(lfile, errors="replace").read()
def field(name):
    m = re.search(re.escape(name) + r": (.*)", t)
    return m.group(1).strip() if m else ""
def seconds(s):
    parts = [float(p) for p in s.split(":")]
    return sum(p * 60 ** i for i, p in enumerate(reversed(parts)))
cpu = float(field("User time (seconds)") or 0) + float(field("System time (seconds)") or 0)
wall = seconds(field("Elapsed (wall clock) time (h:mm:ss or m:ss)") or "0")
rec = {"run": label, "parcels": int(parcels), "input": inp, "tiles": int(tiles), "input_bytes": int(nbytes),
       "jobs": int(jobs), "rc": int(rc), "load_before": float(load), "wall_s": wall, "cpu_s": round(cpu, 2),
       "peak_rss_mb": round(int(field("Maximum resident set size (kbytes)") or 0) / 1024, 1)}
m = re.search(r"timing: ingest\+clip ([\d.]+) s, reconstruction ([\d.]+) s, store writes ([\d.]+) s, "
              r"summary\+report\+exports ([\d.]+) s, total ([\d.]+) s", log)
if m:
    for k, v in zip(["ingest_s", "reconstruct_s", "store_write_s", "outputs_s", "batch_total_s"], m.groups()):
        rec[k] = float(v)
if "batch" in label or "slurm" in label:
    rec["parcels_per_s"] = round(int(parcels) / wall, 2) if wall else None
    rec["parcels_per_cpu_s"] = round(int(parcels) / cpu, 2) if cpu else None
    if "store_write_s" in rec:
        rec["store_writes_per_s"] = round(int(parcels) / rec["store_write_s"], 1) if rec["store_write_s"] else None
print(json.dumps(rec))
PYEOF
  [ "$rc" = 0 ] || [ "$rc" = 3 ] || echo "  (exit $rc; see $WORK/$label.log)" >&2
}

dir_bytes() { du -sb "$1" | cut -f1; }
slurm_ready() {
  [ -x scripts/services.sh ] && "$C3D" slurm --help 2>/dev/null | grep -q -- --shards &&
    scripts/services.sh start >/dev/null 2>&1
}

# The towns first, all at once (generation is single-threaded and not what is measured).
for n in $SIZES; do
  measure "sample_laz_$n" "$n" "generate" 0 0 -- "$C3D" sample --out "$WORK/town$n" --parcels "$n" --seed 7 \
    --laz --tiles "$TILE" &
  [ -z "$BASE" ] || measure "sample_las_base_$n" "$n" "generate" 0 0 -- "$BASE" sample --out "$WORK/las$n" \
    --parcels "$n" --seed 7 &
done
wait

for n in $SIZES; do
  T="$WORK/town$n"
  tiles=( "$T"/cloud/*.laz )
  common=(--parcels "$T/parcels.gpkg" --dtm "$T/dtm.tif" --formats cityjsonseq --jobs "$JOBS")
  measure "batch_laz_tiles_$n" "$n" "LAZ tiles of ${TILE} m" "${#tiles[@]}" "$(dir_bytes "$T/cloud")" -- \
    "$C3D" batch --cloud "${tiles[@]}" --out "$WORK/out_laz$n" "${common[@]}"
  rm -rf "$WORK/out_laz$n"
  if [ -n "$BASE" ]; then
    measure "batch_las_base_$n" "$n" "one LAS (baseline binary)" 1 "$(dir_bytes "$WORK/las$n/cloud.las")" -- \
      "$BASE" batch --cloud "$WORK/las$n/cloud.las" --out "$WORK/out_las$n" "${common[@]}"
    rm -rf "$WORK/las$n" "$WORK/out_las$n"
  fi
  if slurm_ready; then
    eval "$(scripts/services.sh env)"
    for tasks in 1 2 4; do
      db="bench_scale_$$_${n}_$tasks"
      psql -q "$C3D_PG_URL" -c "CREATE DATABASE $db" || continue
      measure "slurm_${tasks}_tasks_$n" "$n" "LAZ tiles, $tasks Slurm tasks, PostGIS" "${#tiles[@]}" \
        "$(dir_bytes "$T/cloud")" -- "$C3D" slurm --shards "$tasks" --out "$WORK/slurm$tasks" \
        --store "${C3D_PG_URL%/*}/$db" --cloud "${tiles[@]}" "${common[@]}"
      psql -q "$C3D_PG_URL" -c "DROP DATABASE $db" || true; rm -rf "$WORK/slurm$tasks"
    done
  else
    echo "bench_scale: no Slurm runs (needs scripts/services.sh and a 'cadastre3d slurm' sub-command)" >&2
  fi
  rm -rf "$T"
done

"$PY" - "$RESULTS" > "$OUT/scale.md" <<'PYEOF'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
cols = ["run", "parcels", "input", "tiles", "input_bytes", "jobs", "wall_s", "cpu_s", "peak_rss_mb",
        "parcels_per_s", "parcels_per_cpu_s", "store_write_s", "store_writes_per_s", "load_before", "rc"]
print("| " + " | ".join(cols) + " |")
print("|" + "---|" * len(cols))
for r in rows:
    print("| " + " | ".join(str(r.get(c, "")) for c in cols) + " |")
PYEOF
cat "$OUT/scale.md"
echo "bench_scale: $RESULTS, $OUT/scale.md"
