#!/usr/bin/env bash
# A full disk while writing outputs: `nhc report -o DIR` and
# `nhc simulate -o FILE` exit 4 naming the path and "No space left on device" (as root, on a
# nearly full 200 KiB tmpfs) or "File too large" (otherwise, under a file-size limit); no DIR,
# no partial file, no temporary file is left, and an existing DIR is untouched.
# Usage: disk_full_test.sh NHC SCENE WORK_DIR
nhc=$1 scene=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"
export NHC_CACHE_DIR=$work/cache
report_flags=(--tolerances 1e-3:1e-5 --repeats 1 --jacobian dense --projection off --quiet)
run -- simulate "$scene"  # warm the cache: only the outputs meet the full disk
expect "warming the cache" 0 ""

target=$work/out
if is_root && mkdir -p "$target" && mount -t tmpfs -o size=200k tmpfs "$target" 2>/dev/null; then
  trap 'umount "$target"' EXIT
  on_tmpfs=1
  dd if=/dev/zero of="$target/filler" bs=1k count=196 2>/dev/null
  reason="No space left on device"
  limited() { "$nhc" "$@"; }
else
  on_tmpfs=0
  reason="File too large"
  limited() { (trap '' XFSZ; ulimit -f 2; exec "$nhc" "$@"); }
fi
run_limited() {
  limited "$@" >"$work/stdout" 2>"$work/stderr"; rc=$?; err=$(cat "$work/stderr")
}

run_limited report "$scene" "${report_flags[@]}" -o "$target/report"
expect "report on a full disk" 4 "$reason"
grep -qF "$target/report" <<<"$err" || fail "report on a full disk: the message does not name the directory: $err"
[ ! -e "$target/report" ] || fail "report on a full disk: a half-written directory was left: $(ls "$target/report")"
no_leftovers "report on a full disk" "$target"

# An existing report directory stays as it was.
mkdir -p "$target/old" && echo "previous" >"$target/old/report.md"
run_limited report "$scene" "${report_flags[@]}" -o "$target/old"
expect "report over an existing DIR on a full disk" 4 "$reason"
[ "$(ls "$target/old")" = report.md ] && [ "$(cat "$target/old/report.md")" = previous ] ||
  fail "report on a full disk: the existing directory was changed: $(ls "$target/old")"
no_leftovers "report over an existing DIR" "$target"

run_limited simulate "$scene" --outputs 20000 -o "$target/out.csv"
expect "simulate on a full disk" 4 "cannot write $target/out.csv: $reason"
[ ! -e "$target/out.csv" ] || fail "simulate on a full disk: a partial CSV was left"
no_leftovers "simulate on a full disk" "$target"

run_limited derive "$scene" -o "$target/derivation.txt"
[ "$rc" -eq 0 ] || [ "$rc" -eq 4 ] || fail "derive on a full disk: exit code $rc"
[ "$rc" -eq 0 ] || [ ! -e "$target/derivation.txt" ] || fail "derive on a full disk: a partial file was left"

# An ensemble resumed on a full disk: exit 4 with the system's reason, the
# file it resumes unchanged, no crash at exit (HDF5 crashed closing a file whose flush had failed).
ensemble_flags=(--vary "q1'(0)=1:2:4")
[ "$on_tmpfs" -eq 0 ] || rm -f "$target/filler"
run -- ensemble "$scene" "${ensemble_flags[@]}" -o "$target/ensemble.h5"
expect "an ensemble with room" 0 ""
if [ "$on_tmpfs" -eq 1 ]; then  # leave 4 KiB, less than the file's HDF5 structure alone
  free=$(df -k --output=avail "$target" | tail -1)
  dd if=/dev/zero of="$target/filler" bs=1k count=$((free > 4 ? free - 4 : 0)) 2>/dev/null
fi
before=$(md5sum <"$target/ensemble.h5")
run_limited ensemble "$scene" "${ensemble_flags[@]}" -o "$target/ensemble.h5" --resume
expect "ensemble --resume on a full disk" 4 "cannot write $target/ensemble.h5: $reason"
[ "$(md5sum <"$target/ensemble.h5")" = "$before" ] || fail "ensemble --resume on a full disk changed the file"
no_leftovers "ensemble --resume on a full disk" "$target"

# With room, the report directory appears whole.
rm -f "$target/filler"
run -- report "$scene" "${report_flags[@]}" -o "$target/report"
expect "report with room" 0 ""
[ -f "$target/report/report.md" ] && [ -f "$target/report/workprec.csv" ] || fail "report with room: incomplete"
no_leftovers "report with room" "$target"
finish "disk-full test"
