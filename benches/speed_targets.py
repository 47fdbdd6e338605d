"""Issue 26's speed targets, measured in one run: the Iltis runs in both formulations and the
cases shared with Exudyn 1.13.6 side by side, every case interleaved, medians of REPS.

Set-up once (only for the Exudyn cases; without exudyn they are left out):
              python3 -m venv /tmp/exu && /tmp/exu/bin/pip install exudyn==1.13.6 numpy scipy
Run (from the project root, after `cargo build --release -p flexmbd-cli`):
              /tmp/exu/bin/python benches/speed_targets.py target/release/flexmbd 5 > speed.md
              (arguments: the flexmbd binary, the repetitions, and the folder of the shared Exudyn
              cases, default ../shared/tools/exudyn: case2_spinup_ffrf.py, case5_fourbar_rigid.py)

flexmbd's times are the JSON `cpu_seconds` of `flexmbd simulate ... --json` (integration only, the
initial conditions included), with the phase split it reports (`time_evaluation`,
`time_factorization`, `time_projection`, sampled every 32nd step); Exudyn's are its SolveDynamic
wall time, as `side_by_side.py` of the shared tools takes them. The cases:

- Iltis scene C (`models/iltis_vehicle.ron`, 8 s, shape integrals): rigid and with its 12 flexible
  links (`--set bodies.NAME.flexible=true`), relative and absolute; the 2.5 s bump
  (`models/iltis_bump.ron`) relative and absolute.
- Shared with Exudyn: the rigid double four-bar (5 s, h = 1 ms); the 2D linear floating-frame spin-up
  beam with 4 and with 24 bending modes (Omega_s = 2 rad/s, 20 s, h = 1 ms).
"""
import json, os, statistics, subprocess, sys

binp = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else 'target/release/flexmbd')
reps = int(sys.argv[2]) if len(sys.argv) > 2 else 5
cases_dir = sys.argv[3] if len(sys.argv) > 3 else os.path.join('..', 'shared', 'tools', 'exudyn')
root = os.getcwd()

FLEXIBLE = [f'{part}_{corner}' for part in ('aarm', 'leaf_link', 'tie_rod')
            for corner in ('fl', 'fr', 'rl', 'rr')]
TWELVE = [a for name in FLEXIBLE for a in ('--set', f'bodies.{name}.flexible=true')]
SPIN = ['models/spin_up_beam_2d.ron', '--stiffening', 'linear',
        '--set', 'drivers.spin.law.SpinUp.omega_s=2', '--set', 'bodies.beam.model.Beam.axial_modes=0']
MODES_24 = ['--set', 'bodies.beam.model.Beam.normal_modes=24']


def flexmbd(args):
    out = subprocess.run([binp, 'simulate', *args, '--json'], cwd=root, capture_output=True, text=True)
    s = json.loads(out.stdout)
    if s['status'] != 'ok':
        raise SystemExit(f"flexmbd {' '.join(args)}: {s.get('message')}")
    return s


# (name, target seconds or None, flexmbd arguments)
vehicle = [
    ('bump 2.5 s relative', 0.025, ['models/iltis_bump.ron', '--formulation', 'relative']),
    ('bump 2.5 s absolute', None, ['models/iltis_bump.ron', '--formulation', 'absolute']),
    ('vehicle 8 s rigid relative', 0.05, ['models/iltis_vehicle.ron', '--formulation', 'relative']),
    ('vehicle 8 s rigid absolute', None, ['models/iltis_vehicle.ron', '--formulation', 'absolute']),
    ('vehicle 8 s 12 flexible relative', 0.40,
     ['models/iltis_vehicle.ron', '--formulation', 'relative', *TWELVE]),
    ('vehicle 8 s 12 flexible absolute', 1.0,
     ['models/iltis_vehicle.ron', '--formulation', 'absolute', *TWELVE]),
]
shared = [
    ('fourbar-rigid', ['models/double_four_bar.ron', '--duration', '5']),
    ('ffrf-lin-4', SPIN),
    ('ffrf-lin-24', SPIN + MODES_24),
]

exudyn = {}
try:
    sys.path.insert(0, os.path.abspath(cases_dir))
    import case2_spinup_ffrf as c2
    import case5_fourbar_rigid as c5
    fem4, info4 = c2.make_fem('CB-root-4')
    fem24, info24 = c2.make_fem('CB-root-24')
    exudyn = {
        'fourbar-rigid': lambda: c5.run(1e-3, 5.0, sensors=False)[0],
        'ffrf-lin-4': lambda: c2.build_and_solve(fem4, info4, 2.0, 1e-3)[0],
        'ffrf-lin-24': lambda: c2.build_and_solve(fem24, info24, 2.0, 1e-3)[0],
    }
except ImportError as e:
    print(f"<!-- Exudyn cases left out: {e} -->")

runs = {name: [] for name, _, _ in vehicle}
for name, _ in shared:
    for form in ('relative', 'absolute'):
        runs[f'{name} {form}'] = []
    if name in exudyn:
        runs[f'{name} exudyn'] = []
for _ in range(reps):
    for name, _, args in vehicle:
        runs[name].append(flexmbd(args))
    for name, args in shared:
        if name in exudyn:
            runs[f'{name} exudyn'].append(exudyn[name]())
        for form in ('relative', 'absolute'):
            runs[f'{name} {form}'].append(flexmbd(args + ['--formulation', form]))


def median(name, key='cpu_seconds'):
    return statistics.median(r[key] for r in runs[name])


def phases(name):
    e, f, p = (median(name, k) for k in ('time_evaluation', 'time_factorization', 'time_projection'))
    it = statistics.median(r['newton_iterations'] / r['steps'] for r in runs[name])
    return f"{e:.3f} / {f:.3f} / {p:.3f} | {it:.2f}"


print(f"# Speed targets (issue 26): medians of {reps}, cases interleaved\n")
print("| run | CPU (s) | target (s) | met | evaluation / factorisation / projections (s) | Newton it./step |")
print("|---|---|---|---|---|---|")
for name, target, _ in vehicle:
    t = median(name)
    met = '' if target is None else ('yes' if t <= target else f'no ({t / target:.1f}x over)')
    tgt = '' if target is None else f'{target:g}'
    print(f"| {name} | {t:.4f} | {tgt} | {met} | {phases(name)} |")
if exudyn:
    print("\n| shared case | Exudyn (s) | flexmbd relative (s) | ratio | flexmbd absolute (s) | ratio |")
    print("|---|---|---|---|---|---|")
    for name, _ in shared:
        ex = statistics.median(runs[f'{name} exudyn'])
        rel, ab = median(f'{name} relative'), median(f'{name} absolute')
        print(f"| {name} | {ex:.4f} | {rel:.4f} | {ex / rel:.1f}x | {ab:.4f} | {ex / ab:.1f}x |")
    print("\nTarget: at least 20x faster than Exudyn in both formulations.")
