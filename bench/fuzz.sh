#!/usr/bin/env bash
# bench/fuzz.sh [SECONDS_PER_TARGET [TARGET...]]: builds the libFuzzer targets of fuzz/ (clang, ASan +
# UBSan, in build-sanitize/ by scripts/sanitized-build.sh), runs each for SECONDS_PER_TARGET
# (default 60; TARGETs such as ply_fuzz run only those) from its seed corpus in fuzz/corpus/,
# and prints the executions and findings of each. Exits 1 if anything was found: a crash, a sanitizer report, an exception other than
# splat::Error, more than 1 GB of memory, or an input taking over 10 s. Findings are kept in
# build-sanitize/fuzz-findings/TARGET/; new corpus entries in build-sanitize/fuzz-corpus/TARGET/
# (the committed seeds are not touched). CI runs it for 5 s per target (scripts/test.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
build=build-sanitize
targets=("${@:2}")
if [ ${#targets[@]} -eq 0 ]; then
  for source in fuzz/*_fuzz.cpp; do targets+=("$(basename "$source" .cpp)"); done
fi

bash scripts/sanitized-build.sh "${targets[@]}"
source scripts/sanitizer-options.sh
export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1"
# The targets write each input to a file under TMPDIR: a folder of this run's, removed at the
# end, so jobs that a finding or a timeout ends abruptly leave nothing in /tmp.
export TMPDIR="$PWD/$build/fuzz-tmp"
rm -rf "$TMPDIR" && mkdir -p "$TMPDIR"
trap 'rm -rf "$TMPDIR"' EXIT
total_findings=0
printf '%-20s %14s %9s %s\n' target executions findings "corpus"
for target in "${targets[@]}"; do
  name="${target%_fuzz}"
  corpus="$build/fuzz-corpus/$name" findings="$build/fuzz-findings/$name" log="$build/fuzz-logs/$name.log"
  rm -rf "$findings"  # a finding counts in the run that found it
  mkdir -p "$corpus" "$findings" "$(dirname "$log")"
  [ -d "fuzz/corpus/$name" ] && cp -n fuzz/corpus/"$name"/* "$corpus"/ 2>/dev/null || true
  # -fork keeps going after a finding (so one bug does not hide the next) and records each.
  "$build/bin/$target" "$corpus" -fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 \
    -max_total_time="$seconds" -rss_limit_mb=1024 -malloc_limit_mb=1024 -timeout=10 \
    -artifact_prefix="$findings/" -print_final_stats=1 > "$log" 2>&1 || true
  executions=$( (grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" || true) | awk '{s += $2} END {print s + 0}')
  # In fork mode the per-job stats are summed from its "#N" progress lines instead.
  if [ "$executions" = 0 ]; then
    executions=$( (grep -o '^#[0-9]*' "$log" || true) | tr -d '#' | sort -n | tail -1)
  fi
  found=$(find "$findings" -type f | wc -l)
  total_findings=$((total_findings + found))
  printf '%-20s %14s %9d %s\n' "$name" "${executions:-0}" "$found" "$(ls "$corpus" | wc -l) inputs"
done
if [ "$total_findings" -gt 0 ]; then
  echo "fuzz: $total_findings finding(s); inputs in $build/fuzz-findings/, logs in $build/fuzz-logs/" >&2
  exit 1
fi
echo "fuzz: no findings"
