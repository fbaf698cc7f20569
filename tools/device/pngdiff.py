#!/usr/bin/env python3
"""pngdiff.py A.png B.png...: per-byte differences of 8-bit RGBA PNGs (as skygraph writes them)
against A: the largest, and how many bytes differ by more than one code. Standard library only,
so it runs on the GPU machine and here alike. Exit status 1 when any byte differs by more than 1."""
import zlib, struct, sys
def load(path):
    data = open(path, 'rb').read()
    pos, idat, w, h = 8, b'', 0, 0
    while pos < len(data):
        n, t = struct.unpack('>I4s', data[pos:pos+8]); body = data[pos+8:pos+8+n]; pos += 12 + n
        if t == b'IHDR': w, h, depth, ctype = struct.unpack('>IIBB', body[:10]); assert depth == 8 and ctype == 6, (depth, ctype)
        elif t == b'IDAT': idat += body
    raw, bpp, stride = zlib.decompress(idat), 4, w * 4
    out, prev, i = [], bytearray(stride), 0
    for y in range(h):
        f = raw[i]; line = bytearray(raw[i+1:i+1+stride]); i += 1 + stride
        for x in range(stride):
            a = line[x-bpp] if x >= bpp else 0; b = prev[x]; c = prev[x-bpp] if x >= bpp else 0
            if f == 1: line[x] = (line[x] + a) & 255
            elif f == 2: line[x] = (line[x] + b) & 255
            elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c; pa, pb, pc = abs(p-a), abs(p-b), abs(p-c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out.append(bytes(line)); prev = line
    return w, h, b''.join(out)
wa, ha, a = load(sys.argv[1])
status = 0
for p in sys.argv[2:]:
    wb, hb, b = load(p)
    if (wa, ha) != (wb, hb):
        print(p, 'size', (wb, hb), 'differs from', (wa, ha)); status = 1; continue
    d = [abs(x - y) for x, y in zip(a, b)]
    over = sum(1 for v in d if v > 1)
    print(f'{p}: largest difference {max(d)} codes, {over} of {len(d)} bytes differ by more than 1')
    status |= over > 0
sys.exit(status)
