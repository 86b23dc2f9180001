#!/usr/bin/env python3
"""Side-by-side PNG montage without dependencies: scripts/montage.py [--crop X,Y,W,H] OUT.png SCALE IN.png...
Each input (8-bit RGB or RGBA, non-interlaced), or its W x H region from pixel (X, Y) with --crop,
is scaled up by SCALE (nearest) and placed left to right."""
import struct
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    pos, idat = 8, b""
    while pos < len(data):
        n = struct.unpack(">I", data[pos:pos + 4])[0]
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
            if depth != 8 or ctype not in (2, 6):
                sys.exit(f"{path}: only 8-bit RGB or RGBA PNGs")
        elif kind == b"IDAT":
            idat += body
    raw, ch = zlib.decompress(idat), {2: 3, 6: 4}[ctype]
    stride, rows, prev, i = w * ch, [], bytearray(w * ch), 0
    for _ in range(h):
        f, line = raw[i], bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - ch] if x >= ch else 0
            b, c = prev[x], prev[x - ch] if x >= ch else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return w, h, ch, rows


def write_png(path, w, h, rows):
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def crop(image, x0, y0, w, h):
    iw, ih, ch, rows = image
    if x0 < 0 or y0 < 0 or w <= 0 or h <= 0 or x0 + w > iw or y0 + h > ih:
        sys.exit(f"--crop {x0},{y0},{w},{h} is not inside the {iw}x{ih} image")
    return w, h, ch, [row[x0 * ch:(x0 + w) * ch] for row in rows[y0:y0 + h]]


def main():
    args = sys.argv[1:]
    region = None
    if args and args[0].startswith("--crop"):
        spec = args[0].partition("=")[2] or (args[1] if len(args) > 1 else "")
        args = args[1:] if "=" in args[0] else args[2:]
        try:
            region = [int(v) for v in spec.split(",")]
            assert len(region) == 4
        except (ValueError, AssertionError):
            sys.exit(f"--crop takes X,Y,W,H in pixels, not '{spec}'")
    if len(args) < 3:
        sys.exit(__doc__)
    out, scale, images = args[0], int(args[1]), [read_png(p) for p in args[2:]]
    if region:
        images = [crop(im, *region) for im in images]
    width, height = sum(im[0] for im in images) * scale, max(im[1] for im in images) * scale
    rows = []
    for y in range(height):
        row = bytearray()
        for w, h, ch, px in images:
            src = px[min(y // scale, h - 1)]
            for x in range(w * scale):
                row += src[(x // scale) * ch:(x // scale) * ch + 3]
        rows.append(row)
    write_png(out, width, height, rows)


if __name__ == "__main__":
    main()
