"""Loaded TE ripple: the fast level against the FE level, position by position.

Reference: the FE level's tables at its default mesh stored in
``tests/data/fe_reference_paper_cases.json`` (the segment; the FE level's far-field
correction is a constant per gear, which shifts the LTE by a constant per torque and
leaves its peak-to-peak unchanged). Printed per case and flank: the LTE peak-to-peak
of the fast level (the default, or the options given, and the earlier default
``CALIBRATED_BEAM``) against the FE's, and for ``--detail`` the per-position curves at the middle torque
(LTE about its mean, stiffness, the load shares of the tooth pairs, the tip-edge load).

    python benchmarks/ltca_ripple.py                          # all cases, both flanks
    python benchmarks/ltca_ripple.py --cases 03 --flanks drive --detail
    python benchmarks/ltca_ripple.py --cases 03 --flanks drive --fe 1.0 --json out.json
    python benchmarks/ltca_ripple.py --contact matching_depth --fit-body --parallel

``--contact`` picks the fast level's contact term (``FastCompliance(contact=...)``, with
its calibrated body coefficient), ``--root`` its tooth below the involute
(``FastCompliance(root=...)``), ``--beam-at`` where its slice beam's deflection is
taken (``FastCompliance(beam_at=...)``), ``--tooth`` the tooth above the root circle
(``FastCompliance(tooth=...)``: the beam or the plane-strain FE slice), ``--body`` its
body coefficient (default: none with the shared far field, the calibrated one with
``--foundation normal``), ``--coupling-length`` the slices'
coupling along the face (``FastCompliance(coupling_length=...)``), ``--foundation``
the split of the fillet foundation (``FastCompliance(foundation=...)``: all in the
slices, or the body's far field shared by the whole gear), ``--face-ends`` the helical
face ends in the slices (``FastCompliance(helix_ends=HELIX_ENDS)``). ``--fit-body`` fits
the body coefficient for it (the
minimax rule of ``tests/test_ltca_calibration.py`` over the stored whole-gear FE mean
stiffness, cases 01-04, both flanks, three torques) and prints the errors at the fit
rounded to two decimals. ``--parallel`` compares the mean stiffness of three parallel
pairs with the whole-gear FE level (``tests/data/fe_parallel_whole_gear.json``) and of
two with ISO 6336-1's c_gamma_alpha.

``--fe REFINE`` runs the FE level itself (mesh ``MeshOptions().refined(REFINE)``, the
segment, 24 positions) and splits each level's compliance under the FE's own contact
loads into its parts, per position: ``F^T C F / F_n^2`` of the pinion's and the gear's
blocks within one tooth pair (self) and between tooth pairs (cross), the contact terms
and the shared terms; the difference of a part between the positions of the largest
and the smallest LTE is its share of the ripple. ``--far-field-matrix`` (with ``--fe``)
also replaces the FE level's constant far field by the entry-wise extrapolated one
(the coarse extent study of ``FECompliance.far_field``) and gives the LTE peak-to-peak
with both. The FE runs take minutes (case 03 at the default mesh: about 3.5 minutes,
3.4 GB); run one at a time.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from gearbox.geometry import PairSpec, design_pair  # noqa: E402
from gearbox.ltca import FastCompliance, LTCAOptions, ltca_cycle, solve_contact  # noqa: E402
from gearbox.ltca.beveloid import scene_grids  # noqa: E402
from gearbox.ltca.compliance import CALIBRATED_BEAM, HELIX_ENDS  # noqa: E402
from gearbox.scene import load_scene  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]

FE_GRIDS = {"edge_borders": False}  # the stored FE runs' grids (see bench_fe.py)
STORED = ROOT / "tests" / "data" / "fe_reference_paper_cases.json"
PARALLEL = ROOT / "tests" / "data" / "fe_parallel_whole_gear.json"
SIDE = {"drive": "R", "coast": "L"}
P = 24


def case_grids(case: str, flank: str):
    scene = load_scene(ROOT / "models" / f"case{case}.toml").replaced(ltca=FE_GRIDS)
    design = design_pair(PairSpec.from_scene(scene))
    grids, _, _ = scene_grids(design, scene, SIDE[flank], P)
    return scene, design, grids


def cycle(grids, torques, compliance):
    return ltca_cycle(
        lambda f: grids[int(round(f * P)) % P],
        torques,
        options=LTCAOptions(positions=P),
        compliance=compliance,
    )


def stored_fe(case: str, flank: str) -> dict:
    runs = json.loads(STORED.read_text())["default_mesh"]["runs"]
    (run,) = [r for r in runs if r["case"] == case and r["flank"] == flank]
    return run


class Frozen:
    """A compliance level from stored tooth matrices (one per position) and a
    contact diagonal: the FE level's parts recombined without re-running it."""

    name = "frozen"
    load_dependent = True

    def __init__(self, grids, matrices, diagonal):
        self._pos = {id(g): p for p, g in enumerate(grids)}
        self._C = matrices
        self._diag = diagonal

    def tooth_matrix(self, grid):
        return self._C[self._pos[id(grid)]]

    def contact_diagonal(self, grid, line_load):
        return self._diag(grid, line_load)


def _pair_energy(C, grid, F):
    """F^T C F split into the blocks within one tooth pair and between pairs."""
    self_, cross = 0.0, 0.0
    for a in grid.pairs():
        ia = grid.pair == a
        for b in grid.pairs():
            ib = grid.pair == b
            e = float(F[ia] @ C[np.ix_(ia, ib)] @ F[ib])
            if a == b:
                self_ += e
            else:
                cross += e
    return self_, cross


def fast_parts(grid, compliance: FastCompliance) -> dict:
    """The fast level's tooth matrix split by gear and term (m/N)."""
    return {
        "slices pinion": compliance.slice_matrix(grid, 0),
        "slices gear": compliance.slice_matrix(grid, 1),
        "torsion": compliance.torsion_matrix(grid),
        "body": compliance.body_matrix(grid),
    }


def decompose(
    case: str, flank: str, refine: float, torque: float, far_matrix: bool, fast: FastCompliance
):
    from gearbox.fe import FECompliance, FEOptions, MeshOptions
    from gearbox.surface import blanks_from_design

    scene, design, grids = case_grids(case, flank)
    fe = FECompliance(
        FEOptions(mesh=MeshOptions().refined(refine), far_field="none"),
        blanks=blanks_from_design(design),
    )
    fe.reserve(grids)
    g0 = [fe.gear_matrix(g, 0) for g in grids]
    g1 = [fe.gear_matrix(g, 1) for g in grids]
    loc = [fe.local_matrix(g) for g in grids]
    seg = Frozen(
        grids, [a + b + c for a, b, c in zip(g0, g1, loc, strict=True)], fe.contact_diagonal
    )
    torques = scene["load"]["torques_Nm"]
    res_fe = cycle(grids, torques, seg)
    res_fast = cycle(grids, torques, fast)
    rows = []
    for p, g in enumerate(grids):
        F = solve_contact(g, seg, torque).load
        fn2 = float(F.sum()) ** 2
        q = F / g.line_length
        row = {}
        for name, C in (("FE pinion", g0[p]), ("FE gear", g1[p])):
            s, c = _pair_energy(C, g, F)
            row[name + " self"], row[name + " cross"] = s / fn2, c / fn2
        row["FE contact"] = (
            float(F @ (fe.contact_diagonal(g, q) * F)) + _pair_energy(loc[p], g, F)[0]
        ) / fn2
        for name, C in fast_parts(g, fast).items():
            s, c = _pair_energy(C, g, F)
            row["fast " + name] = (s + c) / fn2
            row["fast " + name + " cross"] = c / fn2
        row["fast Weber"] = float(F @ (fast.contact_diagonal(g, q) * F)) / fn2
        for contact in ("centre_line", "matching_depth"):
            w = FastCompliance(contact=contact).contact_diagonal(g, q)
            row["fast Weber " + contact] = float(F @ (w * F)) / fn2
        rows.append(row)
    out = {
        "case": case,
        "flank": flank,
        "refine": refine,
        "torques_Nm": torques,
        "fe_lte_m": res_fe.lte.tolist(),
        "fe_stiffness_N_per_m": res_fe.stiffness.tolist(),
        "fe_lte_pp_m": np.ptp(res_fe.lte, axis=1).tolist(),
        "fast_lte_pp_m": np.ptp(res_fast.lte, axis=1).tolist(),
        "fe_pair_share": res_fe.pair_share.tolist(),
        "parts_torque_Nm": torque,
        "parts_m_per_N": rows,
    }
    if far_matrix:
        out["far_field_matrix"] = far_field_matrix(fe, grids, g0, g1, loc, torques)
    return out


def far_field_matrix(fe, grids, g0, g1, loc, torques) -> dict:
    """LTE peak-to-peak with the constant far field and with the entry-wise one."""
    from gearbox.errors import InputError
    from gearbox.fe.compliance import _Lattice
    from gearbox.fe.extent import aitken_limit

    def limit(seq):
        try:
            return aitken_limit(seq)
        except InputError:  # entries that do not converge monotonically: the last term
            d1, d2 = seq[-2] - seq[-3], seq[-1] - seq[-2]
            with np.errstate(all="ignore"):
                r = d2 / d1
            ok = (r > 0) & (r < 1)
            r = np.where(ok, r, 0.0)
            return np.where(ok, seq[-1] + d2 * r / (1 - r), seq[-1])

    study = {}
    for gear in (0, 1):
        loads = fe.loads(grids[0], gear)
        gm = fe._model(loads, gear, grids[0].youngs_modulus, grids[0].poisson_ratio)
        out = fe._far_field_study(gm, loads.side)
        runs = fe._far_field_runs()
        cl = np.array([out[r] for r in runs if r[0] == "clamped"])
        fr = np.array([out[r] for r in runs if r[0] == "free"])
        d = 0.5 * (limit(cl) + limit(fr)) - out[("clamped", fe.options.neighbours)]
        nb = fe.options.neighbours
        teeth = list(gm.model.mesh.teeth[nb : len(gm.model.mesh.teeth) - nb])
        lat = fe._lattice(gm, loads.side)
        sub = _Lattice(
            z=lat.z[np.unique([0, lat.z.size // 2, lat.z.size - 1])],
            u=lat.u[np.unique([0, lat.u.size // 2, lat.u.size - 1])],
        )
        study[gear] = (d, teeth, lat, sub)

    def matrix(g, gear):
        d, teeth, lat, sub = study[gear]
        nl, ns = lat.z.size * lat.u.size, sub.z.size * sub.u.size
        L = fe.loads(g, gear)
        C = np.zeros((g.size, g.size))
        for ta in np.unique(L.tooth):
            ia = np.flatnonzero(L.tooth == ta)
            wa, ka = fe._weights(sub, L.z[ia], L.u[ia]), teeth.index(int(ta))
            for tb in np.unique(L.tooth):
                ib = np.flatnonzero(L.tooth == tb)
                wb, kb = fe._weights(lat, L.z[ib], L.u[ib]), teeth.index(int(tb))
                C[np.ix_(ib, ia)] = wb @ d[kb * nl : (kb + 1) * nl, ka * ns : (ka + 1) * ns] @ wa.T
        return 0.5 * (C + C.T)

    const = float(np.mean(study[0][0]) + np.mean(study[1][0]))
    base = [a + b + c for a, b, c in zip(g0, g1, loc, strict=True)]
    res_c = cycle(grids, torques, Frozen(grids, [C + const for C in base], fe.contact_diagonal))
    full = [C + matrix(g, 0) + matrix(g, 1) for C, g in zip(base, grids, strict=True)]
    res_m = cycle(grids, torques, Frozen(grids, full, fe.contact_diagonal))
    return {
        "constant_m_per_N": const,
        "spread": [float(np.std(study[k][0]) / np.mean(study[k][0])) for k in (0, 1)],
        "lte_pp_constant_m": np.ptp(res_c.lte, axis=1).tolist(),
        "lte_pp_matrix_m": np.ptp(res_m.lte, axis=1).tolist(),
        "stiffness_constant_N_per_m": res_c.stiffness.mean(axis=1).tolist(),
        "stiffness_matrix_N_per_m": res_m.stiffness.mean(axis=1).tolist(),
    }


def weber_check(case: str, flank: str, position: int = 20, torque: float = 300.0) -> None:
    """Weber's flattening to the tooth centre line and to the FE level's matching depth,
    against the FE level's half-space part above that depth (no FE model needed)."""
    from gearbox.fe import FECompliance
    from gearbox.ltca.compliance import _half_thickness
    from gearbox.ltca.slice_model import weber_approach

    _, _, grids = case_grids(case, flank)
    g = grids[position]
    F = solve_contact(g, FastCompliance(), torque).load
    on, q = F > 0, F / g.line_length
    E, nu = g.youngs_modulus, g.poisson_ratio
    fe = FECompliance()
    d = fe.options.matching_depth * float(g.tooth1.normal_module[0])
    h1, h2 = _half_thickness(g.tooth1), _half_thickness(g.tooth2)
    w_h = weber_approach(q, g.curvature_radius, h1, h2, E, nu)
    w_d = weber_approach(q, g.curvature_radius, np.full_like(h1, d), np.full_like(h2, d), E, nu)
    C = fe.local_matrix(g)
    C[np.diag_indices_from(C)] += fe.contact_diagonal(g, q)
    print(
        f"\ncase {case} {flank}, position {position}, {torque:.0f} N m, fast loads, median over "
        f"the loaded points (um): Weber to the centre line {1e6 * np.median(w_h[on]):.3f}, "
        f"to the matching depth {1e6 * np.median(w_d[on]):.3f}; FE half-space above it "
        f"{1e6 * np.median((C @ F)[on]):.3f}"
    )


def detail(case: str, flank: str, fast: FastCompliance, t: int = 1) -> None:
    _, _, grids = case_grids(case, flank)
    run = stored_fe(case, flank)
    res = cycle(grids, run["torques_Nm"], fast)
    lf = np.asarray(run["lte_m"])[t]
    kf = np.asarray(run["stiffness_N_per_m"])[t]
    la, ka = res.lte[t], res.stiffness[t]
    print(f"\ncase {case} {flank}, {run['torques_Nm'][t]:.0f} N m, per position:")
    print(" pos  LTE-mean FE / fast (um)  ratio  k FE segment / fast (MN/m)  edge  pair shares")
    for p in range(P):
        dfe, dfa = 1e6 * (lf[p] - lf.mean()), 1e6 * (la[p] - la.mean())
        print(
            f" {p:3d}  {dfe:7.3f} {dfa:7.3f}  {dfa / dfe if abs(dfe) > 0.1 else float('nan'):6.2f}"
            f"  {kf[p] / 1e6:7.1f} {ka[p] / 1e6:7.1f}  {res.edge_load_fraction[t, p]:5.2f}  "
            + " ".join(f"{s:.2f}" for s in res.pair_share[t, p])
        )


def whole_gear_stiffness(case: str, flank: str) -> np.ndarray:
    """The FE level's whole-gear mean mesh stiffness per torque (N/m): the stored
    default-mesh segment times the coarse extent study's whole / segment ratio."""
    from gearbox.fe.extent import extent_limit

    data = json.loads(STORED.read_text())
    run = stored_fe(case, flank)

    def seq(bc):
        rs = [
            r
            for r in data["extent"]["runs"]
            if r["case"] == case and r["flank"] == SIDE[flank] and r["cut_faces"] == bc
        ]
        return [r["k_fe"] for r in sorted(rs, key=lambda r: r["neighbours"])]

    cl = seq("clamped")
    lim, _ = extent_limit(cl, seq("free"))
    return np.asarray(run["mean_stiffness_N_per_m"]) * lim / np.asarray(cl[0])


def calibration_errors(cases, flanks, compliance) -> np.ndarray:
    """Fast / whole-gear FE - 1 of the mean mesh stiffness, shape (cases x flanks, 3)."""
    out = []
    for case in cases:
        for flank in flanks:
            _, _, grids = case_grids(case, flank)
            run = stored_fe(case, flank)
            k = cycle(grids, run["torques_Nm"], compliance).stiffness.mean(axis=1)
            out.append(k / whole_gear_stiffness(case, flank) - 1)
    return np.asarray(out)


def fit_body(cases, flanks, base: FastCompliance) -> float:
    """Minimax body coefficient: the mean stiffness with the body term is the one
    without it in series with ``c s`` (s from a second run at c = 0.3, exact for a
    parallel pair and within rounding here); the fit is checked by a full run. ``base``:
    the fast level whose body coefficient is fitted (its other options kept)."""
    k0, k1, kfe = [], [], []
    for case in cases:
        for flank in flanks:
            _, _, grids = case_grids(case, flank)
            run = stored_fe(case, flank)
            for c, out in ((0.0, k0), (0.3, k1)):
                comp = replace(base, body_compliance=c)
                out.append(cycle(grids, run["torques_Nm"], comp).stiffness.mean(axis=1))
            kfe.append(whole_gear_stiffness(case, flank))
    k0, k1, kfe = (np.asarray(v) for v in (k0, k1, kfe))
    s = (1 / k1 - 1 / k0) / 0.3
    cs = np.linspace(0.0, 3.0, 3001)
    worst = [np.max(np.abs(1 / (1 / k0 + s * c) / kfe - 1)) for c in cs]
    return float(cs[int(np.argmin(worst))])


def parallel_errors(compliance) -> dict:
    """Fast / whole-gear FE - 1 of the mean mesh stiffness of the stored parallel pairs."""
    import math

    from gearbox.ltca import ParallelPair, parallel_grid

    data = json.loads(PARALLEL.read_text())
    out = {}
    for p in data["pairs"]:
        pair = ParallelPair(
            p["normal_module_mm"] * 1e-3,
            math.radians(p["normal_pressure_angle_deg"]),
            math.radians(p["helix_angle_deg"]),
            tuple(p["teeth"]),
            face_width=p["face_width_mm"] * 1e-3,
        )
        res = ltca_cycle(
            lambda f, pair=pair: parallel_grid(pair, f, data["n_face"]),
            [data["torque_Nm"]],
            options=LTCAOptions(positions=data["positions"]),
            compliance=compliance,
        )
        k = res.stiffness[0].mean() * math.cos(pair.base_helix_angle) ** 2 / pair.face_width
        out[p["name"]] = k / (p["fe_whole_gear"] * 1e9) - 1
    return out


def iso_ratio(pair, torque: float, compliance=None, n_face: int = 20, positions: int = 24):
    """Mean mesh stiffness of a parallel pair over ISO 6336-1's c_gamma_alpha, and the
    cycle result. ISO's c' and c_gamma are transverse: load F_n cos(beta_b) per face
    width over the transverse deflection LTE / cos(beta_b), so the mean stiffness
    enters as ``k cos^2(beta_b) / b``."""
    import math

    from gearbox.ltca import iso_mesh_stiffness, parallel_grid

    res = ltca_cycle(
        lambda f: parallel_grid(pair, f, n_face),
        [torque],
        options=LTCAOptions(positions=positions),
        compliance=compliance,
    )
    k = res.stiffness[0].mean() * math.cos(pair.base_helix_angle) ** 2 / pair.face_width
    iso = iso_mesh_stiffness(
        teeth=pair.teeth,
        helix_angle=pair.helix_angle,
        normal_pressure_angle=pair.normal_pressure_angle,
        profile_shift=pair.profile_shift,
        transverse_contact_ratio=pair.transverse_contact_ratio,
        load_per_width=torque / pair.pitch_radius(0) / pair.face_width,
    )
    return k / iso.c_gamma_alpha, res


def iso_ratios(compliance) -> dict:
    """:func:`iso_ratio` of the spur and 15 deg helical pairs z 30/45, m 4, b 30 at
    400 N m, 24 positions, 20 face slices (the pairs of tests/test_ltca_parallel.py)."""
    import math

    from gearbox.ltca import ParallelPair

    out = {}
    for beta in (0.0, 15.0):
        pair = ParallelPair(4e-3, math.radians(20), math.radians(beta), (30, 45), face_width=0.03)
        out[f"beta {beta:.0f} deg"] = iso_ratio(pair, 400.0, compliance)[0]
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="+", default=["01", "02", "03", "04"])
    ap.add_argument("--flanks", nargs="+", default=["drive", "coast"], choices=list(SIDE))
    ap.add_argument("--detail", action="store_true", help="per-position curves")
    ap.add_argument("--fe", type=float, help="run the FE level at this mesh refinement")
    ap.add_argument("--far-field-matrix", action="store_true")
    ap.add_argument("--contact", default="centre_line", choices=("centre_line", "matching_depth"))
    d = FastCompliance()  # the defaults
    ap.add_argument("--root", default=d.root, choices=("radial", "fillet"))
    ap.add_argument("--beam-at", default=d.beam_at, choices=("load_point", "centre_line"))
    ap.add_argument("--tooth", default=d.tooth, choices=("beam", "fe"))
    ap.add_argument(
        "--coupling-length", type=float, default=d.coupling_length, help="over the tooth depth"
    )
    ap.add_argument("--foundation", default=d.foundation, choices=("normal", "split"))
    ap.add_argument(
        "--body",
        type=float,
        help="body coefficient (default: 0 with the split foundation, else the calibrated one)",
    )
    ap.add_argument("--face-ends", action="store_true", help="the helical face ends (HELIX_ENDS)")
    ap.add_argument("--fit-body", action="store_true", help="fit the body coefficient")
    ap.add_argument("--parallel", action="store_true", help="parallel pairs against the FE")
    ap.add_argument("--json", type=Path)
    a = ap.parse_args(argv)
    fast = FastCompliance(
        contact=a.contact,
        root=a.root,
        beam_at=a.beam_at,
        tooth=a.tooth,
        body_compliance=a.body,
        coupling_length=a.coupling_length,
        foundation=a.foundation,
        helix_ends=HELIX_ENDS if a.face_ends else None,
    )
    # the column to compare with: the previous default (the slice beam, Sainsot's
    # foundation in the slices, body coefficient 0.24) for the default contact term,
    # the default contact term for the other
    other, other_name = (
        (CALIBRATED_BEAM, "calibrated beam (before)")
        if a.contact == "centre_line"
        else (FastCompliance(), "contact to the centre line")
    )
    print(
        f"contact {a.contact}, root {a.root}, beam at the {a.beam_at}, tooth {a.tooth}, "
        f"coupling length {a.coupling_length}, foundation {a.foundation}, body coefficient "
        f"{fast.body_compliance}, face ends {'on' if a.face_ends else 'off'}"
    )
    print("LTE peak-to-peak (um) at 150 / 300 / 450 N m; fast / FE - 1")
    print(
        f"{'case':>4} {'flank':>5}  {'FE (stored)':>20}  {'fast':>20}  {'error':>20}  {other_name}"
    )
    for case in a.cases:
        for flank in a.flanks:
            run = stored_fe(case, flank)
            _, _, grids = case_grids(case, flank)
            fe_pp = np.ptp(np.asarray(run["lte_m"]), axis=1)
            pp = {}
            for key, c in ((True, fast), (False, other)):
                pp[key] = np.ptp(cycle(grids, run["torques_Nm"], c).lte, axis=1)

            def fmt(x, f="{:6.3f}"):
                return " / ".join(f.format(v) for v in x)

            print(
                f"{case:>4} {flank:>5}  {fmt(fe_pp * 1e6)}  {fmt(pp[True] * 1e6)}  "
                f"{fmt(100 * (pp[True] / fe_pp - 1), '{:+5.1f}')}  "
                f"{fmt(100 * (pp[False] / fe_pp - 1), '{:+5.1f}')}",
                flush=True,
            )
            if a.detail:
                detail(case, flank, fast)
                weber_check(case, flank)
    err = calibration_errors(a.cases, a.flanks, fast)
    print(
        f"mean stiffness against the whole-gear FE level: {100 * err.min():+.1f} .. "
        f"{100 * err.max():+.1f} %"
    )
    if a.fit_body:
        c = round(fit_body(a.cases, a.flanks, fast), 2)
        fitted = replace(fast, body_compliance=c)
        err = calibration_errors(a.cases, a.flanks, fitted)
        print(
            f"fitted body coefficient {c:.2f}: mean stiffness {100 * err.min():+.1f} .. "
            f"{100 * err.max():+.1f} %"
        )
    if a.parallel:
        # with --fit-body, the fitted coefficient
        par = fitted if a.fit_body else fast
        print(
            f"parallel pairs (body coefficient {par.body_compliance}), mean stiffness "
            "against the whole-gear FE level:"
        )
        for name, e in parallel_errors(par).items():
            print(f"  {name}: {100 * e:+.1f} %")
        print("z 30/45, m 4, b 30, 400 N m, mean stiffness over ISO 6336-1 c_gamma_alpha:")
        for name, r in iso_ratios(par).items():
            print(f"  {name}: {r:.3f}")
    if a.fe is None:
        return 0
    out = {"command": "python benchmarks/ltca_ripple.py " + " ".join(argv or sys.argv[1:])}
    out["runs"] = []
    for case in a.cases:
        for flank in a.flanks:
            scene = load_scene(ROOT / "models" / f"case{case}.toml").replaced(ltca=FE_GRIDS)
            torques = scene["load"]["torques_Nm"]
            r = decompose(case, flank, a.fe, torques[len(torques) // 2], a.far_field_matrix, fast)
            out["runs"].append(r)
            print(f"\nFE level, MeshOptions().refined({a.fe}), case {case} {flank}:")
            print("  LTE p-p FE  (um): " + " / ".join(f"{v * 1e6:.3f}" for v in r["fe_lte_pp_m"]))
            print("  LTE p-p fast(um): " + " / ".join(f"{v * 1e6:.3f}" for v in r["fast_lte_pp_m"]))
            rows = r["parts_m_per_N"]
            lte = np.asarray(r["fe_lte_m"])[len(torques) // 2]
            hi, lo = int(np.argmax(lte)), int(np.argmin(lte))
            print(
                f"  compliance parts F^T C F / F_n^2 (1e-10 m/N) under the FE loads at "
                f"{r['parts_torque_Nm']:.0f} N m; positions {hi} (largest LTE) and {lo} (smallest):"
            )
            for k in rows[0]:
                print(
                    f"    {k:22s} {1e10 * rows[hi][k]:7.3f} {1e10 * rows[lo][k]:7.3f}"
                    f"   difference {1e10 * (rows[hi][k] - rows[lo][k]):+7.3f}"
                )
            if "far_field_matrix" in r:
                ff = r["far_field_matrix"]
                print(
                    "  LTE p-p with the far field as a constant / as the entry-wise matrix (um): "
                    + " / ".join(f"{v * 1e6:.3f}" for v in ff["lte_pp_constant_m"])
                    + "  |  "
                    + " / ".join(f"{v * 1e6:.3f}" for v in ff["lte_pp_matrix_m"])
                )
    if a.json is not None:
        a.json.write_text(json.dumps(out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
