#!/usr/bin/env python3
"""Generate splat's test scenes: our own glTF 2.0 models and the scene specs.

    python3 scenes/generate/make_scenes.py

writes scenes/models/*.gltf and scenes/<name>.json, then runs check_gltf.py on them.
Everything is built here from code (meshes, textures, materials): no third-party assets.
Python standard library only, and deterministic: rerunning gives identical bytes, so the
generated files can be committed and a diff shows any change.

The glTF we write is deliberately the small subset splat-scene reads (scenes/README.md):
one buffer embedded as a base64 data URI, triangle primitives with uint32 indices,
float32 POSITION (with min/max) / NORMAL / TEXCOORD_0, nodes with translation / rotation /
scale, pbrMetallicRoughness materials, PNG textures embedded as data URIs. Y is up.

The code is split by job, all in this directory: vectors.py (vector and quaternion helpers),
meshes.py (mesh builders), textures.py (PNG writer and textures), gltf_writer.py (glTF and
spec JSON writing); this file holds the scene definitions and main().
"""

import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
if HERE not in sys.path:  # the sibling modules below, from any working directory
    sys.path.insert(0, HERE)

from gltf_writer import (MODELS_DIR, SCENES_DIR, directional, material, node, orbit,  # noqa: E402
                         point, write_gltf, write_spec)
from meshes import box, cylinder, merge, plane, rod, torus, transformed, uv_sphere  # noqa: E402
from textures import (band_texture, fine_texture, floor_texture, png_bytes,  # noqa: E402
                      toy_texture, wall_texture)
from vectors import quat_axis_angle, quat_mul  # noqa: E402


# ---------------------------------------------------------------------------------------------
# The scenes. Units are arbitrary ("metres"); objects stay inside a sphere of radius 1.2
# around the origin (the NeRF baseline's box is +-1.5) unless a scene probes depth range.

def model_default():
    """The toy: textured letter box, banded sphere and a red cylinder on a round grey plinth."""
    images = {"toy_letters": png_bytes(toy_texture()), "toy_bands": png_bytes(band_texture())}
    materials = {
        "letters": material(texture="toy_letters", roughness=0.7),
        "bands": material(texture="toy_bands", roughness=0.4),
        "red": material((0.80, 0.12, 0.10, 1), roughness=0.5),
        "plinth": material((0.55, 0.55, 0.58, 1), roughness=0.9),
    }
    sphere = uv_sphere(1.0)  # unit sphere, sized by the node's uniform scale
    nodes = [
        # Plinth: radius 0.9, 0.12 thick, top face at y = -0.5.
        node("plinth", cylinder(0.9, 0.12, 64), "plinth", translation=(0, -0.56, 0)),
        # Box 0.7 on a side, standing on the plinth, turned 25 degrees about Y.
        node("letter_box", box(0.7, 0.7, 0.7), "letters", translation=(-0.3, -0.15, 0.15),
             rotation=quat_axis_angle((0, 1, 0), 25)),
        # Sphere radius 0.3 resting on the plinth, tilted so its bands are not axis-aligned.
        node("banded_sphere", sphere, "bands", translation=(0.5, -0.2, 0.25),
             rotation=quat_axis_angle((1, 0, 1), 20), scale=(0.3, 0.3, 0.3)),
        # Cylinder radius 0.15, height 0.8, behind the others.
        node("red_cylinder", cylinder(0.15, 0.8), "red", translation=(0.3, -0.1, -0.45)),
    ]
    return nodes, materials, images


def model_fine_texture():
    """A 1.3 cube wearing the 512x512 high-frequency texture on every face, turned so that
    three faces show at once."""
    images = {"fine": png_bytes(fine_texture())}
    materials = {"fine": material(texture="fine", roughness=0.8)}
    rot = quat_mul(quat_axis_angle((0, 1, 0), 30), quat_axis_angle((1, 0, 0), 15))
    nodes = [node("fine_cube", box(1.3, 1.3, 1.3), "fine", rotation=rot)]
    return nodes, materials, images


def model_thin_structures():
    """A cubic lattice of square bars 12-13 mm thick (5 bars per edge direction), a ring of
    3 mm wire round it, and a fan of wires 2-16 mm thick from a small hub on top."""
    materials = {
        "bars_x": material((0.85, 0.20, 0.15, 1), roughness=0.6),
        "bars_y": material((0.20, 0.70, 0.25, 1), roughness=0.6),
        "bars_z": material((0.20, 0.35, 0.85, 1), roughness=0.6),
        "wire": material((0.90, 0.85, 0.75, 1), metallic=0.0, roughness=0.5),
        "hub": material((0.25, 0.25, 0.25, 1), roughness=0.7),
    }
    side, n = 1.0, 5
    # 12, 12.5 and 13 mm for the x, y and z bars: where bars cross, no two faces of different
    # colours are coplanar (coplanar faces would z-fight in the ray tracer).
    tx, ty, tz = 0.012, 0.0125, 0.013
    coords = [-side / 2 + k * side / (n - 1) for k in range(n)]
    bars = {"bars_x": [], "bars_y": [], "bars_z": []}
    for a in coords:
        for b in coords:
            bars["bars_x"].append(transformed(box(side + tx, tx, tx), translation=(0, a, b)))
            bars["bars_y"].append(transformed(box(ty, side + ty, ty), translation=(a, 0, b)))
            bars["bars_z"].append(transformed(box(tz, tz, side + tz), translation=(a, b, 0)))
    nodes = [node(k, merge(v), k) for k, v in sorted(bars.items())]
    # Equatorial ring of wire, radius 1.0, tube radius 1.5 mm (3 mm thick).
    nodes.append(node("ring", torus(1.0, 0.0015, 128, 8), "wire",
                      rotation=quat_axis_angle((1, 0, 0), 10)))
    # Fan of 8 wires from a hub above the lattice, thickness doubling every two wires.
    hub = (0.0, 0.75, 0.0)
    wires = []
    for k in range(8):
        ang = k / 8 * 2 * math.pi
        end = (0.95 * math.cos(ang), 0.3, 0.95 * math.sin(ang))
        wires.append(rod(hub, end, 0.001 * 2 ** (k // 2)))  # radius 1, 1, 2, 2, ... 8 mm
    nodes.append(node("wire_fan", merge(wires), "wire"))
    nodes.append(node("hub", uv_sphere(0.03, 16, 8), "hub", translation=hub))
    return nodes, materials, {}


def model_shiny():
    """A polished gold torus (metallic 1, roughness 0.15) round a glossy red ball, on a matte
    plinth: highlights that move with the viewpoint."""
    materials = {
        "gold": material((1.0, 0.78, 0.34, 1), metallic=1.0, roughness=0.15),
        "gloss_red": material((0.7, 0.05, 0.05, 1), metallic=0.0, roughness=0.08),
        "plinth": material((0.45, 0.45, 0.48, 1), roughness=0.95),
    }
    nodes = [
        # Torus: ring radius 0.72, tube 0.24 (outer radius 0.96), stood up 60 degrees.
        # Its lowest point is at 0.1 - (0.72 sin 60 + 0.24) = -0.7635: it rests on the plinth.
        node("gold_torus", torus(0.72, 0.24), "gold", translation=(0, 0.1, 0),
             rotation=quat_axis_angle((1, 0, 0), 60)),
        node("red_ball", uv_sphere(0.3, 64, 32), "gloss_red", translation=(0, 0.1, 0)),
        node("plinth", cylinder(0.8, 0.1, 64), "plinth", translation=(0, -0.813, 0)),  # top -0.763
    ]
    return nodes, materials, {}


def model_depth_range():
    """The toy's box and sphere near the origin inside an enclosure: a floor 30 wide and a
    brick wall (inward-facing cylinder radius 12, 8 high) far outside the unit sphere, with
    six pillars at radius 6 for intermediate depths."""
    images = {"toy_letters": png_bytes(toy_texture()), "toy_bands": png_bytes(band_texture()),
              "floor": png_bytes(floor_texture()), "brick": png_bytes(wall_texture())}
    materials = {
        "letters": material(texture="toy_letters", roughness=0.7),
        "bands": material(texture="toy_bands", roughness=0.4),
        "floor": material(texture="floor", roughness=0.9),
        "brick": material(texture="brick", roughness=0.9),
        "pillar": material((0.85, 0.82, 0.70, 1), roughness=0.8),
    }
    pillar = cylinder(0.25, 4.0, 24)
    nodes = [
        node("letter_box", box(0.6, 0.6, 0.6), "letters", translation=(-0.25, -0.7, 0.1),
             rotation=quat_axis_angle((0, 1, 0), 25)),
        node("banded_sphere", uv_sphere(0.3), "bands", translation=(0.4, -0.7, -0.1)),
        # Floor at y = -1: 30 x 30, checker tile repeated every 1 unit. Split into 1-unit
        # squares so rasterizers that clip whole triangles at the near plane still draw it.
        node("floor", plane(30.0, 30.0, uv_repeat=30.0, divisions=30), "floor",
             translation=(0, -1.0, 0)),
        # Wall: radius 12, from y = -1 to y = 7; bricks repeated 24 times round, 4 up.
        node("wall", cylinder(12.0, 8.0, 96, caps=False, inward=True, u_repeat=24.0,
                              v_repeat=4.0), "brick", translation=(0, 3.0, 0)),
    ]
    for k in range(6):
        ang = (k + 0.5) / 6 * 2 * math.pi
        nodes.append(node("pillar_%d" % k, pillar, "pillar",
                          translation=(6 * math.cos(ang), 1.0, 6 * math.sin(ang))))
    return nodes, materials, images


def model_simple():
    """Three matte solid-coloured shapes, no texture: a few thousand Gaussians suffice."""
    materials = {
        "red": material((0.80, 0.15, 0.12, 1), roughness=0.9),
        "green": material((0.20, 0.65, 0.25, 1), roughness=0.9),
        "blue": material((0.15, 0.30, 0.80, 1), roughness=0.9),
    }
    nodes = [
        node("red_box", box(0.7, 0.7, 0.7), "red", translation=(-0.35, -0.35, 0.1),
             rotation=quat_axis_angle((0, 1, 0), 20)),
        node("green_sphere", uv_sphere(0.35), "green", translation=(0.5, -0.35, 0.3)),
        node("blue_box", box(0.5, 0.9, 0.5), "blue", translation=(0.3, -0.25, -0.45),
             rotation=quat_axis_angle((0, 1, 0), -15)),
    ]
    return nodes, materials, {}


# ---------------------------------------------------------------------------------------------

def main():
    os.makedirs(MODELS_DIR, exist_ok=True)
    models = {"default": model_default, "fine_texture": model_fine_texture,
              "thin_structures": model_thin_structures, "shiny": model_shiny,
              "depth_range": model_depth_range, "simple": model_simple}
    for name, build in models.items():
        nodes, materials, images = build()
        write_gltf(os.path.join(MODELS_DIR, name + ".gltf"), nodes, materials, images)

    # Key light from above-front-left, a warm point fill, soft ambient: the usual setup.
    key = directional((-0.3, -1.0, -0.5), 2.0)
    fill = point((2.0, 3.0, 2.0), 20.0, (1.0, 0.95, 0.9))
    amb = [0.25, 0.25, 0.25]
    std = dict(radius=4.0, elevation=(10, 60), fov=40, size=(200, 200))
    # The toy and the simple shapes sit on the ground (y ~ -0.5 .. -0.7): aim a little below
    # the origin and come closer so they fill the frame.
    low = dict(radius=3.5, elevation=(10, 60), fov=40, size=(200, 200), target=(0, -0.2, 0))

    write_spec("default", "Textured toy (letter box, banded sphere, cylinder, plinth): "
               "the main demo scene, mid-frequency texture on a few simple shapes.",
               "models/default.gltf", orbit(train=60, test=12, **low), [key, fill], amb, None)
    write_spec("fine_texture", "High-frequency texture (stripes to 2 texels, 4-texel checker, "
               "zone plate, block noise at 512x512) on a cube: fine detail and aliasing.",
               "models/fine_texture.gltf",
               orbit(3.6, (10, 50), 40, (256, 256), 60, 12), [key, fill], amb, None)
    write_spec("thin_structures", "Thin structures: a lattice of 12-13 mm bars, a 3 mm wire ring "
               "and a fan of 2-16 mm wires.", "models/thin_structures.gltf",
               orbit(train=60, test=12, **std), [key, fill], [0.3, 0.3, 0.3], None)
    write_spec("shiny", "View-dependent appearance: polished gold torus and glossy red ball "
               "under a bright point light (highlights move with the view).",
               "models/shiny.gltf", orbit(train=60, test=12, **std),
               [point((1.5, 2.5, 2.0), 40.0), directional((0.4, -1.0, 0.3), 0.6)],
               [0.12, 0.12, 0.12], None)
    write_spec("depth_range", "Large depth range: a near toy at the centre, pillars at 6 and a "
               "brick wall at 12 units, floor to the wall (well outside the unit sphere).",
               "models/depth_range.gltf",
               orbit(4.0, (5, 25), 60, (200, 200), 60, 12, target=(0, -0.4, 0)),
               [directional((-0.4, -1.0, -0.3), 2.0)], [0.35, 0.35, 0.38], [0.55, 0.68, 0.85])
    write_spec("few_views", "Sparse views: the default toy with only 8 training views.",
               "models/default.gltf", orbit(train=8, test=12, **low), [key, fill], amb, None)
    write_spec("simple", "Simple scene: three matte solid-coloured untextured shapes, meant "
               "to need only a few thousand Gaussians.", "models/simple.gltf",
               orbit(train=60, test=12, **low), [key, fill], amb, None)

    import check_gltf  # same directory; re-reads everything just written
    if not check_gltf.check_all(SCENES_DIR):
        raise SystemExit("self-check failed")


if __name__ == "__main__":
    main()
