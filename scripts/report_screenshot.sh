#!/usr/bin/env bash
# Opens splat-eval's report.html in headless Chromium (Debian's chromium package) and saves
# what it shows as a PNG, to check the page offline the way a reader sees it.
#   scripts/report_screenshot.sh OUT_DIR [SCREENSHOT.png] [HEIGHT]
# Default screenshot: OUT_DIR/report_screenshot.png; default height 4000 px (the whole page
# of a comparison run; pass more for a report with sweep and stability sections).
set -euo pipefail
out=${1:?usage: report_screenshot.sh OUT_DIR [SCREENSHOT.png] [HEIGHT]}
shot=${2:-$out/report_screenshot.png}
height=${3:-4000}
report=$(realpath "$out/report.html")
[[ -f $report ]] || { echo "error: $report: no report.html (run splat-eval first)" >&2; exit 2; }
browser=$(command -v chromium || command -v chromium-browser || true)
[[ -n $browser ]] || { echo "error: chromium not found (sudo apt-get install chromium)" >&2; exit 2; }
shot_abs=$(realpath -m "$shot")
# --no-sandbox: CI and containers run as root, where Chromium's sandbox refuses to start.
"$browser" --headless --no-sandbox --disable-gpu --hide-scrollbars --allow-file-access-from-files \
  --window-size=1200,"$height" --screenshot="$shot_abs" "file://$report" > /dev/null 2>&1
[[ -s $shot_abs ]] || { echo "error: chromium wrote no screenshot" >&2; exit 1; }
echo "$shot_abs"
