#!/usr/bin/env bash
# Proves check_format.sh can fail: in a scratch copy of the repository's .clang-format, a
# well-formatted file passes and mis-formatted ones fail, and the failure names each of them
# (all files go to one clang-format process, so the names come from its report), and a
# missing folder fails.
set -u
clang_format=$1
root=$2
here=$(dirname "$0")
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cp "$root/.clang-format" "$scratch/"
mkdir -p "$scratch/src"
printf 'int f(int a) { return a + 1; }\n' > "$scratch/src/good.cpp"
bash "$here/check_format.sh" "$clang_format" "$scratch" src || { echo "a formatted file failed"; exit 1; }
printf 'int  f( int a ){return a+1;}\n' > "$scratch/src/bad.cpp"
printf 'int  g( int a ){return a+1;}\n' > "$scratch/src/worse.h"
out=$(bash "$here/check_format.sh" "$clang_format" "$scratch" src)
if [ $? -eq 0 ]; then echo "a mis-formatted file passed"; exit 1; fi
for name in src/bad.cpp src/worse.h; do
  case "$out" in *"not formatted: $name "*) ;; *) echo "failure does not name $name: $out"; exit 1;; esac
done
case "$out" in *good.cpp*) echo "failure names the formatted file: $out"; exit 1;; esac
# A folder that does not exist fails instead of checking nothing.
if bash "$here/check_format.sh" "$clang_format" "$scratch" nosuchdir >/dev/null 2>&1; then
  echo "a missing folder passed"; exit 1
fi
echo "check_format.sh fails on mis-formatted files and names each, as it should"
