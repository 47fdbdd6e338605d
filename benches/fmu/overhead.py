"""The overhead of running the Iltis vehicle as an FMU (issue 28; docs/design.md, "The FMU").

The Iltis vehicle with a road input (models/iltis_vehicle.ron plus `inputs: [road_offset]`) is
exported with `flexmbd fmu` and stepped 8000 times at a 1 ms communication step, the outputs
read after each step, (a) from FMPy's FMU3Slave (Python, ctypes) and (b) from a minimal C
importer (step_fmu.c, compiled here with cc), against (c) the library's 8000 steps in
`flexmbd simulate` (the CPU time of an 8 s run less that of a one-step run, so the compile and
static start cancel). CPU time (user + sys) throughout; RUNS interleaved runs, medians.

    cargo build --release -p flexmbd-cli -p flexmbd-fmi
    python3 benches/fmu/overhead.py [RUNS] [FLEXMBD]    # needs fmpy and cc
"""

import pathlib
import resource
import statistics
import subprocess
import sys
import tempfile
import time
import zipfile

import fmpy
from fmpy.fmi3 import FMU3Slave

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
STEPS, H = 8000, 1e-3


def child_cpu(command):
    """The CPU time of running `command`, and its standard output."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(command, capture_output=True, text=True, check=True).stdout
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime), out


def fmpy_loop(unzipped, description, outputs):
    fmu = FMU3Slave(guid=description.guid, unzipDirectory=unzipped,
                    modelIdentifier=description.coSimulation.modelIdentifier, instanceName="iltis")
    fmu.instantiate()
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    start = time.process_time()
    for k in range(STEPS):
        fmu.doStep(k * H, H)
        fmu.getFloat64(outputs)
    cpu = time.process_time() - start
    fmu.terminate()
    fmu.freeInstance()
    return cpu


def main():
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    cli = sys.argv[2] if len(sys.argv) > 2 else str(ROOT / "target" / "release" / "flexmbd")
    work = pathlib.Path(tempfile.mkdtemp(prefix="fmu-overhead-"))
    text = (ROOT / "models" / "iltis_vehicle.ron").read_text()
    scene = work / "iltis_road.ron"
    scene.write_text(text.replace(
        "    sensors: [", '    inputs: [(name: "road_offset", kind: Road(road: "road"))],\n    sensors: [', 1))
    fmu_file = work / "iltis.fmu"
    subprocess.run([cli, "fmu", str(scene), "--output", str(fmu_file)], check=True, capture_output=True)
    unzipped = work / "iltis"
    zipfile.ZipFile(fmu_file).extractall(unzipped)
    description = fmpy.read_model_description(str(unzipped))
    outputs = [v.valueReference for v in description.modelVariables if v.causality == "output"]
    importer = work / "step_fmu"
    subprocess.run(["cc", "-O2", "-o", str(importer), str(HERE / "step_fmu.c"), "-ldl"], check=True)
    c_command = [str(importer), str(unzipped), "iltis", description.guid, str(H), str(STEPS),
                 str(outputs[0]), str(len(outputs))]
    py, c, lib = [], [], []
    for run in range(runs):
        py.append(fmpy_loop(str(unzipped), description, outputs))
        out = child_cpu(c_command)[1]
        c.append(float(out.split(":")[1].split("s CPU")[0]))
        whole = child_cpu([cli, "simulate", str(scene), "--duration", "8"])[0]
        lib.append(whole - child_cpu([cli, "simulate", str(scene), "--duration", "0.001"])[0])
        print(f"run {run}: FMPy {py[-1]:.3f} s, C importer {c[-1]:.3f} s, library {lib[-1]:.3f} s", flush=True)
    b = statistics.median(lib)
    for name, values in [("FMPy (FMU3Slave)", py), ("C importer", c)]:
        a = statistics.median(values)
        print(f"{name}: {a:.3f} s against the library's {b:.3f} s: {100 * (a / b - 1):+.1f} % "
              f"({1e6 * (a - b) / STEPS:+.1f} us per communication step)")


if __name__ == "__main__":
    main()
