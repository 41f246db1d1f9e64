#!/usr/bin/env python3
"""Prints the test-PSNR-against-time curve of a splat-train metrics.json (P1), with the
Gaussian count and time per iteration, when each whole dB was first scored, and the best PSNR
reached within a time budget.

    python3 bench/history.py OUT/metrics.json [--budget-seconds 1200]
"""
import argparse
import json


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("metrics")
    parser.add_argument("--budget-seconds", type=float, default=1200.0)
    args = parser.parse_args()
    with open(args.metrics) as f:
        m = json.load(f)
    print(f"{'iteration':>9} {'train s':>8} {'gaussians':>9} {'ms/iter':>8} {'test PSNR':>9} {'SSIM':>7}")
    best_in_budget = None
    for h in m["history"]:
        ms = h.get("ms_per_iteration", {}).get("total")
        psnr = h.get("test_psnr")
        if psnr is not None and h["seconds"] <= args.budget_seconds:
            best_in_budget = max(best_in_budget or 0.0, psnr)
        if psnr is None and h["iteration"] % 1000:
            continue  # keep the table short: test points and every 1000th iteration
        print(f"{h['iteration']:>9} {h['seconds']:>8.1f} {h['num_gaussians']:>9} "
              f"{'' if ms is None else f'{ms:8.1f}':>8} "
              f"{'' if psnr is None else f'{psnr:9.3f}':>9} "
              f"{'' if h.get('test_ssim') is None else format(h['test_ssim'], '7.4f'):>7}")
    t = m.get("test", {})
    print(f"final: {m['iterations']} iterations, {m['train_seconds']:.1f} s, {m['num_gaussians']} Gaussians, "
          f"{m['model_bytes']} bytes, test PSNR {t.get('psnr', float('nan')):.3f} SSIM {t.get('ssim', float('nan')):.4f}, "
          f"peak memory {m.get('peak_memory_bytes', 0) / 2**20:.0f} MiB")
    if "ms_per_iteration" in m:
        parts = ", ".join(f"{k} {v:.1f}" for k, v in m["ms_per_iteration"].items())
        print(f"mean ms per iteration: {parts}")
    for level in m.get("time_to_psnr", []):
        print(f"{level['psnr']:.0f} dB first scored at iteration {level['iteration']}, "
              f"{level['seconds']:.1f} s (not yet at {level['after_seconds']:.1f} s)")
    if best_in_budget is not None:
        print(f"best test PSNR within {args.budget_seconds:.0f} s of training: {best_in_budget:.3f} dB")


if __name__ == "__main__":
    main()
