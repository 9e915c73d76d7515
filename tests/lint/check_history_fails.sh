#!/usr/bin/env bash
# Proves check_history.pl can fail: on a scratch tree, a clean one passes; a date in README.md,
# a commit hash in docs/, an issue reference in a C++ comment and one in a CMake comment each
# fail, named by file and line; the same words in code (a checksum in a string, a number)
# pass; a line on the allow-list passes.
set -u
here=$(dirname "$0")
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/docs" "$scratch/sim" "$scratch/tests/data"
# The planted words are put together here, so that this file holds none of them itself.
date="2026-12""-03" hash="a004""eef" issue="issue"
printf '# voxfall\nCited as Guzzetti et al. 2002, 9(1):1079-1093.\n' >"$scratch/README.md"
printf 'const char* kSum = "a0b1fc62901dbc87";  // a checksum in code is data\nint n = 10000000;\n' \
  >"$scratch/sim/a.cpp"
printf 'set(X 1)  # why this is so\n' >"$scratch/CMakeLists.txt"
printf 'until %s in test data\n' "$date" >"$scratch/tests/data/notes.md"
check() { perl "$here/check_history.pl" "$scratch" "$@"; }
out=$(check) || { echo "a clean tree failed:"; echo "$out"; exit 1; }

printf 'Measured on %s.\n' "$date" >>"$scratch/README.md"
printf 'See %s for the change.\n' "$hash" >"$scratch/docs/perf.md"
printf 'int f();  // %s 13: no run explodes\n/* as %s #8 asked */\n' "$issue" "$issue" \
  >>"$scratch/sim/a.cpp"
printf 'set(Y 2)  # hazard maps (%s 11)\n' "$issue" >>"$scratch/CMakeLists.txt"
out=$(check)
if [ $? -eq 0 ]; then echo "planted history passed"; exit 1; fi
for want in "README.md:3: a date ($date)" "docs/perf.md:1: a commit hash ($hash)" \
  "sim/a.cpp:3: an issue reference (${issue} 13)" "sim/a.cpp:4: an issue reference (${issue} #8)" \
  "CMakeLists.txt:2: an issue reference (${issue} 11)"; do
  case "$out" in *"$want"*) ;; *) echo "report lacks '$want':"; echo "$out"; exit 1;; esac
done
case "$out" in *a0b1fc62901dbc87*|*tests/data*) echo "flagged code or test data: $out"; exit 1;; esac

# An allow-list entry lets exactly its line pass.
printf 'docs/perf.md: See %s\n' "$hash" >"$scratch/allow.txt"
out=$(check "$scratch/allow.txt")
case "$out" in *docs/perf.md*) echo "an allowed line was reported: $out"; exit 1;; esac
case "$out" in *"README.md:3"*) ;; *) echo "the allow-list hid another line: $out"; exit 1;; esac
echo "check_history.pl fails on planted dates, hashes and issue references, as it should"
