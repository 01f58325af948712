#!/usr/bin/env bash
# The interpreted model's program in the scene cache (jit/nhc/jit/build.hpp, docs/interpreter.md)
# across processes: a second interpreted run takes it from there ("(scene cache)"), writes the
# same CSV as the first and as the compiled model; the entry is private; an entry damaged
# (truncated, one byte changed), foreign (another scene's program under this key, with a valid
# digest), not a program (valid digest), or writable by others is rejected with one warning,
# rebuilt, and used again.
# Usage: program_cache_test.sh NHC SCENE WORK_DIR
nhc=$1 scene_in=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "$0")/common.sh"
export NHC_CACHE_DIR=$work/cache
unset NHC_BACKEND
scene=$work/scene.toml
cp "$scene_in" "$scene"
interpreted() { run -- simulate "$scene" --backend interpreted -o "$work/last.csv"; }

interpreted
expect "cold interpreted run" 0 ""
cp "$work/last.csv" "$work/cold.csv"
! grep -q "(scene cache)" <<<"$out" || fail "the cold run says it used the scene cache: $out"
program=$(grep -l "nhc interpreted program" "$NHC_CACHE_DIR"/scenes/*.entry)
[ "$(wc -w <<<"$program")" -eq 1 ] || fail "expected one interpreted program entry, found: $program"
[ "$(stat -c %a "$program")" = 600 ] || fail "$program has mode $(stat -c %a "$program"), expected 600"
cp "$program" "$work/good.entry"

interpreted
expect "warm interpreted run" 0 ""
grep -q "derive .* s (scene cache), interpreted" <<<"$out" || fail "the warm run derived again: $out"
! grep -q warning <<<"$err" || fail "the warm run warned: $err"
cmp -s "$work/last.csv" "$work/cold.csv" || fail "the warm run wrote another CSV"
run -- simulate "$scene" --backend auto -o "$work/auto.csv"
expect "warm auto run" 0 ""
grep -q "(scene cache)" <<<"$out" || fail "the warm auto run derived again: $out"
cmp -s "$work/auto.csv" "$work/cold.csv" || fail "the warm auto run wrote another CSV"
run -- simulate "$scene" --backend compiled -o "$work/compiled.csv"
expect "compiled run" 0 ""
cmp -s "$work/compiled.csv" "$work/cold.csv" || fail "the compiled model wrote another CSV than the interpreted one"

# rewrite_payload PYTHON_EXPRESSION: the program entry with its payload changed and its length
# and digest made to match (a foreign writer that knows the format).
rewrite_payload() {
  python3 - "$program" "$1" "${2:-}" <<'PY'
import hashlib, sys
path, how, other = sys.argv[1:4]
data = open(path, 'rb').read()
lines = data.split(b'\n', 4)
payload = lines[4]
if how == 'cut':
    at = payload.index(b'program ')
    end = payload.index(b'\n', at)
    size = int(payload[at + 8:end])
    body = payload[end + 1:end + 1 + size]
    body = body[:size // 2]
    payload = payload[:at] + b'program ' + str(len(body)).encode() + b'\n' + body + payload[end + 1 + size:]
else:  # another entry's payload under this entry's key
    payload = open(other, 'rb').read().split(b'\n', 4)[4]
lines[2] = b'sha256 ' + hashlib.sha256(payload).hexdigest().encode()
lines[3] = b'bytes ' + str(len(payload)).encode()
open(path, 'wb').write(b'\n'.join(lines[:4]) + b'\n' + payload)
PY
}

# Another scene's program (its name changed), made in a cache of its own.
other=$work/other.toml
sed 's/^name = .*/name = "another_scene"/' "$scene_in" >"$other"
grep -q '^name = "another_scene"' "$other" || fail "the test could not rename the scene"
NHC_CACHE_DIR=$work/other-cache "$nhc" simulate "$other" --backend interpreted -o "$work/other.csv" >/dev/null ||
  fail "the other scene's run failed"
other_program=$(grep -l "nhc interpreted program" "$work"/other-cache/scenes/*.entry)

for damage in truncated byte foreign cut writable; do
  cp "$work/good.entry" "$program"
  chmod 600 "$program"
  case $damage in
    truncated) head -c 200 "$work/good.entry" >"$program"; expected="truncated or damaged" ;;
    byte) python3 -c "import sys; p=sys.argv[1]; d=bytearray(open(p,'rb').read()); d[-30]^=1; open(p,'wb').write(d)" "$program"
          expected="does not match its SHA-256 digest" ;;
    foreign) rewrite_payload other "$other_program"; expected="not one nhc can run" ;;
    cut) rewrite_payload cut; expected="not one nhc can run" ;;
    writable) chmod 620 "$program"; expected="writable by others" ;;
  esac
  interpreted
  expect "$damage program" 0 "rejected: "
  [ "$(grep -c "scene cache entry .* rejected: .*; rebuilding it" <<<"$err")" -eq 1 ] ||
    fail "$damage program: expected one warning: $err"
  grep -qF "$expected" <<<"$err" || fail "$damage program: the warning lacks '$expected': $err"
  ! grep -q "(scene cache)" <<<"$out" || fail "$damage program: it was used: $out"
  cmp -s "$work/last.csv" "$work/cold.csv" || fail "$damage program: another CSV"
  [ -f "$program" ] || fail "$damage program: not rebuilt"
  interpreted
  expect "$damage program, rebuilt" 0 ""
  grep -q "(scene cache)" <<<"$out" || fail "$damage program: the rebuilt entry was not used: $out"
  ! grep -q warning <<<"$err" || fail "$damage program, rebuilt: warned: $err"
done
no_leftovers "program cache" "$NHC_CACHE_DIR" "$work"
finish "program cache test"
