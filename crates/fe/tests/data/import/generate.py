#!/usr/bin/env python3
"""Regenerate the import test data of crates/fe/tests/import_*.rs (see README.md).

Needs gmsh, ccx (CalculiX) and SciPy on PATH / in Python. Run from anywhere:
    python3 crates/fe/tests/data/import/generate.py

1. Gmsh meshes a steel bar with hexahedra (bar_mesh.inp, Abaqus syntax).
2. CalculiX writes its free-free K and M (*FREQUENCY, SOLVER=MATRIXSTORAGE:
   bar_free.sti, .mas, .dof) and the clamped frequencies (bar_clamped.inp → .dat,
   extracted to bar_ccx_frequencies.txt).
3. The CalculiX matrices are converted, value for value (shortest round-trip decimal
   of each double, exact zeros dropped), to the other layouts the readers accept:
   generic Matrix Market + node list + DOF map, an Ansys-style HBMAT .mapping and
   NLIST listing, and Abaqus *MATRIX OUTPUT (MATRIX INPUT layout) with an
   assembly/instance version of the input file. These are conversions, not exports
   of Abaqus or Ansys, which we do not have.
4. SciPy computes the reference frequencies on the same matrices, and on the Ansys
   rotor export from Exudyn kept verbatim in exudyn/ (see README.md).
"""
import pathlib
import re
import shutil
import subprocess
import tempfile

import numpy as np
import scipy
import scipy.linalg

HERE = pathlib.Path(__file__).resolve().parent
L, B, H = 0.2, 0.02, 0.02          # bar length, width, height (m)
NX, NY, NZ = 6, 1, 1               # hexahedra along x, y, z
E, NU, RHO = 2.1e11, 0.3, 7850.0   # steel (Pa, -, kg/m^3)
N_FREQ = 10

GEO = f"""L = {L}; B = {B}; H = {H};
Point(1) = {{0,0,0}}; Point(2) = {{L,0,0}};
Line(1) = {{1,2}};
Transfinite Line{{1}} = {NX + 1};
e1[] = Extrude{{0,B,0}}{{ Line{{1}}; Layers{{{NY}}}; Recombine; }};
e2[] = Extrude{{0,0,H}}{{ Surface{{e1[1]}}; Layers{{{NZ}}}; Recombine; }};
Physical Volume("bar") = {{e2[1]}};
"""


def run(cmd, cwd):
    subprocess.run(cmd, cwd=cwd, check=True, stdout=subprocess.DEVNULL)


def read_nodes(inp):
    nodes, section = {}, None
    for line in inp.read_text().splitlines():
        if line.startswith("*"):
            section = line.split(",")[0].strip().upper()
            continue
        if section == "*NODE" and line.strip():
            f = [s.strip() for s in line.split(",")]
            nodes[int(f[0])] = tuple(float(v) for v in f[1:4])
    return nodes


def ccx_deck(clamp, boundary, step):
    s = "** CalculiX deck written by generate.py\n*INCLUDE, INPUT=bar_mesh.inp\n"
    s += "*NSET, NSET=CLAMP\n" + ", ".join(map(str, clamp)) + "\n"
    s += f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{E}, {NU}\n*DENSITY\n{RHO}\n"
    s += "*SOLID SECTION, ELSET=bar, MATERIAL=STEEL\n"
    if boundary:
        s += "*BOUNDARY\nCLAMP, 1, 3\n"
    return s + f"*STEP\n{step}\n*END STEP\n"


def run_calculix(clamp):
    with tempfile.TemporaryDirectory() as tmp:
        t = pathlib.Path(tmp)
        shutil.copy(HERE / "bar_mesh.inp", t)
        for job, bc, step in [
            ("bar_free", False, f"*FREQUENCY, SOLVER=MATRIXSTORAGE\n{N_FREQ}"),
            ("bar_clamped", True, f"*FREQUENCY\n{N_FREQ}"),
        ]:
            (HERE / f"{job}.inp").write_text(ccx_deck(clamp, bc, step))
            shutil.copy(HERE / f"{job}.inp", t)
            run(["ccx", job], t)
        for ext in ["sti", "mas", "dof"]:
            shutil.copy(t / f"bar_free.{ext}", HERE)
        dat = (t / "bar_clamped.dat").read_text()
    rows = re.findall(r"^\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$", dat, re.M)
    hz = [float(r[3]) for r in rows[:N_FREQ]]
    with open(HERE / "bar_ccx_frequencies.txt", "w") as f:
        f.write(f"# CalculiX {ccx_version()} *FREQUENCY of bar_clamped.inp: the lowest {N_FREQ}\n")
        f.write("# frequencies (Hz) as printed in bar_clamped.dat (7 significant digits)\n")
        f.writelines(f"{float(v)!r}\n" for v in hz)


def ccx_version():
    out = subprocess.run(["ccx", "-v"], capture_output=True, text=True).stdout
    return out.strip().split()[-1]


def read_ccx_matrix(path, n):
    a = np.zeros((n, n))
    for line in path.read_text().split("\n"):
        if line.strip():
            i, j, v = line.split()
            a[int(i) - 1, int(j) - 1] = float(v)
            a[int(j) - 1, int(i) - 1] = float(v)
    return a


def lower_entries(a):
    n = a.shape[0]
    return [(i, j, a[i, j]) for j in range(n) for i in range(j, n) if a[i, j] != 0.0]


def write_matrix_market(path, a, what):
    e = lower_entries(a)
    with open(path, "w") as f:
        f.write("%%MatrixMarket matrix coordinate real symmetric\n")
        f.write(f"% {what} of bar_free (CalculiX MATRIXSTORAGE), converted by generate.py\n")
        f.write(f"{a.shape[0]} {a.shape[0]} {len(e)}\n")
        f.writelines(f"{i + 1} {j + 1} {float(v)!r}\n" for i, j, v in e)


def write_abaqus_mtx(path, a, dofs, instance):
    with open(path, "w") as f:
        f.write("** converted by generate.py from CalculiX bar_free (not an Abaqus export)\n")
        for i, j, v in lower_entries(a):
            (ni, di), (nj, dj) = dofs[i], dofs[j]
            f.write(f"{instance}.{ni},{di}, {instance}.{nj},{dj}, {float(v)!r}\n")


def write_part_inp(nodes):
    mesh = (HERE / "bar_mesh.inp").read_text()
    body = mesh[mesh.index("*NODE"):]
    s = "*Heading\n** bar_mesh.inp wrapped in a part and an instance by generate.py\n"
    s += "*Part, name=BAR\n" + body + "*End Part\n"
    s += "*Assembly, name=Assembly\n*Instance, name=BAR-1, part=BAR\n*End Instance\n"
    s += "*Nset, nset=CLAMP, instance=BAR-1\n"
    s += ", ".join(str(n) for n, p in sorted(nodes.items()) if p[0] == 0.0) + "\n"
    s += "*End Assembly\n"
    (HERE / "bar_part.inp").write_text(s)


def write_text_formats(nodes, dofs):
    names = {1: "ux", 2: "uy", 3: "uz"}
    ansys = {1: "UX", 2: "UY", 3: "UZ"}
    with open(HERE / "bar_nodes.txt", "w") as f:
        f.write("# id x y z (m), from bar_mesh.inp\n")
        f.writelines(f"{n} {float(p[0])!r} {p[1]!r} {p[2]!r}\n" for n, p in sorted(nodes.items()))
    with open(HERE / "bar_dofs.txt", "w") as f:
        f.write("# node dof, one line per matrix row, from bar_free.dof\n")
        f.writelines(f"{n} {names[d]}\n" for n, d in dofs)
    with open(HERE / "bar_nlist.lis", "w") as f:
        f.write(" LIST ALL SELECTED NODES.   DSYS=      0\n\n")
        f.write("    NODE        X                   Y                   Z           THXY     THYZ     THZX\n")
        f.writelines(f"{n:9d} {p[0]!r:>20} {p[1]!r:>20} {p[2]!r:>20}    0.00     0.00     0.00\n"
                     for n, p in sorted(nodes.items()))
    with open(HERE / "bar.mapping", "w") as f:
        f.write("Matrix Eqn   Node   DOF\n")
        f.writelines(f"{k + 1:10d} {n:6d}   {ansys[d]}\n" for k, (n, d) in enumerate(dofs))


def frequencies_hz(k, m):
    w2 = scipy.linalg.eigh(k, m, eigvals_only=True)
    return np.sqrt(np.maximum(w2, 0.0)) / (2 * np.pi)


def main():
    (HERE / "bar.geo").write_text(GEO)
    run(["gmsh", "-3", "bar.geo", "-format", "inp", "-o", "bar_mesh.inp"], HERE)
    nodes = read_nodes(HERE / "bar_mesh.inp")
    clamp = [n for n, p in sorted(nodes.items()) if p[0] == 0.0]
    run_calculix(clamp)
    dofs = [tuple(int(v) for v in l.split(".")) for l in (HERE / "bar_free.dof").read_text().split()]
    n = len(dofs)
    k = read_ccx_matrix(HERE / "bar_free.sti", n)
    m = read_ccx_matrix(HERE / "bar_free.mas", n)
    write_matrix_market(HERE / "bar_K.mtx", k, "K")
    write_matrix_market(HERE / "bar_M.mtx", m, "M")
    write_abaqus_mtx(HERE / "bar_STIF1.mtx", k, dofs, "BAR-1")
    write_abaqus_mtx(HERE / "bar_MASS1.mtx", m, dofs, "BAR-1")
    write_part_inp(nodes)
    write_text_formats(nodes, dofs)
    free = [r for r, (node, _) in enumerate(dofs) if node not in clamp]
    clamped = frequencies_hz(k[np.ix_(free, free)], m[np.ix_(free, free)])[:N_FREQ]
    free_free = frequencies_hz(k, m)[:12]
    with open(HERE / "bar_scipy_frequencies.txt", "w") as f:
        f.write(f"# SciPy {scipy.__version__} scipy.linalg.eigh(K, M) on bar_free.sti/.mas (dense).\n")
        f.write(f"# clamped: the DOFs of the {len(clamp)} nodes at x = 0 removed; lowest {N_FREQ} (Hz)\n")
        f.writelines(f"clamped {float(v)!r}\n" for v in clamped)
        f.write("# free-free: lowest 12 (Hz), six rigid-body modes first\n")
        f.writelines(f"free {float(v)!r}\n" for v in free_free)


def read_matrix_market(path):
    lines = [l for l in path.read_text().splitlines() if l.strip() and not l.startswith("%")]
    n = int(lines[0].split()[0])
    a = np.zeros((n, n))
    for l in lines[1:]:
        i, j, v = l.split()
        a[int(i) - 1, int(j) - 1] = a[int(j) - 1, int(i) - 1] = float(v)
    return a


def rotor_reference():
    d = HERE / "exudyn"
    k = read_matrix_market(d / "rotorAnsysStiffnessMatrixSparse.txt")
    m = read_matrix_market(d / "rotorAnsysMassMatrixSparse.txt")
    f = frequencies_hz(k, m)[:16]
    with open(d / "rotor_scipy_frequencies.txt", "w") as out:
        out.write(f"# SciPy {scipy.__version__} scipy.linalg.eigh(K, M), dense, on the Ansys MMF\n")
        out.write("# exports (free-free): lowest 16 (Hz), six rigid-body modes first\n")
        out.writelines(f"{float(v)!r}\n" for v in f)


if __name__ == "__main__":
    rotor_reference()
    main()
