#!/usr/bin/env python3
"""Where a trained model's Gaussians sit relative to the training cameras (issue 40).

    python3 bench/gaussian_census.py [--view NAME] MODEL.ply COLMAP_DATASET [MODEL2.ply ...]

For every Gaussian: the smallest ratio, over the cameras that see its centre inside their
frame, of its depth to that camera's median depth of the model (1 = as far as the scene the
camera looks at; 0.2 = a fifth of the way, in front of it). Gaussians seen by no camera are
counted apart. The table gives, per band of that ratio, the count, the opacity-weighted count
(what is drawn), mean opacity and the median of the largest axis relative to the scene
radius: floaters in front of the cameras show as many opaque Gaussians in the near bands.
The test split (every 8th image in name order) is left out, as splat-train does; with
--view NAME (an image name without its extension, training or test) that one camera alone is
used: what sits in front of a test view that renders badly.
Plain Python (no numpy): a 150k-Gaussian model against 70 cameras takes about a minute.
"""
import math
import struct
import sys


def read_ply(path):
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        count = 0
        names = []
        for line in header:
            parts = line.split()
            if parts[:2] == ["element", "vertex"]:
                count = int(parts[2])
            elif parts and parts[0] == "property":
                if parts[1] != "float":
                    raise SystemExit(f"error: {path}: only float vertex properties are read")
                names.append(parts[2])
        if "binary_little_endian" not in " ".join(header):
            raise SystemExit(f"error: {path}: not a binary little-endian PLY")
        row = struct.Struct("<" + "f" * len(names))
        data = f.read(row.size * count)
    index = {n: i for i, n in enumerate(names)}
    out = []
    for k in range(count):
        v = row.unpack_from(data, k * row.size)
        position = (v[index["x"]], v[index["y"]], v[index["z"]])
        opacity = 1.0 / (1.0 + math.exp(-max(-60.0, min(60.0, v[index["opacity"]]))))
        size = math.exp(max(v[index["scale_0"]], v[index["scale_1"]], v[index["scale_2"]]))
        out.append((position, opacity, size))
    return out


def quaternion_matrix(w, x, y, z):
    return ((1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
            (2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
            (2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)))


def read_cameras(dataset, view=None):
    """Training cameras, or the one named `view`: (name, R, t, (fx, fy, cx, cy, w, h))."""
    intrinsics = {}
    with open(f"{dataset}/sparse/0/cameras.bin", "rb") as f:
        (n,) = struct.unpack("<Q", f.read(8))
        params_per_model = {0: 3, 1: 4, 2: 4, 3: 5, 4: 8}
        for _ in range(n):
            cid, model, w, h = struct.unpack("<iiQQ", f.read(24))
            p = struct.unpack("<" + "d" * params_per_model[model], f.read(8 * params_per_model[model]))
            if model in (0, 2, 3):  # SIMPLE_PINHOLE, SIMPLE_RADIAL, RADIAL: f, cx, cy
                intrinsics[cid] = (p[0], p[0], p[1], p[2], w, h)
            else:  # PINHOLE, OPENCV: fx, fy, cx, cy
                intrinsics[cid] = (p[0], p[1], p[2], p[3], w, h)
    images = []
    with open(f"{dataset}/sparse/0/images.bin", "rb") as f:
        (n,) = struct.unpack("<Q", f.read(8))
        for _ in range(n):
            iid, qw, qx, qy, qz, tx, ty, tz, cid = struct.unpack("<idddddddi", f.read(64))
            name = b""
            while (c := f.read(1)) != b"\0":
                name += c
            (points,) = struct.unpack("<Q", f.read(8))
            f.read(24 * points)
            images.append((name.decode(), quaternion_matrix(qw, qx, qy, qz), (tx, ty, tz), intrinsics[cid]))
    images.sort(key=lambda image: image[0])
    if view is not None:
        chosen = [image for image in images if image[0].rsplit(".", 1)[0] == view]
        if not chosen:
            raise SystemExit(f"error: {dataset}: no image named {view}")
        return chosen
    return [image for i, image in enumerate(images) if i % 8 != 0]


def census(model, cameras):
    depths = []  # per camera, the depth of every Gaussian whose centre it sees
    per_gaussian = [[] for _ in model]
    for name, r, t, (fx, fy, cx, cy, w, h) in cameras:
        seen = []
        for g, (p, _, _) in enumerate(model):
            z = r[2][0] * p[0] + r[2][1] * p[1] + r[2][2] * p[2] + t[2]
            if z <= 1e-6:
                continue
            u = fx * (r[0][0] * p[0] + r[0][1] * p[1] + r[0][2] * p[2] + t[0]) / z + cx
            if not 0 <= u < w:
                continue
            v = fy * (r[1][0] * p[0] + r[1][1] * p[1] + r[1][2] * p[2] + t[1]) / z + cy
            if not 0 <= v < h:
                continue
            seen.append((g, z))
        if not seen:
            continue
        median = sorted(z for _, z in seen)[len(seen) // 2]
        for g, z in seen:
            per_gaussian[g].append(z / median)
    return [min(ratios) if ratios else None for ratios in per_gaussian]


def scene_radius(cameras):
    centres = []
    for _, r, t, _ in cameras:  # centre = -R^T t
        centres.append(tuple(-sum(r[row][col] * t[row] for row in range(3)) for col in range(3)))
    mean = tuple(sum(c[a] for c in centres) / len(centres) for a in range(3))
    return 1.1 * max(math.dist(c, mean) for c in centres)


BANDS = [(0.0, 0.2), (0.2, 0.4), (0.4, 0.7), (0.7, 1.5), (1.5, float("inf"))]


def report(path, model, ratios, radius):
    print(f"{path}: {len(model)} Gaussians, scene radius {radius:.3f}")
    print("  depth/median  count   share  drawn(Σopacity)  mean opacity  median size/radius")
    rows = [(f"{lo:.1f}-{hi:.1f}", [g for g, q in zip(model, ratios) if q is not None and lo <= q < hi])
            for lo, hi in BANDS]
    rows.append(("unseen", [g for g, q in zip(model, ratios) if q is None]))
    for label, members in rows:
        if not members:
            print(f"  {label:>12}  {0:6d}")
            continue
        drawn = sum(o for _, o, _ in members)
        sizes = sorted(s for _, _, s in members)
        print(f"  {label:>12}  {len(members):6d}  {100 * len(members) / len(model):5.1f}%  {drawn:14.0f}"
              f"  {drawn / len(members):12.3f}  {sizes[len(sizes) // 2] / radius:18.5f}")


def main():
    args = sys.argv[1:]
    view = None
    if args[:1] == ["--view"] and len(args) > 1:
        view, args = args[1], args[2:]
    if len(args) < 2:
        raise SystemExit(__doc__)
    radius = scene_radius(read_cameras(args[1]))
    cameras = read_cameras(args[1], view)
    for path in [args[0]] + args[2:]:
        model = read_ply(path)
        report(path, model, census(model, cameras), radius)


if __name__ == "__main__":
    main()
