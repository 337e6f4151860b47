"""Minimal reader for the VTU files deal.II writes (inline binary, zlib
compressed or raw): points, triangles and point data as numpy arrays."""
import base64
import re
import struct
import zlib

import numpy

_TYPES = {"Float32": "<f4", "Float64": "<f8", "Int32": "<i4",
          "Int64": "<i8", "UInt8": "<u1", "UInt32": "<u4"}


def _decode(text, dtype, compressed):
    text = "".join(text.split())
    if not compressed:
        raw = base64.b64decode(text)
        (n_bytes,) = struct.unpack("<I", raw[:4])
        return numpy.frombuffer(raw[4:4 + n_bytes], dtype=dtype)
    (n_blocks,) = struct.unpack("<I", base64.b64decode(text[:8])[:4])
    header_bytes = 4 * (3 + n_blocks)
    header_chars = 4 * ((header_bytes + 2) // 3)
    header = struct.unpack(f"<{3 + n_blocks}I",
                           base64.b64decode(text[:header_chars]))
    data = base64.b64decode(text[header_chars:])
    chunks, offset = [], 0
    for size in header[3:]:
        chunks.append(zlib.decompress(data[offset:offset + size]))
        offset += size
    return numpy.frombuffer(b"".join(chunks), dtype=dtype)


def read(filename):
    """Return (points (n, 2), triangles (m, 3), {name: array})."""
    with open(filename) as f:
        text = f.read()
    compressed = "vtkZLibDataCompressor" in text
    arrays = {}
    pattern = re.compile(r'<DataArray ([^>]*)>(.*?)</DataArray>', re.S)
    for attributes, body in pattern.findall(text):
        dtype = _TYPES[re.search(r'type="(\w+)"', attributes).group(1)]
        name = re.search(r'Name="([^"]+)"', attributes)
        components = re.search(r'NumberOfComponents="(\d+)"', attributes)
        values = _decode(body, dtype, compressed)
        if components and int(components.group(1)) > 1:
            values = values.reshape(-1, int(components.group(1)))
        arrays[name.group(1) if name else "points"] = values
    points = arrays.pop("points")[:, :2].astype(float)
    triangles = arrays.pop("connectivity").reshape(-1, 3)
    for key in ("offsets", "types"):
        arrays.pop(key, None)
    return points, triangles, arrays
