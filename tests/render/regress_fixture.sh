# Sourced by the report tests: a scratch folder $scratch, removed on exit, and
# make_failing_suite DIR SOURCE_DIR VOXFALL makes, in DIR, a suite
# of two cases of scenes/cubes.toml at 160x90, "same" and "moved", writes their goldens, then
# moves the second cube of "moved" by 2 cm, so that a run fails that case alone (its checksum
# and its three frames) and passes the other.
make_failing_suite() {
  local dir=$1 src=$2 exe=$3
  mkdir -p "$dir/suite" "$dir/meshes"
  cp "$src/scenes/meshes/cube.obj" "$dir/meshes/"
  cp "$src/scenes/cubes.toml" "$dir/same.toml"
  cp "$src/scenes/cubes.toml" "$dir/moved.toml"
  cat >"$dir/suite/suite.toml" <<'TOML'
[[case]]
name = "same"
scene = "../same.toml"
frames = [0, 30, 60]
size = [160, 90]

[[case]]
name = "moved"
scene = "../moved.toml"
frames = [0, 30, 60]
size = [160, 90]
TOML
  "$exe" regress "$dir/suite" --update -o "$dir/update-report" >/dev/null || return 1
  grep -q '^position = \[1.0, 0.2, 0.3\]' "$dir/moved.toml" || { echo "cubes.toml changed"; return 1; }
  sed -i 's/^position = \[1.0, 0.2, 0.3\]/position = [1.0, 0.22, 0.3]/' "$dir/moved.toml"
}

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
