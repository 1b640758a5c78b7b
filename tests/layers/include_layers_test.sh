#!/usr/bin/env bash
# The layers, checked: every `#include "olt/X/..."` in src/Y/ or include/olt/Y/ must name a folder
# that Y may use (below). The build cannot see this: every library exports all of include/, so an
# include running upward compiles. Known exceptions, to be removed (issue "One engine, typed
# stages": stages include nothing from cache/, job/ or runtime/), are listed in
# include_layers_known.txt; the test fails on a new one, and on a listed one that is gone (so the
# list only shrinks).
#   bash tests/layers/include_layers_test.sh REPO
set -euo pipefail
repo=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
known="$repo/tests/layers/include_layers_known.txt"

# What each folder may include besides itself: what it links, and what those link (CMakeLists.txt),
# without the upper half's mixing that the exceptions list holds.
declare -A may=(
  [core]=""
  [model]="core"
  [config]="core"
  [job]="core config"
  [cache]="core model"
  [formats]="core model config"
  [source]="core model"
  [registration]="core model"
  [laser]="core model"
  [poses]="core model registration laser"
  [reconstruct]="core model"
  [propagate]="core model"
  [eval]="core model"
  [modules]="core model formats reconstruct"
  [stages]="core model config formats source registration laser poses reconstruct propagate eval"
  [runtime]="core model config job cache formats stages"
  [watch]="core model config job cache runtime"
  [cli]="core model config job cache formats eval runtime stages watch"
)

found=$(mktemp)
trap 'rm -f "$found"' EXIT
cd "$repo"
# One grep over every file ("FILE:olt/USED/"), then the table checked per line in the shell.
files=$(find src include/olt \( -name '*.h' -o -name '*.cpp' \) ! -path src/main.cpp | sort)
for file in $files; do
  case "$file" in src/*) folder=$(cut -d/ -f2 <<< "$file") ;; *) folder=$(cut -d/ -f3 <<< "$file") ;; esac
  if [ -z "${may[$folder]+set}" ]; then
    echo "$file: folder '$folder' has no entry in $0's table"
    echo "unknown $file" >> "$found"
  fi
done
{ grep -oE '^#include "olt/[a-z_]+/' $files || true; } | sed -E 's#:\#include "olt/([a-z_]+)/# \1#' | sort -u |
  while read -r file used; do
    case "$file" in src/*) folder=${file#src/} ;; *) folder=${file#include/olt/} ;; esac
    folder=${folder%%/*}
    [ -z "${may[$folder]+set}" ] && continue
    [ "$used" = "$folder" ] && continue
    case " ${may[$folder]} " in *" $used "*) continue ;; esac
    echo "$file: $used" >> "$found"
  done

new=$(grep -vxF -f <(grep -v '^#' "$known") "$found" || true)
gone=$(grep -v '^#' "$known" | grep -vxF -f "$found" || true)
status=0
if [ -n "$new" ]; then
  echo "includes running upward (a folder using one it may not; see the table in $0):"
  echo "$new" | sed 's/^/  /'
  status=1
fi
if [ -n "$gone" ]; then
  echo "no longer there: remove from $known:"
  echo "$gone" | sed 's/^/  /'
  status=1
fi
[ $status -eq 0 ] && echo "include layers: $(grep -vc '^#' "$known") known exceptions, none new"
exit $status
