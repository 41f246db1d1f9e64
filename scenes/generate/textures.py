"""Textures: images are lists of rows of (r, g, b) tuples, written as 8-bit RGB PNG.

png_bytes encodes an image; the *_texture functions build the scenes' textures from code
(deterministic: hash01 is our own noise, no random module state).
"""

import math
import struct
import zlib


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
