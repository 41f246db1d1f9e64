"""glTF writer and scene spec JSON writer for make_scenes.py.

write_gltf writes nodes (mesh + material) as a self-contained .gltf in the subset splat-scene
reads (scenes/README.md); write_spec writes scenes/<name>.json. material, node, orbit,
directional and point build the descriptions these take.
"""

import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES_DIR = os.path.dirname(HERE)
MODELS_DIR = os.path.join(SCENES_DIR, "models")


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
