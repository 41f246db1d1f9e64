#!/usr/bin/env python3
"""Tables of bench/batch_bench.sh's runs: every OUT/<run>/metrics.json found.

    python3 bench/batch_tables.py OUT
"""
import json
import pathlib
import re
import sys


def load(path):
    try:
        with open(path / "metrics.json") as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def psnr(m):
    return m.get("test", {}).get("psnr", float("nan"))


def quality(out):
    rows = []
    for batch in (1, 2, 4):
        m = load(out / f"lego-b{batch}")
        if m:
            e = m.get("exchange", {})
            rows.append(f"| {batch} | {m['ranks']} | {m['iterations']:,} | {m['num_gaussians']:,} | {psnr(m):.3f} | "
                        f"{m['test']['ssim']:.4f} | {m['train_seconds']:.0f} | "
                        f"{m['ms_per_iteration'].get('exchange', 0):.1f} | {e.get('megabytes_sent', 0):.1f} | "
                        f"{e.get('rows_drawn_in_block', float('nan')):.3f} | "
                        f"{e.get('rows_drawn_in_batch', float('nan')):.3f} |")
    if rows:
        print("| batch | ranks | views | Gaussians | test PSNR | SSIM | training s | exchange ms/step "
              "| MB sent/rank/step | rows drawn in block | in batch |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
        print("\n".join(rows))
        print()


def scenes(out):
    names = sorted({re.sub(r"-b\d+$", "", p.name[len("scene-"):]) for p in out.glob("scene-*") if p.is_dir()})
    if not names:
        return
    print("| scene | batch 1 | batch 2 | batch 4 |")
    print("|---|---|---|---|")
    for name in names:
        cells = []
        for batch in (1, 2, 4):
            m = load(out / f"scene-{name}-b{batch}")
            cells.append(f"{psnr(m):.3f} ({m['num_gaussians']:,})" if m else "—")
        print(f"| {name} | " + " | ".join(cells) + " |")
    print()


def scaling(out):
    runs = sorted(out.glob("scaling-*-k*"), key=lambda p: (int(p.name.split("-")[1]), p.name))
    rows = []
    for path in runs:
        m = load(path)
        if not m:
            continue
        t = m["ms_per_iteration"]
        rows.append(f"| {m['num_gaussians']:,} | {m['ranks']} | {t['total']:.1f} | {t['forward']:.1f} | "
                    f"{t['backward']:.1f} | {t.get('exchange', 0):.1f} | {t['optimizer']:.1f} | "
                    f"{m.get('exchange', {}).get('megabytes_sent', float('nan')):.1f} | "
                    f"{m.get('exchange', {}).get('rows_drawn_in_block', float('nan')):.3f} |")
    if rows:
        print("| Gaussians (end) | ranks | ms per step of 4 views | forward | backward | exchange | optimizer "
              "| MB sent per rank per step | rows drawn in a block |")
        print("|---|---|---|---|---|---|---|---|---|")
        print("\n".join(rows))


def main():
    out = pathlib.Path(sys.argv[1])
    quality(out)
    scenes(out)
    scaling(out)


if __name__ == "__main__":
    main()
