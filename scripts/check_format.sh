#!/usr/bin/env bash
# Checks that every C++ source of the tree is formatted by the house .clang-format (what CI runs).
# Usage: scripts/check_format.sh [--fix]
set -euo pipefail
cd "$(dirname "$0")/.."
format="${CLANG_FORMAT:-clang-format}"
command -v "$format" >/dev/null || { echo "check_format: $format not found (Debian: apt-get install clang-format)" >&2; exit 2; }
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h' '*.c' | grep -v '^fuzz/corpus/')
if [ "${1:-}" = "--fix" ]; then
  "$format" -i "${files[@]}"
  exit 0
fi
if ! "$format" --dry-run --Werror "${files[@]}" 2>/tmp/brdfbake-format.$$; then
  grep -E '^[^ ].*: (error|warning):' /tmp/brdfbake-format.$$ | cut -d: -f1 | sort -u | sed 's/^/not formatted: /' >&2
  rm -f /tmp/brdfbake-format.$$
  echo "check_format: run scripts/check_format.sh --fix (clang-format $("$format" --version | grep -o '[0-9][0-9.]*' | head -1))" >&2
  exit 1
fi
rm -f /tmp/brdfbake-format.$$
echo "check_format: ${#files[@]} files formatted"
