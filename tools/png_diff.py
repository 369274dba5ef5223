#!/usr/bin/env python3
"""Compares two 8-bit PNG frames (as the demo writes them) pixel by pixel: prints how many pixels differ
and the largest difference of one channel, e.g. `1 of 230400 pixels differ, max channel diff 1`.
Standard library only (zlib). Exit status 0 when it compared (equal or not), 2 on a file it cannot read
(not a PNG, another size or format, interlaced), 1 on usage errors.

usage: tools/png_diff.py A.png B.png
"""
import struct, sys, zlib


def pixels(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    i, idat, header = 8, b"", None
    while i + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[i:i + 8])
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", data[i + 8:i + 21])
        elif kind == b"IDAT":
            idat += data[i + 8:i + 8 + length]
        i += 12 + length
    if header is None:
        raise ValueError("no IHDR chunk")
    w, h, depth, colour, _, _, interlace = header
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(colour)
    if depth != 8 or channels is None or interlace != 0:
        raise ValueError("only 8-bit, non-interlaced grey/RGB/RGBA PNGs are read")
    raw, stride = zlib.decompress(idat), w * channels
    out, prev = bytearray(), bytearray(stride)
    for y in range(h):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):  # undo the row filter (PNG spec, section 9)
            a = line[x - channels] if x >= channels else 0
            b, c = prev[x], prev[x - channels] if x >= channels else 0
            if kind == 1: line[x] = (line[x] + a) & 255
            elif kind == 2: line[x] = (line[x] + b) & 255
            elif kind == 3: line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out += line
        prev = line
    return (w, h, channels), bytes(out)


def main(argv):
    if any(a in ("-h", "--help") for a in argv):
        print(__doc__.strip())
        return 0
    if len(argv) != 2:
        print("png_diff: two PNG files expected (see --help)", file=sys.stderr)
        return 1
    try:
        loaded = []
        for path in argv:
            try:
                loaded.append(pixels(path))
            except (OSError, ValueError, zlib.error, struct.error) as e:
                raise ValueError(f"{path}: {e}")
        (sa, a), (sb, b) = loaded
    except ValueError as e:
        print(f"png_diff: {e}", file=sys.stderr)
        return 2
    if sa != sb:
        print(f"png_diff: {argv[0]} is {sa[0]}x{sa[1]}x{sa[2]}, {argv[1]} is {sb[0]}x{sb[1]}x{sb[2]}", file=sys.stderr)
        return 2
    n = sa[2]
    differ = sum(1 for i in range(0, len(a), n) if a[i:i + n] != b[i:i + n])
    most = max((abs(x - y) for x, y in zip(a, b)), default=0)
    print(f"{differ} of {sa[0] * sa[1]} pixels differ, max channel diff {most}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
