#!/usr/bin/env bash
# Reports render in headless Chromium (scripts/check-report-render).
#   render_in_chromium.sh real LOOPSCAN CHECKER WORK   a real `run` report, an `evaluate` PR
#                                                      figure and the demo's page must render
#                                                      with data
#   render_in_chromium.sh defects CHECKER WORK         the checker must fail, naming each figure
#                                                      and its reason, on broken and empty figures
# Exits 77 (ctest SKIP) without Chromium: a missing browser must not look like a pass.
set -euo pipefail
mode=$1
shift
if ! command -v "${CHROMIUM:-chromium}" >/dev/null; then
  echo "SKIP: chromium not found; install it (Debian: apt-get install chromium) to run this test"
  exit 77
fi

if [ "$mode" = real ]; then
  cli=$1 checker=$2 work=$3
  rm -rf "$work" && mkdir -p "$work"
  # A rendered 30-frame sequence through `run` (VO, describe, closing; its report inlines the
  # trajectory and loop-closing figures), and a simulated drive's precision-recall figure.
  "$cli" render --trajectory builtin:short --scale 0.25 --frames 30 --out "$work/seq" >/dev/null
  printf 'odometry_metrics:\n  segment_lengths_m: [10]\n' >"$work/segments.yaml"
  "$cli" run --kitti "$work/seq" --out "$work/run" --methods sc --config "$work/segments.yaml" \
    --quiet >/dev/null
  "$cli" simulate --trajectory builtin:short --season summer --seed 3 --out "$work/sim" >/dev/null
  "$cli" describe --method sc --poses "$work/sim/poses_history_file.txt" \
    --points "$work/sim/pts_history_file.txt" --out "$work/sc" >/dev/null
  "$cli" evaluate --method sc --signatures "$work/sc" --gt "$work/sim/gt.txt" \
    --out "$work/eval" >/dev/null
  # The demo's page on the short route: PR curves, route figures, heat maps, scans, closing.
  "$cli" demo --trajectory builtin:short --out "$work/demo" >/dev/null 2>&1
  code=0
  out=$("$checker" "$work/run/report.html" "$work/eval/pr.svg" "$work/demo/report/index.html") ||
    code=$?
  echo "$out"
  [ "$code" -eq 0 ] || { echo "FAIL: a real report's figure does not render (exit $code)"; exit 1; }
  # The page's figures and the PR figure were judged, not skipped as absent.
  grep -Eq '^ok +.*report\.html figure 1 ' <<<"$out" && grep -Eq '^ok +.*pr\.svg: ' <<<"$out" &&
    grep -Eq "^ok +.*index\\.html figure $(grep -o '<figure' "$work/demo/report/index.html" | wc -l) " \
      <<<"$out" ||
    { echo "FAIL: the report's figures or pr.svg were not checked"; exit 1; }
  exit 0
fi

checker=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
svg='<svg xmlns="http://www.w3.org/2000/svg" width="320" height="240" viewBox="0 0 320 240">'
bg='<rect x="0" y="0" width="320" height="240" fill="white"/>'
axes='<g class="grid" stroke="#e0e0e0"><line x1="40" y1="120" x2="300" y2="120"/></g>
<g class="tick-labels"><text x="40" y="235">0</text><text x="300" y="235">1</text></g>
<rect class="frame" x="40" y="20" width="260" height="200" fill="none" stroke="black"/>'
data='<g class="series"><path d="M40,200 L120,60 L300,40" fill="none" stroke="#1f77b4"/></g>'
# A good figure (the control: the checker does not fail everything), then the defects.
printf '%s\n%s\n%s\n%s\n</svg>\n' "$svg" "$bg" "$axes" "$data" >"$work/good.svg"
# Mismatched end tag: HTML would still draw it, an .svg file or an XML parser would not.
printf '%s\n%s\n%s\n%s</gg>\n</svg>\n' "$svg" "$bg" "$axes" "${data%</g>}" >"$work/broken.svg"
printf '%s\n%s\n</svg>\n' "$svg" "$bg" >"$work/empty.svg"
printf '%s\n%s\n%s\n</svg>\n' "$svg" "$bg" "$axes" >"$work/axes-only.svg"  # a plot, no data
{
  echo '<!DOCTYPE html><html><body>'
  for f in good broken empty axes-only; do
    echo "<figure>$(cat "$work/$f.svg")<figcaption>$f</figcaption></figure>"
  done
  echo '</body></html>'
} >"$work/page.html"
# A page cut off inside its last figure (a killed writer).
{ echo '<!DOCTYPE html><html><body><figure>'; head -c -30 "$work/good.svg"; } >"$work/cut.html"

set +e
# axes-only is judged inline only: the same script judges a page's figures and an .svg file.
out=$("$checker" "$work/good.svg" "$work/broken.svg" "$work/empty.svg" "$work/page.html" \
  "$work/cut.html")
code=$?
set -e
echo "$out"
fail=0
expect() {  # expect LINE-REGEX: one line of the checker's output must match
  grep -Eq "$1" <<<"$out" || { echo "FAIL: no line matching: $1"; fail=1; }
}
[ "$code" -eq 1 ] || { echo "FAIL: checker exit $code, expected 1 (a figure is broken)"; fail=1; }
expect '^ok +.*/good\.svg: '
expect '^FAIL +.*/broken\.svg: not well-formed XML'
expect '^FAIL +.*/empty\.svg: .*no data drawn.*blank screenshot: 0 non-white'
expect '^ok +.*page\.html figure 1 "good"'
expect '^FAIL +.*page\.html figure 2 "broken": .*not well-formed XML'
expect '^FAIL +.*page\.html figure 3 "empty": no data drawn'
expect '^FAIL +.*page\.html figure 4 "axes-only": no data drawn'
expect '^FAIL +.*cut\.html figure 1: .*not well-formed XML'
[ "$fail" -eq 0 ] && echo "the checker names every defect"
exit "$fail"
