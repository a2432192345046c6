"""The grid pieces of a run on several ranks equal the serial grid files' cells (issue 27).

Usage: grid_pieces_check.py SERIAL_DIR SPLIT_DIR METHOD RANKS

For every `<method>_grid_<frame>.vtu` of the serial run, the split run has no such file but
`<method>_grid_<frame>.pvtu` listing `<method>_grid_<frame>_r<r>.vtu` for r = 0..RANKS-1 in
rank order, and `<method>_grid.pvd` lists the `.pvtu`. Every serial cell is in exactly one
piece, found by its corner coordinates (the pieces' vertices are the serial grid's, bit for
bit: FEM's deformed by the nodal displacement), and its cell arrays (stress, velocity) and
its corners' point arrays (FEM's nodal velocity; the node layer of a cut is in the pieces
on both sides) are the serial cell's bit for bit. Reads the
files with the standard library only (impact's VTU: raw appended data, zlib blocks with a
UInt64 header, or ASCII), so it runs under plain `python3`.
"""
import re
import struct
import sys
import zlib
from pathlib import Path

# (Float64 read as its bits, so that equal means bit for bit: -0.0 is not 0.0, NaN is NaN)
TYPES = {"Float64": ("Q", 8), "Int64": ("q", 8), "UInt8": ("B", 1)}


def float_bits(text):
    return struct.unpack("<Q", struct.pack("<d", float(text)))[0]


def read_vtu(path):
    """The points, the cells (tuples of vertex indices), the cell and the point arrays of a
    VTU."""
    data = path.read_bytes()
    head, _, appended = data.partition(b'<AppendedData encoding="raw">')
    if appended:
        appended = appended[appended.index(b"_") + 1 :]
    text = head.decode()
    arrays = {}
    section = None
    for m in re.finditer(r"<(/?)(Points|Cells|PointData|CellData)>|<DataArray ([^>]*?)(/?)>([^<]*)", text):
        if m.group(2):
            section = None if m.group(1) else m.group(2)
            continue
        attrs = dict(re.findall(r'(\w+)="([^"]*)"', m.group(3)))
        if section is None:
            continue
        code, size = TYPES[attrs["type"]]
        if attrs.get("format") == "appended":
            at = int(attrs["offset"])
            blocks = struct.unpack_from("<3Q", appended, at)
            sizes = struct.unpack_from(f"<{blocks[0]}Q", appended, at + 24)
            pos, raw = at + 24 + 8 * blocks[0], b""
            for s in sizes:
                raw += zlib.decompress(appended[pos : pos + s])
                pos += s
            values = list(struct.unpack(f"<{len(raw) // size}{code}", raw))
        else:
            conv = float_bits if code == "Q" else int
            values = [conv(v) for v in m.group(5).split()]
        arrays[(section, attrs["Name"])] = (values, int(attrs.get("NumberOfComponents", 1)))
    points = arrays[("Points", "Points")][0]
    points = [tuple(points[3 * i : 3 * i + 3]) for i in range(len(points) // 3)]
    connectivity = arrays[("Cells", "connectivity")][0]
    offsets = [0] + arrays[("Cells", "offsets")][0]
    cells = [tuple(connectivity[a:b]) for a, b in zip(offsets, offsets[1:])]
    def split(section, count):
        return {
            name: [tuple(v[i * k : (i + 1) * k]) for i in range(count)]
            for (sec, name), (v, k) in arrays.items()
            if sec == section
        }

    return points, cells, split("CellData", len(cells)), split("PointData", len(points))


def keyed(path):
    """Each cell's arrays and its corners' point arrays by its corners' coordinates (sorted)."""
    points, cells, data, point_data = read_vtu(path)
    out = {}
    for c, cell in enumerate(cells):
        key = tuple(sorted(points[v] for v in cell))
        assert key not in out, f"{path.name}: cell {c} twice"
        out[key] = {name: values[c] for name, values in data.items()}
        corners = sorted((points[v], tuple(point_data[n][v] for n in sorted(point_data))) for v in cell)
        out[key]["corners"] = tuple(corners)
    return out


def main(serial, split, method, ranks):
    serial, split, ranks = Path(serial), Path(split), int(ranks)
    frames = sorted(p.name[: -len(".vtu")] for p in serial.glob(f"{method}_grid_*.vtu"))
    assert len(frames) >= 2, f"only {frames} in {serial}"
    pvd = (split / f"{method}_grid.pvd").read_text()
    for frame in frames:
        assert not (split / f"{frame}.vtu").exists(), f"{frame}.vtu written whole"
        assert f'file="{frame}.pvtu"' in pvd, f"{method}_grid.pvd lacks {frame}.pvtu"
        sources = re.findall(r'Source="([^"]+)"', (split / f"{frame}.pvtu").read_text())
        assert sources == [f"{frame}_r{r}.vtu" for r in range(ranks)], sources
        whole = keyed(serial / f"{frame}.vtu")
        joined = {}
        for source in sources:
            piece = keyed(split / source)
            assert piece, f"{source}: no cell"
            assert not joined.keys() & piece.keys(), f"{source}: a cell of another piece"
            joined.update(piece)
        assert joined.keys() == whole.keys(), f"{frame}: the pieces' cells are not the grid's"
        for key, arrays in whole.items():
            assert joined[key] == arrays, f"{frame}: cell at {key[0]} differs"
    print(f"{len(frames)} grid frames of {method} on {ranks} ranks: every cell the serial one")


if __name__ == "__main__":
    main(*sys.argv[1:])
