#!/usr/bin/env python3
"""Regenerate the FE data of models/solid_slider_crank.ron: a solid steel crank and connecting rod.

Needs ccx (CalculiX 2.20) on PATH and NumPy/SciPy. Run from anywhere:
    python3 models/fe/generate_slider_crank.py

1. Each part is a straight steel bar of rectangular section, W (along y) x T (along z), its
   pin axes along z at x = 0 and x = PITCH, each pin at the centre of an end element: the bar
   runs from x = -DX/2 to PITCH + DX/2. The mesh is a structured grid of 8-node bricks
   (C3D8), DX long, W/2 wide (2 across y), T thick (1 through z), written by this script in
   Abaqus syntax (a box needs no mesher; Gmsh's transfinite mesh of it would be the same
   grid). The grid is symmetric about each pin axis, so each pin's interface nodes (the 12
   nodes within PIN_RADIUS = 0.035 m of the axis: the nodes of the end column of 2 bricks)
   have their centroid on the axis, at (0, 0, 0) and (PITCH, 0, 0) (asserted below).
2. CalculiX computes the free K and M of each mesh (*FREQUENCY, SOLVER=MATRIXSTORAGE, no
   support) and its own lowest frequencies with the pin at x = 0 clamped (*BOUNDARY on the 12
   pin nodes, *FREQUENCY): <part>_ccx_frequencies.txt.
3. K and M are written value for value (shortest round-trip decimal of each double CalculiX
   printed) in the generic layout flexmbd reads (docs/import.md): <part>_nodes.txt (id x y z),
   <part>_dofs.txt (node dof per matrix row), <part>_K.mtx, <part>_M.mtx (Matrix Market
   coordinate real symmetric, lower triangle). This is smaller than CalculiX's own layout
   (the script prints both sizes).
4. SciPy (dense scipy.linalg.eigh) gives the frequencies of those K, M with the 12 nodes of
   pin O clamped (all three translations held; tag O) and with the nodes of both pins clamped
   (tag OB): <part>_scipy_frequencies.txt. These are the normal modes flexmbd's
   `frame: Interface("O")` with RBE2 spiders gives without a boundary interface (O) and the
   fixed-interface modes with `boundary: ["B"]` (or ["C"]) (OB): a spider clamped to a fixed
   point holds its nodes fixed.
"""
import pathlib
import re
import subprocess
import tempfile

import numpy as np
import scipy
import scipy.linalg

HERE = pathlib.Path(__file__).resolve().parent
E, NU, RHO = 2.1e11, 0.3, 7850.0   # steel (Pa, -, kg/m^3), as the other exports of models/fe
W, T = 0.04, 0.02                  # section: width along y, thickness along z (m), CHOSEN
DX = 0.05                          # element length along x (m), CHOSEN: 0.3 and 1.0 are multiples
NY, NZ = 2, 1                      # elements across y and through z, CHOSEN (coarse)
PIN_RADIUS = 0.035                 # interface selection radius (m): the end element's nodes only
PARTS = {"crank": 0.3, "rod": 1.0}  # pin-to-pin length (m): models/slider_crank.ron's r and L
N_FREQ = 10


def mesh(pitch):
    nx = int(round(pitch / DX)) + 1
    xs = [-DX / 2 + DX * i for i in range(nx + 1)]
    ys = [-W / 2 + W / NY * j for j in range(NY + 1)]
    zs = [-T / 2 + T / NZ * k for k in range(NZ + 1)]
    nodes, ident = {}, {}
    for k, z in enumerate(zs):
        for j, y in enumerate(ys):
            for i, x in enumerate(xs):
                nid = len(nodes) + 1
                nodes[nid] = (round(x, 12), round(y, 12), round(z, 12))
                ident[(i, j, k)] = nid
    elems = []
    for k in range(NZ):
        for j in range(NY):
            for i in range(nx):
                c = lambda a, b, d: ident[(i + a, j + b, k + d)]
                elems.append([c(0, 0, 0), c(1, 0, 0), c(1, 1, 0), c(0, 1, 0),
                              c(0, 0, 1), c(1, 0, 1), c(1, 1, 1), c(0, 1, 1)])
    return nodes, elems


def pin_nodes(nodes, x0):
    return [n for n, (x, y, z) in nodes.items() if (x - x0) ** 2 + y ** 2 <= PIN_RADIUS ** 2]


def inp(nodes, elems, name):
    s = f"** {name}: written by generate_slider_crank.py\n*NODE\n"
    s += "".join(f"{n}, {x!r}, {y!r}, {z!r}\n" for n, (x, y, z) in nodes.items())
    s += f"*ELEMENT, TYPE=C3D8, ELSET={name.upper()}\n"
    s += "".join(f"{e + 1}, " + ", ".join(map(str, c)) + "\n" for e, c in enumerate(elems))
    return s


def run(cmd, cwd):
    subprocess.run(cmd, cwd=cwd, check=True, stdout=subprocess.DEVNULL)


def read_ccx_matrix(path, n):
    a = np.zeros((n, n))
    for line in path.read_text().split("\n"):
        if line.strip():
            i, j, v = line.split()
            a[int(i) - 1, int(j) - 1] = float(v)
            a[int(j) - 1, int(i) - 1] = float(v)
    return a


def ccx_version():
    out = subprocess.run(["ccx", "-v"], capture_output=True, text=True).stdout
    return out.strip().split()[-1]


def part(name, pitch):
    nodes, elems = mesh(pitch)
    clamp = pin_nodes(nodes, 0.0)
    far = pin_nodes(nodes, pitch)
    assert len(clamp) == 12 and len(far) == 12
    for sel, x0 in [(clamp, 0.0), (far, pitch)]:
        c = np.mean([nodes[n] for n in sel], axis=0)
        assert np.allclose(c, [x0, 0, 0], atol=1e-14), c
    material = (f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{E}, {NU}\n*DENSITY\n{RHO}\n"
                f"*SOLID SECTION, ELSET={name.upper()}, MATERIAL=STEEL\n")
    with tempfile.TemporaryDirectory() as tmp:
        t = pathlib.Path(tmp)
        (t / "mesh.inp").write_text(inp(nodes, elems, name))
        fixed = "*NSET, NSET=PIN_O\n" + ", ".join(map(str, clamp)) + "\n*BOUNDARY\nPIN_O, 1, 3\n"
        for job, bc, step in [("free", "", "*FREQUENCY, SOLVER=MATRIXSTORAGE\n1"),
                              ("freq", fixed, f"*FREQUENCY\n{N_FREQ}")]:
            (t / f"{job}.inp").write_text(
                f"** CalculiX deck of generate_slider_crank.py\n*INCLUDE, INPUT=mesh.inp\n{material}{bc}"
                f"*STEP\n{step}\n*END STEP\n")
            run(["ccx", job], t)
        dofs = [tuple(int(v) for v in l.split(".")) for l in (t / "free.dof").read_text().split()]
        n = len(dofs)
        k, m = (read_ccx_matrix(t / f"free.{e}", n) for e in ("sti", "mas"))
        ccx_size = sum((t / f"free.{e}").stat().st_size for e in ("sti", "mas", "dof"))
        ccx_size += (t / "mesh.inp").stat().st_size
        dat = (t / "freq.dat").read_text()
    rows = re.findall(r"^\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$", dat, re.M)
    ccx_freqs = [r[3] for r in rows[:N_FREQ]]

    names = {1: "ux", 2: "uy", 3: "uz"}
    (HERE / f"{name}_nodes.txt").write_text(
        f"# {name} of models/solid_slider_crank.ron: id x y z (m), by generate_slider_crank.py\n"
        + "".join(f"{nid} {x!r} {y!r} {z!r}\n" for nid, (x, y, z) in nodes.items()))
    (HERE / f"{name}_dofs.txt").write_text(
        "# node dof, one line per matrix row, from CalculiX's .dof\n"
        + "".join(f"{nd} {names[d]}\n" for nd, d in dofs))
    for a, tag in [(k, "K"), (m, "M")]:
        lo = np.tril(a)
        ii, jj = np.nonzero(lo)
        with open(HERE / f"{name}_{tag}.mtx", "w") as f:
            f.write("%%MatrixMarket matrix coordinate real symmetric\n")
            f.write(f"% {tag} of {name}: CalculiX {ccx_version()} SOLVER=MATRIXSTORAGE, by generate_slider_crank.py\n")
            f.write(f"{n} {n} {len(ii)}\n")
            f.writelines(f"{i + 1} {j + 1} {float(lo[i, j])!r}\n" for i, j in zip(ii, jj))
    mm_size = sum((HERE / f).stat().st_size for f in
                  [f"{name}_nodes.txt", f"{name}_dofs.txt", f"{name}_K.mtx", f"{name}_M.mtx"])

    # SciPy references: the 12 nodes of pin O clamped (translations; solid nodes have no
    # rotations), tag "O"; the nodes of both pins clamped (the fixed-interface modes of the
    # scene's Craig-Bampton reduction: frame at O, boundary B, both RBE2), tag "OB"
    lines = []
    for tag, held in [("O", set(clamp)), ("OB", set(clamp) | set(far))]:
        free = [r for r, (nd, _) in enumerate(dofs) if nd not in held]
        w2 = scipy.linalg.eigh(k[np.ix_(free, free)], m[np.ix_(free, free)], eigvals_only=True,
                               subset_by_index=[0, N_FREQ - 1])
        f_hz = np.sqrt(w2) / (2 * np.pi)
        lines += [f"{tag} {float(v)!r}\n" for v in f_hz]
        print(f"  scipy {tag}:", " ".join(f"{v:.4f}" for v in f_hz))
    mass = np.sum(m) / 3
    (HERE / f"{name}_scipy_frequencies.txt").write_text(
        f"# {name}: the {N_FREQ} lowest frequencies (Hz) of {name}_K.mtx/{name}_M.mtx by SciPy {scipy.__version__}\n"
        f"# scipy.linalg.eigh (dense; NumPy {np.__version__}), with the 12 nodes of pin O (x = 0) clamped (O)\n"
        f"# and with the 12 nodes of each pin clamped (OB)\n" + "".join(lines))
    (HERE / f"{name}_ccx_frequencies.txt").write_text(
        f"# {name}: CalculiX {ccx_version()}'s own {N_FREQ} lowest frequencies (Hz, as printed in its .dat),\n"
        f"# pin O clamped (*BOUNDARY on the 12 pin nodes, 1-3), *FREQUENCY\n" + "".join(f"{v}\n" for v in ccx_freqs))
    print(f"{name}: {len(nodes)} nodes, {len(elems)} C3D8, {n} DOFs, mass {mass:.6f} kg "
          f"(exact {RHO * (pitch + DX) * W * T:.6f}); generic {mm_size} B, CalculiX layout {ccx_size} B")
    print("  ccx:  ", " ".join(ccx_freqs))


if __name__ == "__main__":
    for name, pitch in PARTS.items():
        part(name, pitch)
