#!/usr/bin/env bash
# `voxfall regress --junit FILE` read back by a JUnit parser (junitparser, Debian's
# python3-junitparser): one suite per case, a test per frame and per checksum, the failing case's
# four tests failed with the metrics in the message, the passing case clean. The checker is
# first shown to fail on a file with a failure removed. Skipped (exit 77) without junitparser.
#   regress_junit_test.sh VOXFALL SOURCE_DIR
set -u
exe=$1
src=$2
# Debian's python3 first: a python3 earlier on the PATH (pyenv, a venv) lacks Debian's packages.
python=""
for p in /usr/bin/python3 python3; do
  if "$p" -c 'import junitparser' 2>/dev/null; then python=$p; break; fi
done
[ -n "$python" ] ||
  { echo "python3-junitparser is not installed: skipping (.ci/install-deps installs it)"; exit 77; }
. "$(dirname "$0")/regress_fixture.sh"  # also makes $scratch, removed on exit

check() {
  "$python" - "$1" <<'PY'
import sys
from junitparser import JUnitXml, Failure, Error
xml = JUnitXml.fromfile(sys.argv[1])
want = {"same": 0, "moved": 4}  # failures per case: the checksum and three frames
problems, seen = [], {}
for suite in xml:
    cases = list(suite)
    failed = [c for c in cases if any(isinstance(r, Failure) for r in c.result)]
    errors = [c for c in cases if any(isinstance(r, Error) for r in c.result)]
    seen[suite.name] = len(failed)
    if len(cases) != 4 or suite.tests != 4:
        problems.append(f"{suite.name}: {len(cases)} tests, {suite.tests} declared, not 4")
    if suite.failures != len(failed) or errors:
        problems.append(f"{suite.name}: declares {suite.failures} failures, holds {len(failed)}")
    names = sorted(c.name for c in cases)
    if names != ["checksum", "frame_0000.png", "frame_0030.png", "frame_0060.png"]:
        problems.append(f"{suite.name}: tests {names}")
    for c in failed:
        message = c.result[0].message or ""
        if c.name != "checksum" and "SSIM" not in message:
            problems.append(f"{suite.name}/{c.name}: no metrics in '{message}'")
if seen != want:
    problems.append(f"failures per case {seen}, not {want}")
if problems:
    print("\n".join(problems))
sys.exit(1 if problems else 0)
PY
}

make_failing_suite "$scratch" "$src" "$exe" || { echo "could not make the suite"; exit 1; }
"$exe" regress "$scratch/suite" -o "$scratch/report" --junit "$scratch/junit.xml" >/dev/null
[ $? -eq 1 ] || { echo "the moved case did not fail"; exit 1; }

# A failure dropped from the file (its element and the count left as they were) must be seen.
perl -0pe 's#<failure [^>]*>[^<]*</failure>##' "$scratch/junit.xml" >"$scratch/edited.xml"
if check "$scratch/edited.xml" >/dev/null; then echo "the checker passed an edited file"; exit 1; fi

check "$scratch/junit.xml" || exit 1
echo "the JUnit XML reads back with the right tests and failures"
