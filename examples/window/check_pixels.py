#!/usr/bin/env python3
"""Checks a screenshot of the window against the graph's CheckerPass.

  check_pixels.py SCREENSHOT.ppm GRAPH.json [--size WxH] [--swapped]

Every pixel (x, y) must be, within two 8-bit codes per channel, the sRGB encoding of
colors[(x // tile + y // tile) % 2] of the graph's CheckerPass params (what checker.frag writes
into the HDR image, passed through by the TonemappingPass into the B8G8R8A8_SRGB swapchain).
--size: the screenshot must be that size too. --swapped expects the two colours the other way
round: the negative control, which must fail.
Prints the size and the number of mismatching pixels; exit 0 when there are none.
"""
import json
import sys


def srgb_code(linear):
    linear = min(max(linear, 0.0), 1.0)
    encoded = 12.92 * linear if linear <= 0.0031308 else 1.055 * linear ** (1 / 2.4) - 0.055
    return encoded * 255.0


def read_ppm(path):
    data = open(path, "rb").read()
    fields, pos = [], 0
    while len(fields) < 4:  # magic, width, height, maximum, separated by whitespace
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":  # a comment (ImageMagick writes the window's name)
            pos = data.index(b"\n", pos)
            continue
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        fields.append(data[start:pos])
    if fields[0] != b"P6" or int(fields[3]) != 255:
        raise SystemExit(f"{path}: not an 8-bit binary PPM")
    width, height = int(fields[1]), int(fields[2])
    pixels = data[pos + 1:]
    if len(pixels) != width * height * 3:
        raise SystemExit(f"{path}: {len(pixels)} bytes of pixels for {width}x{height}")
    return width, height, pixels


def main():
    args = sys.argv[1:]
    swapped = "--swapped" in args
    size = args[args.index("--size") + 1] if "--size" in args else None
    width, height, pixels = read_ppm(args[0])
    if size is not None and f"{width}x{height}" != size:
        print(f"{width}x{height}, expected {size}")
        return 1
    graph = json.load(open(args[1]))
    params = next(p["params"] for p in graph["passes"] if p["type"] == "CheckerPass")
    expected = [[srgb_code(c) for c in color] for color in params["colors"]]
    if swapped:
        expected.reverse()
    tile = params["tile"]
    bad = 0
    for y in range(height):
        row = pixels[y * width * 3:(y + 1) * width * 3]
        for x in range(width):
            want = expected[(x // tile + y // tile) % 2]
            got = row[x * 3:x * 3 + 3]
            if any(abs(got[c] - want[c]) > 2.0 for c in range(3)):
                if bad < 3 and not swapped:
                    print(f"pixel ({x}, {y}): {tuple(got)}, expected {tuple(round(w) for w in want)}")
                bad += 1
    print(f"{width}x{height}: {bad} mismatching pixels{' (colours swapped)' if swapped else ''}")
    return 0 if bad == 0 and width > 0 else 1


if __name__ == "__main__":
    sys.exit(main())
