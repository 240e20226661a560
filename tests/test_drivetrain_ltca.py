"""The dynamics on a real loaded-TCA mesh table (gearbox.ltca), paper case 03."""

import math
from pathlib import Path

import numpy as np
import pytest

from gearbox.drivetrain.model import DrivetrainModel
from gearbox.drivetrain.simulate import mesh_force_metrics, simulate
from gearbox.scene import load_scene

pytest.importorskip("diffrax")

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_dynamics_run_on_the_loaded_tca_table():
    # Statics: the mean mesh force is the pinion torque over the drive rotation radius
    # (moment balance of the pinion; 1e-3: the mean over whole mesh cycles of a settled
    # response, whose low-order content averages out to about 1e-4 here). The spectrum's
    # strongest lines are mesh harmonics (N1 x pinion speed and multiples).
    from gearbox.drivetrain.diffrax_backend import DiffraxSolver
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca.table import scene_ltca

    scene = load_scene(ROOT / "models" / "case03.toml")
    table = scene_ltca(design_pair(PairSpec.from_scene(scene)), scene).table
    m = DrivetrainModel.from_scene(scene, table)
    ts = simulate(m, DiffraxSolver(), mesh_cycles=64)
    assert ts.success, ts.failure
    met = mesh_force_metrics(ts, m)
    assert met["mesh_force_mean_N"] == pytest.approx(m.torque / m.drive.lambda1, rel=1e-3)
    f = ts["mesh_force_N"] - ts["mesh_force_N"].mean()
    spec = np.abs(np.fft.rfft(f))
    freq = np.fft.rfftfreq(f.size, ts.time[1] - ts.time[0])
    band = freq > 600.0
    fm = 29 * m.speed / (2 * math.pi)
    top = freq[band][np.argmax(spec[band])] / fm
    assert abs(top - round(top)) < 1e-6 * top  # the strongest line is a mesh harmonic
    i = int(round(fm / freq[1]))
    assert spec[i] > 20 * max(spec[i - 3], spec[i + 3])  # and the mesh order is a sharp line
