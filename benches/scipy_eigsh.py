#!/usr/bin/env python3
"""SciPy's eigsh on the matrices the Rust measurement wrote (crates/fe/examples/eigen_vs_scipy.rs).

    python3 benches/scipy_eigsh.py DIR OUT [--modes 20] [--tol 1e-10]

Reads DIR/K.mtx, DIR/M.mtx and DIR/shift.txt, converts K and M to CSC (untimed), then times
eigsh(K, k, M, sigma=shift, which='LM', tol=tol) in shift-invert mode: SciPy factorises
K - sigma M with SuperLU (splu) and drives ARPACK's dsaupd/dseupd. Prints one line with the
time, the resident set before the solve and the peak, and writes the omega^2 ascending to OUT.
"""
import argparse
import resource
import time

import numpy as np
import scipy
import scipy.io
import scipy.sparse.linalg as sla


def rss_mib():
    current = 0.0
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                current = float(line.split()[1]) / 1024.0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    return current, peak


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("dir")
    parser.add_argument("out")
    parser.add_argument("--modes", type=int, default=20)
    parser.add_argument("--tol", type=float, default=1e-10)
    args = parser.parse_args()
    k = scipy.io.mmread(f"{args.dir}/K.mtx").tocsc()
    m = scipy.io.mmread(f"{args.dir}/M.mtx").tocsc()
    with open(f"{args.dir}/shift.txt") as f:
        sigma = float(f.read())
    before, _ = rss_mib()
    start = time.perf_counter()
    values, vectors = sla.eigsh(k, k=args.modes, M=m, sigma=sigma, which="LM", tol=args.tol)
    seconds = time.perf_counter() - start
    _, peak = rss_mib()
    order = np.argsort(values)
    values = values[order]
    vectors = vectors[:, order]
    residuals = []
    for j in range(args.modes):
        x = vectors[:, j]
        kx, mx = k @ x, m @ x
        r = np.linalg.norm(kx - values[j] * mx)
        a = np.linalg.norm(kx - sigma * mx) + abs(values[j] - sigma) * np.linalg.norm(mx)
        residuals.append(r / a)
    np.savetxt(args.out, values)
    print(
        f"N {k.shape[0]} nnz {k.nnz} solve_s {seconds:.3f} rss_before_mib {before:.0f} "
        f"peak_rss_mib {peak:.0f} max_residual {max(residuals):.2e} scipy {scipy.__version__}"
    )


if __name__ == "__main__":
    main()
