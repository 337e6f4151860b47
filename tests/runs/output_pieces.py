#!/usr/bin/env python3
"""Output/Cells per file: a rank with more cells writes its VTU in pieces.

Usage: output_pieces.py SIGNORINI_BINARY SOURCE_DIR WORK_DIRECTORY

The 2D block at one refinement (384 triangles, two cycles: the second
refined) is written
- in one file (the default limit): solution-CC.vtu;
- with `Cells per file = 100` on 1 rank: ceil(cells / 100) pieces of at
  most 100 cells, solution-CC.PPP.vtu, listed in solution-CC.pvtu, which
  solution.pvd names; every file is in the manifest. The pieces, read in
  order, hold the same points, cell types and values as the one file, to
  the bit (decoded here from deal.II's zlib-compressed base64 arrays);
- the same limit on 2 ranks: each rank's cells in its own pieces, all the
  cells written once (the pieces' cell counts add up to the mesh's).
"""
import base64
import math
import os
import re
import struct
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from serial_parallel import read, run  # noqa: E402

TYPES = {"Float32": 4, "Float64": 8, "Int32": 4, "Int64": 8, "UInt8": 1}


def arrays(path):
    """{name: [raw bytes of each DataArray of that name]} of a .vtu file."""
    with open(path) as f:
        text = f.read()
    found = {}
    for match in re.finditer(r"<DataArray([^>]*)>(.*?)</DataArray>", text,
                             re.S):
        attributes, body = match.group(1), match.group(2).strip()
        name = re.search(r'Name="([^"]*)"', attributes)
        name = name.group(1) if name else "points"
        # deal.II's layout: base64(UInt32 header: blocks, block size, last
        # block size, compressed sizes), then base64(compressed blocks)
        n_blocks = struct.unpack("<I", base64.b64decode(body[:8])[:4])[0]
        header_length = 4 * math.ceil(4 * (3 + n_blocks) / 3)
        header = base64.b64decode(body[:header_length])
        sizes = struct.unpack(f"<{n_blocks}I", header[12:12 + 4 * n_blocks])
        data = base64.b64decode(body[header_length:])
        raw, position = b"", 0
        for size in sizes:
            raw += zlib.decompress(data[position:position + size])
            position += size
        found.setdefault(name, []).append(raw)
    return found


def cells(path):
    with open(path) as f:
        return sum(int(n) for n in re.findall(r'NumberOfCells="(\d+)"',
                                              f.read()))


def pieces_of(directory, cycle):
    """The pieces that solution-CC.pvtu lists, checked against the files."""
    record = os.path.join(directory, f"solution-{cycle:02d}.pvtu")
    with open(record) as f:
        pieces = re.findall(r'<Piece Source="([^"]*)"', f.read())
    expected = [f"solution-{cycle:02d}.{p:03d}.vtu" for p in range(len(pieces))]
    if pieces != expected:
        sys.exit(f"{record} lists {pieces}, expected {expected}")
    return pieces


def main():
    binary, source, work = sys.argv[1:4]
    prm = os.path.join(source, "tests", "runs", "output_pieces.prm")
    one_file = os.path.join(work, "one_file")
    run(binary, prm, one_file, 1)
    problems = []
    statistics = read(os.path.join(one_file, "statistics.csv"))
    for ranks in (1, 2):
        directory = os.path.join(work, f"pieces-{ranks}")
        run(binary, prm, directory, ranks,
            "subsection Output\n  set Cells per file = 100\nend\n")
        with open(os.path.join(directory, ".signorini-manifest")) as f:
            manifest = f.read().split("\n")
        with open(os.path.join(directory, "solution.pvd")) as f:
            pvd = f.read()
        for row in statistics:
            cycle, n_cells = int(row["cycle"]), int(row["cells"])
            pieces = pieces_of(directory, cycle)
            if f'file="solution-{cycle:02d}.pvtu"' not in pvd:
                problems.append(f"{ranks} ranks: solution.pvd misses cycle {cycle}")
            for name in pieces + [f"solution-{cycle:02d}.pvtu"]:
                if name not in manifest:
                    problems.append(f"{ranks} ranks: {name} not in the manifest")
            counts = [cells(os.path.join(directory, p)) for p in pieces]
            if sum(counts) != n_cells or max(counts) > 100:
                problems.append(f"{ranks} ranks, cycle {cycle}: pieces of "
                                f"{counts} cells for a mesh of {n_cells}")
            if ranks == 1:
                if len(pieces) != math.ceil(n_cells / 100):
                    problems.append(f"cycle {cycle}: {len(pieces)} pieces")
                whole = arrays(os.path.join(one_file,
                                            f"solution-{cycle:02d}.vtu"))
                joined = {}
                for p in pieces:
                    for name, parts in arrays(os.path.join(directory,
                                                           p)).items():
                        joined.setdefault(name, []).extend(parts)
                for name, parts in whole.items():
                    # (connectivity and offsets number each piece's points)
                    if name in ("connectivity", "offsets"):
                        continue
                    if b"".join(parts) != b"".join(joined.get(name, [])):
                        problems.append(f"cycle {cycle}: {name} differs "
                                        "between the pieces and the one file")
            print(f"{ranks} rank(s), cycle {cycle}: {n_cells} cells in "
                  f"{len(pieces)} pieces of {min(counts)} to {max(counts)}")
    if problems:
        sys.exit("\n".join(problems))
    print("output pieces: OK")


if __name__ == "__main__":
    main()
