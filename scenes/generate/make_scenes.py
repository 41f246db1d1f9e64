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
"""

import base64
import json
import math
import os
import struct
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES_DIR = os.path.dirname(HERE)
MODELS_DIR = os.path.join(SCENES_DIR, "models")


# ---------------------------------------------------------------------------------------------
# Small vector helpers (tuples of floats).

def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def mul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(a):
    n = math.sqrt(dot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


def quat_axis_angle(axis, degrees):
    """Quaternion (x, y, z, w) for a rotation about `axis`: glTF's node rotation order."""
    ax = normalize(axis)
    h = math.radians(degrees) / 2
    s = math.sin(h)
    return (ax[0] * s, ax[1] * s, ax[2] * s, math.cos(h))


def quat_mul(a, b):
    """a * b: rotate by b first, then by a."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def quat_rotate(q, v):
    """Rotate vector v by unit quaternion q (v' = q v q*)."""
    qv = (q[0], q[1], q[2])
    t = mul(cross(qv, v), 2.0)
    return add(add(v, mul(t, q[3])), cross(qv, t))


# ---------------------------------------------------------------------------------------------
# Meshes: a mesh is a dict of parallel vertex lists (positions, normals, uvs) and a flat
# triangle index list. Builders emit triangles through add_triangle, which orients each one
# counter-clockwise as seen from the side its normals point to, so no builder has to get the
# winding right by hand (glTF front faces are CCW).

def new_mesh():
    return {"p": [], "n": [], "t": [], "i": []}


def add_vertex(m, p, n, uv):
    m["p"].append(tuple(float(x) for x in p))
    m["n"].append(normalize(n))
    m["t"].append((float(uv[0]), float(uv[1])))
    return len(m["p"]) - 1


def add_triangle(m, a, b, c):
    """Add triangle (a, b, c); skip degenerate ones (e.g. at sphere poles); fix the winding."""
    pa, pb, pc = m["p"][a], m["p"][b], m["p"][c]
    face = cross(sub(pb, pa), sub(pc, pa))
    if dot(face, face) < 1e-20:
        return
    avg_n = add(add(m["n"][a], m["n"][b]), m["n"][c])
    if dot(face, avg_n) < 0:
        b, c = c, b
    m["i"].extend((a, b, c))


def add_quad(m, a, b, c, d):
    """Quad a-b-c-d (in order around its boundary) as two triangles."""
    add_triangle(m, a, b, c)
    add_triangle(m, a, c, d)


def param_surface(nu, nv, f, m=None):
    """Grid surface: f(u, v) -> (position, normal) for u, v in [0, 1]; texture uv = (u, v).

    Seam vertices are duplicated (u = 0 and u = 1) so texture coordinates stay continuous.
    """
    m = m if m is not None else new_mesh()
    base = len(m["p"])
    for j in range(nv + 1):
        for i in range(nu + 1):
            u, v = i / nu, j / nv
            p, n = f(u, v)
            add_vertex(m, p, n, (u, v))
    row = nu + 1
    for j in range(nv):
        for i in range(nu):
            a = base + j * row + i
            add_quad(m, a, a + 1, a + 1 + row, a + row)
    return m


def box(sx, sy, sz, uv_scale=1.0):
    """Axis-aligned box centred at the origin. Each face carries the whole texture, upright
    when seen from outside (u to the right, v downwards, as glTF's uv origin is top-left)."""
    h = (sx / 2, sy / 2, sz / 2)
    m = new_mesh()
    # (outward normal, texture right axis, texture down axis) per face.
    faces = [((1, 0, 0), (0, 0, -1), (0, -1, 0)), ((-1, 0, 0), (0, 0, 1), (0, -1, 0)),
             ((0, 1, 0), (1, 0, 0), (0, 0, 1)), ((0, -1, 0), (1, 0, 0), (0, 0, -1)),
             ((0, 0, 1), (1, 0, 0), (0, -1, 0)), ((0, 0, -1), (-1, 0, 0), (0, -1, 0))]
    for n, ru, dv in faces:
        hn = abs(dot(n, h))
        hu = abs(dot(ru, h))
        hv = abs(dot(dv, h))
        centre = mul(n, hn)
        idx = []
        for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            p = add(centre, add(mul(ru, a * hu), mul(dv, b * hv)))
            idx.append(add_vertex(m, p, n, ((a + 1) / 2 * uv_scale, (b + 1) / 2 * uv_scale)))
        add_quad(m, *idx)
    return m


def uv_sphere(radius, segments=48, rings=24):
    """Sphere around the origin; u runs around Y (longitude), v from the top pole down."""
    def f(u, v):
        theta, phi = v * math.pi, u * 2 * math.pi
        n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
        return mul(n, radius), n
    return param_surface(segments, rings, f)


def cylinder(radius, height, segments=40, caps=True, inward=False, v_repeat=1.0, u_repeat=1.0):
    """Cylinder along Y centred at the origin. inward=True flips the normals (seen from inside,
    as for an enclosing wall); caps get their own vertices so their normals stay flat."""
    sign = -1.0 if inward else 1.0

    def f(u, v):
        phi = u * 2 * math.pi
        n = (math.cos(phi), 0.0, -math.sin(phi))
        return (radius * n[0], height / 2 - v * height, radius * n[2]), mul(n, sign)
    m = param_surface(segments, 1, f)
    # Scale the side's uvs for repeating textures (the sampler wraps).
    m["t"] = [(u * u_repeat, v * v_repeat) for u, v in m["t"]]
    if caps:
        for y, ny in ((height / 2, 1.0), (-height / 2, -1.0)):
            centre = add_vertex(m, (0, y, 0), (0, ny, 0), (0.5, 0.5))
            ring = []
            for k in range(segments):
                phi = k / segments * 2 * math.pi
                c, s = math.cos(phi), -math.sin(phi)
                ring.append(add_vertex(m, (radius * c, y, radius * s), (0, ny, 0),
                                       (0.5 + 0.5 * c, 0.5 + 0.5 * s)))
            for k in range(segments):
                add_triangle(m, centre, ring[k], ring[(k + 1) % segments])
    return m


def plane(sx, sz, uv_repeat=1.0, divisions=1):
    """Horizontal plane (normal +Y) centred at the origin; uvs repeat uv_repeat times."""
    def f(u, v):
        return ((u - 0.5) * sx, 0.0, (v - 0.5) * sz), (0.0, 1.0, 0.0)
    m = param_surface(divisions, divisions, f)
    m["t"] = [(u * uv_repeat, v * uv_repeat) for u, v in m["t"]]
    return m


def torus(major, minor, segments=64, sides=32):
    """Torus around the Y axis: ring radius `major`, tube radius `minor`."""
    def f(u, v):
        phi, theta = u * 2 * math.pi, v * 2 * math.pi
        n = (math.cos(theta) * math.cos(phi), math.sin(theta), -math.cos(theta) * math.sin(phi))
        ring = (major * math.cos(phi), 0.0, -major * math.sin(phi))
        return add(ring, mul(n, minor)), n
    return param_surface(segments, sides, f)


def transformed(m, rotation=(0, 0, 0, 1), translation=(0, 0, 0), scale=1.0):
    """Copy of mesh m with a rigid transform + uniform scale baked into its vertices (used to
    merge many small parts, e.g. lattice bars, into one mesh instead of hundreds of nodes)."""
    out = new_mesh()
    out["p"] = [add(quat_rotate(rotation, mul(p, scale)), translation) for p in m["p"]]
    out["n"] = [quat_rotate(rotation, n) for n in m["n"]]
    out["t"] = list(m["t"])
    out["i"] = list(m["i"])
    return out


def merge(meshes):
    out = new_mesh()
    for m in meshes:
        base = len(out["p"])
        out["p"] += m["p"]
        out["n"] += m["n"]
        out["t"] += m["t"]
        out["i"] += [base + i for i in m["i"]]
    return out


def rod(a, b, radius, segments=12):
    """Thin capped cylinder from point a to point b (a wire)."""
    d = sub(b, a)
    length = math.sqrt(dot(d, d))
    y = (0.0, 1.0, 0.0)
    axis = cross(y, d)
    if dot(axis, axis) < 1e-12:  # already along +-Y
        rot = (0, 0, 0, 1) if d[1] > 0 else quat_axis_angle((1, 0, 0), 180)
    else:
        rot = quat_axis_angle(axis, math.degrees(math.acos(max(-1, min(1, d[1] / length)))))
    return transformed(cylinder(radius, length, segments), rot, mul(add(a, b), 0.5))


# ---------------------------------------------------------------------------------------------
# Textures: images are lists of rows of (r, g, b) tuples, written as 8-bit RGB PNG.

def png_bytes(pixels):
    """Encode an RGB image as PNG: filter type 0 on every row, zlib level 9 (deterministic)."""
    height, width = len(pixels), len(pixels[0])
    raw = bytearray()
    for row in pixels:
        raw.append(0)
        for r, g, b in row:
            raw += bytes((r, g, b))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr)
            + chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b""))


def image(width, height, f):
    return [[f(x, y) for x in range(width)] for y in range(height)]


def hash01(*ints):
    """Deterministic integer hash -> [0, 1): our own 'noise', no random module state."""
    h = 2166136261
    for v in ints:
        h = ((h ^ (v & 0xFFFFFFFF)) * 16777619) & 0xFFFFFFFF
        h ^= h >> 13
        h = (h * 0x5BD1E995) & 0xFFFFFFFF
        h ^= h >> 15
    return h / 2.0 ** 32


def hsv(h, s, v):
    """HSV in [0,1] -> 8-bit RGB tuple."""
    i = int(h * 6) % 6
    f = h * 6 - int(h * 6)
    p, q, t = v * (1 - s), v * (1 - f * s), v * (1 - (1 - f) * s)
    r, g, b = [(v, t, p), (q, v, p), (p, v, t), (p, q, v), (t, p, v), (v, p, q)][i]
    return (round(r * 255), round(g * 255), round(b * 255))


# 5x7 block glyphs for the toy's texture: asymmetric letters make every face and its
# orientation recognisable, which helps both pose sanity checks and the eye.
GLYPHS = {
    "S": ["01111", "10000", "10000", "01110", "00001", "00001", "11110"],
    "P": ["11110", "10001", "10001", "11110", "10000", "10000", "10000"],
    "L": ["10000", "10000", "10000", "10000", "10000", "10000", "11111"],
    "A": ["01110", "10001", "10001", "11111", "10001", "10001", "10001"],
    "T": ["11111", "00100", "00100", "00100", "00100", "00100", "00100"],
    "F": ["11111", "10000", "10000", "11110", "10000", "10000", "10000"],
    "R": ["11110", "10001", "10001", "11110", "10100", "10010", "10001"],
    "G": ["01111", "10000", "10000", "10111", "10001", "10001", "01110"],
}


def toy_texture(size=256):
    """4x4 tiles of different hues, each holding a block letter; a thin dark grid between
    tiles. Mid-frequency detail that a couple of minutes of training can reproduce."""
    tile = size // 4
    cell = tile // 8  # glyph cell size in texels: a 5x7 glyph inside an 8x8-cell tile
    letters = "SPLATFRGSPLATFRG"

    def f(x, y):
        tx, ty = x // tile, y // tile
        k = ty * 4 + tx
        lx, ly = x % tile, y % tile
        if lx < 2 or ly < 2:
            return (30, 30, 35)
        base = hsv((k * 0.27) % 1.0, 0.55, 0.95)
        # Glyph cells: columns 1..5 and rows 0..6 of the tile (offset half a cell down).
        gx, gy = lx // cell - 1, (ly - cell // 2) // cell
        if 0 <= gx < 5 and 0 <= gy < 7 and ly >= cell // 2 and GLYPHS[letters[k]][gy][gx] == "1":
            return (250, 250, 245) if k % 2 else (25, 25, 30)
        return base
    return image(size, size, f)


def band_texture(width=128, height=64):
    """Sphere texture: 8 coloured longitude segments, a white equator and dark polar caps,
    so its rotation is visible from every side."""
    def f(x, y):
        v = y / height
        if abs(v - 0.5) < 0.04:
            return (245, 245, 245)
        if v < 0.12 or v > 0.88:
            return (40, 40, 50)
        seg = x * 8 // width
        return hsv(seg / 8, 0.75 if v < 0.5 else 0.45, 0.9)
    return image(width, height, f)


def fine_texture(size=512):
    """Four quadrants of high-frequency detail at 512x512: (top-left) stripe bands whose period
    halves from 32 to 2 texels, (top-right) a dense 4-texel checker, (bottom-left) a zone plate
    (a chirp from low frequency to one cycle per two texels), (bottom-right) coloured block
    noise in 4-texel blocks. Each is 1-pixel-scale or finer in a 256x256 view of the cube."""
    half = size // 2

    def f(x, y):
        qx, qy = x // half, y // half
        lx, ly = x % half, y % half
        if qx == 0 and qy == 0:
            period = 32 >> min(4, ly * 5 // half)  # 32, 16, 8, 4, 2 texels
            on = (lx // (period // 2)) % 2 == 0
            return (235, 235, 225) if on else (20, 30, 60)
        if qx == 1 and qy == 0:
            on = ((lx // 4) + (ly // 4)) % 2 == 0
            return (240, 200, 40) if on else (30, 20, 20)
        if qx == 0 and qy == 1:
            r2 = (lx - half / 2) ** 2 + (ly - half / 2) ** 2
            # Phase pi * r^2 / (half/2): local frequency reaches 0.5 cycles/texel at the
            # quadrant's inscribed circle (the corners beyond it alias in the texture itself,
            # which is fine: they are a known-aliased reference).
            c = 0.5 + 0.5 * math.cos(math.pi * r2 / (half / 2) / 2)
            g = round(20 + 215 * c)
            return (g, g, g)
        h = hash01(lx // 4, ly // 4, 7)
        return hsv(h, 0.8, 0.35 + 0.6 * hash01(lx // 4, ly // 4, 11))
    return image(size, size, f)


def floor_texture(size=64):
    """Tile for the depth scene's floor (repeated many times by the sampler): a grey checker
    with a dark grout line, so perspective foreshortening is visible out to the far wall."""
    def f(x, y):
        if x < 2 or y < 2:
            return (50, 50, 55)
        on = ((x * 2 // size) + (y * 2 // size)) % 2 == 0
        return (190, 185, 175) if on else (120, 125, 130)
    return image(size, size, f)


def wall_texture(size=128):
    """Tile for the far wall: brick courses with per-brick colour variation."""
    def f(x, y):
        course = y // (size // 8)
        off = (size // 8) if course % 2 else 0
        bx = (x + off) % size
        if y % (size // 8) < 2 or bx % (size // 4) < 2:
            return (200, 195, 185)  # mortar
        brick = ((x + off) // (size // 4)) % 4
        t = hash01(course, brick, 3)
        return (round(140 + 60 * t), round(60 + 30 * t), round(45 + 20 * t))
    return image(size, size, f)


# ---------------------------------------------------------------------------------------------
# glTF writer.

def f32(x):
    """Round a Python float to float32, so min/max equal exactly what the buffer holds."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def material(color=(1, 1, 1, 1), texture=None, metallic=0.0, roughness=0.8):
    """A material description; `texture` is a PNG image name (key into the images dict)."""
    return {"color": color, "texture": texture, "metallic": metallic, "roughness": roughness}


def node(name, mesh, mat, translation=None, rotation=None, scale=None):
    return {"name": name, "mesh": mesh, "material": mat, "translation": translation,
            "rotation": rotation, "scale": scale}


def write_gltf(path, nodes, materials, images):
    """Write nodes (each one mesh with one material) as a self-contained .gltf file.

    Meshes shared by several nodes (same Python object, same material) are written once.
    """
    buf = bytearray()
    doc = {"asset": {"version": "2.0", "generator": "splat scenes/generate/make_scenes.py"},
           "scene": 0, "scenes": [{"name": os.path.splitext(os.path.basename(path))[0],
                                   "nodes": list(range(len(nodes)))}],
           "nodes": [], "meshes": [], "materials": [], "accessors": [], "bufferViews": [],
           "buffers": []}

    def add_view(data, target):
        while len(buf) % 4:  # glTF: accessor data aligned to its component size
            buf.append(0)
        doc["bufferViews"].append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(data),
                                   "target": target})
        buf.extend(data)
        return len(doc["bufferViews"]) - 1

    def add_accessor(values, kind):
        """values: list of tuples (VEC2 / VEC3 float32) or ints (SCALAR uint32 indices)."""
        if kind == "SCALAR":
            data = struct.pack("<%dI" % len(values), *values)
            acc = {"bufferView": add_view(data, 34963), "componentType": 5125,
                   "count": len(values), "type": "SCALAR"}
        else:
            flat = [f32(c) for v in values for c in v]
            data = struct.pack("<%df" % len(flat), *flat)
            acc = {"bufferView": add_view(data, 34962), "componentType": 5126,
                   "count": len(values), "type": kind}
            if kind == "VEC3":  # min/max required for POSITION; cheap to give for all VEC3
                width = 3
                acc["min"] = [min(flat[k::width]) for k in range(width)]
                acc["max"] = [max(flat[k::width]) for k in range(width)]
        doc["accessors"].append(acc)
        return len(doc["accessors"]) - 1

    # Images and textures in a fixed order (sorted names) for deterministic output.
    image_names = sorted({materials[n["material"]]["texture"] for n in nodes
                          if materials[n["material"]]["texture"]})
    if image_names:
        # Repeat wrap (the glTF default, spelled out): the depth scene tiles its floor/wall.
        doc["samplers"] = [{"wrapS": 10497, "wrapT": 10497}]
        doc["images"] = [{"name": name, "uri": "data:image/png;base64,"
                          + base64.b64encode(images[name]).decode("ascii")}
                         for name in image_names]
        doc["textures"] = [{"sampler": 0, "source": k} for k in range(len(image_names))]

    material_index = {}
    mesh_index = {}
    for n in nodes:
        mname = n["material"]
        if mname not in material_index:
            mat = materials[mname]
            pbr = {"baseColorFactor": [float(c) for c in mat["color"]],
                   "metallicFactor": float(mat["metallic"]),
                   "roughnessFactor": float(mat["roughness"])}
            if mat["texture"]:
                pbr["baseColorTexture"] = {"index": image_names.index(mat["texture"])}
            doc["materials"].append({"name": mname, "pbrMetallicRoughness": pbr})
            material_index[mname] = len(doc["materials"]) - 1
        key = (id(n["mesh"]), mname)
        if key not in mesh_index:
            m = n["mesh"]
            prim = {"attributes": {"POSITION": add_accessor(m["p"], "VEC3"),
                                   "NORMAL": add_accessor(m["n"], "VEC3"),
                                   "TEXCOORD_0": add_accessor(m["t"], "VEC2")},
                    "indices": add_accessor(m["i"], "SCALAR"),
                    "material": material_index[mname], "mode": 4}
            doc["meshes"].append({"name": n["name"], "primitives": [prim]})
            mesh_index[key] = len(doc["meshes"]) - 1
        out = {"name": n["name"], "mesh": mesh_index[key]}
        for k in ("translation", "rotation", "scale"):
            if n[k] is not None:
                out[k] = [float(c) for c in n[k]]
        doc["nodes"].append(out)

    doc["buffers"].append({"byteLength": len(buf), "uri": "data:application/octet-stream;base64,"
                           + base64.b64encode(bytes(buf)).decode("ascii")})
    with open(path, "w", newline="\n") as fh:
        json.dump(doc, fh, indent=1)
        fh.write("\n")


def write_spec(name, description, gltf, cameras, lights, ambient, background,
               samples_per_pixel=16, seed=0):
    """Scene spec scenes/<name>.json: exactly the keys splat-scene accepts (it rejects others)."""
    spec = {"description": description, "gltf": gltf, "cameras": cameras, "lights": lights,
            "ambient": ambient, "background": background,
            "samples_per_pixel": samples_per_pixel, "seed": seed}
    with open(os.path.join(SCENES_DIR, name + ".json"), "w", newline="\n") as fh:
        fh.write(compact_json(spec) + "\n")


def compact_json(value, indent=0):
    """JSON with objects one key per line but lists of numbers on one line (easy to read)."""
    pad = "  " * (indent + 1)
    if isinstance(value, dict):
        items = ['%s%s: %s' % (pad, json.dumps(k), compact_json(v, indent + 1))
                 for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + "  " * indent + "}"
    if isinstance(value, list) and any(isinstance(v, (dict, list)) for v in value):
        items = [pad + compact_json(v, indent + 1) for v in value]
        return "[\n" + ",\n".join(items) + "\n" + "  " * indent + "]"
    return json.dumps(value)


def orbit(radius, elevation, fov, size, train, test, target=(0, 0, 0)):
    return {"rig": "orbit", "target": list(target), "radius": radius,
            "elevation_deg": list(elevation), "fov_deg": fov,
            "width": size[0], "height": size[1], "train": train, "test": test}


def directional(direction, intensity, color=(1, 1, 1)):
    return {"type": "directional", "direction": list(direction), "color": list(color),
            "intensity": intensity}


def point(position, intensity, color=(1, 1, 1)):
    return {"type": "point", "position": list(position), "color": list(color),
            "intensity": intensity}


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

    sys.dont_write_bytecode = True  # no __pycache__ in the source tree
    import check_gltf  # same directory; re-reads everything just written
    if not check_gltf.check_all(SCENES_DIR):
        raise SystemExit("self-check failed")


if __name__ == "__main__":
    main()
