#!/usr/bin/env bash
# kill -9 of nhc while it compiles: the compiler dies with it (the watchdog of
# tools/subprocess.cpp kills its process group), and the temporaries the killed nhc left in the
# cache are swept by the next run once their process is gone (io/temporary_files.hpp).
# Usage: kill9_compile_test.sh NHC SCENE WORK_DIR
nhc=$1 scene=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"
export NHC_CACHE_DIR=$work/cache

# "The compiler": records its pid, then takes its time.
cat > "$work/slow_cxx" <<EOS
#!/bin/sh
echo \$\$ > "$work/compiler.pid"
sleep 60
exec c++ "\$@"
EOS
chmod +x "$work/slow_cxx"
NHC_CXX="$work/slow_cxx" "$nhc" simulate "$scene" -o "$work/out.csv" > "$work/log" 2>&1 &
nhc_pid=$!
for _ in $(seq 1 600); do [ -s "$work/compiler.pid" ] && break; sleep 0.05; done
[ -s "$work/compiler.pid" ] || { fail "the compiler never started: $(cat "$work/log")"; finish "kill -9 test"; }
compiler=$(cat "$work/compiler.pid")
kill -9 "$nhc_pid"
wait "$nhc_pid" 2>/dev/null
gone=no
for _ in $(seq 1 100); do
  if ! kill -0 "$compiler" 2>/dev/null; then gone=yes; break; fi
  sleep 0.05
done
[ $gone = yes ] || { fail "the compiler (pid $compiler) still runs after kill -9 of nhc"; kill -9 "$compiler"; }
pkill -9 -f "$work/slow_cxx" 2>/dev/null

# A temporary of a process that is gone, old enough to be stale, and one of a live process.
stale="$NHC_CACHE_DIR/entry.so.tmp${nhc_pid}_0_1"
live="$NHC_CACHE_DIR/entry.so.tmp$$_0_1"
mkdir -p "$NHC_CACHE_DIR"
touch -d '2 hours ago' "$stale" "$live"
run -- simulate "$scene" -o "$work/out.csv"
expect "the run after kill -9" 0 ""
[ ! -e "$stale" ] || fail "the stale temporary $stale of the killed nhc is still there"
[ -e "$live" ] || fail "the temporary of a live process was removed"
rm -f "$live"
finish "kill -9 test"
