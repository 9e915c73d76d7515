#!/usr/bin/env bash
# Fails when a C++ source under the given folders is not formatted as the repository's
# .clang-format says: `check_format.sh CLANG_FORMAT ROOT DIR...` checks every *.h and *.cpp
# under ROOT/DIR (tests/data excluded) with `clang-format --dry-run --Werror` and lists the
# files that differ. Fix them with `clang-format -i FILE`.
set -u
clang_format=$1
root=$2
shift 2
cd "$root" || exit 2
status=0
while IFS= read -r -d '' file; do
  if ! "$clang_format" --dry-run --Werror "$file" >/dev/null 2>&1; then
    echo "not formatted: $file (run: clang-format -i $file)"
    status=1
  fi
done < <(find "$@" \( -name '*.h' -o -name '*.cpp' \) -not -path '*/data/*' -print0 | sort -z)
exit $status
