#!/usr/bin/env bash
# The C++ compiler missing, failing or hanging, and the disk filling while it compiles: exit 4 with the path and the system's reason, the compiler's output trimmed to its
# first errors (no "#pragma once in main file"), no compiler left running, nothing half-written
# in the cache.
# Usage: compiler_test.sh NHC SCENE WORK_DIR
nhc=$1 scene=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"
cache=$work/cache

no_entry() {
  [ -z "$(find "$cache" -name '*.so*' 2>/dev/null)" ] || fail "$1: a cache entry was left: $(ls "$cache")"
  no_leftovers "$1" "$cache"
}

run NHC_CACHE_DIR="$cache" NHC_CXX="$work/no-such-compiler" -- simulate "$scene"
expect "missing compiler" 4 "the C++ compiler $work/no-such-compiler cannot be run: No such file or directory (set NHC_CXX"
no_entry "missing compiler"

# A compiler that answers --version and fails on the code with 200 lines of errors.
cat >"$work/failing-c++" <<'SH'
#!/bin/sh
case "$*" in *--version*) echo "failing-c++ 1.0"; exit 0 ;; esac
echo "In file included from model.cpp:1:"
for i in $(seq 1 200); do echo "model.hpp:$i:1: error: error number $i"; done
exit 1
SH
chmod +x "$work/failing-c++"
run NHC_CACHE_DIR="$cache" NHC_CXX="$work/failing-c++" -- simulate "$scene"
expect "failing compiler" 4 "the C++ compiler failed on the code of"
grep -qF "model.hpp:1:1: error: error number 1" <<<"$err" || fail "failing compiler: the first error is not shown"
grep -qF "error number 50" <<<"$err" && fail "failing compiler: the output is not trimmed"
grep -qF "more lines]" <<<"$err" || fail "failing compiler: no note of the trimmed lines"
no_entry "failing compiler"

# A compiler that hangs (and whose children hang): stopped after NHC_COMPILE_TIMEOUT.
cat >"$work/hanging-c++" <<'SH'
#!/bin/sh
case "$*" in *--version*) echo "hanging-c++ 1.0"; exit 0 ;; esac
sleep 300 &
sleep 300
SH
chmod +x "$work/hanging-c++"
start=$(date +%s)
run NHC_CACHE_DIR="$cache" NHC_CXX="$work/hanging-c++" NHC_COMPILE_TIMEOUT=1 -- simulate "$scene"
expect "hanging compiler" 4 "the C++ compiler took longer than 1 s on the code of"
[ $(($(date +%s) - start)) -lt 20 ] || fail "hanging compiler: not stopped in time"
sleep 0.2
pgrep -f "$work/hanging-c++" >/dev/null && fail "hanging compiler: still running"
no_entry "hanging compiler"
run NHC_CACHE_DIR="$cache" NHC_COMPILE_TIMEOUT=soon -- simulate "$scene"
expect "bad NHC_COMPILE_TIMEOUT" 2 "NHC_COMPILE_TIMEOUT: error: 'soon' is not a number of seconds"

# The real compiler, the disk full: a 200 KiB tmpfs nearly filled (as root), else a file-size
# limit of a few KiB (the compiler's own temporary files then hit it too).
if is_root && mkdir -p "$work/small" && mount -t tmpfs -o size=200k tmpfs "$work/small" 2>/dev/null; then
  trap 'umount "$work/small"' EXIT
  dd if=/dev/zero of="$work/small/filler" bs=1k count=185 2>/dev/null
  cache=$work/small/cache
  run NHC_CACHE_DIR="$cache" -- simulate "$scene"
  expect "disk full while compiling" 4 "No space left on device"
  no_entry "disk full while compiling"
  rm -f "$work/small/filler"
else
  cache=$work/limited
  (trap '' XFSZ; ulimit -f 8; exec env NHC_CACHE_DIR="$cache" "$nhc" simulate "$scene") >"$work/stdout" 2>"$work/stderr"
  rc=$?; err=$(cat "$work/stderr")
  expect "file-size limit while compiling" 4 "File too large"
  no_entry "file-size limit while compiling"
fi
grep -qF "pragma once" <<<"$err" && fail "the compiler warned about #pragma once"

# The real compiler works, quietly: no compiler output on success.
cache=$work/cache
run NHC_CACHE_DIR="$cache" -- simulate "$scene"
expect "working compiler" 0 ""
[ -z "$err" ] || fail "working compiler: unexpected output on stderr: $err"
finish "compiler test"
