"""Where the fast level has been checked: notes for a pair outside that range.

The fast level (:class:`~gearbox.ltca.compliance.FastCompliance`) is a slice model
with terms fitted on, and checked against, the FE level (``fidelity = "fe"``) over a
range of tooth geometries (docs/ltca.md, "Limits and next steps"). Outside it the
tables are still computed, and :func:`fast_level_notes` says which gear leaves the
range, by how much, and what was measured just past its edge. The loaded TCA puts the
notes in :attr:`gearbox.ltca.table.LTCAResult.notes` (its summary's ``notes``); the
report lists them among its warnings and ``gearbox ltca`` prints them.

The limits, each a checked geometry's (not a guess; the figures are those measured and
recorded in docs/ltca.md and docs/fe.md by the benchmarks named there):

- helix angle (:data:`HELIX_DEG`): the paper's pairs reach 25 deg (case 01's pinion),
  where the fast level reads the FE level's mean stiffness within 5 %; against the FE
  segment the slices' excess over spur grows from +6 % at 15 deg to +30 % at 30 deg on
  a face of 7.5 m_n (+14 / +71 % on 3 m_n);
- face width over normal module (:data:`FACE_MODULES`): at b = 5 m_n the FE level's
  tooth rocks under a load rising across the face (1.10 / 1.07, pinion / gear), which
  the slices leave out; a spur tooth of b = 3 m_n is 37 % softer in the FE level;
- the gear body's tilt term ``BODY_TILT sin(beta_b)^2 (r_f / b)^2``
  (:func:`~gearbox.ltca.compliance.body_tilt`, :data:`BODY_TILT_MAX`): fitted on the FE
  level's whole gears up to 1.41 / E (the gear z 40 at 30 deg, r_f / b 2.9); it grows as
  (r_f / b)^2, the tilt of a solid plate of the face width, so beyond that it is the
  plate's extrapolation (a 29 / 200 pair of 30 deg on a 40 mm face reads 138 MN/m
  against 588 for 29 / 45), where real bodies carry webs and hubs.
"""

from __future__ import annotations

import math

import numpy as np

from .compliance import body_tilt
from .grid import ContactGrid

__all__ = ["BODY_TILT_MAX", "FACE_MODULES", "HELIX_DEG", "fast_level_notes"]

#: Largest reference helix angle (deg) of the paper's pairs, on which the fast level
#: was checked against the FE level (case 01's pinion, 25 deg).
HELIX_DEG = 25.0

#: Narrowest face (in normal modules) the fast level's face load distribution holds
#: to: at 5 m_n the FE level's tooth rocks (1.10 / 1.07, pinion / gear).
FACE_MODULES = 5.0

#: Largest body tilt term (over 1 / E per unit face width) of the whole gears
#: ``BODY_TILT`` was fitted on: 1.41 (the gear z 40 at 30 deg, r_f / b 2.9).
BODY_TILT_MAX = 1.41

_GEARS = ("pinion", "gear")


def fast_level_notes(grid: ContactGrid) -> tuple[str, ...]:
    """Notes on ``grid``'s pair where it lies outside the range the fast level was
    checked on (module docstring): one string per quantity, naming the gears, their
    values and the limit; empty inside the range."""
    helix, face, tilt = [], [], []
    for i, name in enumerate(_GEARS):
        teeth = grid.tooth1 if i == 0 else grid.tooth2
        beta = math.degrees(float(np.mean(np.abs(teeth.helix_angle))))
        m_n = float(np.mean(teeth.normal_module))
        b = float(grid.n_slots * np.mean(grid.width if i == 0 else grid.width2))
        if beta > HELIX_DEG + 0.05:
            helix.append(f"{name} {beta:.1f} deg")
        if b < FACE_MODULES * m_n * (1.0 - 1e-3):
            face.append(f"{name} {b * 1e3:.1f} mm = {b / m_n:.2f} m_n")
        t = body_tilt(grid, i)
        if t > BODY_TILT_MAX * (1.0 + 1e-3):
            r_f = float(np.mean(teeth.root_radius))
            tilt.append(
                f"{name} {t:.2f} / E: {t / BODY_TILT_MAX:.1f} times, r_f / b {r_f / b:.1f}, "
                f"helix {beta:.1f} deg"
            )
    notes = []
    if helix:
        notes.append(
            f"helix angle above the {HELIX_DEG:g} deg of the paper's pairs, the largest the "
            f"fast level was checked at against the FE level ({'; '.join(helix)}): its slices "
            "are too stiff on helical teeth, more so at larger angles (against the FE "
            "segment, over spur: +6 % at 15 deg, +30 % at 30 deg on a face of 7.5 m_n); "
            'check with ltca.fidelity = "fe" (ltca.face_ends = true takes part of the excess)'
        )
    if face:
        notes.append(
            f"face narrower than the {FACE_MODULES:g} m_n the fast level's face load "
            f"distribution holds to ({'; '.join(face)}): the tooth's rocking across the face "
            "is left out (a spur tooth of 3 m_n is 37 % softer in the FE level under a load "
            'rising across its face); check with ltca.fidelity = "fe"'
        )
    if tilt:
        notes.append(
            f"gear body tilt beyond the {BODY_TILT_MAX:g} / E the fast level's body term was "
            f"fitted on, at r_f / b 2.9 and 30 deg ({'; '.join(tilt)}): the body is a solid "
            "plate of the face width, which tilts as (r_f / b)^2 under the axial tooth load; "
            "a body with web and hub differs, so read the body's part of the mesh stiffness "
            "as an assumption"
        )
    return tuple(notes)
