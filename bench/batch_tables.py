#!/usr/bin/env python3
"""Tables of bench/batch_bench.sh's runs: every OUT/<run>/metrics.json found.

    python3 bench/batch_tables.py OUT
"""
import pathlib
import re
import sys

from run_metrics import load


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


def exchange_bytes(n, ranks, views_per_rank):
    """What each rank sends a step (splat/train/batch_exchange.cpp): two slices of the 59·N
    gradient values to each other rank, and its views' statistics (8 + 3·N floats each)."""
    slice_ = -(-59 * n // ranks)
    return 4 * (ranks - 1) * (2 * slice_ + views_per_rank * (8 + 3 * n))


def projection(out):
    """Expected speed-up on K machines like this one, one view per machine a step, from a
    measured one-machine run: its time per view t and its Adam step a (ms), over a network of
    W Gbit/s counting the wire time only. One machine takes K·t + a for K views; K machines
    t + a + bytes/W."""
    sources = [p for p in sorted(out.glob("scaling-*-k1"), key=lambda p: int(p.name.split("-")[1]))]
    sources += [out / "lego-b1"]
    ks = (2, 4, 8, 16, 32)
    rows = []
    for path in sources:
        m = load(path)
        if not m:
            continue
        t = m["ms_per_iteration"]
        views = int(path.name.split("-")[-1][1:]) if path.name.startswith("lego-b") else 4
        adam = t["optimizer"]
        per_view = (t["total"] - adam) / views
        n = m["num_gaussians"]
        for gbit in (1, 10, 25):
            cells = []
            for k in ks:
                wire = exchange_bytes(n, k, 1) / (gbit * 1e9 / 8) * 1e3
                cells.append(f"{(k * per_view + adam) / (per_view + adam + wire):.1f}")
            rows.append(f"| {path.name} | {n:,} | {per_view:.1f} | {adam:.1f} | {gbit} | " + " | ".join(cells) + " |")
    if rows:
        print()
        print("| measured run | Gaussians | ms per view | Adam ms | Gbit/s | " + " | ".join(f"K = {k}" for k in ks) + " |")
        print("|---|---|---|---|---|" + "---|" * len(ks))
        print("\n".join(rows))


def main():
    out = pathlib.Path(sys.argv[1])
    quality(out)
    scenes(out)
    scaling(out)
    projection(out)


if __name__ == "__main__":
    main()
