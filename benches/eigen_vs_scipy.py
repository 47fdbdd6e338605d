#!/usr/bin/env python3
"""Side by side: flexmbd's sparse eigen-solver and SciPy's eigsh on the same free-free hex8 bars.

    cargo build --release -p flexmbd-fe --example eigen_vs_scipy
    python3 benches/eigen_vs_scipy.py --sizes 4 6 9 14 19 --runs 3 --work /tmp/eigen_vs_scipy

For each size n (a 0.4 x 0.1 x 0.1 m steel bar of 4n x n x n bricks) the Rust example writes
K and M as Matrix Market files and the shift; then each side runs `--runs` times in its own
process under /usr/bin/time -v (peak RSS = "Maximum resident set size"), timing only the
factorisation and the eigen-iteration (file reading and assembly are outside the timed part).
Prints a Markdown table of medians and the largest relative difference of the elastic w^2
between the two (the six rigid w^2 are both at round-off level and compared against the
first elastic one). `--scipy-max N` skips SciPy above N DOFs (it needs hours there).
"""
import argparse
import os
import re
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
TARGET = os.environ.get("CARGO_TARGET_DIR", os.path.join(HERE, "..", "target"))
RUST = os.path.join(TARGET, "release", "examples", "eigen_vs_scipy")
SCIPY = os.path.join(HERE, "scipy_eigsh.py")


def timed(cmd):
    """Run cmd under /usr/bin/time -v; the program's key-value line and the peak RSS in MiB."""
    proc = subprocess.run(["/usr/bin/time", "-v"] + cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{proc.stdout}\n{proc.stderr}")
    line = [l for l in proc.stdout.splitlines() if l.startswith("N ")][-1]
    tokens = line.split()
    values = dict(zip(tokens[0::2], tokens[1::2]))
    peak = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", proc.stderr).group(1))
    values["time_v_peak_mib"] = peak / 1024.0
    return values


def read(path):
    with open(path) as f:
        return [float(v) for v in f.read().split()]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--sizes", type=int, nargs="+", default=[4, 6, 9, 14, 19])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--modes", type=int, default=20)
    parser.add_argument("--work", default="/tmp/eigen_vs_scipy")
    parser.add_argument("--scipy-max", type=int, default=10**9)
    args = parser.parse_args()
    rows = []
    for n in args.sizes:
        d = os.path.join(args.work, f"bar{n}")
        subprocess.run([RUST, "write", str(n), d], check=True, capture_output=True)
        ours = [timed([RUST, "solve", str(n), f"{d}/rust.txt", "--modes", str(args.modes)])
                for _ in range(args.runs)]
        dofs = int(ours[0]["N"])
        theirs = []
        if dofs <= args.scipy_max:
            theirs = [timed(["python3", SCIPY, d, f"{d}/scipy.txt", "--modes", str(args.modes)])
                      for _ in range(args.runs)]
        med = lambda runs, key: statistics.median(float(r[key]) for r in runs)
        row = {
            "N": dofs,
            "nnz": int(ours[0]["nnz"]),
            "ours_s": med(ours, "solve_s"),
            "ours_numeric_s": med(ours, "numeric_s"),
            "ours_solves_s": med(ours, "solves_s"),
            "ours_orth_s": med(ours, "orth_s"),
            "ours_peak": med(ours, "time_v_peak_mib"),
            "factor_entries": int(ours[0]["factor_entries"]),
            "solves": int(ours[0]["solves"]),
            "ours_residual": max(float(r["max_residual"]) for r in ours),
        }
        if theirs:
            w_ours, w_theirs = read(f"{d}/rust.txt"), read(f"{d}/scipy.txt")
            first = w_theirs[6]
            rigid = max(abs(a - b) / first for a, b in zip(w_ours[:6], w_theirs[:6]))
            elastic = max(abs(a - b) / b for a, b in zip(w_ours[6:], w_theirs[6:]))
            row.update({
                "scipy_s": med(theirs, "solve_s"),
                "scipy_peak": med(theirs, "time_v_peak_mib"),
                "scipy_residual": max(float(r["max_residual"]) for r in theirs),
                "elastic_diff": elastic,
                "rigid_diff": rigid,
            })
        rows.append(row)
        print(row, file=sys.stderr, flush=True)
    print("| N | nnz(K) | nnz(L) | ours (s) | SciPy (s) | ours peak RSS (MiB) | SciPy peak RSS (MiB) "
          "| max rel. diff. elastic ω² | rigid ω² diff / ω²₇ | max residual ours / SciPy |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        if "scipy_s" in r:
            print(f"| {r['N']} | {r['nnz']} | {r['factor_entries']} | {r['ours_s']:.3f} | {r['scipy_s']:.3f} "
                  f"| {r['ours_peak']:.0f} | {r['scipy_peak']:.0f} | {r['elastic_diff']:.1e} "
                  f"| {r['rigid_diff']:.1e} | {r['ours_residual']:.1e} / {r['scipy_residual']:.1e} |")
        else:
            print(f"| {r['N']} | {r['nnz']} | {r['factor_entries']} | {r['ours_s']:.3f} | not run "
                  f"| {r['ours_peak']:.0f} | – | – | – | {r['ours_residual']:.1e} / – |")
    print()
    print("| N | ours: numeric factorisation (s) | solves (s) | orthogonalisation (s) | vectors solved |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['N']} | {r['ours_numeric_s']:.3f} | {r['ours_solves_s']:.3f} | {r['ours_orth_s']:.3f} | {r['solves']} |")


if __name__ == "__main__":
    main()
