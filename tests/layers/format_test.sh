#!/usr/bin/env bash
# Every C++ file of src/, include/ and tests/ as clang-format (.clang-format) would write it: the
# check CI runs, so formatting never drifts again. Fix with:
#   clang-format -i $(git ls-files 'src/*' 'include/*' 'tests/*' | grep -E '\.(h|cpp)$')
#   bash tests/layers/format_test.sh REPO
set -euo pipefail
repo=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
cd "$repo"
tool=$(command -v clang-format-14 || command -v clang-format || true)
if [ -z "$tool" ]; then
  echo "skipped: clang-format is not installed"
  exit 0
fi
files=$(find src include tests -name '*.h' -o -name '*.cpp' | sort)
if ! "$tool" --dry-run -Werror $files; then
  echo "files above differ from clang-format's layout (.clang-format); fix with clang-format -i FILE"
  exit 1
fi
echo "format: $(echo "$files" | wc -l) files as clang-format writes them"
