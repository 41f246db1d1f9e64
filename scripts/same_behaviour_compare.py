#!/usr/bin/env python3
"""Compares two output folders of scripts/same_behaviour.sh: every model, checkpoint, config and
test render byte for byte, and metrics.json with its timings and memory left out (wall-clock
figures differ from run to run; everything else must not). Prints each difference; exits 1 if
there is any.
    python3 scripts/same_behaviour_compare.py BEFORE AFTER"""
import filecmp
import json
import pathlib
import sys

# metrics.json keys that measure the machine, not the run's arithmetic.
TIMING_KEYS = {"train_seconds", "ms_per_iteration", "seconds", "peak_memory_bytes", "data"}


def without_timings(value):
    if isinstance(value, dict):
        return {k: without_timings(v) for k, v in value.items() if k not in TIMING_KEYS}
    if isinstance(value, list):
        return [without_timings(v) for v in value]
    return value


def main(before, after):
    before, after = pathlib.Path(before), pathlib.Path(after)
    differences = []
    files = sorted(p.relative_to(before) for p in before.rglob("*") if p.is_file())
    if not files:
        differences.append(f"{before}: no files")
    for name in files:
        a, b = before / name, after / name
        if not b.is_file():
            differences.append(f"{name}: missing in {after}")
        elif name.name == "metrics.json":
            if without_timings(json.loads(a.read_text())) != without_timings(json.loads(b.read_text())):
                differences.append(f"{name}: differs (timings aside)")
        elif not filecmp.cmp(a, b, shallow=False):
            differences.append(f"{name}: differs")
    extra = sorted(str(p.relative_to(after)) for p in after.rglob("*") if p.is_file() and not (before / p.relative_to(after)).exists())
    differences += [f"{name}: only in {after}" for name in extra]
    for line in differences:
        print(line)
    print(f"{len(files)} files compared, {len(differences)} difference(s)")
    return 1 if differences else 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
