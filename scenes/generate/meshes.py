"""Meshes: a mesh is a dict of parallel vertex lists (positions, normals, uvs) and a flat
triangle index list. Builders emit triangles through add_triangle, which orients each one
counter-clockwise as seen from the side its normals point to, so no builder has to get the
winding right by hand (glTF front faces are CCW).

Builders: box, uv_sphere, cylinder, plane, torus, rod; transformed and merge combine meshes.
"""

import math

from vectors import add, cross, dot, mul, normalize, quat_axis_angle, quat_rotate, sub


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
