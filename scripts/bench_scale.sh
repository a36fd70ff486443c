#!/usr/bin/env bash
# The scale benchmark of issue 37 (a script, not a timed test): sample towns
# of growing size written as LAZ tiles, the batch on them, and what it costs.
# For each size: `sample --laz --tiles` (generation time and memory), the
# batch on the tiles (given as a list of --cloud files, which every version
# reads), and, with -b, the same town's LAS through an older binary on the
# same machine in the same session (today's baseline, which reads LAS only).
# Each run: wall time, CPU time (user+sys), peak RSS (/usr/bin/time -v) and
# the batch's own timing line. Parcels per CPU-second is the per-core
# throughput, robust to other load on a shared machine; the load average is
# recorded beside it.
# Slurm rows (with root, scripts/services.sh's single-node Slurm + PostGIS and
# `cadastre3d slurm --launcher`; otherwise it says so and skips them): the
# same town as 1, 2 and 4 shards, submitted for real (`slurm --submit`), all
# tasks writing one PostGIS database; each task gets node CPUs / tasks CPUs
# (at least 1), so with fewer CPUs than tasks they queue. The row waits for
# the finish job (report + export from the store) and records wall time from
# submit to the finish job's end (scontrol), CPU time summed over all tasks and
# the finish job and each task's peak RSS (/usr/bin/time inside the tasks via
# --launcher: the services' Slurm keeps no accounting, so sacct has nothing),
# the node's CPU count, and a check: every parcel in the store once, none
# pending, and scripts/compare_stores.py equal to the row's unsharded batch.
# A failed task, a finish job that never runs, a timeout or a failed check
# fails the row (rc 1, `error` says why, the task logs' tails on stderr).
#   scripts/bench_scale.sh [-b OLD_BIN] [-s "1000 10000"] [-S SIZES] [-B SIZES] [-n "1 2 4"]
#                          [-t TILE_M] [-j JOBS] [-w WAIT_S] [-o OUT] [-k]
#   -s  town sizes (each: sample + batch)      -S  sizes with Slurm rows (default: all of -s; "none")
#   -b  baseline binary                        -B  sizes with baseline rows (default: all of -s; "none")
#   -n  Slurm task counts                      -w  seconds a Slurm row may take (default 14400)
#   -j  the plain batch's --jobs (default: all cores)   -k  keep the towns and outputs (WORK)
#   env C3D=build/cli/cadastre3d, WORK=DIR (the towns; default OUT/work, removed unless -k),
#   C3D_SERVICES_DIR / C3D_PG_PORT / C3D_SLURM_PORT: which services (scripts/services.sh)
# Writes OUT/scale.jsonl (one record a run) and OUT/scale.md (the table).
set -euo pipefail
cd "$(dirname "$0")/.."
C3D="${C3D:-build/cli/cadastre3d}"
BASE=""; SIZES="1000 10000"; TILE=250; JOBS=$(nproc); OUT=""; KEEP=0
SLURM_SIZES=all; BASE_SIZES=all; TASKS="1 2 4"; WAIT_S=14400
while getopts "b:s:S:B:n:t:j:w:o:k" opt; do
  case $opt in
    b) BASE="$OPTARG" ;; s) SIZES="$OPTARG" ;; S) SLURM_SIZES="$OPTARG" ;; B) BASE_SIZES="$OPTARG" ;;
    n) TASKS="$OPTARG" ;; t) TILE="$OPTARG" ;; j) JOBS="$OPTARG" ;; w) WAIT_S="$OPTARG" ;;
    o) OUT="$OPTARG" ;; k) KEEP=1 ;; *) sed -n 2,33p "$0"; exit 2 ;;
  esac
done
# picked SIZE LIST: is SIZE in LIST ("all": every size, "none": none)
picked() { [ "$2" = all ] || [[ " $2 " == *" $1 "* ]]; }
for n in $SLURM_SIZES $BASE_SIZES; do
  [ "$n" = all ] || [ "$n" = none ] || [[ " $SIZES " == *" $n "* ]] ||
    { echo "bench_scale: size $n of -S/-B is not among -s \"$SIZES\"" >&2; exit 2; }
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
if "batch" in label:
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
  [ "$(id -u)" -eq 0 ] && [ -x scripts/services.sh ] && "$C3D" slurm --help 2>/dev/null | grep -q -- --launcher &&
    scripts/services.sh start >/dev/null 2>&1 && eval "$(scripts/services.sh env)" && [ -n "${SLURM_CONF:-}" ]
}
epoch() { date -d "$1" +%s 2>/dev/null || echo ""; }  # a Slurm time (2026-11-26T22:50:01) in seconds
job_field() { scontrol show job -o "$1" 2>/dev/null | grep -o "$2=[^ ]*" | cut -d= -f2; }

# wait_finish FINISH_ID ARRAY_ID START: until the finish job has left the queue;
# prints "ok END_EPOCH" or "error WHY" (after cancelling what is left).
wait_finish() {
  local fin="$1" array="$2" start="$3" q
  while :; do
    q=$(squeue -h -j "$fin" -t PD,CF,R,CG,S -o "%T %r" 2>/dev/null || true)
    [ -n "$q" ] || break
    if [[ "$q" == *DependencyNeverSatisfied* ]]; then
      scancel "$fin" "$array" 2>/dev/null || true; echo "error a shard task failed, finish job never ran"; return
    fi
    if [ "$(( $(date +%s) - ${start%.*} ))" -gt "$WAIT_S" ]; then
      scancel "$fin" "$array" 2>/dev/null || true; echo "error still queued or running after $WAIT_S s"; return
    fi
    sleep 2
  done
  local state end; state=$(job_field "$fin" JobState); end=$(epoch "$(job_field "$fin" EndTime)")
  [ "$state" = COMPLETED ] || { echo "error finish job $fin ended ${state:-unknown (left scontrol)}"; return; }
  echo "ok ${end:-$(date +%s)}"
}

# check_store URL N UNSHARDED_GPKG: every parcel once and none pending, equal to the unsharded run.
check_store() {
  local rows pending
  rows=$(psql -qtA "$1" -c "SELECT count(*) || ' ' || count(DISTINCT parcel_id) FROM parcel_job" 2>&1) ||
    { echo "cannot read parcel_job: $rows"; return 1; }
  pending=$(psql -qtA "$1" -c "SELECT count(*) FROM parcel_job WHERE status = 'pending'")
  [ "$rows" = "$2 $2" ] || { echo "parcel_job holds $rows (rows, distinct) for $2 parcels"; return 1; }
  [ "$pending" = 0 ] || { echo "$pending parcels still pending"; return 1; }
  if [ -f "$3" ]; then
    "$PY" scripts/compare_stores.py "$3" "$1" > "$WORK/compare.txt" 2>&1 ||
      { echo "differs from the unsharded run: $(head -c 300 "$WORK/compare.txt" | tr '\n' ' ')"; return 1; }
    echo "$2 parcels once, equal to the unsharded run"
  else
    echo "$2 parcels once (no unsharded run to compare)"
  fi
}

# slurm_row N TASKS TILE_COUNT INPUT_BYTES UNSHARDED_GPKG -- BATCH_OPTIONS...
slurm_row() {
  local n="$1" tasks="$2" ntiles="$3" bytes="$4" whole="$5"; shift 6
  local label="slurm_${tasks}_tasks_$n" db="bench_scale_$$_${n}_$tasks" out="$WORK/slurm${tasks}_$n"
  local cpus; cpus=$(scontrol show node -o | grep -o 'CPUTot=[0-9]*' | head -1 | cut -d= -f2 || true)
  local cpt=$(( ${cpus:-1} / tasks )); [ "$cpt" -ge 1 ] || cpt=1
  local url="${C3D_PG_URL%/*}/$db" load; load=$(cut -d' ' -f1 /proc/loadavg)
  echo "[$(date -u +%H:%M:%S)] $label: slurm --shards $tasks --cpus-per-task $cpt --submit (node: ${cpus:-?} CPUs)" >&2
  local start; start=$(date +%s.%N)
  local result="error no database or submit failed (see $WORK/$label.log)"
  if psql -q "$C3D_PG_URL" -c "CREATE DATABASE $db" > "$WORK/$label.log" 2>&1 && "$C3D" slurm --shards "$tasks" --cpus-per-task "$cpt" --out "$out" --store "$url" --submit \
       --launcher "/usr/bin/time -v -a -o '$out/slurm'/task-\${SLURM_ARRAY_TASK_ID:-finish}.time" \
       "$@" >> "$WORK/$label.log" 2>&1; then
    local array fin
    array=$(awk '/^shards: job/ {print $3}' "$WORK/$label.log"); fin=$(awk '/^finish: job/ {print $3}' "$WORK/$label.log")
    result=$(wait_finish "$fin" "$array" "$start")
  fi
  local check=""
  if [[ "$result" == ok* ]]; then
    check=$(check_store "$url" "$n" "$whole") || result="error store check: $check"
  fi
  if [[ "$result" == error* ]]; then
    echo "  $label FAILED: ${result#error }" >&2
    for f in "$out"/slurm/*.log; do [ -f "$f" ] && { echo "  == $f" >&2; tail -3 "$f" | sed 's/^/  /' >&2; }; done
  fi
  "$PY" - "$label" "$n" "$ntiles" "$bytes" "$tasks" "$cpt" "${cpus:-0}" "$load" "$start" "$result" "$check" \
    "$out/slurm" >> "$RESULTS" <<'PYEOF'
import glob, json, os, re, sys
label, n, ntiles, nbytes, tasks, cpt, cpus, load, start, result, check, sdir = sys.argv[1:]
n = int(n)
rec = {"run": label, "parcels": n, "input": f"LAZ tiles, {tasks} Slurm tasks, PostGIS", "tiles": int(ntiles),
       "input_bytes": int(nbytes), "tasks": int(tasks), "cpus_per_task": int(cpt), "node_cpus": int(cpus),
       "jobs": int(cpt), "load_before": float(load)}
ok = result.startswith("ok")
rec["rc"] = 0 if ok else 1
if not ok:
    rec["error"] = result[len("error "):]
else:
    rec["check"] = check
    rec["wall_s"] = round(float(result.split()[1]) - float(start), 1)  # submit to the finish job's end
cpu, rss, task_cpu, task_rss = 0.0, 0.0, {}, {}
for path in sorted(glob.glob(os.path.join(sdir, "task-*.time"))):  # one file a task, a record a command
    task = os.path.basename(path)[len("task-"):-len(".time")]
    for run in open(path).read().split("Command being timed")[1:]:
        f = lambda k: float((re.search(re.escape(k) + r": ([\d.]+)", run) or [0, 0])[1])
        c = f("User time (seconds)") + f("System time (seconds)")
        m = f("Maximum resident set size (kbytes)") / 1024
        task_cpu[task] = round(task_cpu.get(task, 0) + c, 2)
        task_rss[task] = round(max(task_rss.get(task, 0), m), 1)
        cpu += c
        rss = max(rss, m)
rec.update({"cpu_s": round(cpu, 2), "peak_rss_mb": round(rss, 1), "task_cpu_s": task_cpu, "task_rss_mb": task_rss})
if ok:
    rec["parcels_per_s"] = round(n / rec["wall_s"], 2) if rec["wall_s"] else None
    rec["parcels_per_cpu_s"] = round(n / cpu, 2) if cpu else None
print(json.dumps(rec))
PYEOF
  psql -q "$C3D_PG_URL" -c "DROP DATABASE $db" >&2 || true
  [ "$KEEP" = 1 ] || rm -rf "$out"
}

# The towns first, all at once (generation is single-threaded and not what is measured).
for n in $SIZES; do
  measure "sample_laz_$n" "$n" "generate" 0 0 -- "$C3D" sample --out "$WORK/town$n" --parcels "$n" --seed 7 \
    --laz --tiles "$TILE" &
  [ -z "$BASE" ] || ! picked "$n" "$BASE_SIZES" || measure "sample_las_base_$n" "$n" "generate" 0 0 -- \
    "$BASE" sample --out "$WORK/las$n" --parcels "$n" --seed 7 &
done
wait

for n in $SIZES; do
  T="$WORK/town$n"
  tiles=( "$T"/cloud/*.laz )
  inputs=(--parcels "$T/parcels.gpkg" --dtm "$T/dtm.tif" --formats cityjsonseq)
  measure "batch_laz_tiles_$n" "$n" "LAZ tiles of ${TILE} m" "${#tiles[@]}" "$(dir_bytes "$T/cloud")" -- \
    "$C3D" batch --cloud "${tiles[@]}" --out "$WORK/out_laz$n" "${inputs[@]}" --jobs "$JOBS"
  if [ -n "$BASE" ] && picked "$n" "$BASE_SIZES"; then
    measure "batch_las_base_$n" "$n" "one LAS (baseline binary)" 1 "$(dir_bytes "$WORK/las$n/cloud.las")" -- \
      "$BASE" batch --cloud "$WORK/las$n/cloud.las" --out "$WORK/out_las$n" "${inputs[@]}" --jobs "$JOBS"
    rm -rf "$WORK/las$n" "$WORK/out_las$n"
  fi
  if ! picked "$n" "$SLURM_SIZES"; then
    :
  elif slurm_ready; then
    for tasks in $TASKS; do  # the tasks take --jobs from their CPUs
      slurm_row "$n" "$tasks" "${#tiles[@]}" "$(dir_bytes "$T/cloud")" "$WORK/out_laz$n/cadastre.gpkg" -- \
        --cloud "${tiles[@]}" "${inputs[@]}"
    done
  else
    echo "bench_scale: no Slurm runs (needs root, scripts/services.sh's Slurm and 'cadastre3d slurm --launcher')" >&2
  fi
  rm -rf "$T" "$WORK/out_laz$n"
done

"$PY" - "$RESULTS" > "$OUT/scale.md" <<'PYEOF'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
cols = ["run", "parcels", "input", "tiles", "input_bytes", "jobs", "wall_s", "cpu_s", "peak_rss_mb",
        "parcels_per_s", "parcels_per_cpu_s", "store_write_s", "store_writes_per_s", "load_before",
        "node_cpus", "task_cpu_s", "task_rss_mb", "rc", "check", "error"]
print("| " + " | ".join(cols) + " |")
print("|" + "---|" * len(cols))
for r in rows:
    cell = lambda v: ", ".join(f"{k}: {x}" for k, x in v.items()) if isinstance(v, dict) else str(v)
    print("| " + " | ".join(cell(r.get(c, "")) for c in cols) + " |")
PYEOF
cat "$OUT/scale.md"
echo "bench_scale: $RESULTS, $OUT/scale.md"
