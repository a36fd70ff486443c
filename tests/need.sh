# Sourced by the check scripts: `missing WHAT` ends a check whose requirement
# is absent: skipped (exit 77, CTest's SKIP_RETURN_CODE) with WHAT, but in CI
# (CI set, not "false" or "0") failed naming it, as C3D_NEED does in the tests.
missing() {
  if [ -n "${CI:-}" ] && [ "${CI}" != false ] && [ "${CI}" != 0 ]; then
    echo "CI requires it: $*" >&2
    exit 1
  fi
  echo "skipped: $*"
  exit 77
}
