"""Root stress of the fast level against the FE level's fillet stress (and ISO 6336-3).

For parallel-axis reference pairs (spur and helical, ``--pairs``) and the paper cases
(models/case01..04.toml, ``--cases``, flanks ``--flanks``), over one mesh cycle and
the scene's torques:

- FE: the FE level's contact solution and its largest principal fillet stress
  (``gearbox.fe.stress.fillet_stress``), the reference; also the FE fillet stress
  under the fast level's contact loads, which isolates the stress model from the
  load distribution;
- fast: the slice root stress spread along the face by the moment image
  (``gearbox.ltca.stress.grid_root_stress``, the mesh tables' value) and, for
  comparison, the independent slices (no spread);
- ISO 6336-3:2006 method B nominal stress with Y_beta for the parallel pairs.

Printed per case, flank and torque: the largest root stress over the cycle (pinion,
gear) of each, and the errors fast / FE - 1; for the pinion the envelope along the
face (largest over the cycle at each FE face sample) of both levels and its largest
difference over the FE maximum. Times of the fast and FE levels.

    python benchmarks/bench_root_stress.py --pairs --cases 03 --flanks R
    python benchmarks/bench_root_stress.py --cases 01 02 03 04 --mesh coarse
    python benchmarks/bench_root_stress.py --kernel
    python benchmarks/bench_root_stress.py --iso

``--against FILE.json ...`` re-evaluates the current fast level (seconds) against the
FE maxima stored by an earlier ``--json`` run (minutes), for the runs it holds.
``--iso`` runs the fast level alone on parallel spur and helical pairs (48 positions)
against ISO 6336-3 with Y_beta, with and without the spread along the face.

``--kernel`` fits the moment image's decay length on the FE level instead: unit loads
at every face slice of a spur tooth (z 20/40, m_n 4 mm, b = 6 m_n, the default mesh
with elements 0.5 m_n long along the face), at three load heights; for the middle
slice's load, the decay length c whose image (free ends) best fits the FE fillet
stress along the face (least squares), and the rule ``c = a h_F + b m_n`` through
the three (:class:`gearbox.ltca.stress.RootStressModel`'s defaults).

``--helix-ends`` fits the factor of a helical tooth's face ends
(:class:`gearbox.ltca.stress.HelixEnds`) on the FE level: one tooth (z 20/40, m_n
4 mm, helix 0, 10, 20 and 30 deg, b = 4 and 6 m_n, the ``face-fine`` mesh, no far
field) under unit loads at every 1 mm face slice of a line of constant radius at
three load heights (0.15, 0.5 and 0.85 of the way from the form to the tip circle);
per load, the scale that fits the fast level's stress along the face (spread, no
helix-end factor) to the FE fillet stress (least squares), over the spur tooth's
at the same slice, gear and height; then the factor's coefficients (least squares
in the logarithm) and the worst fit per helix angle, face and height. About six
minutes (351 s alone on the 2-core machine).

``--stress-only`` takes as the FE reference the FE fillet stress under the fast
level's contact loads (no FE contact solve: one solve per load case, one gear's model
in memory at a time), which isolates the stress model. ``--three-teeth`` meshes one
loaded tooth and its two neighbours at a time (the teeth of a gear are alike): each
loaded tooth's stress comes from its own and its neighbours' loads, and the FE's own
contact uses the middle tooth's lattice responses for every pair of teeth (zero
beyond the next tooth, no far field). On case 03 drive its maxima are within 0.4 % of
the whole segment's; with it a wide face (the 30 deg pair's 60 mm) fits the
``face-fine`` mesh in memory:

    python benchmarks/bench_root_stress.py --pairs "helical 30 deg z20/40 m4 b60" --three-teeth --mesh face-fine
    python benchmarks/bench_root_stress.py --cases 03 --three-teeth --mesh face-fine

``--mesh coarse`` is ``MeshOptions(across=2, profile=4, fillet=2, land=1, rim=2,
face_length=1.0)``; ``default`` is ``MeshOptions()``; ``face-fine`` is
``MeshOptions(face_length=0.5)``, ``face-finer`` ``MeshOptions(face_length=0.25)``.
Timings on a shared machine vary: compare ratios measured in the same run.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from gearbox.fe import FECompliance, FEOptions, MeshOptions  # noqa: E402
from gearbox.fe.stress import fillet_stress  # noqa: E402
from gearbox.geometry import PairSpec, design_pair  # noqa: E402
from gearbox.ltca import FastCompliance, ParallelPair, parallel_grid, solve_contact  # noqa: E402
from gearbox.ltca.beveloid import scene_grids  # noqa: E402
from gearbox.ltca.compliance import HELIX_ENDS  # noqa: E402
from gearbox.ltca.stress import (  # noqa: E402
    HelixEnds,
    RootStressModel,
    acute_end,
    end_distances,
    grid_root_stress,
    iso_pair_root_stress,
    load_height,
    root_stress_profile,
)
from gearbox.scene import load_scene  # noqa: E402
from gearbox.surface import blanks_from_design  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]

FE_GRIDS = {"edge_borders": False}  # the stored FE runs' grids (see bench_fe.py)
MESHES = {
    "default": MeshOptions(),
    # the default with elements half as long along the face: a helical tooth's fillet
    # stress converges slower along the face (docs/ltca.md, "Root stress")
    "face-fine": MeshOptions(face_length=0.5),
    # halved again: the convergence of a face end's peak (with --three-teeth)
    "face-finer": MeshOptions(face_length=0.25),
    "coarse": MeshOptions(across=2, profile=4, fillet=2, land=1, rim=2, face_length=1.0),
}
DEG = math.pi / 180


def _pair(teeth, helix_deg, face_mm, module_mm=4.0, **kw) -> ParallelPair:
    return ParallelPair(
        normal_module=module_mm * 1e-3,
        normal_pressure_angle=20 * DEG,
        helix_angle=helix_deg * DEG,
        teeth=teeth,
        face_width=face_mm * 1e-3,
        **kw,
    )


# (pair, torques N m, face slices): the FE refinement study's spur and helical pairs
# (tests/test_fe_convergence.py) and a parallel pair with case 03's teeth
PAIRS = {
    "spur z20/40 m4 b16": (_pair((20, 40), 0, 16), (400.0,), 8),
    "helical 15 deg z20/40 m4 b12": (_pair((20, 40), 15, 12), (300.0,), 12),
    "helical 20 deg z29/45 m6 b40": (
        _pair((29, 45), 20, 40, 6.0, profile_shift=(0.16, 0.2), root_radius_coefficient=0.25),
        (300.0,),
        20,
    ),
    "helical 30 deg z20/40 m4 b60": (_pair((20, 40), 30, 60), (400.0,), 40),
}
NO_SPREAD = RootStressModel(spread_height=0.0, spread_module=0.0, helix_ends=None)

#: the fast level's compliance (``--face-ends``: with its helical face ends)
FAST = FastCompliance()


# ``--iso``: fast level only, against ISO 6336-3 (tests/test_ltca_stress.py holds two)
ISO_PAIRS = {
    "spur z30/45 m4 b30": (_pair((30, 45), 0, 30), 400.0),
    "helical 15 deg z20/40 m4 b12": (_pair((20, 40), 15, 12), 300.0),
    "helical 15 deg z30/45 m4 b30": (_pair((30, 45), 15, 30), 400.0),
    "helical 20 deg z29/45 m6 b40": (
        _pair((29, 45), 20, 40, 6.0, profile_shift=(0.16, 0.2), root_radius_coefficient=0.25),
        300.0,
    ),
    "helical 30 deg z20/40 m4 b60": (_pair((20, 40), 30, 60), 400.0),
}


def run_iso(positions: int) -> None:
    """Largest root stress over a cycle (40 face slices) against ISO 6336-3."""
    import gearbox.ltca.analysis as analysis

    print(f"\nfast level against ISO 6336-3 method B (with Y_beta), {positions} positions")
    print(
        f"{'pair':>30} {'eps_beta':>8} {'ISO MPa pinion/gear':>20} "
        f"{'fast / ISO':>13} {'slices / ISO':>13}"
    )
    spread = analysis.grid_root_stress
    for name, (pair, tq) in ISO_PAIRS.items():
        iso = [_iso(pair, tq, gear) for gear in (0, 1)]
        got = []
        for model in (None, NO_SPREAD):
            analysis.grid_root_stress = (
                spread if model is None else (lambda g, f: grid_root_stress(g, f, NO_SPREAD))
            )
            r = analysis.ltca_cycle(
                lambda f, p=pair: parallel_grid(p, f, n_face=40),
                [tq],
                options=analysis.LTCAOptions(positions=positions),
            )
            got.append((r.root_stress_pinion.max() / iso[0], r.root_stress_gear.max() / iso[1]))
        analysis.grid_root_stress = spread
        print(
            f"{name:>30} {pair.overlap_ratio:8.2f} {iso[0] / 1e6:9.1f} / {iso[1] / 1e6:7.1f} "
            f"{got[0][0]:6.3f}/{got[0][1]:6.3f} {got[1][0]:6.3f}/{got[1][1]:6.3f}"
        )


def _iso(pair: ParallelPair, torque: float, gear: int) -> float:
    return iso_pair_root_stress(pair, torque, gear).sigma_F0


def _cycle(grids, torques, fe, stress_only: bool = False) -> dict:
    """Largest root stresses over the cycle per torque, both levels, and the
    pinion's envelope along the face. ``stress_only``: the FE level's stress under
    the fast level's loads is the reference (no FE contact solve, one FE solve per
    load case instead of the lattice responses, one gear's model in memory at a
    time)."""
    T = len(torques)
    keys = ("fe", "fe_on_fast", "fast", "slice")
    mx = {k: np.zeros((T, 2)) for k in keys}
    t_fast = t_fe = 0.0
    cases = []  # (grid, torque index, fast loads, pinion's fast profile)
    for g in grids:
        for t, tq in enumerate(torques):
            t0 = time.perf_counter()
            sf = solve_contact(g, FAST, tq)
            s_fast = grid_root_stress(g, sf.load)
            prof = root_stress_profile(g, sf.load, 0)
            t_fast += time.perf_counter() - t0
            s_slice = grid_root_stress(g, sf.load, NO_SPREAD)
            for gear in (0, 1):
                mx["fast"][t, gear] = max(mx["fast"][t, gear], float(s_fast[gear].max()))
                mx["slice"][t, gear] = max(mx["slice"][t, gear], float(s_slice[gear].max()))
            cases.append((g, t, sf.load, prof))
    fs = {}  # (case, gear) -> FE fillet stress of the reference
    t0 = time.perf_counter()
    for gear in (0, 1) if stress_only else (None,):
        for c, (g, t, load, _) in enumerate(cases):
            if stress_only:
                fo = {gear: _stress_under(fe, g, load, gear)}
                fs[c, gear] = fo[gear]
            else:
                se = solve_contact(g, fe, torques[t])
                fo = {k: _stress_under(fe, g, load, k) for k in (0, 1)}
                fs.update({(c, k): _stress_under(fe, g, se.load, k) for k in (0, 1)})
            for k, f in fo.items():
                mx["fe_on_fast"][t, k] = max(mx["fe_on_fast"][t, k], f.max)
        if stress_only:
            fe._models.clear()  # the next gear's model alone in memory
    t_fe += time.perf_counter() - t0
    env_z = fs[0, 0].z
    env_fe = np.zeros((T, env_z.size))
    env_fast = np.zeros((T, env_z.size))
    for c, (_, t, _, prof) in enumerate(cases):
        for gear in (0, 1):
            mx["fe"][t, gear] = max(mx["fe"][t, gear], fs[c, gear].max)
        env_fe[t] = np.maximum(env_fe[t], fs[c, 0].root_stress.max(axis=0))
        fast_at = np.interp(env_z, prof.face, prof.stress.max(axis=0))
        env_fast[t] = np.maximum(env_fast[t], fast_at)
    return {
        "torques": list(torques),
        **{k: v.tolist() for k, v in mx.items()},
        "envelope_z_m": env_z.tolist(),
        "envelope_fe_Pa": env_fe.tolist(),
        "envelope_fast_Pa": env_fast.tolist(),
        "t_fast_s": t_fast,
        "t_fe_s": t_fe,
        "fe_stats": dict(fe.stats),
    }


class _ThreeTeeth(FECompliance):
    """The FE level on three teeth (offsets -1, 0, 1) of a gear, no unloaded
    neighbours: the grid's tooth ``centre`` is put on tooth 0 and its neighbours on
    -1 and +1 (the teeth of a gear are alike), so that a wide helical pair, whose
    whole loaded segment is too large to factorise at the ``face-fine`` mesh, is
    checked one loaded tooth at a time."""

    centre = 0

    def __init__(self, options: FEOptions, blanks=None):
        super().__init__(
            dataclasses.replace(options, neighbours=0),
            blanks=blanks,
            teeth={0: (-1, 1), 1: (-1, 1)},
        )

    def loads(self, grid, gear):
        # teeth beyond the neighbours go onto tooth 0 too: their loads are zeroed by
        # _stress_under, so only the meshed three carry any
        gl = super().loads(grid, gear)
        t = gl.tooth - self.centre
        return dataclasses.replace(gl, tooth=np.where(np.abs(t) <= 1, t, 0))

    def gear_matrix(self, grid, gear):
        """The FE compliance from the middle tooth's lattice responses alone: the
        block of loads on tooth a read on tooth b is the middle tooth's response on
        tooth b - a (zero beyond the next tooth). The far field is left out: a
        constant compliance of all points moves them together and does not change
        the load distribution under a given torque."""
        gl = FECompliance.loads(self, grid, gear)
        gm = self._model(
            dataclasses.replace(gl, tooth=np.zeros_like(gl.tooth)),
            gear,
            grid.youngs_modulus,
            grid.poisson_ratio,
        )
        solved = self._responses(gm, gl.side, 0)
        C = np.zeros((grid.size, grid.size))
        W = self._tooth_weights(self._lattice(gm, gl.side), gl)
        for ta, (ia, Wa) in W.items():
            for tb, (ib, Wb) in W.items():
                if abs(tb - ta) <= 1:
                    C[np.ix_(ib, ia)] = Wb @ solved.depth[tb - ta] @ Wa.T
        return 0.5 * (C + C.T)


def _stress_under(fe, grid, load, gear: int):
    """FE fillet stress of gear ``gear`` under the loads ``load``: on the whole
    segment, or (``_ThreeTeeth``) per loaded tooth with its neighbours' loads, the
    loaded tooth's stress as one row per tooth."""
    if not isinstance(fe, _ThreeTeeth):
        return fillet_stress(fe, grid, load, gear)
    tooth = FECompliance.loads(fe, grid, gear).tooth
    loaded = np.unique(tooth[load > 0])
    rows = []
    for c in loaded:
        fe.centre = int(c)
        fs = fillet_stress(fe, grid, np.where(np.abs(tooth - c) <= 1, load, 0.0), gear)
        rows.append(fs.sigma1[list(fs.teeth).index(0)])
    return dataclasses.replace(fs, teeth=loaded, sigma1=np.array(rows))


def _fe_run(grids, torques, mesh, stress_only, three, blanks=None) -> dict:
    """One cycle against the FE level (see ``_cycle``), the FE reference's kind noted."""
    if three:
        fe = _ThreeTeeth(FEOptions(mesh=mesh), blanks)
    else:
        fe = FECompliance(FEOptions(mesh=mesh), blanks=blanks)
        fe.reserve(grids)
    r = _cycle(grids, torques, fe, stress_only)
    r["mesh"] = mesh.to_dict()
    r["stress_only"] = stress_only
    r["three_teeth"] = three
    return r


def _label(name: str, stress_only: bool, three: bool) -> str:
    notes = ["FE stress under the fast loads"] if stress_only else []
    notes += ["three teeth at a time"] if three else []
    return name + (f" ({', '.join(notes)})" if notes else "")


def run_pair(
    name: str, mesh: MeshOptions, positions: int, stress_only: bool = False, three=False
) -> dict:
    pair, torques, n_face = PAIRS[name]
    grids = [parallel_grid(pair, j / positions, n_face=n_face) for j in range(positions)]
    r = _fe_run(grids, torques, mesh, stress_only, three)
    r["iso"] = [[_iso(pair, tq, gear) for gear in (0, 1)] for tq in torques]
    r["name"] = _label(name, stress_only, three)
    r["pair"] = name
    return r


def _case_grids(case: str, side: str, positions: int):
    """The scene's contact grids of one flank over a cycle, and its torques."""
    scene = load_scene(ROOT / "models" / f"case{case}.toml").replaced(ltca=FE_GRIDS)
    design = design_pair(PairSpec.from_scene(scene))
    grids, _, _ = scene_grids(design, scene, side, positions)
    return grids, scene["load"]["torques_Nm"]


def run_case(
    case: str, side: str, mesh: MeshOptions, positions: int, stress_only=False, three=False
) -> dict:
    scene = load_scene(ROOT / "models" / f"case{case}.toml").replaced(ltca=FE_GRIDS)
    design = design_pair(PairSpec.from_scene(scene))
    grids, torques = _case_grids(case, side, positions)
    r = _fe_run(grids, torques, mesh, stress_only, three, blanks_from_design(design))
    name = f"case {case} {'drive' if side == 'R' else 'coast'}"
    r["name"] = _label(name, stress_only, three)
    r["pair"] = name
    return r


def run_kernel() -> dict:
    """Decay length of the moment image fitted on FE unit loads (see the module doc)."""

    from scipy.optimize import minimize_scalar

    from gearbox.ltca.stress import iso_root_section, moment_image, slice_root_stress

    mn = 4e-3
    pair = ParallelPair(
        normal_module=mn,
        normal_pressure_angle=20 * DEG,
        helix_angle=0.0,
        teeth=(20, 40),
        face_width=6 * mn,
    )
    fe = FECompliance(FEOptions(mesh=dataclasses.replace(MeshOptions(), face_length=0.5)))
    rows = []
    for frac in (0.999, 0.5):
        g = parallel_grid(pair, frac, n_face=24)
        for k in np.unique(g.pair):
            idx = np.flatnonzero(g.pair == k)
            i = int(idx[idx.size // 2])
            unit = np.zeros(g.size)
            unit[i] = 1.0
            fs = fillet_stress(fe, g, unit, 0)
            prof = fs.root_stress[list(fs.teeth).index(k)]
            t = g.tooth1.take([i])
            s = float(slice_root_stress(t, np.array([1.0 / g.width[i]]))[0])
            sec = iso_root_section(
                zn=t.teeth,
                normal_module=t.normal_module,
                normal_pressure_angle=t.normal_pressure_angle,
                profile_shift=t.profile_shift,
                rack_dedendum=t.rack_dedendum,
                rack_root_radius=t.rack_root_radius,
                load_diameter=2 * t.radius,
            )

            def err(c, z=fs.z, y0=g.face[i], w=g.width[i], p=prof / s, fr=g.face_range):
                return float(np.sum((moment_image(z, [y0], w, c, fr)[:, 0] - p) ** 2))

            c = minimize_scalar(err, bounds=(0.05 * mn, 5 * mn), method="bounded").x
            img = moment_image(fs.z, [g.face[i]], g.width[i], c, g.face_range)[:, 0]
            rows.append(
                {
                    "radius_m": float(t.radius[0]),
                    "h_F_m": float(sec.h_F[0]),
                    "decay_m": float(c),
                    "fe_peak_over_image_peak": float(prof.max() / s / img.max()),
                    "fe_integral_over_slice": float(
                        np.sum(prof) * np.mean(np.diff(fs.z)) / s / g.width[i]
                    ),
                }
            )
    A = np.array([[r["h_F_m"], mn] for r in rows])
    coef = np.linalg.lstsq(A, np.array([r["decay_m"] for r in rows]), rcond=None)[0]
    return {"name": "moment-image decay length", "rows": rows, "rule": coef.tolist()}


HEIGHTS = (0.15, 0.5, 0.85)  # from the form (0) to the tip circle (1)


def _unit_load_scales(fe, grid, gear: int) -> np.ndarray:
    """Per slice of a one-tooth grid: the scale that fits the fast level's stress
    along the face under a unit load there (spread, no helix-end factor) to the FE
    fillet stress (least squares over the FE face samples), shape (n,)."""
    plain = RootStressModel(helix_ends=None)
    out = np.zeros(grid.size)
    for j in range(grid.size):
        unit = np.zeros(grid.size)
        unit[j] = 1.0
        fs = fillet_stress(fe, grid, unit, gear)
        f = fs.root_stress.max(axis=0)
        prof = root_stress_profile(grid, unit, gear, plain)
        q = np.interp(fs.z, prof.face, prof.stress.max(axis=0))
        out[j] = (f @ q) / (q @ q)
    return out


def run_helix_ends(faces_mm=(16.0, 24.0)) -> dict:
    """:class:`HelixEnds` fitted on the FE level (see the module doc)."""
    from fe_independent import line_of_constant_radius, pair_of
    from scipy.optimize import least_squares

    # per load: tan beta, height node, eta, u_acute, u_obtuse, ln(scale / spur's),
    # face / m_n, helix (deg)
    samples = []
    for face in faces_mm:
        n = int(round(face))
        spur = {}
        for beta in (0.0, 10.0, 20.0, 30.0):
            pair = pair_of(beta, face)
            fe = FECompliance(FEOptions(far_field="none", mesh=MESHES["face-fine"]))
            lines = parallel_grid(pair, 0.3, n_face=n)
            for gear in (0, 1):
                sign = acute_end(lines, lines.tooth1 if gear == 0 else lines.tooth2)
                for k, h in enumerate(HEIGHTS):
                    g = line_of_constant_radius(pair, gear, h, n)
                    scale = _unit_load_scales(fe, g, gear)
                    if beta == 0:
                        spur[gear, h] = scale
                        continue
                    teeth = g.tooth1 if gear == 0 else g.tooth2
                    eta = load_height(teeth)
                    ua, uo = end_distances(g, teeth, sign)
                    for j in range(n):
                        samples.append(
                            (
                                math.tan(beta * DEG),
                                k,
                                eta[j],
                                ua[j],
                                uo[j],
                                math.log(scale[j] / spur[gear, h][j]),
                                pair.face_width / pair.normal_module,
                                beta,
                            )
                        )
                print(f"  b {face:g} mm, {beta:g} deg, gear {gear}: unit loads done", flush=True)
    S = np.array(samples)
    t, node, eta, ua, uo, lg, bw, beta = S.T
    K = len(HEIGHTS)

    def ln_factor(p):
        out = np.zeros_like(t)
        for k in range(K):
            a, b, la, lo, mid = p[1 + 5 * k : 6 + 5 * k]
            m = node == k
            x = a * np.exp(-ua[m] / la) - b * np.exp(-uo[m] / lo) + mid
            out[m] = (t[m] + p[0] * t[m] ** 2) * x
        return out

    p0 = [1.0] + [0.6, 0.3, 1.5, 1.5, 0.1] * K
    lo_b = [0.0] + [0.0, 0.0, 0.1, 0.1, -1.0] * K
    hi_b = [5.0] + [5.0, 5.0, 10.0, 10.0, 1.0] * K
    p = least_squares(lambda q: ln_factor(q) - lg, p0, bounds=(lo_b, hi_b)).x
    res = ln_factor(p) - lg
    per = [p[1 + 5 * k : 6 + 5 * k] for k in range(K)]
    fit = HelixEnds(
        height=tuple(round(float(np.mean(eta[node == k])), 2) for k in range(K)),
        acute=tuple(round(float(q[0]), 3) for q in per),
        obtuse=tuple(round(float(q[1]), 3) for q in per),
        acute_decay=tuple(round(float(q[2]), 3) for q in per),
        obtuse_decay=tuple(round(float(q[3]), 3) for q in per),
        middle=tuple(round(float(q[4]), 3) for q in per),
        quadratic=round(float(p[0]), 3),
    )
    worst = []
    for f in np.unique(bw):
        for b in np.unique(beta):
            for k in range(K):
                m = (bw == f) & (beta == b) & (node == k)
                i = np.flatnonzero(m)[np.argmax(np.abs(res[m]))]
                worst.append(
                    {
                        "face_mn": float(f),
                        "helix_deg": float(b),
                        "height": HEIGHTS[k],
                        "fe_over_spur_max": float(np.exp(lg[m]).max()),
                        "fe_over_spur_min": float(np.exp(lg[m]).min()),
                        "worst_fit": math.expm1(float(res[i])),
                        "worst_at_u_acute": float(ua[i]),
                    }
                )
    return {
        "name": "helix ends",
        "fit": fit,
        "rms_ln": float(np.sqrt(np.mean(res**2))),
        "rows": worst,
    }


def _print_helix_ends(r: dict) -> None:
    print(
        "\nhelical face ends fitted on FE unit loads (z 20/40, m_n 4 mm, face-fine mesh): "
        "FE / fast over spur, per slice load"
    )
    print(
        f"{'face/m_n':>8} {'helix':>6} {'height':>6} {'min':>6} {'max':>6} "
        f"{'worst fit':>9} {'at u_a':>7}"
    )
    for w in r["rows"]:
        print(
            f"{w['face_mn']:8.0f} {w['helix_deg']:6.0f} {w['height']:6.2f} "
            f"{w['fe_over_spur_min']:6.2f} {w['fe_over_spur_max']:6.2f} "
            f"{w['worst_fit']:+9.1%} {w['worst_at_u_acute']:7.2f}"
        )
    print(f"rms of the fit (ln): {r['rms_ln']:.4f}")
    print(f"fit: {r['fit']!r}")


def _print_kernel(r: dict) -> None:
    print("\nmoment image fitted on FE unit loads (spur z 20/40, m_n 4 mm, b 24 mm)")
    print(
        f"{'load radius mm':>14} {'h_F mm':>7} {'c mm':>6} {'c rule mm':>9} {'FE/image peak':>13} {'FE/slice moment':>15}"
    )
    a, b = r["rule"]
    for row in r["rows"]:
        print(
            f"{row['radius_m'] * 1e3:14.2f} {row['h_F_m'] * 1e3:7.2f} {row['decay_m'] * 1e3:6.2f} "
            f"{(a * row['h_F_m'] + b * 4e-3) * 1e3:9.2f} {row['fe_peak_over_image_peak']:13.3f} "
            f"{row['fe_integral_over_slice']:15.3f}"
        )
    print(f"least squares: c = {a:.3f} h_F + {b:.3f} m_n")


def _fast_maxima(grids, torques) -> tuple[np.ndarray, np.ndarray]:
    """Largest fast-level root stress over the cycle, (T, 2) spread and slices."""
    out = np.zeros((len(torques), 2)), np.zeros((len(torques), 2))
    for g in grids:
        for t, tq in enumerate(torques):
            load = solve_contact(g, FAST, tq).load
            for k, model in enumerate((None, NO_SPREAD)):
                s = grid_root_stress(g, load, model)
                out[k][t] = np.maximum(out[k][t], (s[0].max(), s[1].max()))
    return out


def _mesh_name(mesh: dict | None) -> str:
    """The name in :data:`MESHES` of a stored run's FE mesh ("?" if none matches)."""
    for name, m in MESHES.items():
        if mesh is not None and all(mesh.get(k) == v for k, v in m.to_dict().items()):
            return name
    return "?"


def run_against(path: Path, positions: int) -> None:
    """The current fast level against the FE maxima stored by an earlier ``--json``."""
    stored = json.loads(path.read_text())
    print(
        f"\ncurrent fast level against the FE numbers of {path.name} ({stored['meta']['command']})"
    )
    print(
        f"{'run':>30} {'FE mesh':>8} {'torque':>7} {'FE MPa pinion/gear':>19} {'fast/FE-1':>17} "
        f"{'slices/FE-1':>17}"
    )
    for r in stored["runs"]:
        if "fe" not in r:
            continue
        name = r.get("pair", r["name"])
        mesh = _mesh_name(r.get("mesh"))
        mesh += ("*" if r.get("stress_only") else "") + ("/3" if r.get("three_teeth") else "")
        if name in PAIRS:
            pair, torques, n_face = PAIRS[name]
            grids = [parallel_grid(pair, j / positions, n_face=n_face) for j in range(positions)]
        else:
            _, case, flank = name.split()
            side = "R" if flank == "drive" else "L"
            grids, torques = _case_grids(case, side, positions)
        fast, slices = _fast_maxima(grids, torques)
        fe = np.asarray(r["fe"])
        for t, tq in enumerate(torques):
            e, e0 = fast[t] / fe[t] - 1, slices[t] / fe[t] - 1
            print(
                f"{name:>30} {mesh:>8} {tq:7.0f} {fe[t, 0] / 1e6:9.1f} / {fe[t, 1] / 1e6:7.1f} "
                f"{e[0]:+8.1%}/{e[1]:+8.1%} {e0[0]:+8.0%}/{e0[1]:+8.0%}"
            )
    if any(r.get("stress_only") or r.get("three_teeth") for r in stored["runs"]):
        print(
            "  *: the FE stress under the fast level's loads (--stress-only); "
            "/3: three teeth meshed at a time (--three-teeth)"
        )


def _print(r: dict) -> None:
    print(f"\n{r['name']}  (fast {r['t_fast_s']:.2f} s, FE {r['t_fe_s']:.1f} s)")
    head = (
        f"{'torque':>7} {'gear':>6} {'FE MPa':>7} {'FE(fast F)':>10} {'fast':>7} "
        f"{'slices':>7} {'fast/FE-1':>9} {'slices/FE-1':>11}"
    )
    if "iso" in r:
        head += f" {'ISO MPa':>8} {'fast/ISO-1':>10} {'FE/ISO-1':>9}"
    print(head)
    for t, tq in enumerate(r["torques"]):
        for gear, name in ((0, "pinion"), (1, "gear")):
            fe = r["fe"][t][gear]
            line = (
                f"{tq:7.0f} {name:>6} {fe / 1e6:7.1f} {r['fe_on_fast'][t][gear] / 1e6:10.1f} "
                f"{r['fast'][t][gear] / 1e6:7.1f} {r['slice'][t][gear] / 1e6:7.1f} "
                f"{r['fast'][t][gear] / fe - 1:+9.1%} {r['slice'][t][gear] / fe - 1:+11.1%}"
            )
            if "iso" in r:
                iso = r["iso"][t][gear]
                line += (
                    f" {iso / 1e6:8.1f} {r['fast'][t][gear] / iso - 1:+10.1%} {fe / iso - 1:+9.1%}"
                )
            print(line)
    z = np.asarray(r["envelope_z_m"]) * 1e3
    for t, tq in enumerate(r["torques"]):
        ef = np.asarray(r["envelope_fe_Pa"][t])
        es = np.asarray(r["envelope_fast_Pa"][t])
        dev = np.max(np.abs(es - ef)) / ef.max()
        print(
            f"  pinion along the face at {tq:.0f} N m (z mm: {', '.join(f'{v:.0f}' for v in z)}): "
            f"FE {', '.join(f'{v / 1e6:.0f}' for v in ef)} MPa; "
            f"fast {', '.join(f'{v / 1e6:.0f}' for v in es)} MPa; "
            f"largest difference {dev:.1%} of the FE maximum"
        )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--pairs",
        nargs="*",
        choices=sorted(PAIRS),
        metavar="NAME",
        help="the parallel-axis reference pairs (all without names)",
    )
    ap.add_argument("--kernel", action="store_true", help="fit the moment image on FE unit loads")
    ap.add_argument("--iso", action="store_true", help="fast level against ISO 6336-3 only")
    ap.add_argument(
        "--helix-ends", action="store_true", help="fit the helical face ends on FE unit loads"
    )
    ap.add_argument(
        "--against", type=Path, nargs="+", help="fast level against stored --json FE numbers"
    )
    ap.add_argument(
        "--face-ends",
        action="store_true",
        help="the fast compliance with its helical face ends (HELIX_ENDS)",
    )
    ap.add_argument("--cases", nargs="*", default=[])
    ap.add_argument("--flanks", nargs="+", default=["R", "L"])
    ap.add_argument("--mesh", choices=sorted(MESHES), default="default")
    ap.add_argument("--positions", type=int, default=24)
    ap.add_argument(
        "--three-teeth",
        action="store_true",
        help="three teeth meshed at a time (each loaded tooth and its neighbours)",
    )
    ap.add_argument(
        "--stress-only",
        action="store_true",
        help="the FE stress under the fast level's loads only (no FE contact solve)",
    )
    ap.add_argument("--json", type=Path, help="write every run's numbers to this JSON file")
    a = ap.parse_args(argv)
    if a.face_ends:
        global FAST
        FAST = FastCompliance(helix_ends=HELIX_ENDS)
    mesh = MESHES[a.mesh]
    print(
        f"root stress, fast level against FE ({a.mesh} mesh), {a.positions} positions; "
        "largest over the cycle; errors = fast / FE - 1"
    )
    runs = []
    if a.iso:
        run_iso(48 if a.positions == 24 else a.positions)
    for path in a.against or []:
        run_against(path, a.positions)
    if a.kernel:
        runs.append(run_kernel())
        _print_kernel(runs[-1])
    if a.helix_ends:
        r = run_helix_ends()
        _print_helix_ends(r)
        runs.append({**r, "fit": dataclasses.asdict(r["fit"])})
    if a.pairs is not None:
        for name in a.pairs or PAIRS:
            runs.append(run_pair(name, mesh, a.positions, a.stress_only, a.three_teeth))
            _print(runs[-1])
    for case in a.cases:
        for side in a.flanks:
            runs.append(run_case(case, side, mesh, a.positions, a.stress_only, a.three_teeth))
            _print(runs[-1])
    if a.json is not None:
        meta = {
            "command": "python benchmarks/bench_root_stress.py " + " ".join(argv or sys.argv[1:]),
            "mesh": mesh.to_dict(),
            "positions": a.positions,
        }
        a.json.write_text(json.dumps({"meta": meta, "runs": runs}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
