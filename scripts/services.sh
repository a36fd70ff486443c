#!/usr/bin/env bash
# The services the scale-out tests need, on this machine only (issue 37):
# PostgreSQL 15 with PostGIS 3 on 127.0.0.1, and a single-node Slurm
# (munged, slurmctld, slurmd). Everything lives under one folder, so nothing
# of the system's own configuration changes.
#
#   scripts/services.sh start   # idempotent; prints the environment to use
#   scripts/services.sh start postgres   # PostgreSQL alone (the tests' fixture)
#   scripts/services.sh env     # prints it again:  eval "$(scripts/services.sh env)"
#   scripts/services.sh stop
#
# C3D_SERVICES_DIR (default /tmp/cadastre3d-services), C3D_PG_PORT (default
# 55432) and C3D_SLURM_PORT (default 56817) choose where. Slurm needs root
# (slurmd starts job steps as their user); without root only PostgreSQL starts.
set -euo pipefail

DIR=${C3D_SERVICES_DIR:-/tmp/cadastre3d-services}
PG_PORT=${C3D_PG_PORT:-55432}
SLURM_PORT=${C3D_SLURM_PORT:-56817}  # slurmctld; slurmd listens on the next port
PG_BIN=/usr/lib/postgresql/15/bin
PG_DB=cadastre3d
SLURM_DIR="$DIR/slurm"
SLURM_CONF_FILE="$SLURM_DIR/slurm.conf"
HOST=$(hostname -s)

as_postgres() {  # PostgreSQL refuses to run as root
  if [ "$(id -u)" -eq 0 ]; then runuser -u postgres -- "$@"; else "$@"; fi
}

pg_url() { echo "postgresql://$(pg_user)@127.0.0.1:$PG_PORT/$PG_DB"; }
pg_user() { if [ "$(id -u)" -eq 0 ]; then echo postgres; else id -un; fi; }

start_postgres() {
  local data="$DIR/pg"
  if [ ! -f "$data/PG_VERSION" ]; then
    mkdir -p "$data"
    [ "$(id -u)" -eq 0 ] && chown postgres: "$data" "$DIR"
    as_postgres "$PG_BIN/initdb" -D "$data" --auth=trust -U "$(pg_user)" >"$DIR/pg-initdb.log"
  fi
  if ! as_postgres "$PG_BIN/pg_ctl" -D "$data" status >/dev/null 2>&1; then
    as_postgres "$PG_BIN/pg_ctl" -D "$data" -l "$DIR/pg.log" -w \
      -o "-p $PG_PORT -k $data -c listen_addresses=127.0.0.1" start >/dev/null
  fi
  local psql=(psql -h 127.0.0.1 -p "$PG_PORT" -U "$(pg_user)" -v ON_ERROR_STOP=1 -qtA)
  if [ -z "$("${psql[@]}" -d postgres -c "SELECT 1 FROM pg_database WHERE datname='$PG_DB'")" ]; then
    "${psql[@]}" -d postgres -c "CREATE DATABASE $PG_DB" >/dev/null
  fi
  "${psql[@]}" -d "$PG_DB" -c "CREATE EXTENSION IF NOT EXISTS postgis" >/dev/null
  echo "services: PostgreSQL $("${psql[@]}" -d "$PG_DB" -c 'SHOW server_version') with PostGIS" \
       "$("${psql[@]}" -d "$PG_DB" -c 'SELECT postgis_lib_version()') at $(pg_url)" >&2
}

write_slurm_conf() {
  mkdir -p "$SLURM_DIR/state" "$SLURM_DIR/spool" "$SLURM_DIR/log"
  local cpus mem
  cpus=$(nproc)
  mem=$(awk '/MemTotal/ {print int($2 / 1024 * 0.9)}' /proc/meminfo)
  cat >"$SLURM_CONF_FILE" <<EOF
# Written by scripts/services.sh: a single-node cluster for the tests.
ClusterName=cadastre3d
SlurmctldHost=$HOST(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$SLURM_DIR/state
SlurmdSpoolDir=$SLURM_DIR/spool
SlurmctldPidFile=$SLURM_DIR/slurmctld.pid
SlurmdPidFile=$SLURM_DIR/slurmd.pid
SlurmctldLogFile=$SLURM_DIR/log/slurmctld.log
SlurmdLogFile=$SLURM_DIR/log/slurmd.log
SlurmctldPort=$SLURM_PORT
SlurmdPort=$((SLURM_PORT + 1))
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
SchedulerType=sched/backfill
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=batch Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
}

start_slurm() {
  if [ "$(id -u)" -ne 0 ]; then
    echo "services: not root, Slurm not started" >&2
    return
  fi
  mkdir -p /run/munge && chown munge: /run/munge
  [ -f /etc/munge/munge.key ] || { mungekey --create >/dev/null 2>&1 || /usr/sbin/create-munge-key -f; }
  pgrep -x munged >/dev/null || runuser -u munge -- /usr/sbin/munged
  write_slurm_conf
  export SLURM_CONF="$SLURM_CONF_FILE"
  pgrep -f "slurmctld -f $SLURM_CONF_FILE" >/dev/null || /usr/sbin/slurmctld -f "$SLURM_CONF_FILE"
  pgrep -f "slurmd -f $SLURM_CONF_FILE" >/dev/null || /usr/sbin/slurmd -f "$SLURM_CONF_FILE"
  for _ in $(seq 1 30); do  # the node registers within seconds
    if sinfo -h -o %T 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
      echo "services: Slurm $(sinfo -V | awk '{print $2}') node $HOST idle ($SLURM_CONF)" >&2
      return
    fi
    sleep 1
  done
  echo "services: error: the Slurm node did not come up; see $SLURM_DIR/log" >&2
  exit 1
}

print_env() {
  echo "export C3D_PG_URL=$(pg_url)"
  if [ "$(id -u)" -eq 0 ] && [ -f "$SLURM_CONF_FILE" ]; then echo "export SLURM_CONF=$SLURM_CONF_FILE"; fi
}

# Stops the daemon of this pid file and waits (10 s at most) until it is gone:
# slurmctld writes its state on SIGTERM, and a caller that removes the folder
# next (tests/slurm_shards_check.sh) must not race it ("Directory not empty").
stop_daemon() {
  [ -f "$1" ] || return 0
  local pid
  pid=$(cat "$1")
  kill "$pid" 2>/dev/null || return 0
  for _ in $(seq 100); do
    kill -0 "$pid" 2>/dev/null || return 0
    sleep 0.1
  done
}

stop_all() {
  stop_daemon "$SLURM_DIR/slurmd.pid"
  stop_daemon "$SLURM_DIR/slurmctld.pid"
  if [ -f "$DIR/pg/PG_VERSION" ]; then as_postgres "$PG_BIN/pg_ctl" -D "$DIR/pg" -m fast stop >/dev/null 2>&1 || true; fi
  echo "services: stopped" >&2
}

case "${1:-}" in
  start) mkdir -p "$DIR"; start_postgres; [ "${2:-}" = postgres ] || start_slurm; print_env ;;
  env) print_env ;;
  stop) stop_all ;;
  *) echo "usage: $0 start|env|stop" >&2; exit 2 ;;
esac
