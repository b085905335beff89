#!/usr/bin/env bash
# The diagrams in a real browser: renders the paper's running example
# (examples/paper), the nested fixture and the five diagrams of
# ../shared/corpus and ../shared/reference that were the widest before
# issue 21 with `robosim diagram`, loads the SVGs in headless Chromium, and
# checks from the DOM's bounding boxes that every state is drawn inside its
# parent's box, that no two labels overlap and, for those five, that the
# drawing is at most three times as wide as tall or as tall as wide
# (geometry.js). Keeps a screenshot of each page as a test artefact in
# target/diagram-test/. Then runs the layout benchmark against Graphviz
# `dot` (crates/diagram/tests/quality.rs) with `dot` itself. Installs
# Chromium (Debian's `chromium`), the DejaVu fonts and Graphviz with
# apt-get when they are missing. Never skips.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../../.." && pwd)"
cd "$repo"
out="${CARGO_TARGET_DIR:-$repo/target}/diagram-test"
rm -rf "$out"
mkdir -p "$out/svg"

browser=""
for b in chromium chromium-browser google-chrome; do
  if command -v "$b" >/dev/null 2>&1; then browser="$b"; break; fi
done
if [ -z "$browser" ] || ! fc-list 2>/dev/null | grep -qi "DejaVu Sans Mono"; then
  echo "diagram-browser: installing chromium and fonts-dejavu-core with apt-get"
  if [ "$(id -u)" -eq 0 ]; then sudo=""; else sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends chromium fonts-dejavu-core >/dev/null
  browser=chromium
fi
if ! command -v dot >/dev/null 2>&1; then
  echo "diagram-browser: installing graphviz with apt-get (the layout benchmark's reference)"
  if [ "$(id -u)" -eq 0 ]; then sudo=""; else sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends graphviz >/dev/null
fi
echo "diagram-browser: using $($browser --version 2>/dev/null | head -1) and $(dot -V 2>&1 | head -1)"

bin="${ROBOSIM_BIN:-}"
if [ -z "$bin" ]; then
  cargo build -q -p robosim-cli
  bin="${CARGO_TARGET_DIR:-$repo/target}/debug/robosim"
fi

"$bin" diagram -o "$out/svg" examples/paper tests/data/diagram/nested.rct >/dev/null
# The five widest diagrams before issue 21 (20,506 to 12,111 px wide).
shared="$repo/../shared"
wide=(
  "reference/alpha-algorithm/rc2rs/robochart|pkg223_::MovementC|pkg223_.MovementC"
  "corpus/UoY-RoboStar__SLEEC-TK/sleec-core/Examples/RAD-AssistiveDressingRobot/robochart|RAD::Software|RAD.Software"
  "corpus/UoY-RoboStar__roboarch-examples/ObstacleAvoidance/RoboChart|Control::Control|Control.Control"
  "corpus/UoY-RoboStar__roboarch-examples/ObstacleAvoidance/RoboChart|Control::SkillsManager::SkillsManager|Control.SkillsManager.SkillsManager"
  "corpus/UoY-RoboStar__roboarch-examples/ObstacleAvoidance/RoboChart|ObstacleAvoidance::ObstacleAvoidance|ObstacleAvoidance.ObstacleAvoidance"
)
for w in "${wide[@]}"; do
  IFS='|' read -r dir element _ <<<"$w"
  "$bin" diagram -o "$out/svg" --element "$element" "$shared/$dir" >/dev/null
done

# One page per diagram (each SVG inline, so that the DOM can be measured),
# with the states it must show.
pages=()
declare -A sizes
page() { # name svg expected-states [max-aspect]
  local html="$out/$1.html"
  # The screenshot is as large as the drawing.
  sizes[$1]="$(head -1 "$2" | sed -E 's/.* width="([0-9.]+)" height="([0-9.]+)".*/\1,\2/' | awk -F, '{printf "%d,%d", $1 + 1, $2 + 40}')"
  {
    echo '<!DOCTYPE html><html><head><meta charset="utf-8"><style>body{margin:0;background:#fff}</style></head><body>'
    echo "<div data-expect-states=\"$3\" data-max-aspect=\"${4:-}\">"
    cat "$2"
    echo '</div><script>'
    cat "$here/geometry.js"
    echo '</script></body></html>'
  } >"$html"
  pages+=("$1")
}
page running-example-design "$out/svg/paper_design.SMovement.svg" "Moving Turning"
page running-example-simulation "$out/svg/paper_sim.SimSMovement.svg" "SMoving DMoving STurning DTurning"
page running-example-module "$out/svg/paper_design.CFootBot.svg" ""
page running-example-controller "$out/svg/paper_design.Movement.svg" ""
page nested "$out/svg/nested.Robot.svg" "Working Working::Searching Working::Searching::Scanning Working::Searching::Turning Working::Charging"
for w in "${wide[@]}"; do
  IFS='|' read -r _ _ file <<<"$w"
  page "wide-$file" "$out/svg/$file.svg" "" 3
done

flags=(--headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run --disable-dev-shm-usage --virtual-time-budget=5000)
passed=0
failed=0
for p in "${pages[@]}"; do
  dom="$out/$p.dom.html"
  timeout 120 "$browser" "${flags[@]}" --dump-dom "file://$out/$p.html" >"$dom" 2>"$out/$p.log" || true
  timeout 120 "$browser" "${flags[@]}" --window-size="${sizes[$p]}" --screenshot="$out/$p.png" "file://$out/$p.html" >>"$out/$p.log" 2>&1 || true
  result="$(sed -n '/<pre id="result">/,/<\/pre>/p' "$dom" | sed -e 's/<[^>]*>//g' -e 's/&quot;/"/g' -e 's/&amp;/\&/g')"
  if [ -z "$result" ]; then
    echo "diagram-browser: FAIL $p: the browser produced no result (see $out/$p.log)"
    failed=$((failed + 1))
  elif grep -q '^FAIL' <<<"$result"; then
    echo "diagram-browser: $p"
    echo "$result"
    failed=$((failed + 1))
  else
    echo "diagram-browser: $result"
    passed=$((passed + 1))
  fi
  if [ ! -s "$out/$p.png" ]; then
    echo "diagram-browser: FAIL $p: no screenshot"
    failed=$((failed + 1))
  fi
done
# The layout against Graphviz dot, with dot itself.
if ROBOSIM_REQUIRE_DOT=1 cargo test -q --locked -p robosim-diagram --test quality >"$out/quality.log" 2>&1; then
  echo "diagram-browser: PASS layout against dot (docs/diagrams.md)"
  passed=$((passed + 1))
else
  echo "diagram-browser: FAIL layout against dot:"
  tail -30 "$out/quality.log"
  failed=$((failed + 1))
fi
echo "diagram-browser: screenshots in $out"
echo "diagram-browser: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
