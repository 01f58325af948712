#!/usr/bin/env bash
# Every C++ file of the tree follows .clang-format (clang-format 14, Debian clang-format); the tree
# was formatted as a whole in one commit, so the check covers all of it, not only changed lines.
# The generated headers (generated/, written by nhc itself and compared byte for byte by the tests)
# and CMake-configured templates (*.in) are left out.
#
# usage: scripts/check_format.sh [--fix]
#   Exit 0: every file follows the style; 1: some do not (their names and the first differences are
#   printed; --fix rewrites them in place); 4: clang-format is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v clang-format > /dev/null; then
  echo "check_format: clang-format is needed (Debian package clang-format)" >&2
  exit 4
fi
mapfile -t files < <(git ls-files -- '*.cpp' '*.hpp' '*.h' | grep -v '^generated/')
if [ "${1:-}" = --fix ]; then
  clang-format -i --style=file "${files[@]}"
  exit 0
fi
# One clang-format process for the whole tree; each file that would change is named in a warning.
if out=$(clang-format --style=file --dry-run --Werror "${files[@]}" 2>&1); then
  echo "check_format: ${#files[@]} C++ files follow .clang-format"
  exit 0
fi
mapfile -t bad < <(printf '%s\n' "$out" | sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: error: code should be clang-formatted.*/\1/p' | sort -u)
for f in "${bad[@]}"; do
  diff -u "$f" <(clang-format --style=file "$f") | head -20 || true
done
echo "check_format: ${#bad[@]} file(s) do not follow .clang-format: ${bad[*]}" >&2
echo "  apply with: scripts/check_format.sh --fix" >&2
exit 1
