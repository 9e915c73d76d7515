#!/usr/bin/env bash
# Proves check_layers.py can fail: in a scratch tree checked against the repository's own layer
# list, includes down the layers pass, and each upward include fails and is named (a core
# header including a shape header, the run guard including the world, a render file including
# a command's), and good files are not named; a tree with no sources fails too.
set -u
root=$1
here=$(dirname "$0")
layers="$root/tests/lint/layers.txt"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
check() { python3 "$here/check_layers.py" "$scratch" "$layers"; }
put() { mkdir -p "$(dirname "$scratch/$1")"; printf '%s\n' "${@:2}" > "$scratch/$1"; }

put sim/core/body.h '#pragma once' '#include "sim/core/math.h"'
put sim/shape/shape.h '#include "sim/core/body.h"'
put sim/run_guard.h '#include "sim/core/body.h"'
put sim/world.h '#include "sim/run_guard.h"' '#include "sim/shape/shape.h"'
put render/cli/main.cpp '#include "render/draw_list.h"' '#include "sim/world.h"'
put render/draw_list.h '#include "sim/world.h"'
check >/dev/null || { echo "includes down the layers failed:"; check; exit 1; }

put sim/core/body.h '#pragma once' '#include "sim/shape/shape.h"'
put sim/run_guard.cpp '#include "sim/run_guard.h"' '' '#include "sim/world.h"'
put render/draw_list.cpp '#include "render/cli/options.h"'
out=$(check)
if [ $? -eq 0 ]; then echo "upward includes passed: $out"; exit 1; fi
for want in "sim/core/body.h:2: includes sim/shape/shape.h" \
            "sim/run_guard.cpp:3: includes sim/world.h" \
            "render/draw_list.cpp:1: includes render/cli/options.h"; do
  case "$out" in *"$want"*) ;; *) echo "failure does not name '$want': $out"; exit 1;; esac
done
if printf '%s\n' "$out" | grep -q '^render/cli/main.cpp\|^sim/world.h\|^sim/shape/shape.h'; then
  echo "failure names a good file: $out"; exit 1
fi

rm -rf "$scratch"/*
put notes/readme.h '#include "sim/world.h"'
if check >/dev/null; then echo "a tree without sim/ or render/ passed"; exit 1; fi
echo "check_layers.py fails on upward includes and names each, as it should"
