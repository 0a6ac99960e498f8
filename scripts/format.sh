#!/usr/bin/env bash
# Formats the C++ sources with the project's .clang-format (Debian's clang-format 14).
#
#   scripts/format.sh            reformat every tracked .cc/.h/.cpp file in place
#   scripts/format.sh --check    change nothing; list the files that are not formatted and fail
#
# Generated code and third-party files are not tracked, so `git ls-files` is the list.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
command -v clang-format >/dev/null || { echo "format: clang-format is not installed" >&2; exit 2; }

mapfile -t files < <(git ls-files '*.cc' '*.h' '*.cpp')
if [ "${1:-}" = "--check" ]; then
  bad=()
  for f in "${files[@]}"; do
    clang-format --dry-run -Werror "$f" >/dev/null 2>&1 || bad+=("$f")
  done
  if [ ${#bad[@]} -gt 0 ]; then
    printf 'format: not formatted (run scripts/format.sh): %s\n' "${bad[@]}" >&2
    exit 1
  fi
  echo "format: all ${#files[@]} files formatted"
else
  clang-format -i "${files[@]}"
  echo "format: formatted ${#files[@]} files"
fi
