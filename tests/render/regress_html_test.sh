#!/usr/bin/env bash
# The HTML report of `voxfall regress` opened in a real browser (Debian's chromium, headless,
# from file://): the page loads with no console message, lists both cases with one failing,
# every image on it loads, and the failing frames' expected, actual and diff images are there.
# The checker is first shown to fail on a page with a script error and a missing image.
# Skipped (exit 77) where chromium is not installed.
#   regress_html_test.sh VOXFALL SOURCE_DIR
set -u
exe=$1
src=$2
browser=$(command -v chromium || command -v chromium-browser) ||
  { echo "chromium is not installed: skipping (.ci/install-deps installs it)"; exit 77; }
. "$(dirname "$0")/regress_fixture.sh"  # also makes $scratch, removed on exit

# check_page FILE CASES FAILED: the DOM after the page's script ran, and the browser's log.
check_page() {
  local page=$1 cases=$2 failed=$3 dom body images
  dom=$("$browser" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync \
    --user-data-dir="$scratch/profile" --virtual-time-budget=5000 --enable-logging=stderr \
    --v=0 --dump-dom "file://$page" 2>"$scratch/browser.log")
  body=$(grep -o '<body[^>]*>' <<<"$dom")
  images=$(grep -o '<img ' <<<"$dom" | wc -l)
  local problems=""
  grep -q 'INFO:CONSOLE' "$scratch/browser.log" &&
    problems+="console: $(grep 'INFO:CONSOLE' "$scratch/browser.log" | head -3)\n"
  [[ $body == *"data-cases=\"$cases\""* ]] || problems+="not $cases cases: $body\n"
  [[ $body == *"data-failed=\"$failed\""* ]] || problems+="not $failed failed: $body\n"
  [ "$(grep -o '<section class="case"' <<<"$dom" | wc -l)" -eq "$cases" ] ||
    problems+="not $cases case sections\n"
  [[ $body == *"data-images-loaded=\"$images\""* && $images -gt 0 ]] ||
    problems+="not all $images images loaded: $body\n"
  [[ $body == *'data-images-broken="0"'* ]] || problems+="broken images: $body\n"
  for frame in 0000 0030 0060; do
    for kind in expected actual diff; do
      grep -q "src=\"moved/frame_${frame}_$kind.png\"" <<<"$dom" ||
        problems+="no $kind image of frame $frame\n"
    done
  done
  [ -z "$problems" ] && return 0
  printf "%b" "$problems"
  return 1
}

make_failing_suite "$scratch" "$src" "$exe" || { echo "could not make the suite"; exit 1; }
"$exe" regress "$scratch/suite" -o "$scratch/report" >"$scratch/stdout.txt"
[ $? -eq 1 ] || { echo "the moved case did not fail:"; cat "$scratch/stdout.txt"; exit 1; }

sed 's#</body>#<script>notDefined();</script><img src="missing.png"></body>#' \
  "$scratch/report/index.html" >"$scratch/report/broken.html"
out=$(check_page "$scratch/report/broken.html" 2 1)
if [ $? -eq 0 ]; then echo "the checker passed a broken page"; exit 1; fi
for want in "notDefined is not defined" "broken images"; do
  [[ $out == *"$want"* ]] || { echo "the checker missed '$want': $out"; exit 1; }
done

check_page "$scratch/report/index.html" 2 1 || exit 1
echo "the HTML report loads cleanly in $("$browser" --version 2>/dev/null | head -1)"
