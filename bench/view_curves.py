#!/usr/bin/env python3
"""Each test view's PSNR at every test point of a splat-train run (issue 40).

    python3 bench/view_curves.py RUN_FOLDER [RUN_FOLDER ...]

Reads metrics.json's `test_view_psnr` (splat-train since 2026-11-28) and prints one row per
test point: the views' PSNR, the mean and the Gaussian count. A mean that falls while most
views hold is a few views going wrong (on real captures: floaters in front of the close-up
test views); the table says which.
"""
import pathlib
import sys

from run_metrics import load


def table(folder):
    metrics = load(folder)
    if metrics is None:
        raise SystemExit(f"error: {folder}: no readable metrics.json")
    points = [h for h in metrics.get("history", []) if "test_view_psnr" in h]
    if not points:
        raise SystemExit(f"error: {folder}/metrics.json: no per-view scores (a run from before test_view_psnr)")
    names = list(points[-1]["test_view_psnr"])
    print(f"{folder}")
    print("iteration " + " ".join(f"{name[-7:]:>7}" for name in names) + "    mean  Gaussians")
    for h in points:
        views = " ".join(f"{h['test_view_psnr'].get(name, float('nan')):7.2f}" for name in names)
        print(f"{h['iteration']:9d} {views} {h['test_psnr']:7.2f} {h['num_gaussians']:10d}")


def main():
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    for folder in sys.argv[1:]:
        table(pathlib.Path(folder))


if __name__ == "__main__":
    main()
