#!/usr/bin/env bash
# Runs voxfall's benchmarks and writes their results as CSV files under
# docs/results/MACHINE/, MACHINE being a short name for this CPU model and core count
# (e.g. amd-epyc-2cpu). docs/performance.md says what each file and column means.
#
#   tests/bench/record_results.sh [--quick] [--only GROUPS] [BUILD_DIR]
#
# BUILD_DIR (default: build/ in the repository) must hold a build with the benchmarks
# (tests/bench/sim_bench, tests/bench/ensemble_bench, tests/bench/png_bench, and
# tests/bench/bullet_compare where libbullet-dev was found) and the voxfall binary.
#
# --only GROUPS runs some groups, comma-separated, and writes only their files: sim
# (sim_bench_*.csv), ensemble (ensemble_bench.csv), bullet (bullet_compare_*.csv), commands
# (commands.csv), outputs (png_bench.csv, render_outputs.csv: PNG compression of a frame,
# and the cubes clip rendered to PNG frames and to an MP4 in one run) and camera
# (render_bench.csv: clips with a moving camera drawn and encoded at 1280x720, each pass
# timed; built as tests/bench/render_bench). Default: all.
#
# --quick runs a reduced set in a few minutes: the sim_bench rows of every paper scene at
# Lv 4 (paper's method and extensions) plus a few rows for levels, threads, the clearance step
# and 100 rocks; scenes/rockfall.toml as it is; bullet_compare with 1 round; ensemble_bench;
# a 20-realisation ensemble, a render of the cubes clip and a simulate of rockfall.toml.
# Without it every sim_bench row runs (the Rockfall rows of thousands of rocks take minutes
# each), bullet_compare makes 5 rounds, and the timed commands add the whole crosses clip
# and 1,000 realisations.
#
# Environment: REPETITIONS (default 3 without --quick, 1 with it): repetitions of each
# sim_bench row but the Rockfall ones; the CSV then holds each row's median. It also sets the
# runs of each timed command (default 3 in both modes). ROCKFALL_REPETITIONS (default 1): the
# same for the Rockfall rows (minutes each). VOXFALL_RESULTS_VERSION overrides the version.
#
# Every CSV row starts with the machine (CPU model and core count, e.g. "AMD EPYC (2 CPUs)")
# and the version: git describe of a tagged tree, else `voxfall --version`, with "+modified"
# when the sources (sim/, render/, shaders/, the benchmarks, CMakeLists.txt) differ from the
# commit. A file is replaced only by a run that writes it; a run writes every file into a
# temporary folder first, so an interrupted run leaves the files of the last complete one.
set -euo pipefail

usage() {
  sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'
}

quick=0
build=""
groups="sim,ensemble,bullet,commands,outputs,camera"
expect_groups=0
for arg in "$@"; do
  if ((expect_groups)); then groups=$arg; expect_groups=0; continue; fi
  case "$arg" in
    --quick) quick=1 ;;
    --only) expect_groups=1 ;;
    --only=*) groups=${arg#--only=} ;;
    -h | --help) usage; exit 0 ;;
    -*) echo "record_results.sh: unknown option $arg" >&2; exit 2 ;;
    *)
      if [[ -n "$build" ]]; then echo "record_results.sh: one BUILD_DIR only" >&2; exit 2; fi
      build=$arg
      ;;
  esac
done

if ((expect_groups)); then echo "record_results.sh: --only needs a list of groups" >&2; exit 2; fi
for g in ${groups//,/ }; do
  case "$g" in
    sim | ensemble | bullet | commands | outputs | camera) ;;
    *) echo "record_results.sh: unknown group '$g' (sim, ensemble, bullet, commands, outputs, camera)" >&2; exit 2 ;;
  esac
done
want() { [[ ",$groups," == *",$1,"* ]]; }

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(cd "${build:-$root/build}" && pwd)
bench=$build/tests/bench
voxfall=""
for candidate in "$build/voxfall" "$build/render/voxfall"; do
  if [[ -x "$candidate" ]]; then voxfall=$candidate; break; fi
done
needed=("$voxfall")
if want sim; then needed+=("$bench/sim_bench"); fi
if want ensemble; then needed+=("$bench/ensemble_bench"); fi
if want outputs; then needed+=("$bench/png_bench"); fi
if want camera; then needed+=("$bench/render_bench"); fi
for program in "${needed[@]}"; do
  if [[ ! -x "$program" ]]; then
    echo "record_results.sh: ${program:-voxfall} not found in $build: build the benchmarks" \
      "(e.g. cmake --build build) or name the build folder" >&2
    exit 1
  fi
done

if ((quick)); then reps=${REPETITIONS:-1}; else reps=${REPETITIONS:-3}; fi
rock_reps=${ROCKFALL_REPETITIONS:-1}
runs=${REPETITIONS:-3}  # of each timed command, in both modes (they take seconds)
nproc=$(nproc)

# The machine: /proc/cpuinfo's model name (lscpu's where it has none) and the core count.
model=$(awk -F': *' '/^model name/ { print $2; exit }' /proc/cpuinfo 2>/dev/null || true)
if [[ -z "$model" ]] && command -v lscpu >/dev/null; then
  model=$(lscpu | awk -F': *' '/^Model name/ { print $2; exit }')
fi
model=$(printf '%s' "${model:-unknown CPU}" | tr -d '",' | tr -s ' ' | sed 's/^ //; s/ $//')
machine="$model ($nproc CPUs)"  # no comma: `awk -F,` splits every file but bullet_compare's
slug=$(printf '%s' "$model" | tr '[:upper:]' '[:lower:]' |
  sed -E 's/\((r|tm)\)//g; s/@.*//; s/[0-9]+-core//g; s/\b(cpu|processor)\b//g' |
  sed -E 's/[^a-z0-9]+/-/g; s/^-+//; s/-+$//')
slug="${slug:-cpu}-${nproc}cpu"

# The version.
if [[ -n "${VOXFALL_RESULTS_VERSION:-}" ]]; then
  version=$VOXFALL_RESULTS_VERSION
elif version=$(git -C "$root" describe --tags --dirty 2>/dev/null); then
  :
else
  version=$("$voxfall" --version 2>/dev/null | awk '{ print $NF }')
  version=${version:-unknown}
  if git -C "$root" rev-parse --git-dir >/dev/null 2>&1 &&
    [[ -n "$(git -C "$root" status --porcelain -- sim render shaders 'tests/bench/*.cpp' CMakeLists.txt)" ]]; then
    version="$version+modified"
  fi
fi

out=$root/docs/results/$slug
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/results"
started=$SECONDS

csvq() { local s=${1//\"/\"\"}; printf '"%s"' "$s"; }
prefix="$(csvq "$machine"),$(csvq "$version")"
say() { printf 'record_results.sh: %s\n' "$*" >&2; }

# gbench FILE BINARY FILTER REPETITIONS: Google Benchmark rows as CSV, with the machine,
# version and repetitions in front. With repetitions, only the medians are kept (the name
# loses its _median suffix). Families with different counters go to different files: the
# CSV reporter fixes its columns at the first row.
gbench() {
  local file=$1 binary=$2 filter=$3 n=$4 args=()
  if ((n > 1)); then args=(--benchmark_repetitions="$n" --benchmark_report_aggregates_only=true); fi
  say "$(basename "$binary") --benchmark_filter='$filter' ${args[*]:-}"
  "$binary" --benchmark_filter="$filter" --benchmark_format=csv "${args[@]}" \
    >"$tmp/raw.csv" 2>"$tmp/context.txt" || { cat "$tmp/context.txt" >&2; return 1; }
  awk -v prefix="$prefix" -v n="$n" '
    NR == 1 {
      if ($0 !~ /^name,/) { print "unexpected CSV header: " $0 > "/dev/stderr"; exit 1 }
      print "machine,version,repetitions," $0; next
    }
    {
      line = $0
      if (line ~ /^"[^"]*_(mean|stddev|cv)",/) next   # aggregates other than the median
      aggregated = sub(/_median",/, "\",", line)
      print prefix "," (aggregated ? n : 1) "," line; rows++
    }
    END { if (rows == 0) { print "no benchmark rows" > "/dev/stderr"; exit 1 } }
  ' "$tmp/raw.csv" >"$tmp/results/$file"
}

# Google Benchmark: voxfall's simulation benchmark.
sb=$bench/sim_bench
if ! want sim; then
  :
elif ((quick)); then
  gbench sim_bench_scenes.csv "$sb" \
    '^Scene/[^/]+/4/[01]/1/|^Scene/crosses/[23]/[01]/1/|^Scene/crosses/4/[01]/2/|^SceneClearance/crosses/4/|^SceneFile/rockfall/' \
    "$reps"
  gbench sim_bench_rockfall.csv "$sb" '^Rockfall(Clearance)?/100/' "$rock_reps"
  gbench sim_bench_tree_build.csv "$sb" '^TreeBuild/' "$reps"
  gbench sim_bench_load_dem.csv "$sb" '^loadDem/' "$reps"
else
  gbench sim_bench_scenes.csv "$sb" '^(Scene|SceneClearance|SceneFile)/' "$reps"
  gbench sim_bench_rockfall.csv "$sb" '^Rockfall(Clearance)?/' "$rock_reps"
  gbench sim_bench_rockfall_wide.csv "$sb" '^RockfallWide/' "$rock_reps"
  gbench sim_bench_tree_build.csv "$sb" '^TreeBuild' "$reps"
  gbench sim_bench_diagnostics_build.csv "$sb" '^DiagnosticsBuild1M' "$reps"
  gbench sim_bench_load_dem.csv "$sb" '^loadDem/' "$reps"
fi

# Ensemble throughput (its repetitions are fixed in the benchmark: 3, medians kept).
if want ensemble; then gbench ensemble_bench.csv "$bench/ensemble_bench" '.' 3; fi

# PNG compression of one rendered frame.
if want outputs; then gbench png_bench.csv "$bench/png_bench" '.' "$reps"; fi

# Moving-camera clips (one run each: a row draws its clip four times and takes a minute).
if want camera; then
  gbench render_bench.csv "$bench/render_bench" '.' 1
fi

# bullet_compare: four markdown tables on stdout, one CSV file each. A cell holding several
# values ("15.7, 0.6") becomes several columns; a ratio loses its "x".
if ! want bullet; then
  :
elif [[ -x "$bench/bullet_compare" ]]; then
  if ((quick)); then rounds=1; else rounds=5; fi
  say "bullet_compare $rounds"
  "$bench/bullet_compare" "$rounds" >"$tmp/bullet.md"
  bullet_version=$(pkg-config --modversion bullet 2>/dev/null || echo unknown)
  awk -v prefix="$prefix,$(csvq "$bullet_version"),$rounds" -v dir="$tmp/results" '
    BEGIN {
      common = "machine,version,bullet_version,rounds,scene,"
      file[1] = "bullet_compare_time.csv"; width[1] = 11
      head[1] = "paper_ms_per_sim_s,ext_ms_per_sim_s,ext_clearance_ms_per_sim_s," \
        "bullet_ms_per_sim_s,paper_over_bullet,ext_over_bullet,ext_clearance_over_bullet," \
        "deepest_bullet_mm,deepest_paper_mm,deepest_ext_mm,deepest_ext_clearance_mm"
      file[2] = "bullet_compare_steps.csv"; width[2] = 10
      head[2] = "steps_per_sim_s_paper,steps_per_sim_s_ext,steps_per_sim_s_ext_clearance," \
        "steps_per_sim_s_bullet,us_per_step_paper,us_per_step_ext,us_per_step_ext_clearance," \
        "us_per_step_bullet,ext_over_bullet_steps,ext_over_bullet_per_step"
      file[3] = "bullet_compare_awake.csv"; width[3] = 8
      head[3] = "awake_per_step_ext,awake_per_step_bullet,awake_body_steps_per_sim_s_ext," \
        "awake_body_steps_per_sim_s_bullet,us_per_awake_body_step_ext," \
        "us_per_awake_body_step_bullet,ext_over_bullet_awake_body_steps," \
        "ext_over_bullet_per_awake_body_step"
      file[4] = "bullet_compare_equal_steps.csv"; width[4] = 9
      head[4] = "bullet_steps_per_frame,steps_per_sim_s_ext,steps_per_sim_s_bullet," \
        "ext_ms_per_sim_s,bullet_ms_per_sim_s,ext_over_bullet_time,ext_over_bullet_per_step," \
        "deepest_ext_mm,deepest_bullet_mm"
    }
    /^\| scene \|/ { t++; if (t > 4) exit 1; print common head[t] > (dir "/" file[t]); next }
    /^\|---/ || !/^\|/ { next }
    {
      line = $0; sub(/^\| /, "", line); sub(/ \|$/, "", line)
      n = split(line, cell, / \| /)
      scene = cell[1]; gsub(/"/, "\"\"", scene)
      row = "\"" scene "\""; values = 0
      for (i = 2; i <= n; i++) {
        m = split(cell[i], part, /, /)
        for (j = 1; j <= m; j++) { v = part[j]; sub(/x$/, "", v); row = row "," v; values++ }
      }
      if (values != width[t]) {
        printf "bullet_compare table %d: %d values, expected %d: %s\n", t, values, width[t], $0 > "/dev/stderr"
        exit 1
      }
      print prefix "," row > (dir "/" file[t]); rows[t]++
    }
    END { for (k = 1; k <= 4; k++) if (!rows[k]) { print "bullet_compare: table " k " missing" > "/dev/stderr"; exit 1 } }
  ' "$tmp/bullet.md"
else
  say "bullet_compare not built (libbullet-dev not found): skipped"
fi

# Timed voxfall commands, from the repository root, outputs in a temporary folder. Each runs
# `runs` times; the CSV holds medians (and the extremes of the wall time) plus what the
# command reports itself: frames/s of drawing and encoding and the share of pixels redrawn
# (render), realisations/s (ensemble).
if [[ -x /usr/bin/time ]] && /usr/bin/time --version 2>&1 | grep -q GNU; then
  timer="/usr/bin/time"
elif command -v hyperfine >/dev/null; then
  timer="hyperfine"
else
  timer="bash time"
fi
median() { sort -g | awk '{ v[NR] = $1 } END { if (NR) print v[int((NR + 1) / 2)] }'; }
header="machine,version,name,command,runs,timer,wall_s_median,wall_s_min,wall_s_max,user_s_median,sys_s_median,max_rss_mb,frames,frames_per_s_drawn,pct_redrawn,realisations_per_s"

# once KEY COMMAND...: runs a voxfall command line once (@TMP@ in it is the temporary folder)
# under $timer (not hyperfine), adding its times to $tmp/KEY.times and what it reports to
# $tmp/KEY.reported.
once() {
  local key=$1; shift
  local args=("${@//@TMP@/$tmp}")
  if [[ "$timer" == /usr/bin/time ]]; then
    /usr/bin/time -f '%e %U %S %M' -o "$tmp/time.txt" \
      "$voxfall" "${args[@]}" >"$tmp/cmd.out" 2>"$tmp/cmd.err" ||
      { cat "$tmp/cmd.err" >&2; return 1; }
    tail -n 1 "$tmp/time.txt" >>"$tmp/$key.times"
  else
    local TIMEFORMAT='%R %U %S'
    { time "$voxfall" "${args[@]}" >"$tmp/cmd.out" 2>"$tmp/cmd.err"; } 2>"$tmp/time.txt" ||
      { cat "$tmp/cmd.err" >&2; return 1; }
    echo "$(tail -n 1 "$tmp/time.txt") -" >>"$tmp/$key.times"
  fi
  # "  rendered frames 0..60 (1280x720, ...) in 1.23 s: 49.60 frames/s, 12% of the pixels
  # redrawn" and "voxfall: 20 realisations in 1.20 s (16.67 realisations/s, 2 threads)"
  cat "$tmp/cmd.out" "$tmp/cmd.err" | awk '
    BEGIN { frames = fps = p = r = "-" }
    /rendered .* frames\/s/ {
      for (i = 1; i < NF; i++) {
        if ($(i + 1) == "frames/s,") fps = $i
        if ($(i + 1) == "of" && $(i + 3) == "pixels") { p = $i; sub(/%/, "", p) }
      }
      if ($2 == "frames") { split($3, ab, /\.\./); frames = ab[2] - ab[1] + 1 }
      else if ($2 == "frame") frames = 1
    }
    /realisations\/s/ {
      for (i = 1; i < NF; i++) if ($(i + 1) == "realisations/s,") { r = $i; sub(/^\(/, "", r) }
    }
    END { print frames, fps, p, r }' >>"$tmp/$key.reported"
}

# row FILE NAME KEY SHOWN: FILE's row for NAME (FILE created with the header at its first row)
# from KEY's times and reports: medians, and the extremes of the wall time.
row() {
  local file=$1 name=$2 key=$3 shown=$4
  [[ -f "$tmp/results/$file" ]] || echo "$header" >"$tmp/results/$file"
  local wall wmin wmax user sys rss col line
  wall=$(awk '{ print $1 }' "$tmp/$key.times" | median)
  wmin=$(awk '{ print $1 }' "$tmp/$key.times" | sort -g | head -n 1)
  wmax=$(awk '{ print $1 }' "$tmp/$key.times" | sort -g | tail -n 1)
  user=$(awk '{ print $2 }' "$tmp/$key.times" | median)
  sys=$(awk '{ print $3 }' "$tmp/$key.times" | median)
  rss=$(awk '$4 != "-" { printf "%.1f\n", $4 / 1024 }' "$tmp/$key.times" | median)
  line="$prefix,$(csvq "$name"),$(csvq "$shown"),$runs,$timer,$wall,$wmin,$wmax,$user,$sys,$rss"
  for col in 1 2 3 4; do
    line="$line,$(awk -v c=$col '$c != "-" { print $c }' "$tmp/$key.reported" | median)"
  done
  echo "$line" >>"$tmp/results/$file"
}

# timed FILE NAME COMMAND...: a row of FILE for a voxfall command line run `runs` times; @TMP@
# in it is the temporary folder, written so in the CSV.
timed() {
  local file=$1 name=$2; shift 2
  local shown="voxfall $*" k
  say "$shown ($runs runs, $timer)"
  : >"$tmp/$name.times"
  : >"$tmp/$name.reported"
  if [[ "$timer" == hyperfine ]]; then
    hyperfine --style none --runs "$runs" --export-csv "$tmp/hf.csv" \
      "$(printf '%q ' "$voxfall" "${@//@TMP@/$tmp}")" >/dev/null
    # command,mean,stddev,median,user,system,min,max (the command's own report is not seen):
    # three lines whose medians are hyperfine's medians and whose extremes are its min and max.
    awk -F, 'NR == 2 { print $7, $5, $6, "-"; print $4, $5, $6, "-"; print $8, $5, $6, "-" }' \
      "$tmp/hf.csv" >"$tmp/$name.times"
    echo "- - - -" >"$tmp/$name.reported"
  else
    for ((k = 0; k < runs; ++k)); do once "$name" "$@"; done
  fi
  row "$file" "$name" "$name" "$shown"
}

# alternated FILE NAME_A NAME_B COMMAND_A... -- COMMAND_B...: two rows of FILE, the two command
# lines run in turn, `runs` times each, so that both meet the same load of a shared machine.
alternated() {
  local file=$1 a=$2 b=$3; shift 3
  local left=() k
  while [[ $# -gt 0 && "$1" != "--" ]]; do left+=("$1"); shift; done
  shift
  if [[ "$timer" == hyperfine ]]; then
    timed "$file" "$a" "${left[@]}"
    timed "$file" "$b" "$@"
    return
  fi
  say "voxfall ${left[*]} and voxfall $* in turn ($runs runs each, $timer)"
  : >"$tmp/$a.times"; : >"$tmp/$a.reported"; : >"$tmp/$b.times"; : >"$tmp/$b.reported"
  for ((k = 0; k < runs; ++k)); do
    once "$a" "${left[@]}"
    once "$b" "$@"
  done
  row "$file" "$a" "$a" "voxfall ${left[*]}"
  row "$file" "$b" "$b" "voxfall $*"
}

cd "$root"
if want commands; then
  timed commands.csv simulate_rockfall simulate scenes/rockfall.toml -q
  timed commands.csv render_cubes render scenes/cubes.toml -o @TMP@/cubes.mp4 -y -q
  if ((quick)); then
    timed commands.csv ensemble_20 ensemble scenes/rockfall_ensemble.toml --runs 20 -j "$nproc" -o @TMP@/ensemble -y -q
  else
    timed commands.csv render_crosses render scenes/crosses.toml -o @TMP@/crosses.mp4 -y -q
    timed commands.csv ensemble_1000 ensemble scenes/rockfall_ensemble.toml --runs 1000 -j "$nproc" -o @TMP@/ensemble -y -q
  fi
fi
# The same clip to an MP4 and to PNG frames, in turn in one run (compare these two rows with
# each other, not with other runs).
if want outputs; then
  alternated render_outputs.csv render_cubes_mp4 render_cubes_png \
    render scenes/cubes.toml -o @TMP@/cubes.mp4 -y -q -- \
    render scenes/cubes.toml -o @TMP@/cubes_png/frame_####.png -y -q
fi

mkdir -p "$out"
written=$(cd "$tmp/results" && printf '%s ' *.csv)
mv -f "$tmp"/results/*.csv "$out"/
say "wrote to ${out#"$root"/}/ in $((SECONDS - started)) s: $written"
