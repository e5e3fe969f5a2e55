# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 by the fmpm authors
"""Read fmpm's particle output (particles.pvd and its .pvtu/.vtu pieces,
binary VTU as deal.II writes it, zlib-compressed or not) without VTK."""

import base64
import os
import re
import struct
import sys
import zlib

_CODES = {"Float32": "f", "Float64": "d", "Int32": "i", "UInt8": "B"}


def decode_array(text, dtype, compressed=True):
    """A binary DataArray: base64(header) + base64(data). With zlib the
    header is (blocks, block size, last size, compressed sizes...), the
    data the compressed blocks; without, the header is the byte count."""
    text = text.strip()
    code = _CODES[dtype]
    if compressed:
        n_blocks = struct.unpack("<4I", base64.b64decode(text[:24]))[0]
        header_chars = 4 * ((4 * (3 + n_blocks) + 2) // 3)
        header = struct.unpack("<%dI" % (3 + n_blocks),
                               base64.b64decode(text[:header_chars]))
        data = base64.b64decode(text[header_chars:])
        raw, offset = b"", 0
        for size in header[3:]:
            raw += zlib.decompress(data[offset:offset + size])
            offset += size
    else:
        raw = base64.b64decode(text)[4:]
    count = len(raw) // struct.calcsize(code)
    return struct.unpack("<%d%s" % (count, code), raw[:count * struct.calcsize(code)])


def read_piece(path, fields):
    """Point coordinates (x, y, z lists) and {field: values} of one .vtu.
    A field is NAME or NAME:COMPONENT (stress:0 is sigma_xx; vectors are
    written with 3 and tensors with 9 components)."""
    content = open(path).read()
    compressed = 'compressor="vtkZLibDataCompressor"' in content
    arrays = re.findall(r'<DataArray type="(\w+)"([^>]*)>(.*?)</DataArray>',
                        content, re.S)
    points, values = None, {}
    wanted = {f: f.partition(":") for f in fields}
    for dtype, attributes, text in arrays:
        name = re.search(r'Name="([^"]*)"', attributes)
        n = re.search(r'NumberOfComponents="(\d+)"', attributes)
        n = int(n.group(1)) if n else 1
        if name is None:
            if points is None:
                points = decode_array(text, dtype, compressed)
            continue
        for field, (base, _, component) in wanted.items():
            if name.group(1) == base:
                data = decode_array(text, dtype, compressed)
                values[field] = data[int(component or 0)::n]
    if points is None or len(values) < len(fields):
        missing = [f for f in fields if f not in values]
        sys.exit("%s: no points or no field %s" % (path, ", ".join(missing)))
    return (points[0::3], points[1::3], points[2::3]), values


def pieces_at(directory, time):
    """(time, [.vtu pieces]) of the particle output closest to time."""
    pvd = open(os.path.join(directory, "particles.pvd")).read()
    records = re.findall(r'timestep="([^"]*)"[^>]*file="([^"]*)"', pvd)
    if not records:
        sys.exit("%s: no records in particles.pvd" % directory)
    if time == float("inf"):
        step, name = max(records, key=lambda r: float(r[0]))
    else:
        step, name = min(records, key=lambda r: abs(float(r[0]) - time))
    path = os.path.join(directory, name)
    if name.endswith(".pvtu"):
        content = open(path).read()
        return float(step), [os.path.join(directory, p) for p in
                             re.findall(r'<Piece Source="([^"]*)"', content)]
    return float(step), [path]


def read_output(directory, time, fields):
    """All pieces of the output closest to time: (time, x, y, z, values)."""
    step, pieces = pieces_at(directory, time)
    x, y, z, values = [], [], [], {f: [] for f in fields}
    for piece in pieces:
        (px, py, pz), pv = read_piece(piece, fields)
        x += px
        y += py
        z += pz
        for f in fields:
            values[f] += pv[f]
    return step, x, y, z, values
