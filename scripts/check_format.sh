#!/usr/bin/env bash
# The C++ lines changed since BASE follow .clang-format (clang-format 14, Debian clang-format).
# Only changed lines are checked (git clang-format --diff): the tree as a whole has not been
# reformatted, so that a check of new code does not ask anyone to reformat what they did not touch.
#
# usage: scripts/check_format.sh [BASE]
#   BASE: a commit (default: $NHC_FORMAT_BASE, else the merge base with main, else HEAD, which
#   checks what is not yet committed). Exit 0: the changed lines follow the style; 1: they do not
#   (the diff that would fix them is printed); 4: clang-format is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v git-clang-format > /dev/null || ! command -v clang-format > /dev/null; then
  echo "check_format: git-clang-format and clang-format are needed (Debian package clang-format)" >&2
  exit 4
fi
base=${1:-${NHC_FORMAT_BASE:-}}
if [ -z "$base" ]; then
  base=$(git merge-base HEAD main 2> /dev/null || git rev-parse HEAD)
fi
git rev-parse --verify --quiet "$base^{commit}" > /dev/null ||
  { echo "check_format: '$base' is not a commit" >&2; exit 2; }
# The generated headers (generated/) and vendored text are not ours to format.
mapfile -t files < <(git diff --name-only --diff-filter=ACMR "$base" -- '*.cpp' '*.hpp' '*.h' '*.cpp.in' |
                     grep -v '^generated/' || true)
if [ "${#files[@]}" -eq 0 ]; then
  echo "check_format: no C++ file changed since $(git rev-parse --short "$base")"
  exit 0
fi
# git clang-format compares the working tree with BASE and formats only the lines that differ.
out=$(git clang-format --binary clang-format --style file --diff "$base" -- "${files[@]}" 2>&1) || true
case "$out" in
  "" | "no modified files to format" | "clang-format did not modify any files")
    echo "check_format: ${#files[@]} changed file(s) since $(git rev-parse --short "$base") follow .clang-format"
    exit 0 ;;
esac
echo "$out"
echo "check_format: the changed lines above do not follow .clang-format; apply with" >&2
echo "  git clang-format --style file $(git rev-parse --short "$base")" >&2
exit 1
