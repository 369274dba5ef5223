#!/usr/bin/env bash
# Fails (listing the files) when a C++ source or header differs from the committed .clang-format.
# Run by ctest (SourceFormat); fix with: bash tools/check_format.sh --fix
set -euo pipefail
cd "$(dirname "$0")/.."
fix=0
case "${1:-}" in
  --fix) fix=1 ;;
  -h|--help) echo "usage: tools/check_format.sh [--fix]   (checks every .h/.cpp against .clang-format)"; exit 0 ;;
  "") ;;
  *) echo "check_format: unknown argument '$1' (see --help)" >&2; exit 1 ;;
esac
command -v clang-format >/dev/null || { echo "check_format: clang-format not found (tools/setup.sh installs it)" >&2; exit 1; }
mapfile -t files < <(find . -path ./build -prune -o -path './build-*' -prune -o -path ./out -prune -o -path ./.git -prune \
                        -o -type f \( -name '*.h' -o -name '*.cpp' \) -print | sort)
if [ "$fix" = 1 ]; then clang-format -i "${files[@]}"; exit 0; fi
bad=()
for f in "${files[@]}"; do clang-format --dry-run -Werror "$f" >/dev/null 2>&1 || bad+=("$f"); done
if [ "${#bad[@]}" -gt 0 ]; then
  printf 'check_format: %s differs from .clang-format\n' "${bad[@]}" >&2
  echo "check_format: ${#bad[@]} of ${#files[@]} files; fix with: bash tools/check_format.sh --fix" >&2
  exit 1
fi
echo "check_format: ${#files[@]} files match .clang-format ($(clang-format --version | head -1))"
