#!/usr/bin/env python3
"""Tables of bench/strategy_bench.sh's runs: every OUT/<run>/metrics.json found.

    python3 bench/strategy_tables.py OUT
"""
import pathlib
import sys

from run_metrics import load


def summary(m):
    t = m.get("test", {})
    return (f"{m['iterations']:>6} it  {m['train_seconds']:7.1f} s  {m['num_gaussians']:>8} G  "
            f"{m['model_bytes'] / 2**20:6.1f} MiB  PSNR {t.get('psnr', float('nan')):6.3f}  "
            f"SSIM {t.get('ssim', float('nan')):.4f}")


def curve(m):
    rows = [h for h in m["history"] if "test_psnr" in h]
    return "\n".join(f"    {h['iteration']:>6} {h['seconds']:8.1f} s {h['num_gaussians']:>8} G "
                     f"{h['test_psnr']:7.3f} dB" for h in rows)


def main():
    out = pathlib.Path(sys.argv[1])
    for name in ("lego300", "lego-full", "official7k"):
        m = load(out / name)
        if m:
            print(f"{name:12} {m.get('strategy', '?'):9} {summary(m)}")
            if name == "lego-full":
                print(curve(m))
    pairs = {}
    for run in sorted(out.glob("scene-*-*")) + sorted(out.glob("real-*-*")):
        m = load(run)
        if m and run.is_dir():
            base, strategy = run.name.rsplit("-", 1)
            pairs.setdefault(base, {})[strategy] = m
    if pairs:
        print("\n| data | compact Gaussians | official Gaussians | ratio | compact PSNR | official PSNR | "
              "difference |\n|---|---|---|---|---|---|---|")
    for base, runs in pairs.items():
        c, o = runs.get("compact"), runs.get("official")
        if not (c and o):
            continue
        cg, og = c["num_gaussians"], o["num_gaussians"]
        cp, op = c["test"]["psnr"], o["test"]["psnr"]
        print(f"| {base} | {cg:,} | {og:,} | {cg / og:.2f} | {cp:.2f} | {op:.2f} | {cp - op:+.2f} |")


if __name__ == "__main__":
    main()
