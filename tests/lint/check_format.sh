#!/usr/bin/env bash
# Fails when a C++ source under the given folders is not formatted as the repository's
# .clang-format says: `check_format.sh CLANG_FORMAT ROOT DIR...` checks every *.h and *.cpp
# under ROOT/DIR (tests/data excluded) with `clang-format --dry-run --Werror` and lists the
# files that differ. Fix them with `clang-format -i FILE`. One clang-format process for all
# files (xargs), because its start-up, once per file, would dominate the check's time.
# pipefail: a folder that find cannot read (a typo in the test's arguments) fails the check
# instead of checking nothing.
set -uo pipefail
clang_format=$1
root=$2
shift 2
cd "$root" || exit 2
report=$(find "$@" \( -name '*.h' -o -name '*.cpp' \) -not -path '*/data/*' -print0 | sort -z |
  xargs -0 -r "$clang_format" --dry-run --Werror 2>&1)
[ $? -eq 0 ] && exit 0
# clang-format names each differing place "FILE:LINE:COL: ...clang-format-violations".
files=$(printf '%s\n' "$report" | grep -- '-Wclang-format-violations' | sed 's/:[0-9]*:[0-9]*: .*//' |
  sort -u)
if [ -z "$files" ]; then  # it failed for another reason (a bad .clang-format, a missing folder)
  [ -n "$report" ] && printf '%s\n' "$report"
  echo "could not check the sources under: $* (in $root)"
  exit 1
fi
while IFS= read -r file; do echo "not formatted: $file (run: clang-format -i $file)"; done <<<"$files"
exit 1
