#!/usr/bin/env bash
# CTest's fixture for the tests that need PostgreSQL + PostGIS: the server of
# scripts/services.sh started once, before them. Exit 77 (skipped; in CI a
# failure) without the Debian packages.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
. "$here/tests/need.sh"
[ -x /usr/lib/postgresql/15/bin/initdb ] && [ -n "$(ls /usr/share/postgresql/15/extension/postgis.control 2>/dev/null)" ] ||
  missing "PostgreSQL 15 + PostGIS 3 (scripts/setup.sh's postgresql-15, postgresql-15-postgis-3)"
bash "$here/scripts/services.sh" start postgres
