#!/usr/bin/env bash
# install:package — nhc as an installed package, from scratch:
#   1. cmake --install the build tree into WORK/prefix; nhc --version and the package version
#      are the project version;
#   2. configure examples/app against that prefix only (no package registry), build it
#      (nhc_add_model runs the installed nhc), run `app`, `describe` and `jit_app` (two scenes of
#      one name built in code, JIT-compiled by the installed nhc::jit into a cache of its own), and
#      check their numbers against the closed forms computed here: Appell–Hamel stops at
#      t* = v0 (a^2+b^2)/(g a b);
#   3. edit the scene (b = 0.5 -> 0.25), rebuild: only that header is regenerated, and the app
#      then stops at the new t*.
# usage: install_test.sh SOURCE_DIR BUILD_DIR WORK_DIR CMAKE CXX VERSION
set -euo pipefail
src=$1 build=$2 work=$3 cmake=$4 cxx=$5 version=$6
fail() { echo "install:package FAIL: $*" >&2; exit 1; }
now() { date +%s.%N; }
lap() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }
# check NAME VALUE EXPECTED TOLERANCE: |VALUE - EXPECTED| <= TOLERANCE
check() {
  awk -v v="$2" -v e="$3" -v tol="$4" 'BEGIN { d = v - e; if (d < 0) d = -d; exit !(v != "" && d <= tol) }' ||
    fail "$1 = '$2', expected $3 within $4"
  echo "check $1 = $2 (expected $3 within $4)"
}
# value KEY FILE: the word after "KEY = " on the first line containing it
value() { sed -n "s/.*$1 = \([^ ,]*\).*/\1/p" "$2" | head -n 1; }

start=$(now)
rm -rf "$work"
mkdir -p "$work"
cd "$work"

# 1. Install.
"$cmake" --install "$build" --prefix "$work/prefix" > install.log
for f in bin/nhc libexec/nhc/nhc-main libexec/nhc/nhc-ensemble libexec/nhc/nhc-optimize include/nhc/codegen.hpp include/nhc/scene/scene_builder.hpp \
         include/nhc/runtime/runtime.hpp include/nhc/runtime/model_table.h \
         include/nhc/jit.hpp include/nhc/jit/build.hpp \
         include/nhc/linearize/linearizer.hpp include/nhc/connect/shooting.hpp \
         lib/cmake/nhc/nhcConfig.cmake lib/cmake/nhc/nhcConfigVersion.cmake \
         lib/cmake/nhc/nhcTargets.cmake lib/cmake/nhc/nhcFunctions.cmake; do
  [ -e "prefix/$f" ] || fail "prefix/$f was not installed"
done
[ "$(prefix/bin/nhc --version)" = "nhc $version" ] || fail "nhc --version says '$(prefix/bin/nhc --version)', not 'nhc $version'"
echo "installed $(find prefix -type f | wc -l) files in $(lap "$start") s; $(prefix/bin/nhc --version)"

# 1b. The public API is what is installed: exactly the headers docs/library.md lists (without the
#     ensemble's when nhc was built without HDF5), and all of them compile, in one translation
#     unit, against the installed package alone.
sed -n '/<!-- installed headers: begin -->/,/<!-- installed headers: end -->/p' "$src/docs/library.md" |
  grep '^nhc/' | sort > documented_headers.txt
[ -s documented_headers.txt ] || fail "docs/library.md lists no installed headers"
if [ ! -e prefix/include/nhc/ensemble.hpp ]; then
  grep -v '^nhc/ensemble' documented_headers.txt > documented.tmp && mv documented.tmp documented_headers.txt
fi
(cd prefix/include && find nhc -type f | sort) > installed_headers.txt
if ! diff -u documented_headers.txt installed_headers.txt > headers.diff; then
  cat headers.diff
  fail "the installed headers (+) are not the documented public headers (-) of docs/library.md"
fi
mkdir -p headers
sed 's/.*/#include "&"/' installed_headers.txt > headers/all_headers.cpp
ensemble_target=""
[ -e prefix/include/nhc/ensemble.hpp ] && ensemble_target=nhc::ensemble
cat > headers/CMakeLists.txt <<EOF
cmake_minimum_required(VERSION 3.20)
project(nhc_public_headers LANGUAGES CXX)
find_package(nhc REQUIRED)
add_library(all_headers OBJECT all_headers.cpp)
target_link_libraries(all_headers PRIVATE nhc::codegen nhc::runtime nhc::jit nhc::app nhc::linearize nhc::connect $ensemble_target)
EOF
"$cmake" -S headers -B headers/build -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF > headers.log 2>&1 &&
  "$cmake" --build headers/build >> headers.log 2>&1 ||
  { cat headers.log; fail "the installed headers do not compile against the installed package alone"; }
echo "the $(wc -l < installed_headers.txt) installed headers are the documented ones and compile alone"

# 2. Configure and build examples/app against the prefix alone; the scenes are copies, to edit.
cp "$src/examples/appell_hamel.toml" "$src/examples/particle.toml" .
t=$(now)
"$cmake" -S "$src/examples/app" -B app -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF \
  -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
  -DNHC_APP_APPELL_HAMEL="$work/appell_hamel.toml" -DNHC_APP_PARTICLE="$work/particle.toml" > configure.log ||
  { cat configure.log; fail "configuring examples/app"; }
grep -q "nhc $version from $work/prefix/lib/cmake/nhc" configure.log ||
  { cat configure.log; fail "find_package(nhc) did not take the installed package"; }
echo "configured in $(lap "$t") s"
t=$(now)
"$cmake" --build app -j2 > build.log 2>&1 || { cat build.log; fail "building examples/app"; }
echo "built in $(lap "$t") s"
# Only the installed headers: nothing of the source tree on a compile line.
if grep -E -q -- "-I *$src/(codegen|runtime)|-isystem *$src/(codegen|runtime)" app/compile_commands.json; then
  fail "examples/app compiled against the source tree"
fi
grep -q -- "-isystem $work/prefix/include" app/compile_commands.json || fail "examples/app did not use the installed headers"
# OUT_VAR: the path nhc named at configure time is the header the build wrote.
particle_header=$(sed -n 's/^-- particle header: //p' configure.log)
[ "$particle_header" = "$work/app/nhc_models/app/particle_chetaev.hpp" ] && [ -f "$particle_header" ] ||
  fail "OUT_VAR gave '$particle_header', not the generated particle_chetaev.hpp"
grep -q "generated by nhc $version from appell_hamel.toml" app/nhc_models/app/appell_hamel_chetaev.hpp ||
  fail "the generated banner does not carry version $version"

app/app > app.out || { cat app.out; fail "app exited with $?"; }
cat app.out
grep -q "^nhc package $version\$" app.out || fail "package version is not $version"
# t* for m = 1, g = 9.81, a = 1, b = 0.5, v0 = |(1, 0.5)|.
t_star=$(awk 'BEGIN { printf "%.12f", sqrt(1.25) * (1 + 0.25) / (9.81 * 0.5) }')
check "appell_hamel t_stop" "$(value t_stop app.out)" "$t_star" 1e-6
check "appell_hamel max_relative_error" "$(value max_relative_error app.out)" 0 1e-6
check "appell_hamel energy_drift" "$(value energy_drift app.out)" 0 1e-6
check "particle max_position_error" "$(value max_position_error app.out)" 0 1e-6
check "particle speed_drift" "$(value speed_drift app.out)" 0 1e-8

(cd app && ./describe > describe.out) || { cat app/describe.out; fail "describe exited with $?"; }
tail -n 2 app/describe.out
grep -q "describe: index 2, .*: OK" app/describe.out || fail "describe"
check "describe lambda1(0)" "$(sed -n "s/.*lambda1(0) = \([^ ]*\).*/\1/p" app/describe.out)" \
  "$(awk 'BEGIN { printf "%.12f", 9.81 / 1.25 }')" 1e-9
[ -s app/appell_hamel_chetaev.tex ] && [ -s app/appell_hamel_chetaev.hpp ] || fail "describe wrote no files"

# jit_app: scene in code -> nhc::jit::build -> integrate, twice, for b = 0.5 and b = 0.25.
NHC_CACHE_DIR="$work/jit-cache" app/jit_app > jit.out || { cat jit.out; fail "jit_app exited with $?"; }
cat jit.out
grep -q "tables distinct" jit.out || fail "jit_app: the two models share a table"
for b in 0.5 0.25; do
  line=$(grep "^jit b = $b:" jit.out) || fail "jit_app printed no line for b = $b"
  # z'(0.9 t*) = k v0 (1 - 0.9) with k = b/a, v0 = |(1, 0.5)|
  check "jit_app z'(0.9 t*) for b = $b" "$(echo "$line" | sed -n "s/.*z'(t_end) = \([^ ]*\).*/\1/p")" \
    "$(awk -v b="$b" 'BEGIN { printf "%.12f", b * sqrt(1.25) * 0.1 }')" 1e-7
  check "jit_app max_relative_error for b = $b" "$(value max_relative_error <(echo "$line"))" 0 1e-6
done
grep -q "^jit OK$" jit.out || fail "jit_app"
for so in "$work"/jit-cache/*.so; do
  if readelf -Ws "$so" | grep -q " UNIQUE "; then fail "$so has an STB_GNU_UNIQUE symbol"; fi
done
[ "$(ls "$work"/jit-cache/*.so | wc -l)" = 2 ] || fail "jit_app should have built two shared objects"

# 3. Edit the scene: the next build regenerates its header (and only it), the app follows.
sed -i 's/^b = 0.5$/b = 0.25/' appell_hamel.toml
grep -q "^b = 0.25$" appell_hamel.toml || fail "could not edit the scene"
touch appell_hamel.toml
t=$(now)
"$cmake" --build app -j2 > rebuild.log 2>&1 || { cat rebuild.log; fail "rebuilding examples/app"; }
echo "rebuilt after the scene edit in $(lap "$t") s"
grep -q "generating the chetaev model of appell_hamel.toml" rebuild.log || { cat rebuild.log; fail "the edited scene was not regenerated"; }
if grep -q "of particle.toml" rebuild.log; then fail "the unchanged scene was regenerated"; fi
app/app > app2.out || { cat app2.out; fail "app exited with $? after the edit"; }
grep "appell_hamel" app2.out
t_star=$(awk 'BEGIN { printf "%.12f", sqrt(1.25) * (1 + 0.0625) / (9.81 * 0.25) }')
check "appell_hamel b" "$(value b app2.out)" 0.25 0
check "appell_hamel t_stop after the edit" "$(value t_stop app2.out)" "$t_star" 1e-6

echo "install:package OK in $(lap "$start") s"
