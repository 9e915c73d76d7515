#!/usr/bin/env bash
# Runs the runnable examples of one markdown file, as a reader would type them:
#   run_doc_blocks.sh VOXFALL_EXE SOURCE_DIR FILE.md
# FILE.md is relative to SOURCE_DIR. In a scratch copy of the repository (its tracked and
# unignored files: no build folders, an empty out/), with `voxfall` on the PATH, every block
# fenced as ```sh doctest runs in file order as `bash -e -o pipefail`, each from the copy's root.
# Before them, every ```toml scene file=PATH block is written to PATH in the copy. A block fails
# when it exits non-zero or prints "warning:" (unless fenced ```sh doctest warns); the failure
# names FILE:LINE of the block and shows what it printed. Exit 0 when every block passes.
set -uo pipefail
exe=$1
src=$2
doc=$3
[ -f "$src/$doc" ] || { echo "no such file: $src/$doc"; exit 2; }
[ -x "$exe" ] || { echo "not an executable: $exe"; exit 2; }

work=$(mktemp -d "${TMPDIR:-/tmp}/voxfall_doctest.XXXXXX")
trap 'rm -rf "$work"' EXIT
copy=$work/repo
mkdir -p "$copy" "$work/bin" "$work/blocks"
ln -s "$(realpath "$exe")" "$work/bin/voxfall"

# The files a fresh clone has (plus new, unignored ones of a working tree); without git, all
# but build folders and outputs.
if git -C "$src" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  (cd "$src" && git ls-files -z --cached --others --exclude-standard |
    while IFS= read -r -d '' f; do [ -f "$f" ] && printf '%s\0' "$f"; done |
    tar --null -T - -cf -) | tar -C "$copy" -xf - || { echo "could not copy $src"; exit 2; }
else
  (cd "$src" && tar --exclude='./build*' --exclude='./out/*' -cf - .) | tar -C "$copy" -xf -
fi
mkdir -p "$copy/out"

# Split the file into blocks: one script per block, and a table "KIND LINE FILE INFO".
awk -v dir="$work/blocks" '
  /^```/ {
    # As in CommonMark, only a fence without an info string closes a block.
    if (inblock || inplain) {
      if ($0 ~ /^```[ \t]*$/) {
        if (inblock) close(out)
        inblock = inplain = 0
        next
      }
      if (inblock) print > out
      next
    }
    info = substr($0, 4)
    kind = ""
    if (info ~ /^sh doctest( |$)/) kind = "sh"
    else if (info ~ /^toml scene file=/) kind = "toml"
    if (kind == "") { inplain = 1; next }
    n++
    out = sprintf("%s/%03d.%s", dir, n, kind)
    printf "%s %d %s %s\n", kind, NR, out, info > (dir "/index")
    printf "" > out
    inblock = 1
    next
  }
  inblock { print > out }
' "$src/$doc"
[ -f "$work/blocks/index" ] || { echo "$doc: no runnable blocks"; exit 0; }

failed=0
# Scene files first, so that a block may use a scene shown further down.
while read -r kind line file info; do
  [ "$kind" = toml ] || continue
  target=${info#*file=}
  target=${target%% *}
  mkdir -p "$copy/$(dirname "$target")"
  if [ -e "$copy/$target" ] && ! cmp -s "$file" "$copy/$target"; then
    echo "$doc:$line: the block would replace $target, which differs from it"
    failed=1
  fi
  cp "$file" "$copy/$target"
done <"$work/blocks/index"

count=0
while read -r kind line file info; do
  [ "$kind" = sh ] || continue
  count=$((count + 1))
  (cd "$copy" && PATH="$work/bin:$PATH" timeout 900 bash -e -o pipefail "$file") \
    >"$work/stdout" 2>"$work/stderr" </dev/null
  rc=$?
  problem=""
  if [ $rc -ne 0 ]; then
    problem="exited with $rc"
  elif [[ " $info " != *" warns "* ]] && grep -q 'warning:' "$work/stdout" "$work/stderr"; then
    problem="printed a warning it does not expect (fence it as \`\`\`sh doctest warns if it should)"
  fi
  if [ -n "$problem" ]; then
    failed=1
    echo "$doc:$line: the block $problem:"
    sed 's/^/    | /' "$file"
    echo "  stdout (last 20 lines):"
    tail -n 20 "$work/stdout" | sed 's/^/    /'
    echo "  stderr (last 20 lines):"
    tail -n 20 "$work/stderr" | sed 's/^/    /'
  fi
done <"$work/blocks/index"

if [ $failed -ne 0 ]; then exit 1; fi
echo "$doc: $count runnable blocks passed"
