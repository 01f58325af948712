# Shared by the fault tests (tests/faults/*.sh): failure counting and assertions on nhc runs.
# Each test sets nhc, work and sources this file; `run` runs nhc with its exit code in $rc and
# its standard error in $err.
set -uo pipefail
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
is_root() { [ "$(id -u)" -eq 0 ]; }

# run [VAR=VALUE…] -- ARGS…: nhc with the given environment; sets rc, out, err.
run() {
  local env_args=()
  while [ "$1" != "--" ]; do env_args+=("$1"); shift; done
  shift
  env "${env_args[@]}" "$nhc" "$@" >"$work/stdout" 2>"$work/stderr"
  rc=$?
  out=$(cat "$work/stdout")
  err=$(cat "$work/stderr")
}

# expect WHAT CODE TEXT: the last run exited CODE and said TEXT (a fixed string) on stderr.
expect() {
  local what=$1 code=$2 text=$3
  [ "$rc" -eq "$code" ] || fail "$what: exit code $rc, expected $code; stderr: $err"
  [ -z "$text" ] || grep -qF -- "$text" <<<"$err" || fail "$what: stderr lacks '$text': $err"
}

# no_leftovers WHAT DIR…: no temporary file or directory (*.tmp*) under the directories.
no_leftovers() {
  local what=$1; shift
  local left
  left=$(find "$@" -name '*.tmp*' 2>/dev/null)
  [ -z "$left" ] || fail "$what: temporary files left: $left"
}

finish() {
  [ "$failures" -eq 0 ] && echo "$1: all checks passed"
  exit $((failures > 0))
}
