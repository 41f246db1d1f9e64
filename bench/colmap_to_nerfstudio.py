#!/usr/bin/env python3
"""Writes a nerfstudio-layout copy of a COLMAP dataset, for the nerfstudio loader's benchmark.

    python3 bench/colmap_to_nerfstudio.py COLMAP_TXT_DIR IMAGES_DIR OUT_DIR

COLMAP_TXT_DIR holds cameras.txt, images.txt and points3D.txt (`colmap model_converter
--output_type TXT`); one OPENCV or PINHOLE camera. OUT_DIR gets transforms.json (camera-to-world
in OpenGL axes, the camera's intrinsics and distortion at file level), sparse_pc.ply (the points,
ASCII, as ns-process-data writes it) and a link to IMAGES_DIR as images/. Standard library only.
"""
import json
import math
import os
import sys


def rotation(qw, qx, qy, qz):
    n = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    w, x, y, z = qw / n, qx / n, qy / n, qz / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]


def data_lines(path):
    with open(path) as f:
        return [line.strip() for line in f if line.strip() and not line.startswith("#")]


def main(txt, images, out):
    cameras = data_lines(os.path.join(txt, "cameras.txt"))
    if len(cameras) != 1:
        sys.exit("one camera expected, got %d" % len(cameras))
    _, model, width, height, *params = cameras[0].split()
    params = [float(p) for p in params]
    root = {"w": int(width), "h": int(height), "ply_file_path": "sparse_pc.ply", "frames": []}
    if model == "OPENCV":
        root.update(camera_model="OPENCV", fl_x=params[0], fl_y=params[1], cx=params[2], cy=params[3],
                    k1=params[4], k2=params[5], p1=params[6], p2=params[7])
    elif model == "PINHOLE":
        root.update(camera_model="PINHOLE", fl_x=params[0], fl_y=params[1], cx=params[2], cy=params[3])
    else:
        sys.exit("camera model %s: OPENCV or PINHOLE expected" % model)
    image_lines = data_lines(os.path.join(txt, "images.txt"))
    for line in image_lines[0::2]:  # each image's second line lists its 2D points
        words = line.split()
        qw, qx, qy, qz, tx, ty, tz = (float(v) for v in words[1:8])
        r = rotation(qw, qx, qy, qz)  # world to camera, OpenCV axes
        centre = [-sum(r[k][i] * (tx, ty, tz)[k] for k in range(3)) for i in range(3)]
        # Camera to world: Rᵀ, with the y and z axes turned to OpenGL's.
        matrix = [[r[0][i], -r[1][i], -r[2][i], centre[i]] for i in range(3)] + [[0, 0, 0, 1]]
        root["frames"].append({"file_path": "images/" + " ".join(words[9:]), "transform_matrix": matrix})
    os.makedirs(out, exist_ok=True)
    points = data_lines(os.path.join(txt, "points3D.txt"))
    with open(os.path.join(out, "sparse_pc.ply"), "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\n" % len(points))
        f.write("".join("property float %s\n" % a for a in "xyz"))
        f.write("".join("property uint8 %s\n" % c for c in ("red", "green", "blue")))
        f.write("end_header\n")
        for line in points:
            w = line.split()
            f.write(" ".join(w[1:7]) + "\n")
    with open(os.path.join(out, "transforms.json"), "w") as f:
        json.dump(root, f, indent=1)
    link = os.path.join(out, "images")
    if not os.path.exists(link):
        os.symlink(os.path.abspath(images), link)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
