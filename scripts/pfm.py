"""Reading the PFM images penumbra-render and penumbra-viewer write (visibility.pfm: one channel,
position.pfm: three), for the bench scripts' tables and charts."""
import numpy as np


def read_pfm(path):
    """The image as an H x W x C float32 array (C = 1 for "Pf", 3 for "PF"), its top row first.
    A negative scale marks little-endian data (what penumbra writes), a positive one big-endian.
    """
    with open(path, "rb") as f:
        kind = f.readline().strip()
        if kind not in (b"PF", b"Pf"):
            raise ValueError(f"{path}: not a PFM image")
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        channels = 3 if kind == b"PF" else 1
        data = np.fromfile(f, dtype="<f4" if scale < 0 else ">f4", count=w * h * channels)
    return data.reshape(h, w, channels)[::-1]
