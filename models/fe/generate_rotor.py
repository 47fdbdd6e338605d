#!/usr/bin/env python3
"""Regenerate the unbalanced rotor's FE data of models/unbalanced_rotor.ron (README.md here).

Needs gmsh (4.8.4), ccx (CalculiX 2.20) on PATH and NumPy/SciPy. Run from anywhere:
    python3 models/fe/generate_rotor.py

1. Gmsh meshes a steel rotor with 20-node hexahedra (C3D20): a shaft of diameter 2 R_S and
   length L along x, and a disc of diameter 2 R_D and thickness T at mid-span (rotor.geo).
   The cross-section is an O-grid (a 2 x 2 inner square, 8 patches out to the shaft circle,
   8 x N_DISC patches out to the disc rim), extruded along x in five segments: the left
   journal (one layer), the shaft (N_SHAFT layers), the disc (one layer), the shaft, the
   right journal. Physical groups: the volume ROTOR (the disc ring only in the disc segment),
   the cylindrical surfaces JOURNAL_L and JOURNAL_R of the two journals.
2. Gmsh writes the mesh in Abaqus syntax; it writes the journal surfaces' CPS8 facets as
   elements too, which this script removes (the node sets JOURNAL_L, JOURNAL_R are kept).
   rotor.inp is that mesh with the material, the section and the Abaqus step
   *MATRIX GENERATE appended: the job an Abaqus user would run.
3. CalculiX computes K and M of the same mesh and material (*FREQUENCY,
   SOLVER=MATRIXSTORAGE; no support) and its own lowest free-free frequencies (*FREQUENCY).
4. K and M are converted, value for value (shortest round-trip decimal of each double, exact
   zeros dropped), to the Abaqus *MATRIX OUTPUT default layout (rotor_STIF1.mtx,
   rotor_MASS1.mtx: `node,dof, node,dof, value`, lower triangle column by column), the
   conversion of crates/fe/tests/data/import/generate.py. No Abaqus was run.
5. SciPy (dense scipy.linalg.eigh) gives the free-free frequencies of those K, M, without
   and with the unbalance mass of the scene added at the rim node (rotor_scipy_frequencies.txt).
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
# Geometry (m), CHOSEN (issue 25 item 7(a): a shaft of 20-30 mm ... 0.5-1 m, a disc of
# 0.2-0.3 m, 20-30 mm thick; the shaft made 40 mm so that its bending stays stiffer than the
# bearings and the rigid-rotor estimate of the whirl is close, see unbalanced_rotor.ron).
L, R_S = 0.5, 0.02          # shaft length and radius
R_D, T = 0.125, 0.025       # disc radius and thickness, centred at x = L/2
JOURNAL = 0.05              # journal length at each end (bearing centres at 0.025, 0.475)
S = 0.4 * R_S               # half side of the O-grid's inner square
N_SHAFT, N_DISC = 4, 3      # element layers of each shaft segment; radial divisions of the disc
E, NU, RHO = 2.1e11, 0.3, 7850.0   # steel (Pa, -, kg/m^3), as the bar of crates/fe/tests/data/import
UNBALANCE_NODE_AT = (L / 2, R_D, 0.0)  # rim node of the unbalance (disc mid-plane, +y)
UNBALANCE_MASS = 0.010      # kg (the scene's options.point_masses)
N_FREQ = 20


def geo():
    pts, lines, loops = [], {}, []
    out = [f"// rotor for models/unbalanced_rotor.ron, written by generate_rotor.py"]

    def point(y, z):
        y, z = float(y), float(z)
        pts.append((y, z))
        out.append(f"Point({len(pts)}) = {{0, {y!r}, {z!r}}};")
        return len(pts)

    def line(a, b, n, centre=None):
        k = len(lines) + 1
        lines[(a, b)] = k
        if centre is None:
            out.append(f"Line({k}) = {{{a}, {b}}};")
        else:
            out.append(f"Circle({k}) = {{{a}, {centre}, {b}}};")
        out.append(f"Transfinite Curve{{{k}}} = {n};")
        return k

    def edge(a, b):
        return lines[(a, b)] if (a, b) in lines else -lines[(b, a)]

    def surface(*corners):
        k = len(loops) + 1
        ring = [edge(corners[i], corners[(i + 1) % 4]) for i in range(4)]
        out.append(f"Curve Loop({k}) = {{{', '.join(map(str, ring))}}};")
        out.append(f"Plane Surface({k}) = {{{k}}};")
        out.append(f"Transfinite Surface{{{k}}}; Recombine Surface{{{k}}};")
        loops.append(k)
        return k

    o = point(0.0, 0.0)
    ang = [np.pi / 4 * k for k in range(8)]
    sq = [(S, 0.0), (S, S), (0.0, S), (-S, S), (-S, 0.0), (-S, -S), (0.0, -S), (S, -S)]
    p = [point(y, z) for y, z in sq]
    c = [point(R_S * np.cos(a), R_S * np.sin(a)) for a in ang]
    d = [point(R_D * np.cos(a), R_D * np.sin(a)) for a in ang]
    for k in range(0, 8, 2):
        line(o, p[k], 2)
    for k in range(8):
        line(p[k], p[(k + 1) % 8], 2)
        line(p[k], c[k], 2)
        line(c[k], c[(k + 1) % 8], 2, centre=o)
        line(c[k], d[k], N_DISC + 1)
        line(d[k], d[(k + 1) % 8], 2, centre=o)
    inner = [surface(o, p[2 * q], p[2 * q + 1], p[(2 * q + 2) % 8]) for q in range(4)]
    # ring patches: the arc is the third curve of the loop, so the third lateral surface of
    # each extrusion (checked on the nodes below)
    ring = [surface(p[k], p[(k + 1) % 8], c[(k + 1) % 8], c[k]) for k in range(8)]
    disc = [surface(c[k], c[(k + 1) % 8], d[(k + 1) % 8], d[k]) for k in range(8)]
    n = len(inner + ring + disc)
    out.append(f"s0[] = {{{', '.join(map(str, inner + ring + disc))}}};")
    segments = [JOURNAL, L / 2 - T / 2 - JOURNAL, T, L / 2 - T / 2 - JOURNAL, JOURNAL]
    layers = [1, N_SHAFT, 1, N_SHAFT, 1]
    for g, (dx, nl) in enumerate(zip(segments, layers), start=1):
        out.append(f"e{g}[] = Extrude{{{dx!r}, 0, 0}}{{ Surface{{s{g - 1}[]}}; Layers{{{nl}}}; Recombine; }};")
        out.append(f"For i In {{0:{n - 1}}}\n  s{g}[i] = e{g}[6 * i]; v{g}[i] = e{g}[6 * i + 1]; a{g}[i] = e{g}[6 * i + 4];\nEndFor")
    shaft = [f"v{g}[{{0:11}}]" for g in range(1, 6)]
    out.append(f"Physical Volume(\"ROTOR\") = {{{', '.join(shaft)}, v3[{{12:19}}]}};")
    out.append("Physical Surface(\"JOURNAL_L\") = {a1[{4:11}]};")
    out.append("Physical Surface(\"JOURNAL_R\") = {a5[{4:11}]};")
    out.append("Mesh.ElementOrder = 2; Mesh.SecondOrderIncomplete = 1; Mesh.SaveGroupsOfNodes = 1;")
    return "\n".join(out) + "\n"


def run(cmd, cwd):
    subprocess.run(cmd, cwd=cwd, check=True, stdout=subprocess.DEVNULL)


def strip_surface_elements(text):
    """Drop the CPS8 element blocks and the journal ELSETs Gmsh writes for the physical surfaces."""
    out, skip = [], False
    for line in text.splitlines():
        if line.startswith("*"):
            key = line.upper().replace(" ", "")
            skip = (key.startswith("*ELEMENT,TYPE=CPS") or key.startswith("*ELSET,ELSET=JOURNAL"))
        if not skip:
            out.append(line)
    return "\n".join(out) + "\n"


def read_mesh(text):
    nodes, sets, section, name = {}, {}, None, None
    for line in text.splitlines():
        if line.startswith("*"):
            f = [s.strip() for s in line.split(",")]
            section = f[0].upper()
            name = f[1].split("=")[1] if section == "*NSET" else None
            if name:
                sets[name] = []
            continue
        vals = [s.strip() for s in line.split(",") if s.strip()]
        if section == "*NODE" and vals:
            nodes[int(vals[0])] = tuple(float(v) for v in vals[1:4])
        elif section == "*NSET" and vals:
            sets[name] += [int(v) for v in vals]
    return nodes, sets


def ccx_version():
    out = subprocess.run(["ccx", "-v"], capture_output=True, text=True).stdout
    return out.strip().split()[-1]


def gmsh_version():
    out = subprocess.run(["gmsh", "--version"], capture_output=True, text=True)
    return (out.stdout + out.stderr).strip()


MATERIAL = f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{E}, {NU}\n*DENSITY\n{RHO}\n*SOLID SECTION, ELSET=ROTOR, MATERIAL=STEEL\n"


def run_calculix(mesh):
    with tempfile.TemporaryDirectory() as tmp:
        t = pathlib.Path(tmp)
        (t / "mesh.inp").write_text(mesh)
        for job, step in [("free", "*FREQUENCY, SOLVER=MATRIXSTORAGE\n1"), ("freq", f"*FREQUENCY\n{N_FREQ}")]:
            (t / f"{job}.inp").write_text(
                f"** CalculiX deck of generate_rotor.py\n*INCLUDE, INPUT=mesh.inp\n{MATERIAL}*STEP\n{step}\n*END STEP\n")
            run(["ccx", job], t)
        dofs = [tuple(int(v) for v in l.split(".")) for l in (t / "free.dof").read_text().split()]
        n = len(dofs)
        k, m = (read_ccx_matrix(t / f"free.{e}", n) for e in ("sti", "mas"))
        dat = (t / "freq.dat").read_text()
    rows = re.findall(r"^\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$", dat, re.M)
    return dofs, k, m, [r[3] for r in rows[:N_FREQ]]


def read_ccx_matrix(path, n):
    a = np.zeros((n, n))
    for line in path.read_text().split("\n"):
        if line.strip():
            i, j, v = line.split()
            a[int(i) - 1, int(j) - 1] = float(v)
            a[int(j) - 1, int(i) - 1] = float(v)
    return a


def write_abaqus_mtx(path, a, dofs, what):
    lo = np.tril(a)
    with open(path, "w") as f:
        f.write(f"** {what} of rotor.inp in the Abaqus *MATRIX OUTPUT default layout: CONVERTED by\n")
        f.write("** generate_rotor.py from CalculiX 2.20 SOLVER=MATRIXSTORAGE (not an Abaqus export)\n")
        for j in range(a.shape[0]):  # column by column, rows ascending within
            for i in np.nonzero(lo[:, j])[0]:
                (ni, di), (nj, dj) = dofs[i], dofs[j]
                f.write(f"{ni},{di}, {nj},{dj}, {float(a[i, j])!r}\n")


def frequencies_hz(k, m):
    w2 = scipy.linalg.eigh(k, m, eigvals_only=True)[:N_FREQ]
    return np.sign(w2) * np.sqrt(np.abs(w2)) / (2 * np.pi)


def main():
    (HERE / "rotor.geo").write_text(geo())
    with tempfile.TemporaryDirectory() as tmp:
        shutil.copy(HERE / "rotor.geo", tmp)
        run(["gmsh", "-3", "rotor.geo", "-format", "inp", "-o", "rotor_gmsh.inp"], tmp)
        mesh = strip_surface_elements((pathlib.Path(tmp) / "rotor_gmsh.inp").read_text())
    nodes, sets = read_mesh(mesh)
    for name, lo, hi in [("JOURNAL_L", 0.0, JOURNAL), ("JOURNAL_R", L - JOURNAL, L)]:
        for nd in sets[name]:
            x, y, z = nodes[nd]
            assert lo - 1e-9 <= x <= hi + 1e-9 and abs(np.hypot(y, z) - R_S) < 1e-9, (name, nd, nodes[nd])
    unbalance = min(nodes, key=lambda nd: np.linalg.norm(np.subtract(nodes[nd], UNBALANCE_NODE_AT)))
    centre = min(nodes, key=lambda nd: np.linalg.norm(np.subtract(nodes[nd], (L / 2, 0, 0))))
    assert np.linalg.norm(np.subtract(nodes[unbalance], UNBALANCE_NODE_AT)) < 1e-9
    assert np.linalg.norm(np.subtract(nodes[centre], (L / 2, 0, 0))) < 1e-9
    header = (f"** The rotor of models/unbalanced_rotor.ron: mesh by {gmsh_version() and 'Gmsh ' + gmsh_version()} (rotor.geo),\n"
              "** its CPS8 facets of the journal surfaces removed by generate_rotor.py; material, section\n"
              "** and the Abaqus *MATRIX GENERATE step appended. rotor_STIF1.mtx and rotor_MASS1.mtx were\n"
              "** made by CalculiX from this mesh and material and converted (no Abaqus run).\n"
              f"** Unbalance node (x, y, z) = {nodes[unbalance]}: {unbalance}; disc centre node: {centre}.\n")
    step = ("*STEP\n*MATRIX GENERATE, STIFFNESS, MASS\n*MATRIX OUTPUT, STIFFNESS, MASS\n*END STEP\n")
    (HERE / "rotor.inp").write_text(header + mesh + MATERIAL + step)
    dofs, k, m, ccx = run_calculix(mesh)
    write_abaqus_mtx(HERE / "rotor_STIF1.mtx", k, dofs, "K")
    write_abaqus_mtx(HERE / "rotor_MASS1.mtx", m, dofs, "M")
    with open(HERE / "rotor_ccx_frequencies.txt", "w") as f:
        f.write(f"# CalculiX {ccx_version()} *FREQUENCY (free-free, no unbalance mass) of the rotor mesh:\n")
        f.write(f"# the lowest {N_FREQ} frequencies (Hz) as printed in its .dat (7 significant digits)\n")
        f.writelines(f"{v}\n" for v in ccx)
    mu = m.copy()
    for r, (node, dof) in enumerate(dofs):
        if node == unbalance:
            mu[r, r] += UNBALANCE_MASS
    plain, with_mass = frequencies_hz(k, m), frequencies_hz(k, mu)
    with open(HERE / "rotor_scipy_frequencies.txt", "w") as f:
        f.write(f"# SciPy {scipy.__version__} scipy.linalg.eigh(K, M), dense, on rotor_STIF1.mtx/rotor_MASS1.mtx\n")
        f.write(f"# ({len(dofs)} DOFs, {len(nodes)} nodes), free-free: the lowest {N_FREQ} (Hz), six rigid-body\n")
        f.write("# modes first (signed square roots of the computed eigenvalues); `plain`: K, M as\n")
        f.write(f"# exported; `unbalance`: {UNBALANCE_MASS} kg added on the three DOFs of node {unbalance}.\n")
        f.writelines(f"plain {float(v)!r}\n" for v in plain)
        f.writelines(f"unbalance {float(v)!r}\n" for v in with_mass)
    mass = sum(m[r, c] for r, (n1, d1) in enumerate(dofs) for c in range(len(dofs)) if d1 == 1 and dofs[c][1] == 1)
    print(f"{len(nodes)} nodes, {len(dofs)} DOFs, mass {mass} kg; unbalance node {unbalance}, centre node {centre}")
    print("scipy:", plain[:12])
    print("ccx:", ccx[:12])


if __name__ == "__main__":
    main()
