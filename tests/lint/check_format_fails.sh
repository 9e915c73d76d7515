#!/usr/bin/env bash
# Proves check_format.sh can fail: in a scratch copy of the repository's .clang-format, a
# well-formatted file passes and a mis-formatted one fails, and the failure names the file.
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
out=$(bash "$here/check_format.sh" "$clang_format" "$scratch" src)
if [ $? -eq 0 ]; then echo "a mis-formatted file passed"; exit 1; fi
case "$out" in *"not formatted: src/bad.cpp"*) ;; *) echo "failure does not name the file: $out"; exit 1;; esac
echo "check_format.sh fails on a mis-formatted file, as it should"
