#!/usr/bin/env python3
"""Self-check for the generated scenes: re-read every scenes/models/*.gltf and scenes/*.json
and verify they stay inside the subset splat-scene supports.

    python3 scenes/generate/check_gltf.py [SCENES_DIR]

Independent of make_scenes.py on purpose (it decodes the files from scratch), so a bug in the
writer is not mirrored by the check. Prints one line per file and exits non-zero on failure.
"""

import base64
import json
import math
import os
import struct
import sys
import zlib

COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}
SPEC_KEYS = {"description", "gltf", "cameras", "lights", "ambient", "background",
             "samples_per_pixel", "seed"}
CAMERA_KEYS = {"rig", "target", "radius", "elevation_deg", "fov_deg", "width", "height",
               "train", "test"}


class CheckError(Exception):
    pass


def require(cond, msg):
    if not cond:
        raise CheckError(msg)


def decode_data_uri(uri, mime):
    prefix = "data:%s;base64," % mime
    require(uri.startswith(prefix), "uri is not a %s base64 data URI" % mime)
    return base64.b64decode(uri[len(prefix):], validate=True)


def check_png(data):
    """Parse the PNG chunks, check CRCs, decode IDAT size: 8-bit RGB or RGBA, no interlace."""
    require(data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG signature")
    pos, idat, ihdr = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        require(zlib.crc32(kind + body) & 0xFFFFFFFF == crc, "PNG chunk CRC mismatch")
        if kind == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    require(ihdr is not None, "PNG without IHDR")
    w, h, depth, ctype, _, _, interlace = ihdr
    require(depth == 8 and ctype in (2, 6) and interlace == 0, "PNG must be 8-bit RGB/RGBA")
    channels = 3 if ctype == 2 else 4
    raw = zlib.decompress(idat)
    require(len(raw) == h * (1 + w * channels), "PNG pixel data has the wrong size")
    return w, h


def read_accessor(doc, buf, index):
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    require(view["buffer"] == 0, "only buffer 0 exists")
    require("byteStride" not in view, "interleaved views are not in our subset")
    n = COMPONENTS[acc["type"]]
    fmt = {5126: "f", 5125: "I"}[acc["componentType"]]
    start = view["byteOffset"] + acc.get("byteOffset", 0)
    require(start % 4 == 0, "accessor data not 4-byte aligned")
    size = acc["count"] * n * 4
    require(acc.get("byteOffset", 0) + size <= view["byteLength"], "accessor overruns its view")
    require(view["byteOffset"] + view["byteLength"] <= len(buf), "view overruns the buffer")
    flat = struct.unpack("<%d%s" % (acc["count"] * n, fmt), buf[start:start + size])
    return [flat[k:k + n] for k in range(0, len(flat), n)] if n > 1 else list(flat)


def quat_rotate(q, v):
    qv = q[:3]
    t = [2 * (qv[1] * v[2] - qv[2] * v[1]), 2 * (qv[2] * v[0] - qv[0] * v[2]),
         2 * (qv[0] * v[1] - qv[1] * v[0])]
    c = [qv[1] * t[2] - qv[2] * t[1], qv[2] * t[0] - qv[0] * t[2], qv[0] * t[1] - qv[1] * t[0]]
    return [v[k] + q[3] * t[k] + c[k] for k in range(3)]


def check_gltf(path):
    """Return a summary dict; raise CheckError on the first problem."""
    with open(path) as fh:
        doc = json.load(fh)
    require(doc["asset"]["version"] == "2.0", "asset.version must be 2.0")
    allowed = {"asset", "scene", "scenes", "nodes", "meshes", "materials", "textures", "images",
               "samplers", "accessors", "bufferViews", "buffers"}
    require(set(doc) <= allowed, "unexpected top-level keys %s" % (set(doc) - allowed))
    require(len(doc["buffers"]) == 1, "exactly one buffer")
    buf = decode_data_uri(doc["buffers"][0]["uri"], "application/octet-stream")
    require(len(buf) == doc["buffers"][0]["byteLength"], "buffer byteLength mismatch")

    for img in doc.get("images", []):
        check_png(decode_data_uri(img["uri"], "image/png"))
    for tex in doc.get("textures", []):
        require(0 <= tex["source"] < len(doc["images"]), "texture source out of range")
        if "sampler" in tex:
            require(0 <= tex["sampler"] < len(doc["samplers"]), "sampler out of range")
    for mat in doc["materials"]:
        require(set(mat) <= {"name", "pbrMetallicRoughness"}, "unsupported material keys")
        pbr = mat["pbrMetallicRoughness"]
        require(set(pbr) <= {"baseColorFactor", "baseColorTexture", "metallicFactor",
                             "roughnessFactor"}, "unsupported pbr keys")
        require(len(pbr["baseColorFactor"]) == 4, "baseColorFactor must be RGBA")
        require(all(0 <= c <= 1 for c in pbr["baseColorFactor"]), "colour outside [0,1]")
        require(0 <= pbr["metallicFactor"] <= 1 and 0 <= pbr["roughnessFactor"] <= 1,
                "metallic/roughness outside [0,1]")
        if "baseColorTexture" in pbr:
            require(0 <= pbr["baseColorTexture"]["index"] < len(doc["textures"]),
                    "texture index out of range")

    triangles = 0
    mesh_positions = []
    for mesh in doc["meshes"]:
        positions = []
        for prim in mesh["primitives"]:
            require(prim.get("mode", 4) == 4, "only triangle primitives")
            require(0 <= prim["material"] < len(doc["materials"]), "material out of range")
            attrs = prim["attributes"]
            require(set(attrs) == {"POSITION", "NORMAL", "TEXCOORD_0"}, "attribute set")
            for name, kind in (("POSITION", "VEC3"), ("NORMAL", "VEC3"), ("TEXCOORD_0", "VEC2")):
                acc = doc["accessors"][attrs[name]]
                require(acc["componentType"] == 5126 and acc["type"] == kind,
                        "%s must be float32 %s" % (name, kind))
            pos = read_accessor(doc, buf, attrs["POSITION"])
            nrm = read_accessor(doc, buf, attrs["NORMAL"])
            uv = read_accessor(doc, buf, attrs["TEXCOORD_0"])
            require(len(pos) == len(nrm) == len(uv), "attribute counts differ")
            acc = doc["accessors"][attrs["POSITION"]]
            for k in range(3):  # min/max must be exactly the data's bounds
                require(acc["min"][k] == min(p[k] for p in pos), "POSITION min mismatch")
                require(acc["max"][k] == max(p[k] for p in pos), "POSITION max mismatch")
            require(all(abs(math.sqrt(sum(c * c for c in n)) - 1) < 1e-4 for n in nrm),
                    "normals must be unit length")
            require(all(math.isfinite(c) for v in pos + nrm + uv for c in v), "non-finite value")
            iacc = doc["accessors"][prim["indices"]]
            require(iacc["componentType"] == 5125 and iacc["type"] == "SCALAR",
                    "indices must be uint32 SCALAR")
            idx = read_accessor(doc, buf, prim["indices"])
            require(len(idx) % 3 == 0 and idx, "index count must be a positive multiple of 3")
            require(max(idx) < len(pos), "index out of range")
            triangles += len(idx) // 3
            positions += pos
        mesh_positions.append(positions)

    # World-space extent: nodes are roots only (no children in our files), so world = TRS.
    require(len(doc["scenes"]) == 1 and doc["scene"] == 0, "one scene")
    require(sorted(doc["scenes"][0]["nodes"]) == list(range(len(doc["nodes"]))),
            "every node is a root of the scene")
    radius = 0.0
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for nd in doc["nodes"]:
        require(set(nd) <= {"name", "mesh", "translation", "rotation", "scale"},
                "unsupported node keys")
        require(0 <= nd["mesh"] < len(doc["meshes"]), "node mesh out of range")
        q = nd.get("rotation", [0, 0, 0, 1])
        require(abs(math.sqrt(sum(c * c for c in q)) - 1) < 1e-6, "rotation not unit")
        s = nd.get("scale", [1, 1, 1])
        t = nd.get("translation", [0, 0, 0])
        for p in mesh_positions[nd["mesh"]]:
            w = quat_rotate(q, [p[0] * s[0], p[1] * s[1], p[2] * s[2]])
            w = [w[k] + t[k] for k in range(3)]
            radius = max(radius, math.sqrt(sum(c * c for c in w)))
            lo = [min(lo[k], w[k]) for k in range(3)]
            hi = [max(hi[k], w[k]) for k in range(3)]
    return {"triangles": triangles, "nodes": len(doc["nodes"]),
            "images": len(doc.get("images", [])), "radius": radius, "lo": lo, "hi": hi,
            "bytes": os.path.getsize(path)}


def check_spec(path):
    with open(path) as fh:
        spec = json.load(fh)
    require(set(spec) == SPEC_KEYS, "spec keys %s" % sorted(set(spec) ^ SPEC_KEYS))
    cam = spec["cameras"]
    require(set(cam) == CAMERA_KEYS and cam["rig"] == "orbit", "camera keys")
    lo, hi = cam["elevation_deg"]
    require(-89 <= lo <= hi <= 89, "elevation range")
    require(0 < cam["fov_deg"] < 180 and cam["radius"] > 0, "fov / radius")
    require(cam["width"] > 0 and cam["height"] > 0 and cam["train"] > 0 and cam["test"] > 0,
            "sizes and view counts")
    for light in spec["lights"]:
        keys = {"type", "color", "intensity"} | ({"direction"} if light["type"] == "directional"
                                                 else {"position"})
        require(light["type"] in ("directional", "point") and set(light) == keys, "light keys")
    require(len(spec["ambient"]) == 3, "ambient is RGB")
    require(spec["background"] is None or len(spec["background"]) == 3, "background")
    gltf = os.path.join(os.path.dirname(path), spec["gltf"])
    require(os.path.isfile(gltf), "gltf %s missing" % spec["gltf"])
    return spec


def check_all(scenes_dir):
    ok = True
    models = os.path.join(scenes_dir, "models")
    for name in sorted(os.listdir(models)):
        if name.endswith(".gltf"):
            try:
                r = check_gltf(os.path.join(models, name))
                # The NeRF baseline samples +-1.5: objects stay within radius 1.2 of the
                # origin, except in the scene whose point is a far backdrop.
                require(r["radius"] <= 1.2 or name == "depth_range.gltf",
                        "bounding radius %.3f exceeds 1.2" % r["radius"])
                print("ok   models/%-22s %6d tris %3d nodes %d images  %8d bytes  "
                      "bounding radius %.3f  box [%s]..[%s]"
                      % (name, r["triangles"], r["nodes"], r["images"], r["bytes"], r["radius"],
                         ",".join("%.2f" % c for c in r["lo"]),
                         ",".join("%.2f" % c for c in r["hi"])))
            except (CheckError, KeyError, ValueError, struct.error) as e:
                ok = False
                print("FAIL models/%s: %s" % (name, e))
    for name in sorted(os.listdir(scenes_dir)):
        if name.endswith(".json"):
            try:
                spec = check_spec(os.path.join(scenes_dir, name))
                c = spec["cameras"]
                print("ok   %-29s %dx%d, %d train / %d test, radius %.1f, fov %g -> %s"
                      % (name, c["width"], c["height"], c["train"], c["test"], c["radius"],
                         c["fov_deg"], spec["gltf"]))
            except (CheckError, KeyError, ValueError, TypeError) as e:
                ok = False
                print("FAIL %s: %s" % (name, e))
    return ok


if __name__ == "__main__":
    here = os.path.dirname(os.path.abspath(__file__))
    sys.exit(0 if check_all(sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(here)) else 1)
