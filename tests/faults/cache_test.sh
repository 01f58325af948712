#!/usr/bin/env bash
# The compile cache cannot be poisoned and never stays broken:
# a foreign or world-writable cache directory, a poisoned, foreign-owned, truncated, garbage or
# wrong-model entry. A poisoned library must never be loaded (its constructor leaves a marker);
# a damaged entry is a cache miss, rebuilt with a one-line warning.
# Usage: cache_test.sh NHC SCENE OTHER_SCENE WORK_DIR
nhc=$1 scene=$2 other=$3 work=$4
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"

# The entry names, learnt from a clean cache.
clean=$work/clean
run NHC_CACHE_DIR="$clean" -- simulate "$scene"
expect "clean run" 0 ""
[ "$(stat -c %a "$clean")" = 700 ] || fail "a new cache directory has mode $(stat -c %a "$clean"), expected 700"
entry=$(basename "$(ls "$clean"/*.so)")
[ -f "$clean/$entry.sha256" ] || fail "no digest sidecar beside $entry"
(cd "$clean" && sha256sum -c --quiet "$entry.sha256") || fail "the sidecar does not hold the entry's SHA-256"
run NHC_CACHE_DIR="$clean" -- simulate "$other"
other_entry=$(basename "$(ls "$clean"/*.so | grep -v "/$entry\$")")

# A shared object whose constructor leaves a marker: whoever loads it runs it.
marker=$work/poison-ran
printf '#include <fcntl.h>\n#include <unistd.h>\n__attribute__((constructor)) static void poison() { close(open("%s", O_CREAT | O_WRONLY, 0644)); }\nextern "C" const void* nhc_model_table_get() { return 0; }\n' \
  "$marker" >"$work/poison.cpp"
c++ -shared -fPIC -o "$work/poison.so" "$work/poison.cpp" || fail "cannot build the poison"

# Finding 1: HOME and XDG_CACHE_HOME unset, $TMPDIR/nhc-cache-<uid> created first by someone
# else, world-writable, holding a poisoned entry with a matching digest.
tmp=$work/tmp; mkdir -p "$tmp"; chmod 1777 "$tmp"
trap_dir=$tmp/nhc-cache-$(id -u)
mkdir "$trap_dir"
cp "$work/poison.so" "$trap_dir/$entry"
(cd "$trap_dir" && sha256sum "$entry" >"$entry.sha256")
chmod 777 "$trap_dir"
is_root && chown -R nobody "$trap_dir"
run -u HOME -u XDG_CACHE_HOME -u NHC_CACHE_DIR TMPDIR="$tmp" -- simulate "$scene"
expect "foreign temporary cache" 0 "is not private"
[ ! -e "$marker" ] || fail "the poisoned library in $trap_dir was loaded"
fresh=$(ls -d "$trap_dir"-* 2>/dev/null | head -n 1)
[ -n "$fresh" ] && [ "$(stat -c %a "$fresh")" = 700 ] || fail "no fresh private cache beside $trap_dir"
[ "$(ls "$trap_dir" | wc -l)" -eq 2 ] || fail "nhc wrote into the foreign directory $trap_dir"

# A configured cache directory writable by others, or owned by someone else: refused, exit 4.
ww=$work/world; cp -r "$clean" "$ww"; chmod 777 "$ww"
run NHC_CACHE_DIR="$ww" -- simulate "$scene"
expect "world-writable cache" 4 "the compile cache $ww is unusable: it is writable by others (mode 0777)"
chmod 770 "$ww"
run NHC_CACHE_DIR="$ww" -- simulate "$scene"
expect "group-writable cache" 4 "it is writable by its group (mode 0770)"
if is_root; then
  foreign=$work/foreign; cp -r "$clean" "$foreign"; chown nobody "$foreign"
  run NHC_CACHE_DIR="$foreign" -- simulate "$scene"
  expect "foreign-owned cache" 4 "it is owned by user id $(id -u nobody), not by you"
  # A foreign-owned entry in one's own cache: rebuilt.
  own=$work/own_foreign_entry; cp -r "$clean" "$own"; chown nobody "$own/$entry"
  run NHC_CACHE_DIR="$own" -- simulate "$scene"
  expect "foreign-owned entry" 0 "rejected: owned by user id $(id -u nobody), not by you; rebuilding it"
  [ "$(stat -c %u "$own/$entry")" -eq 0 ] || fail "the foreign-owned entry was not replaced"
else
  echo "note: not root; the foreign-owner cases are skipped"
fi

# Poisoned entry in the user's own cache without a matching digest: never opened.
poisoned=$work/poisoned; cp -r "$clean" "$poisoned"; cp "$work/poison.so" "$poisoned/$entry"
run NHC_CACHE_DIR="$poisoned" -- simulate "$scene"
expect "poisoned entry" 0 "its bytes do not match its SHA-256 digest (damaged or replaced); rebuilding it"
[ ! -e "$marker" ] || fail "the poisoned entry was loaded"

# Finding 2: a truncated or garbage entry is a miss, rebuilt; the next run uses the new entry.
for damage in truncated garbage missing_digest; do
  d=$work/$damage; cp -r "$clean" "$d"
  case $damage in
    truncated) head -c 2000 "$clean/$entry" >"$d/$entry" ;;
    garbage) head -c 14000 /dev/urandom >"$d/$entry" ;;
    missing_digest) rm "$d/$entry.sha256" ;;
  esac
  run NHC_CACHE_DIR="$d" -- simulate "$scene"
  expect "$damage entry" 0 "cache entry $d/$entry rejected"
  [ "$(grep -c warning <<<"$err")" -eq 1 ] || fail "$damage entry: expected one warning line: $err"
  cmp -s "$d/$entry" "$clean/$entry" || fail "$damage entry: not rebuilt to the same bytes"
  run NHC_CACHE_DIR="$d" -- simulate "$scene"
  expect "$damage entry, next run" 0 ""
  grep -q "(cached)" <<<"$out" || fail "$damage entry: the rebuilt entry is not reused"
  [ -z "$err" ] || fail "$damage entry: the next run still warns: $err"
  no_leftovers "$damage entry" "$d"
done

# Wrong model: another scene's library and its (valid) digest under this entry's name. It
# passes the digest; its nhc_model_build_key gives it away after loading.
wm=$work/wrong_model; cp -r "$clean" "$wm"
cp "$clean/$other_entry" "$wm/$entry"; cp "$clean/$other_entry.sha256" "$wm/$entry.sha256"
run NHC_CACHE_DIR="$wm" -- simulate "$scene"
expect "wrong-model entry" 0 "rejected: built for something else (its nhc_model_build_key differs); rebuilding it"
grep -q "nhc simulate: $(basename "$scene" .toml), " <<<"$out" || fail "wrong-model entry: wrong run: $out"
cmp -s "$wm/$entry" "$clean/$entry" || fail "wrong-model entry: not rebuilt"

finish "cache fault test"
