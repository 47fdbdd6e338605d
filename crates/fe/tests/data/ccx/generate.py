#!/usr/bin/env python3
"""Regenerate CalculiX's K and M of small distorted meshes, one per element type, for
crates/fe/tests/solid_calculix.rs (see README.md).

Needs ccx (CalculiX 2.20, Debian package) on PATH. Run from anywhere:
    python3 crates/fe/tests/data/ccx/generate.py

Each mesh is two bricks along x of a box 0.2 x 0.1 x 0.1 m whose corner nodes are moved by
fixed offsets (so no element is a parallelepiped); the C3D10 and C3D20 mid-edge nodes sit at
the middle of straight edges; the tetrahedra cut each brick into six (Kuhn's subdivision
along its main diagonal). The deck writes the free-free K and M with
*FREQUENCY, SOLVER=MATRIXSTORAGE (files <job>.sti, .mas, .dof), material steel
E = 2.1e11 Pa, nu = 0.3, rho = 7850 kg/m^3.
"""
import pathlib
import shutil
import subprocess
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
E, NU, RHO = 2.1e11, 0.3, 7850.0
NX = 2
SIZE = (0.1, 0.1, 0.1)


def corner_grid():
    """Corner nodes (i, j, k) of the NX x 1 x 1 grid with their distorted positions."""
    pos = {}
    for k in range(2):
        for j in range(2):
            for i in range(NX + 1):
                # Fixed, different offsets: up to 12 % of the brick side.
                d = [0.012 * ((3 * i + 5 * j + 7 * k) % 5 - 2),
                     0.009 * ((2 * i + 3 * j + 5 * k) % 4 - 1.5),
                     0.010 * ((5 * i + 2 * j + 3 * k) % 3 - 1)]
                pos[(i, j, k)] = [SIZE[0] * i + d[0], SIZE[1] * j + d[1], SIZE[2] * k + d[2]]
    return pos


HEX = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
HEX20_EDGES = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4),
               (0, 4), (1, 5), (2, 6), (3, 7)]
# Kuhn's six tetrahedra of a cube along its diagonal 0-6 (positive orientation).
KUHN = [(0, 1, 2, 6), (0, 2, 3, 6), (0, 3, 7, 6), (0, 7, 4, 6), (0, 4, 5, 6), (0, 5, 1, 6)]
TET10_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]


class Mesh:
    def __init__(self):
        self.nodes, self.index, self.elements = [], {}, []

    def node(self, key, p):
        if key not in self.index:
            self.nodes.append(p)
            self.index[key] = len(self.nodes)
        return self.index[key]

    def mid(self, a, b):
        key = ("mid",) + tuple(sorted((a, b)))
        pa, pb = self.nodes[a - 1], self.nodes[b - 1]
        return self.node(key, [(x + y) / 2 for x, y in zip(pa, pb)])


def volume(p):
    a = [p[1][d] - p[0][d] for d in range(3)]
    b = [p[2][d] - p[0][d] for d in range(3)]
    c = [p[3][d] - p[0][d] for d in range(3)]
    return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]))


def build(kind):
    grid = corner_grid()
    m = Mesh()
    for i in range(NX):
        corners = [m.node(("c", i + a, b, c), grid[(i + a, b, c)]) for a, b, c in HEX]
        if kind in ("C3D8", "C3D20"):
            conn = corners
            if kind == "C3D20":
                conn = conn + [m.mid(corners[a], corners[b]) for a, b in HEX20_EDGES]
            m.elements.append(conn)
        else:
            for t in KUHN:
                conn = [corners[v] for v in t]
                assert volume([m.nodes[n - 1] for n in conn]) > 0
                if kind == "C3D10":
                    conn = conn + [m.mid(conn[a], conn[b]) for a, b in TET10_EDGES]
                m.elements.append(conn)
    return m


def deck(kind, m):
    s = f"** {kind}: two distorted bricks (generate.py)\n*NODE, NSET=NALL\n"
    s += "".join(f"{n}, {p[0]!r}, {p[1]!r}, {p[2]!r}\n" for n, p in enumerate(m.nodes, 1))
    s += f"*ELEMENT, TYPE={kind}, ELSET=EALL\n"
    for e, conn in enumerate(m.elements, 1):
        items = [str(e)] + [str(n) for n in conn]
        # Abaqus data lines hold at most 16 items: continue on the next line.
        lines = [items[k:k + 15] for k in range(0, len(items), 15)]
        s += ",\n".join(", ".join(line) for line in lines) + "\n"
    s += f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{E}, {NU}\n*DENSITY\n{RHO}\n"
    s += "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n"
    s += "*STEP\n*FREQUENCY, SOLVER=MATRIXSTORAGE\n6\n*END STEP\n"
    return s


def main():
    for kind in ("C3D4", "C3D10", "C3D8", "C3D20"):
        job = kind.lower()
        text = deck(kind, build(kind))
        (HERE / f"{job}.inp").write_text(text)
        with tempfile.TemporaryDirectory() as tmp:
            t = pathlib.Path(tmp)
            (t / f"{job}.inp").write_text(text)
            subprocess.run(["ccx", job], cwd=t, check=True, stdout=subprocess.DEVNULL)
            for ext in ("sti", "mas", "dof"):
                shutil.copy(t / f"{job}.{ext}", HERE / f"{job}.{ext}")


if __name__ == "__main__":
    main()
