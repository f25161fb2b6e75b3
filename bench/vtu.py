"""Reads consph's binary .vtu frames (appended raw data, UInt64 headers) into NumPy arrays."""
import re

import numpy as np

_TYPES = {"Float64": np.float64, "Float32": np.float32, "UInt32": np.uint32, "Int64": np.int64, "UInt8": np.uint8}


def read_vtu(path):
    """Returns {name: array} with 'position' (N, 3) and every point array of the frame."""
    raw = open(path, "rb").read()
    start = raw.index(b"<AppendedData")
    data = raw[raw.index(b"_", start) + 1:]
    header = raw[:start].decode()
    out = {}
    for m in re.finditer(r'<DataArray type="(\w+)"(?: Name="(\w+)")?(?: NumberOfComponents="(\d+)")? format="appended" offset="(\d+)"', header):
        dtype, name, comps, offset = m.group(1), m.group(2), int(m.group(3) or 1), int(m.group(4))
        if name in ("connectivity", "offsets", "types"):
            continue
        nbytes = int(np.frombuffer(data[offset:offset + 8], np.uint64)[0])
        arr = np.frombuffer(data[offset + 8:offset + 8 + nbytes], _TYPES[dtype])
        out[name or "position"] = arr.reshape(-1, comps) if comps > 1 else arr
    return out
