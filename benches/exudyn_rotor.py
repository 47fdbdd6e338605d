"""flexmbd against Exudyn 1.13.6 on the unbalanced rotor (models/unbalanced_rotor.ron), side by side.

Issue 25's check: the same imported FE model (models/fe/rotor.inp, rotor_STIF1.mtx, rotor_MASS1.mtx)
run by both codes at the same step; (1) do the histories agree, (2) how much faster is flexmbd.

Set-up once:  python3 -m venv /tmp/exu && /tmp/exu/bin/pip install exudyn==1.13.6 numpy scipy
Run (from the project root, after `cargo build --release -p flexmbd-cli`):
              /tmp/exu/bin/python benches/exudyn_rotor.py target/release/flexmbd 5
              (arguments: the flexmbd binary, the repetitions; default target/release/flexmbd, 5)

The Exudyn model (built here, the same data as the scene):
- Mesh: Exudyn's FEMinterface.ImportFromAbaqusInputFile reads one *Part with '*Node' and one
  '*Element' block, so rotor.inp's 895 nodes and 112 C3D20 (in 112 *ELEMENT blocks, no *Part) are
  rewritten into that shape (same nodes in the same order, same connectivity) in a temporary folder.
  Matrices: ReadStiffnessMatrixFromAbaqus / ReadMassMatrixFromAbaqus read Abaqus' FORMAT=COORDINATE
  triplets (global DOF row, column, value); the exports are in the default layout (node, dof, node,
  dof, value; lower triangle), so they are rewritten value for value as full symmetric triplets.
- 10 g at node 444: added to M at the node's three translational DOFs before the modes (as the
  scene's point_masses).
- Modes: FEMinterface.ComputeEigenmodes(8, excludeRigidBodyModes=6, useSparseSolver=True): the 8
  lowest free-free elastic modes, M-orthonormal, so M-orthogonal to the rigid-body modes (the
  linearised mean-axis/Tisserand conditions; flexmbd imposes mean axes on its free-free frame).
- Body: ObjectFFRFreducedOrderInterface(...).AddObjectFFRFreducedOrder (C++ object, no Python user
  function), rigid-body node with Euler parameters (Exudyn's default), frame at (0, 0, 0),
  initialAngularVelocity = (2 pi 50, 0, 0), gravity (0, 0, -9.81) as LoadMassProportional.
- Modal damping 1 %: the object's dampingMatrixReduced set to diag(2 zeta omega_i) (the modes are
  mass-normalised), as flexmbd's ModalRatio(zeta: 0.01).
- Bearings: MarkerSuperElementPosition on the 40 nodes of JOURNAL_L / JOURNAL_R with equal weights
  1/40 (the journal's mean translation = flexmbd's RBE3 point, whose centroid is on the axis);
  CartesianSpringDamper to ground markers at (0.025, 0, 0) and (0.475, 0, 0), k = 5e6 N/m,
  c = 500 N s/m along y and z at both, along x at the left only.
- Solver: generalized-alpha, spectral radius 0.9 (as the project's other Exudyn cases), h = 2.5e-4 s,
  0.5 s, modified Newton, relative tolerance 1e-8, dense linear solver (15 ODE2 coordinates + 1
  Euler-parameter constraint); sensors every 5e-4 s (the scene's output_interval), stored in memory,
  no solution file, no graphics.
- Sensors (only what is compared): the disc centre's mesh node 391 position (ground), the two
  connectors' forces, the rigid-body node's rotation (its first Tait-Bryan angle, the spin).

flexmbd: `flexmbd simulate models/unbalanced_rotor.ron --formulation absolute|relative --json
--output CSV` (default inertia route, shape integrals); the scene's 15 sensors are written to the CSV
every 5e-4 s, so flexmbd does at least the output work Exudyn does.

Compared: the disc centre's y and z displacement histories, the bearing forces (left y, z, x; right
y, z) and the spin angle (flexmbd's `spin` sensor, the first Cardan angle of R = Rx Ry Rz, and
Exudyn's Rotation output of the node, the same angle; both unwrapped), at equal time and at equal
spin angle; over the last 5 revolutions (0.4-0.5 s): the whirl radius of the disc centre about its
mean, the 1x (synchronous) harmonic of each signal (least squares at the mean spin rate: amplitude,
phase, mean = the static sag and bearing loads), the whirl's phase behind the spin angle, the mean
spin rate (from the angle). The spin rate is taken from the angle, not from a velocity sensor: the
rim's velocity in the rotor's frame carries the synchronous whirl (25 um x 314 rad/s / 0.125 m =
0.065 rad/s, 0.02 %).

Times, per repetition, the cases interleaved (Exudyn, flexmbd absolute, flexmbd relative), medians:
flexmbd's JSON cpu_seconds (integration only) and preprocessing_seconds (reading the export, the
sparse free-free modes, the mass cloud) against Exudyn's SolveDynamic wall time and, separately, its
preprocessing (FEM import of the rewritten files, eigenmodes, the reduced-order interface).

Measured 2026-11-28, 2-core VM shared with other sessions (load average 4-4.5 during the runs),
flexmbd at main 3f118a8 (/work/main/target/release/flexmbd), Exudyn 1.13.6 (pip wheel), NumPy 2.4.6,
SciPy 1.17.1. Both bodies have the same mass 14.317940 kg, centre of mass y 8.7303e-5 m and modes
548.1587, 548.1592, 806.2618, 807.4321, 2166.2234, 2171.6241, 2418.0730, 2640.7489 Hz.
- Histories: the steady whirl (last 5 revolutions) agrees to 0.02 % (absolute) and 0.007 %
  (relative): disc whirl radius 25.720 (Exudyn), 25.715, 25.722 um; sag -21.779 um in all three;
  bearing 1x amplitudes 78.79 / 78.77 / 78.80 N, static bearing load -70.228 N in all three; the
  whirl's phase behind the spin angle -24.56 / -24.54 / -24.56 mrad. Compared at equal time the
  histories differ by up to 5.9 % (absolute) and 2.1 % (relative) of the whirl amplitude: that is the
  spin angle, which drifts by O(h^2) in Exudyn (-21.0 mrad at 0.5 s) and flexmbd absolute (-80.9 mrad;
  -20.5 and -5.3 at h/2 and h/4), while the relative formulation's (-0.30 mrad) is step-converged
  (-0.30 at h/2, h/4) and Exudyn's tends to it (-5.5 at h/2, -1.6 at h/4). The drifts are the
  trapezoidal-type phase error of coordinates that oscillate with the spin, (w h)^2 / 12 per radian
  turned: flexmbd absolute's frame coordinates turn at w = Omega, 157 rad x (Omega h)^2 / 12 = 80.7
  mrad; Exudyn's Euler parameters at Omega / 2, a quarter of it, 20.2 mrad; the relative
  formulation's floating base turns through Cardan angles (x, y', z''), the first of which is the
  spin itself, growing linearly, which the trapezoidal rule integrates without phase error. Compared at equal spin
  angle the histories agree to 0.31 % (absolute) and 0.13 % (relative) after 0.3 s, 0.74 % and
  0.22 % over the whole run.
- Times, 11 repetitions (medians [min-max]): Exudyn SolveDynamic 2.30 s wall [2.17-3.10] (1.53 s
  process CPU; 17 322 Newton iterations, 668 Jacobians, i.e. 8.7 iterations per step: its modified
  Newton keeps a Jacobian in Euler parameters that goes stale as the rotor turns 0.079 rad a step);
  flexmbd absolute 0.051 s [0.036-0.072], 45x faster; relative 0.023 s [0.015-0.031], 100x faster.
  Two 5-repetition runs gave 60x / 109x and 33x / 88x (the flexmbd runs last 15-90 ms and take the
  other sessions' load in their medians). Preprocessing: Exudyn 0.93 s (FEM import 0.57, eigen 0.30,
  interface 0.09), flexmbd 0.48 s (absolute) and 0.49 s (relative).
- Diagnostic, the same model started at rest: Exudyn 0.38 s (one Jacobian, 2 iterations a step),
  flexmbd 0.033 s (absolute, 12x) and 0.024 s (relative, 16x): without the spin the ratio is below 20x;
  the rotor's ratio owes much to Exudyn's Newton iterations under spin.
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy.sparse as sp

ROOT = os.getcwd()
FE = os.path.join(ROOT, 'models', 'fe')
SCENE = 'models/unbalanced_rotor.ron'
H, T_END, OUT = 2.5e-4, 0.5, 5e-4
K_B, C_B = 5e6, 500.0
ZETA, N_MODES = 0.01, 8
OMEGA0 = 2 * np.pi * 50
M_U, NODE_U, NODE_DISC = 0.010, 444, 391      # Abaqus labels (1-based)
REV = 2 * np.pi / OMEGA0


# ---------------------------------------------------------------- the export, rewritten for Exudyn
def read_inp(path):
    """nodes (labels 1..N in order), C3D20 connectivity, node sets (1-based labels) of rotor.inp"""
    nodes, elems, sets = [], [], {}
    mode, cur, pending = None, None, []
    for raw in open(path):
        line = raw.strip()
        if not line or line.startswith('**'):
            continue
        if line.startswith('*'):
            key = line.upper()
            mode = None
            if key.startswith('*NODE') and not key.startswith('*NODE '):
                mode = 'node'
            elif key.startswith('*ELEMENT') and 'C3D20' in key:
                mode = 'elem'
            elif key.startswith('*NSET'):
                mode, cur = 'nset', key.split('NSET=')[1].split(',')[0].strip()
                sets[cur] = []
            continue
        vals = [v for v in line.split(',') if v.strip()]
        if mode == 'node':
            if int(vals[0]) != len(nodes) + 1:
                raise ValueError(f'{path}: node labels must run 1..N in order (got {vals[0]})')
            nodes.append([float(v) for v in vals[1:4]])
        elif mode == 'elem':
            pending += [int(v) for v in vals]
            if len(pending) == 21:
                elems.append(pending[1:])
                pending = []
        elif mode == 'nset':
            sets[cur] += [int(v) for v in vals]
    return np.array(nodes), elems, sets


def read_matrix(path, n):
    """Abaqus *MATRIX OUTPUT default layout (node, dof, node, dof, value; one triangle) -> full CSR"""
    a = np.loadtxt(path, delimiter=',', comments='**')
    r = (a[:, 0].astype(int) - 1) * 3 + a[:, 1].astype(int) - 1
    c = (a[:, 2].astype(int) - 1) * 3 + a[:, 3].astype(int) - 1
    off = r != c
    rows = np.concatenate([r, c[off]])
    cols = np.concatenate([c, r[off]])
    vals = np.concatenate([a[:, 4], a[off, 4]])
    return sp.coo_matrix((vals, (rows, cols)), shape=(n, n)).tocsr()


def write_for_exudyn(tmp):
    """Exudyn-readable copies of the export: one *Part/*Node/*Element, COORDINATE triplets"""
    nodes, elems, sets = read_inp(os.path.join(FE, 'rotor.inp'))
    n = 3 * len(nodes)
    inp = os.path.join(tmp, 'rotor_exudyn.inp')
    with open(inp, 'w') as f:
        f.write('*Part, name=Part-1\n*Node\n')
        for i, p in enumerate(nodes):
            f.write(f'{i + 1}, {p[0]:.17g}, {p[1]:.17g}, {p[2]:.17g}\n')
        f.write('*Element, type=C3D20\n')
        for i, e in enumerate(elems):
            f.write(f'{i + 1}, ' + ', '.join(map(str, e)) + '\n')
        f.write('*End Part\n')
    files = {'inp': inp}
    for key, name in (('K', 'rotor_STIF1.mtx'), ('M', 'rotor_MASS1.mtx')):
        A = read_matrix(os.path.join(FE, name), n).tocoo()
        files[key] = os.path.join(tmp, f'rotor_{key}_coordinate.txt')
        np.savetxt(files[key], np.column_stack([A.row + 1, A.col + 1, A.data]),
                   fmt=['%d', '%d', '%.17g'])
    return files, sets


# ---------------------------------------------------------------- Exudyn
def exudyn_preprocess(files, node_type='NodeType.RotationEulerParameters'):
    """FEM import, point mass, free-free modes, reduced-order interface; returns (cms, fem, seconds)"""
    from exudyn.FEM import FEMinterface, ObjectFFRFreducedOrderInterface
    t0 = time.perf_counter()
    fem = FEMinterface()
    fem.ImportFromAbaqusInputFile(files['inp'], typeName='Part', name='Part-1')
    fem.ReadMassMatrixFromAbaqus(files['M'])
    fem.ReadStiffnessMatrixFromAbaqus(files['K'])
    k = 3 * (NODE_U - 1)
    fem.massMatrix = fem.massMatrix + sp.csr_matrix(
        (np.full(3, M_U), (np.arange(k, k + 3), np.arange(k, k + 3))), shape=fem.massMatrix.shape)
    t1 = time.perf_counter()
    fem.ComputeEigenmodes(N_MODES, excludeRigidBodyModes=6, useSparseSolver=True)
    t2 = time.perf_counter()
    cms = ObjectFFRFreducedOrderInterface(fem, rigidBodyNodeType=node_type)
    t3 = time.perf_counter()
    return cms, fem, dict(import_=t1 - t0, eigen=t2 - t1, interface=t3 - t2, total=t3 - t0)


def exudyn_run(cms, fem, sets, solver='GeneralizedAlpha', sensors=True, timers=False, settings=(),
               omega=OMEGA0):
    """build the system and solve; returns (SolveDynamic wall seconds, histories, sizes)"""
    import exudyn as exu
    from exudyn.itemInterface import (ObjectGround, MarkerBodyPosition, MarkerSuperElementPosition,
                                      CartesianSpringDamper, SensorSuperElement, SensorObject,
                                      SensorNode)
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    ob = cms.AddObjectFFRFreducedOrder(mbs, positionRef=[0, 0, 0], initialVelocity=[0, 0, 0],
                                       initialAngularVelocity=[omega, 0, 0],
                                       gravity=[0, 0, -9.81])
    oF, nRB = ob['oFFRFreducedOrder'], ob['nRigidBody']
    w_modes = np.sqrt(fem.eigenValues)           # rad/s; the modes are M-orthonormal
    D = exu.MatrixContainer()
    D.SetWithDenseMatrix(np.diag(2 * ZETA * w_modes * np.diag(cms.massMatrixReduced)),
                         useDenseMatrix=False)
    mbs.SetObjectParameter(oF, 'dampingMatrixReduced', D)

    oG = mbs.AddObject(ObjectGround())
    pos = fem.GetNodePositionsAsArray()
    conns = []
    for name, kx in (('JOURNAL_L', K_B), ('JOURNAL_R', 0.0)):
        ids = [i - 1 for i in sets[name]]
        centre = pos[ids].mean(axis=0)
        mJ = mbs.AddMarker(MarkerSuperElementPosition(bodyNumber=oF, meshNodeNumbers=ids,
                                                      weightingFactors=[1 / len(ids)] * len(ids)))
        mG = mbs.AddMarker(MarkerBodyPosition(bodyNumber=oG, localPosition=list(centre)))
        conns.append(mbs.AddObject(CartesianSpringDamper(
            markerNumbers=[mG, mJ], stiffness=[kx, K_B, K_B],
            damping=[C_B if kx else 0.0, C_B, C_B])))
    if sensors:
        store = dict(storeInternal=True, writeToFile=False)
        ovt = exu.OutputVariableType
        sDisc = mbs.AddSensor(SensorSuperElement(bodyNumber=oF, meshNodeNumber=NODE_DISC - 1,
                                                 outputVariableType=ovt.Position, **store))
        sF = [mbs.AddSensor(SensorObject(objectNumber=c, outputVariableType=ovt.Force, **store))
              for c in conns]
        sW = mbs.AddSensor(SensorNode(nodeNumber=nRB, outputVariableType=ovt.Rotation, **store))
    mbs.Assemble()

    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = int(round(T_END / H))
    ss.timeIntegration.endTime = T_END
    ss.timeIntegration.verboseMode = 0
    ss.timeIntegration.adaptiveStep = False
    ss.timeIntegration.newton.useModifiedNewton = True
    ss.timeIntegration.newton.relativeTolerance = 1e-8
    ss.timeIntegration.newton.absoluteTolerance = 1e-4
    ss.timeIntegration.generalizedAlpha.spectralRadius = 0.9
    ss.timeIntegration.generalizedAlpha.computeInitialAccelerations = True
    ss.solution.file.write = False
    ss.solution.sensors.writePeriod = OUT
    ss.linearSolver.solverType = exu.LinearSolverType.EXUdense
    for path, value in settings:                # (dotted attribute, value) overrides, for probes
        obj = ss
        for a in path.split('.')[:-1]:
            obj = getattr(obj, a)
        setattr(obj, path.split('.')[-1], value)
    ss.show.computationTime = timers
    if timers:
        ss.timeIntegration.verboseMode = 1
    ss.show.statistics = timers
    t0, c0 = time.perf_counter(), time.process_time()
    mbs.SolveDynamic(ss, solverType=getattr(exu.DynamicSolverType, solver))
    wall = time.perf_counter() - t0
    it = mbs.sys['dynamicSolver'].it
    info = dict(nODE2=mbs.systemData.ODE2Size(), nAE=mbs.systemData.AEsize(),
                process=time.process_time() - c0, newton=it.newtonStepsCount,
                jacobians=it.newtonJacobiCount)
    if not sensors:
        return wall, None, info

    P = mbs.GetSensorStoredData(sDisc)
    FL, FR = (mbs.GetSensorStoredData(s) for s in sF)
    W = mbs.GetSensorStoredData(sW)
    p0 = pos[NODE_DISC - 1]
    hist = dict(t=P[:, 0], disc_y=P[:, 2] - p0[1], disc_z=P[:, 3] - p0[2],
                bearing_l_x=FL[:, 1], bearing_l_y=FL[:, 2], bearing_l_z=FL[:, 3],
                bearing_r_y=FR[:, 2], bearing_r_z=FR[:, 3], spin=np.unwrap(W[:, 1]))
    return wall, hist, info


# ---------------------------------------------------------------- flexmbd
def flexmbd(binp, formulation, csv, extra=()):
    out = subprocess.run([binp, 'simulate', SCENE, '--formulation', formulation, '--json',
                          '--output', csv, *extra], cwd=ROOT, capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(f'flexmbd {formulation}: exit {out.returncode}: {out.stderr}')
    return json.loads(out.stdout)


def read_csv(csv):
    a = np.genfromtxt(csv, delimiter=',', names=True)
    h = {k: a[k] for k in a.dtype.names}
    h['spin'] = np.unwrap(h['spin'])
    return h


# ---------------------------------------------------------------- comparison
SIGNALS = ['disc_y', 'disc_z', 'bearing_l_y', 'bearing_l_z', 'bearing_r_y', 'bearing_r_z',
           'bearing_l_x']
T_STEADY = T_END - 5 * REV                       # the last 5 revolutions


def window(h, key, t0=T_STEADY):
    return h['t'][h['t'] >= t0 - 1e-12], h[key][h['t'] >= t0 - 1e-12]


def steady(h, key):
    """mean and half the peak-to-peak over the last 5 revolutions"""
    x = window(h, key)[1]
    return dict(mean=x.mean(), amp=(x.max() - x.min()) / 2)


def harmonic(h, key):
    """least-squares a + b cos(Omega t) + c sin(Omega t) over the last 5 revolutions, Omega the
    mean spin rate there: (amplitude, phase phi of cos(Omega t + phi), largest residual, mean a)"""
    w = spin_rate(h)
    t, x = window(h, key)
    A = np.column_stack([np.ones_like(t), np.cos(w * t), np.sin(w * t)])
    co = np.linalg.lstsq(A, x, rcond=None)[0]
    return np.hypot(co[1], co[2]), np.arctan2(-co[2], co[1]), np.abs(x - A @ co).max(), co[0]


def spin_rate(h):
    """mean spin rate over the last 5 revolutions, from the unwrapped spin angle"""
    t, a = window(h, 'spin')
    return (a[-1] - a[0]) / (t[-1] - t[0])


def whirl_radius(h):
    y, z = window(h, 'disc_y')[1], window(h, 'disc_z')[1]
    return np.mean(np.hypot(y - y.mean(), z - z.mean()))


def compare(ref, other, label):
    """max |other - ref| over 0-0.5 s and over 0.3-0.5 s, relative to ref's steady amplitude (the
    spin angle in mrad): other interpolated to ref's times, and to ref's spin angles (the same
    signals compared at equal spin angle, which takes out the spin's phase drift)"""
    rows = []
    late = ref['t'] >= 0.3
    for k in SIGNALS + ['spin']:
        d = np.interp(ref['t'], other['t'], other[k]) - ref[k]
        e = np.interp(ref['spin'], other['spin'], other[k]) - ref[k]
        e[ref['spin'] > other['spin'][-1]] = 0.0   # beyond the other's last angle: not compared
        scale = steady(ref, k)['amp'] if k != 'spin' else 1e-3
        rows.append((label, k, np.abs(ref[k]).max(), np.abs(d).max() / scale,
                     np.abs(d[late]).max() / scale, np.abs(e).max() / scale,
                     np.abs(e[late]).max() / scale))
    return rows


def main():
    binp = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else 'target/release/flexmbd')
    reps = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    tmp = tempfile.mkdtemp(prefix='exudyn_rotor_')
    files, sets = write_for_exudyn(tmp)
    csv = {f: os.path.join(tmp, f'flexmbd_{f}.csv') for f in ('absolute', 'relative')}

    fast = [('timeIntegration.newton.relativeTolerance', 1e-6)]
    times = {k: [] for k in ('exudyn solve', 'exudyn solve, rtol 1e-6', 'exudyn solve (process CPU)',
                             'exudyn preprocessing', 'exudyn import', 'exudyn eigen',
                             'exudyn interface', 'flexmbd absolute', 'flexmbd relative',
                             'flexmbd absolute preprocessing', 'flexmbd relative preprocessing',
                             'no spin: exudyn solve', 'no spin: flexmbd absolute',
                             'no spin: flexmbd relative')}
    still = ['--set', 'bodies.rotor.velocity.angular.0=0']
    fx = {}
    for r in range(reps):
        cms, fem, pre = exudyn_preprocess(files)
        wall, hist_ex, info = exudyn_run(cms, fem, sets)
        times['exudyn solve'].append(wall)
        times['exudyn solve (process CPU)'].append(info['process'])
        for f in ('absolute', 'relative'):
            fx[f] = flexmbd(binp, f, csv[f])
            times[f'flexmbd {f}'].append(fx[f]['cpu_seconds'])
            times[f'flexmbd {f} preprocessing'].append(fx[f]['preprocessing_seconds'])
        wall_fast, hist_fast, info_fast = exudyn_run(cms, fem, sets, settings=fast)
        times['exudyn solve, rtol 1e-6'].append(wall_fast)
        times['exudyn preprocessing'].append(pre['total'])
        times['exudyn import'].append(pre['import_'])
        times['exudyn eigen'].append(pre['eigen'])
        times['exudyn interface'].append(pre['interface'])
        # diagnostic: the same model started at rest (gravity and bearings only, no unbalance
        # force): Exudyn's modified Newton then keeps one Jacobian for the whole run
        times['no spin: exudyn solve'].append(exudyn_run(cms, fem, sets, sensors=True, omega=0.0)[0])
        for f in ('absolute', 'relative'):
            times[f'no spin: flexmbd {f}'].append(
                flexmbd(binp, f, csv[f] + '.still', still)['cpu_seconds'])
    hist = {'exudyn': hist_ex, **{f: read_csv(csv[f]) for f in csv}}

    print(f"# Exudyn {__import__('exudyn').__version__}: {info['nODE2']} ODE2 coordinates, "
          f"{info['nAE']} algebraic, {info['newton']} Newton iterations, {info['jacobians']} "
          f"Jacobians (rtol 1e-6: {info_fast['newton']}, {info_fast['jacobians']}); "
          f"whirl radius with rtol 1e-6 {1e6 * whirl_radius(hist_fast):.4f} um")
    print(f"# Exudyn's body: mass {cms.totalMass:.6f} kg, centre of mass y {cms.chiU[1]:.4e} m; "
          "free-free f [Hz] = " + ', '.join(f'{w:.4f}' for w in np.sqrt(fem.eigenValues) / 2 / np.pi)
          + " (flexmbd: `flexmbd modes models/unbalanced_rotor.ron --body rotor`)")
    for f in csv:
        print(f"# flexmbd {f}: {fx[f]['n_coordinates']} coordinates, {fx[f]['n_constraints']} "
              f"constraints, {fx[f]['steps']} steps, {fx[f]['newton_iterations']} Newton "
              f"iterations, {fx[f]['factorizations']} factorizations")
    print(f"\n## steady state over the last 5 revolutions ({T_STEADY:.2f}-{T_END} s)")
    print(f"{'quantity':34s} {'Exudyn':>12s} {'absolute':>12s} {'relative':>12s}  abs/Exu-1  rel/Exu-1")
    qty = [('whirl radius disc [um]', lambda h: 1e6 * whirl_radius(h)),
           ('disc y 1x amplitude [um]', lambda h: 1e6 * harmonic(h, 'disc_y')[0]),
           ('disc z 1x amplitude [um]', lambda h: 1e6 * harmonic(h, 'disc_z')[0]),
           ('disc y mean [um]', lambda h: 1e6 * harmonic(h, 'disc_y')[3]),
           ('disc z mean (sag) [um]', lambda h: 1e6 * harmonic(h, 'disc_z')[3]),
           ('disc y residual beyond 1x [um]', lambda h: 1e6 * harmonic(h, 'disc_y')[2]),
           ('disc y 1x phase [mrad]', lambda h: 1e3 * harmonic(h, 'disc_y')[1]),
           ('disc y 1x phase - spin angle [mrad]',
            lambda h: 1e3 * (harmonic(h, 'disc_y')[1] - (window(h, 'spin')[1]
                                                         - spin_rate(h) * window(h, 'spin')[0]).mean()))]
    for k in SIGNALS[2:6]:
        qty.append((f'{k} 1x amplitude [N]', lambda h, k=k: harmonic(h, k)[0]))
        qty.append((f'{k} mean [N]', lambda h, k=k: harmonic(h, k)[3]))
    qty.append(('bearing_l_x peak [N]', lambda h: np.abs(window(h, 'bearing_l_x')[1]).max()))
    qty.append(('spin rate mean [rad/s]', spin_rate))
    qty.append(('spin angle at 0.5 s - Omega0 t [mrad]', lambda h: 1e3 * (h['spin'][-1] - OMEGA0 * h['t'][-1])))
    for name, fn in qty:
        v = [fn(hist[c]) for c in ('exudyn', 'absolute', 'relative')]
        rel = [f'{(x / v[0] - 1) * 100:+8.3f} %' if abs(v[0]) > 1e-9 else '        -' for x in v[1:]]
        print(f"{name:34s} {v[0]:12.5g} {v[1]:12.5g} {v[2]:12.5g}  {rel[0]} {rel[1]}")

    print("\n## histories: max |flexmbd - Exudyn| / Exudyn's steady amplitude (the spin angle: mrad)")
    print(f"{'':36s} {'at equal time':>19s}  {'at equal spin angle':>19s}")
    print(f"{'flexmbd':9s} {'signal':12s} {'max|Exudyn|':>12s} {'0-0.5 s':>9s} {'0.3-0.5 s':>9s}"
          f"  {'0-0.5 s':>9s} {'0.3-0.5 s':>9s}")
    for f in csv:
        for row in compare(hist['exudyn'], hist[f], f):
            if row[1] == 'spin':
                print(f"{row[0]:9s} {row[1]:12s} {row[2]:12.4g} {row[3]:7.3f}mr {row[4]:7.3f}mr")
            else:
                print(f"{row[0]:9s} {row[1]:12s} {row[2]:12.4g} {row[3]:9.3%} {row[4]:9.3%}"
                      f"  {row[5]:9.3%} {row[6]:9.3%}")

    med = {k: statistics.median(v) for k, v in times.items()}
    print(f"\n## times: median of {reps} (interleaved), seconds [min-max]")
    for k, v in times.items():
        ratio = ''
        if k.startswith('no spin: flexmbd'):
            ratio = f"  ({med['no spin: exudyn solve'] / med[k]:.1f}x faster than Exudyn, no spin)"
        if k in ('flexmbd absolute', 'flexmbd relative'):
            ratio = (f"  ({med['exudyn solve'] / med[k]:.1f}x faster than Exudyn's SolveDynamic, "
                     f"{med['exudyn solve, rtol 1e-6'] / med[k]:.1f}x than with rtol 1e-6)")
        elif k.endswith('preprocessing') and k.startswith('flexmbd'):
            ratio = f"  ({med['exudyn preprocessing'] / med[k]:.1f}x faster than Exudyn's)"
        print(f"{k:32s} {med[k]:9.4f}  [{min(v):.4f}-{max(v):.4f}]{ratio}")
    np.savez(os.path.join(tmp, 'histories.npz'),
             **{f'{c}_{k}': v for c, h in hist.items() for k, v in h.items()})
    print(f"\n# histories saved in {tmp}/histories.npz")


if __name__ == '__main__':
    main()
