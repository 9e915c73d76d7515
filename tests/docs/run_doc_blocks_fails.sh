#!/usr/bin/env bash
# Proves run_doc_blocks.sh can fail: on a scratch repository (no git) holding one markdown file,
# a file whose blocks all pass passes; a block that exits non-zero, a block that prints a
# warning it does not expect, and a scene block that would replace a different file fail, each
# named by its line; a block fenced `warns` may warn; plain fences are not run; scene blocks are
# written before the shell blocks run; blocks share the copy in file order; `voxfall` on the
# PATH is the executable given.
#   run_doc_blocks_fails.sh VOXFALL_EXE
set -u
exe=$1
here=$(dirname "$0")
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/repo/scenes"
fence='```'

write_doc() {  # the common, passing part, then whatever is given
  cat >"$scratch/repo/doc.md" <<EOF
# A manual page
${fence}sh
exit 1   # a plain block: shown, never run
${fence}
${fence}sh doctest
test -f scenes/made.toml          # written before any shell block
voxfall --version > out/version.txt
${fence}
${fence}text
${fence}sh doctest
exit 1   # inside a text block: not a block of its own
${fence}
${fence}sh doctest
grep -q . out/version.txt          # the previous block's output, same copy
${fence}
${fence}sh doctest warns
echo "voxfall: warning: expected here" >&2
${fence}
${fence}toml scene file=scenes/made.toml
[simulation]
duration = 1.0
${fence}
$1
EOF
}

run() { bash "$here/run_doc_blocks.sh" "$exe" "$scratch/repo" doc.md; }

write_doc ""
out=$(run) || { echo "a passing file failed:"; echo "$out"; exit 1; }
case "$out" in *"3 runnable blocks passed"*) ;; *) echo "wrong count: $out"; exit 1;; esac

expect_failure() {  # $1: what is planted, $2: the text the report must contain
  write_doc "$1"
  out=$(run)
  if [ $? -eq 0 ]; then echo "passed with $2 planted:"; echo "$out"; exit 1; fi
  case "$out" in *"$2"*) ;; *) echo "report lacks '$2':"; echo "$out"; exit 1;; esac
}
write_doc ""
line=$(wc -l <"$scratch/repo/doc.md")  # the planted block starts on the last line
expect_failure "${fence}sh doctest
false
${fence}" "doc.md:$line: the block exited with 1"
expect_failure "${fence}sh doctest
echo 'voxfall: warning: 3 of 20 rocks were still moving' >&2
${fence}" "doc.md:$line: the block printed a warning"
printf 'different\n' >"$scratch/repo/scenes/made.toml"
expect_failure "" "the block would replace scenes/made.toml"
echo "run_doc_blocks.sh fails on a failing block, an unexpected warning and a clashing scene file"
