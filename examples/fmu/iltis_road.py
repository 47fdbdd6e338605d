"""Drive the Iltis vehicle FMU's road from Python (issue 28): the vehicle of
models/iltis_vehicle.ron with an input on its road is exported with `flexmbd fmu`, loaded with
FMPy, and stepped at 1 ms while the road under it is lifted by a 2 cm, 1.5 Hz sine
(`road_offset.dz`); the chassis heave and the front-left tyre force are written to a CSV file,
and plotted when matplotlib is installed. (The vehicle drives at 5 m/s onto the scene's own
ramp at 3 m: the sine rides on it.)

    cargo build --release -p flexmbd-cli -p flexmbd-fmi
    python3 examples/fmu/iltis_road.py [OUT_DIR]        # needs fmpy (pip install fmpy)
"""

import csv
import math
import os
import pathlib
import subprocess
import sys
import tempfile

import fmpy
from fmpy.fmi3 import FMU3Slave

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="iltis-fmu-"))
    out.mkdir(parents=True, exist_ok=True)
    scene = out / "iltis_road.ron"
    text = (ROOT / "models" / "iltis_vehicle.ron").read_text()
    scene.write_text(text.replace(
        "    sensors: [", '    inputs: [(name: "road_offset", kind: Road(road: "road"))],\n    sensors: [', 1))
    fmu_file = out / "iltis.fmu"
    cli = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "release" / "flexmbd"
    subprocess.run([str(cli), "fmu", str(scene), "--output", str(fmu_file)], check=True)

    unzipped = fmpy.extract(str(fmu_file))
    description = fmpy.read_model_description(unzipped)
    vr = {v.name: v.valueReference for v in description.modelVariables}
    fmu = FMU3Slave(guid=description.guid, unzipDirectory=unzipped,
                    modelIdentifier=description.coSimulation.modelIdentifier, instanceName="iltis")
    fmu.instantiate()
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    h, duration, rows = 1e-3, 3.0, []
    sensors = [vr["chassis_z"], vr["tyre_fl"]]
    for k in range(round(duration / h)):
        t = k * h
        # The road's value holds through the step: set it for the step's end time.
        fmu.setFloat64([vr["road_offset.dz"]], [0.02 * math.sin(2 * math.pi * 1.5 * (t + h))])
        fmu.doStep(t, h)
        if (k + 1) % 10 == 0:
            rows.append([t + h, *fmu.getFloat64(sensors)])
    fmu.terminate()
    fmu.freeInstance()

    table = out / "iltis_road.csv"
    with open(table, "w", newline="") as f:
        csv.writer(f).writerows([["t", "chassis_z", "tyre_fl"], *rows])
    print(f"{len(rows)} rows in {table}; chassis_z from {min(r[1] for r in rows):.4f} "
          f"to {max(r[1] for r in rows):.4f} m, tyre_fl from {min(r[2] for r in rows):.0f} "
          f"to {max(r[2] for r in rows):.0f} N")
    try:
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, axes = plt.subplots(2, 1, sharex=True)
    axes[0].plot([r[0] for r in rows], [r[1] for r in rows])
    axes[0].set_ylabel("chassis z (m)")
    axes[1].plot([r[0] for r in rows], [r[2] for r in rows])
    axes[1].set_ylabel("tyre FL (N)")
    axes[1].set_xlabel("t (s)")
    fig.savefig(out / "iltis_road.png")
    print(f"plot in {out / 'iltis_road.png'}")


if __name__ == "__main__":
    main()
