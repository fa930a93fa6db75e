#!/usr/bin/python3
"""relMSE and relRMSE of images against a reference, computed apart from vpm (its own EXR reader for
scanline files with ZIP or no compression and FLOAT or HALF channels, and NumPy formulas), to check
`vpm compare` (docs/metrics.md): both print the same figures.

usage: /usr/bin/python3 scripts/metric_crosscheck.py IMAGE.exr... REFERENCE.exr
REFERENCE.variance.exr (vpm render --variance) must sit beside the reference: its floor is subtracted.
"""
import struct, sys, zlib
import numpy as np

def read_exr(path):
    data = open(path, "rb").read()
    assert struct.unpack("<I", data[:4])[0] == 20000630
    pos, attrs = 8, {}
    while data[pos] != 0:
        name_end = data.index(b"\0", pos); name = data[pos:name_end].decode()
        type_end = data.index(b"\0", name_end + 1)
        size = struct.unpack("<i", data[type_end + 1:type_end + 5])[0]
        attrs[name] = data[type_end + 5:type_end + 5 + size]; pos = type_end + 5 + size
    pos += 1
    chans, p, raw = [], 0, attrs["channels"]
    while raw[p] != 0:
        e = raw.index(b"\0", p); chans.append((raw[p:e].decode(), struct.unpack("<i", raw[e + 1:e + 5])[0])); p = e + 17
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"])
    w, h, comp = x1 - x0 + 1, y1 - y0 + 1, attrs["compression"][0]
    lines = {0: 1, 2: 1, 3: 16}[comp]
    nchunks = (h + lines - 1) // lines
    offsets = struct.unpack("<%dQ" % nchunks, data[pos:pos + 8 * nchunks])
    img = {c: np.zeros((h, w), np.float64) for c, _ in chans}
    for off in offsets:
        y, size = struct.unpack("<ii", data[off:off + 8]); block = data[off + 8:off + 8 + size]
        n = min(lines, y1 + 1 - y)
        expected = sum(n * w * (4 if t == 2 else 2) for _, t in chans)
        if comp != 0 and size < expected:
            t = np.frombuffer(zlib.decompress(block), np.uint8).astype(np.int32)
            t = np.cumsum(np.concatenate([t[:1], t[1:] - 128])) & 0xFF   # undo the predictor
            t = t.astype(np.uint8); half = (len(t) + 1) // 2
            out = np.empty_like(t); out[0::2] = t[:half]; out[1::2] = t[half:]
            block = out.tobytes()
        q = 0
        for row in range(n):
            for c, typ in chans:   # channels in name order, one row each
                nbytes = w * (4 if typ == 2 else 2)
                img[c][y - y0 + row] = np.frombuffer(block[q:q + nbytes], np.float32 if typ == 2 else np.float16)
                q += nbytes
    return np.stack([img["R"], img["G"], img["B"]], -1)

Y = lambda a: 0.2126 * a[..., 0] + 0.7152 * a[..., 1] + 0.0722 * a[..., 2]
ref = Y(read_exr(sys.argv[-1]))
if len(sys.argv) < 3:
    sys.exit(__doc__)
var = Y(read_exr(sys.argv[-1][:-4] + ".variance.exr"))   # grey: its luminance is the value
for f in sys.argv[1:-1]:
    I = Y(read_exr(f))
    raw = np.mean((I - ref) ** 2 / (ref ** 2 + 0.01)); floor = np.mean(var / (ref ** 2 + 0.01))
    rr = np.sqrt(np.mean((I - ref) ** 2)) / ref.mean(); rf = np.sqrt(np.mean(var)) / ref.mean()
    print("%s: relMSE %.5g (raw %.5g - floor %.5g); relRMSE %.4g (raw %.4g, floor %.4g)"
          % (f, raw - floor, raw, floor, np.sign(rr**2 - rf**2) * np.sqrt(abs(rr**2 - rf**2)), rr, rf))
