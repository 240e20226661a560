"""The slices' tooth outline against the generated flank's fillet, across profile
shifts: undercut, ordinary, and above ``h_fP - rho_fP`` (x = 1.0 for the ISO 53 rack),
where the rack's tip round is centred on or above the pitch line.

The slice model writes the fillet in closed form (the trochoid of the round, rolling
angle by rolling angle, :func:`gearbox.ltca.slice_model.fillet_root`); the generated
surface finds it as the envelope of the rack with its equation of meshing
(:mod:`gearbox.surface.generation`). Before, a shift above 1.0 had put the closed
form's cut points on the far side of the round (an outline without its fillet, 0.34 mm
short of the root on a 46-tooth section at x = 1.02, m 1 mm), and x = 1.0 exactly, a
node of the FE tooth tables' lattice, had failed their factorisation: 9 of 100 random
valid beveloid designs stopped with "Factor is exactly singular"
(benchmarks/ltca_random_designs.py, seed 1; none now).
"""

import math

import numpy as np
import pytest
from test_ltca_undercut import _spur_sections

from gearbox.ltca.slice_fe import section_outline
from gearbox.surface import ToothBlank, flank_points, form_point, profile_range


def _distance_to_polyline(p, q):
    """Distance of each point p (n, 2) from the polyline q (m, 2)."""
    a, b = q[:-1], q[1:]
    v = b - a
    t = np.clip(np.einsum("nmk,mk->nm", p[:, None, :] - a, v) / np.sum(v * v, axis=1), 0, 1)
    d = a + t[..., None] * v - p[:, None, :]
    return np.sqrt(np.sum(d * d, axis=-1)).min(axis=1)


@pytest.mark.parametrize(
    "z,x", [(46, 0.5), (46, 1.0), (46, 1.02), (46, 1.3), (20, 1.1), (12, 0.0), (10, -0.2)]
)
def test_the_slices_fillet_is_the_generated_fillet(z, x):
    """Fillet points of the generated spur flank, root to the fillet's end (or its cut
    on an undercut tooth), lie on the closed-form outline: the distance falls as the
    outline's samples squared (a chord's error), measured 8.5e-9..1.8e-8 m at 400
    samples and 7.7e-11..1.8e-10 m at 4000."""
    sec = _spur_sections(z, x)
    blank = ToothBlank(z, 0.006, math.radians(20.0), 0.0, 0.0, x, 0.03).validate()
    uf, _ = form_point(blank, "R", np.zeros(1))
    u = np.linspace(profile_range(blank)[0], uf[0], 50)
    pos = flank_points(blank, "R", np.zeros(u.size), u).position
    p = np.column_stack([np.abs(pos[:, 0]), pos[:, 1]])
    rho, psi = section_outline(sec, 0, normal=False, samples=4000)
    q = np.column_stack([rho * np.sin(psi), rho * np.cos(psi)])
    assert _distance_to_polyline(p, q).max() < 5e-10
    # the outline starts on the root circle
    assert rho[0] == pytest.approx(float(sec.root_radius[0]), abs=1e-11)


def test_a_beveloid_gear_shifted_past_one_runs():
    """One of the random designs that had stopped: a 12/44 pair whose gear's local
    normal shift runs 1.01 to 1.23 along its face (its slices' tables take the lattice
    node x = 1.0). The loaded TCA now runs, conjugate unloaded (below 0.02 um p-p;
    measured 0.002 / 0.011 um) and of a stiffness like the paper's pairs' (measured 675
    / 523 MN/m drive / coast at 300 N m)."""
    from gearbox import load_scene
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca.beveloid import beveloid_ltca
    from gearbox.surface import blanks_from_design

    scene = load_scene("models/case03.toml").replaced(
        pair={"offset_mm": 177.3781932955625, "shaft_angle_deg": 7.789957112928619},
        pinion={
            "teeth": 12,
            "helix_angle_deg": 18.118582977932583,
            "cone_angle_deg": 0.16362212337612636,
            "profile_shift_xt": 0.5788364528945718,
        },
        gear={"teeth": 44, "cone_angle_deg": 1.9260759842661308},
        ltca={"positions": 6},
        load={"torques_Nm": [300.0]},
    )
    design = design_pair(PairSpec.from_scene(scene))
    gear = blanks_from_design(design)[1]
    ends = np.array([gear.z_toe, gear.z_heel])
    x = gear.rack_shift(ends) * math.cos(gear.cone_angle) / gear.normal_module
    assert 1.0 < x.min() < 1.02 and x.max() > 1.2
    res = beveloid_ltca(design, scene)
    for flank in ("drive", "coast"):
        rows = res.summary()["flanks"][flank]
        row = rows[next(iter(rows))]
        assert 3e8 < row["mean_mesh_stiffness_N_per_m"] < 1e9
        assert row["unloaded_te_peak_to_peak_m"] < 2e-8
