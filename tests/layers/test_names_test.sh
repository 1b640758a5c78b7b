#!/usr/bin/env bash
# Every Catch test name is one ctest can run: catch_discover_tests splits a name at ';' (each half
# then matches no test and "passes": the test silently never runs), and Catch reads a name starting
# with '-' as an option.
#   bash tests/layers/test_names_test.sh REPO
set -euo pipefail
repo=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
cd "$repo"
# The names: the first string literal after TEST_CASE( (on its line or the next).
bad=$(grep -rhoz --include='*_test.cpp' -E 'TEST_CASE\(\s*"[^"]*"' tests | tr '\0' '\n' |
  sed -E 's/^TEST_CASE\(\s*"//; s/"$//' | grep -E ';|^-' || true)
if [ -n "$bad" ]; then
  echo "test names ctest cannot run (a ';' or a leading '-'; use ' - ' or words):"
  echo "$bad" | sed 's/^/  /'
  exit 1
fi
echo "test names: $(grep -rhoz --include='*_test.cpp' -E 'TEST_CASE\(\s*"' tests | tr '\0' '\n' | grep -c TEST_CASE) runnable by ctest"
