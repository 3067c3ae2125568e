"""Minimal PFM (portable float map) reading and writing with numpy.

Images are float32 arrays of shape (height, width, 3), row 0 at the top.  On disk PFM
stores rows bottom to top; a negative scale means little-endian.
"""

import numpy as np


def write_pfm(path, img):
    img = np.asarray(img, dtype=np.float32)
    if img.ndim == 2:
        img = np.repeat(img[:, :, None], 3, axis=2)
    if img.ndim != 3 or img.shape[2] not in (1, 3):
        raise ValueError(f"expected (h, w, 3) or (h, w, 1) image, got {img.shape}")
    h, w, c = img.shape
    header = ("PF" if c == 3 else "Pf") + f"\n{w} {h}\n-1.0\n"
    data = np.ascontiguousarray(np.flipud(img)).astype("<f4")
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(data.tobytes())


def read_pfm(path):
    """Returns a float32 array (h, w, 3) (grey PFMs are repeated into three channels)."""
    with open(path, "rb") as f:
        data = f.read()
    tokens = []
    pos = 0
    # Header: magic, width, height, scale, separated by whitespace; one whitespace
    # character after the scale, then the raster.
    while len(tokens) < 4:
        while data[pos : pos + 1].isspace():
            pos += 1
        start = pos
        while not data[pos : pos + 1].isspace():
            pos += 1
        tokens.append(data[start:pos].decode("ascii"))
    pos += 1
    magic, w, h, scale = tokens[0], int(tokens[1]), int(tokens[2]), float(tokens[3])
    if magic == "PF":
        c = 3
    elif magic == "Pf":
        c = 1
    else:
        raise ValueError(f"{path}: not a PFM file (magic {magic!r})")
    dtype = "<f4" if scale < 0 else ">f4"
    n = w * h * c
    raster = np.frombuffer(data, dtype=dtype, count=n, offset=pos)
    img = np.flipud(raster.reshape(h, w, c)).astype(np.float32)
    if c == 1:
        img = np.repeat(img, 3, axis=2)
    return img
