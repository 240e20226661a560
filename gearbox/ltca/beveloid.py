"""Crossed beveloid pairs: contact grids from the generated flanks, loaded TCA and
mesh tables (paper section 3.2).

Separation field. The pinion's active flank (gearbox.surface, tooth 0) is sampled on
a grid of face slices x profile points. At pinion angle phi_1 the gear stands at the
nominal angle ``phi_2 = phi_2,0 - (N_1/N_2) phi_1`` (gearbox.tca.Assembly frames, Sf).
For every pinion point p with outward unit normal n the gear flank is met along the
normal, ``r_2(z_2, u_2) = p + t n``, by a bounded Newton iteration on (z_2, u_2, t)
with the exact surface derivatives; ``t`` is the initial separation along the common
normal (negative = interpenetration of the rigid flanks at the nominal gear angle;
the contact problem only needs separations up to a common rigid rotation, so the
unloaded transmission error comes out of it: ``phi_0 = min_i s_i / m_i``).
Points whose partner lies off the gear's active flank (beyond its face, below its
form circle, above its tip) cannot touch and are dropped.

Tooth pairs. All teeth are alike and the nominal gear motion is linear, so tooth
pair k at pinion angle phi_1 is the reference pair at ``phi_1 + 2 pi k / N_1`` (and
sits at the same place in Sf). The field of the reference pair is computed once over
its whole engagement and reused for every pair and position.

Contact lines. In each face slice the contact point is the minimum of the separation
along the profile (parabolic refinement); a minimum on the border of the valid
profile range means the contact would lie beyond the flank edge (tip or form
circle): such points are marked ``edge`` and loads on them are flagged.

Flank modifications (:class:`~gearbox.ltca.modification.FlankModification`: tip and
root relief, profile and lead crowning, end relief, helix slope; scene keys
``ltca.pinion_*`` and ``ltca.gear_*``): the material removed normal to each flank is
added to the separation, on the pinion at the pinion point's radius and on the gear at
the gear partner's radius, in the field, on its continuation and in the three exact
evaluations of the contact-line refinement; the unloaded TE, the loaded contact and the
edge detection then see the modified flanks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import __version__
from ..errors import InputError, Problem, Problems
from ..geometry.checks import TOPPING_MIN_SAN
from ..geometry.involute import inv
from .analysis import LTCAOptions, ltca_cycle, root_stress_method
from .compliance import compliance_for, describe_compliance
from .grid import ContactGrid, ToothSections
from .modification import (
    FlankModification,
    TipRelief,
    as_modification,
    describe_pair,
    removal_map,
    topography_from_section,
    topography_notes,
)

__all__ = [
    "SeparationField",
    "FlankModification",
    "TipRelief",
    "modification_maps",
    "modifications_from_scene",
    "beveloid_ltca",
    "separation_field",
    "tip_relief_from_scene",
]

_SIDE_INDEX = {"R": 0, "L": 1}
_FLANK_SIDE = {"drive": "R", "coast": "L"}


def modifications_from_scene(design, scene) -> tuple[FlankModification, FlankModification]:
    """(pinion, gear) flank modifications of the scene's ``[ltca]`` keys (um, mm -> m).

    Tip relief must start above the base circle and root relief end below the tip
    circle over the whole face width, end relief be at most half the face width;
    otherwise the error names the length key, its value and the valid range.
    """
    from ..surface import blanks_from_design

    lt = scene["ltca"]
    blanks = blanks_from_design(design)
    out = []
    probs = Problems()
    for name, gd, blank in zip(
        ("pinion", "gear"), (design.pinion, design.gear), blanks, strict=True
    ):

        def um(key, name=name):
            return float(lt.get(f"{name}_{key}_um", 0.0)) * 1e-6

        def mm(key, name=name):
            return float(lt.get(f"{name}_{key}_length_mm", 0.0)) * 1e-3

        def shape(key, name=name):
            return lt.get(f"{name}_{key}_shape", "linear")

        mod = FlankModification(
            tip_relief=um("tip_relief"),
            tip_relief_length=mm("tip_relief"),
            tip_relief_shape=shape("tip_relief"),
            root_relief=um("root_relief"),
            root_relief_length=mm("root_relief"),
            root_relief_shape=shape("root_relief"),
            profile_crowning=um("profile_crowning"),
            lead_crowning=um("lead_crowning"),
            end_relief=um("end_relief"),
            end_relief_length=mm("end_relief"),
            end_relief_shape=shape("end_relief"),
            helix_slope=um("helix_slope"),
            profile_slope=um("profile_slope"),
            flank_twist=um("flank_twist"),
            topography=topography_from_section(lt, name, probs),
        )
        ends = np.array([blank.z_toe, blank.z_heel])
        ra = blank.tip_radius(ends)
        if mod.topography is not None:
            _topography_on_the_flank(mod.topography, name, blank, gd, ends, ra, probs)
        for kind in ("tip_relief", "root_relief", "end_relief"):
            if getattr(mod, kind) > 0:
                limit, hi_open = _relief_limit(kind, blank, gd, ends, ra)
                probs.in_range(
                    f"ltca.{name}_{kind}_length_mm",
                    getattr(mod, f"{kind}_length") * 1e3,
                    0.0,
                    limit * 1e3,
                    lo_open=True,
                    hi_open=hi_open,
                )
        out.append(mod)
    probs.raise_if_any("invalid flank modification")
    return out[0], out[1]


def _relief_limit(kind: str, blank, gd, ends, ra) -> tuple[float, bool]:
    """(largest length (m), whether it is excluded) of a relief of ``kind``: tip relief
    must start above the base circle, root relief end below the tip circle (at both
    face ends), end relief reach at most the face middle."""
    if kind == "tip_relief":
        return float(np.min(ra) - max(gd.base_radius)), True
    if kind == "root_relief":
        return float(np.min(ra - np.max(_form_radius(blank, gd, ends), axis=0))), True
    return 0.5 * blank.face_width, False


def _topography_on_the_flank(topo, name, blank, gd, ends, ra, probs) -> None:
    """A problem for each axis of a topography's grid that misses the gear's flank: a
    profile grid outside the roll lengths from the form circle to the tip (from the
    reference circle, either flank, both face ends), a face grid outside the face. Such
    a grid is most likely in another coordinate (from the base circle, from a face end);
    held beyond its border it would only shift the flank."""
    rb = np.asarray(gd.base_radius)[:, None]
    xr = np.sqrt(gd.reference_pitch_radius**2 - rb**2)
    lo = float(np.min(np.sqrt(np.maximum(_form_radius(blank, gd, ends) ** 2 - rb**2, 0)) - xr))
    hi = float(np.max(np.sqrt(ra[None, :] ** 2 - rb**2) - xr))
    half = 0.5 * blank.face_width
    for axis, grid, a, b in (("profile", topo.profile, lo, hi), ("face", topo.face, -half, half)):
        if grid[-1] <= a or grid[0] >= b:
            probs.add(
                f"ltca.{name}_topography_{axis}_mm",
                [round(v * 1e3, 6) for v in grid],
                f"must reach into the {name}'s flank, [{a * 1e3:.4g}, {b * 1e3:.4g}] mm "
                + (
                    "of roll length from the reference circle"
                    if axis == "profile"
                    else "from the face middle"
                ),
            )


def tip_relief_from_scene(design, scene) -> tuple[FlankModification, FlankModification]:
    """The scene's flank modifications (:func:`modifications_from_scene`; the name of
    the first version, when tip relief was the only one)."""
    return modifications_from_scene(design, scene)


def _form_radius(blank, gd, z) -> np.ndarray:
    """Form-circle radius (where the involute starts: rack parameter u = 0, or on an
    undercut flank where the fillet cuts it, :func:`gearbox.surface.involute_start`)
    of both flanks at axial positions ``z``, shape (2, len(z)): rows R, L."""
    from ..surface import involute_start

    z = np.asarray(z, dtype=float)
    rows = []
    for side in ("R", "L"):
        p, _, _, _ = _jets(blank, side, z, involute_start(blank, side, z))
        rows.append(np.hypot(p[:, 0], p[:, 1]))
    return np.stack(rows)


@dataclass(frozen=True)
class SeparationField:
    """Initial separations of the reference tooth pair over its engagement (SI).

    phi1: (M,) pinion angles (rad); z, u: (S,), (U,) pinion face positions (m) and
    profile parameters per slot (u shape (S, U)); separation: (M, S, U) m (NaN where
    the point cannot touch); point, normal: (S, U, 3) pinion flank points and outward
    normals in S1; gear_radius: (M, S, U) radius of the gear partner point (m);
    gear_z: (M, S, U) its axial position in S2 (m); iterations: Newton iterations.

    Contact line per (angle, slot), shapes (M, S) (and (M, S, 3)): ``line_has`` the
    slot can touch; ``line_edge`` the sampled minimum lies on the border of the
    valid profile range (the contact would continue beyond the flank edge);
    ``line_u`` profile parameter, ``line_separation`` (m) and ``line_curvature``
    (1/m, second derivative of the separation along the profile arc length) of the
    minimum, refined by a parabola through three exact evaluations a quarter cell
    apart around the coarse vertex; ``line_point``, ``line_normal`` pinion point and
    normal in S1; ``line_gear_radius``, ``line_gear_z`` the gear partner.
    """

    side: str
    phi1: np.ndarray
    z: np.ndarray
    u: np.ndarray
    separation: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    gear_radius: np.ndarray
    gear_z: np.ndarray
    iterations: int
    line_has: np.ndarray
    line_edge: np.ndarray
    line_u: np.ndarray
    line_separation: np.ndarray
    line_curvature: np.ndarray
    line_point: np.ndarray
    line_normal: np.ndarray
    line_gear_radius: np.ndarray
    line_gear_z: np.ndarray


def _jets(blank, side, z, u):
    from ..surface import flank_jets

    r, n, _ = flank_jets(blank, side, z, u, involute_only=True)
    R = np.stack([c.d for c in r], axis=-1)  # (6, N, 3): value, d/dz, d/du, ...
    return R[0], R[1], R[2], np.moveaxis(n, 0, -1)


def _project(gear, side, M2, O2, p, n, x0, max_iter=30, tol=1e-9):
    """Solve M2 r2(z2, u2) + O2 = p + t n for (z2, u2, t), vectorised; x0 (N, 3).

    Bounded Newton steps (half a module); each point stops when its residual is below
    ``tol`` (m); points still off by more than 0.1 mm after 10 steps are given up
    (their normal line misses the flank). On an undercut gear u2 is kept above the
    envelope's fold (:func:`gearbox.surface.fold_parameter`, at 1.1 times its u*,
    below the real flank's start): below the fold lies the folded
    branch, a second sheet that a step across the cusp would settle on (on a 14/21
    parallel pair with the gear undercut by 1.6 mm that had read the stiffness 27 %
    below the closed form's). Returns (x, converged mask, iterations).
    """
    from ..surface import fold_parameter

    x = x0.copy()
    m = gear.normal_module
    N = x.shape[0]
    active = np.arange(N)
    ok = np.zeros(N, dtype=bool)
    it = 0
    for it in range(1, max_iter + 1):  # noqa: B007 - reported
        xa = x[active]
        r, rz, ru, _ = _jets(gear, side, xa[:, 0], xa[:, 1])
        Ma = M2[active]
        na = n[active]
        F = np.einsum("nij,nj->ni", Ma, r) + O2 - p[active] - xa[:, 2:3] * na
        res = np.max(np.abs(F), axis=1)
        done = res < tol
        ok[active[done]] = True
        lost = (it > 10) & (res > 1e-4)
        go = ~(done | lost)
        if not go.any():
            break
        J = np.stack(
            [
                np.einsum("nij,nj->ni", Ma[go], rz[go]),
                np.einsum("nij,nj->ni", Ma[go], ru[go]),
                -na[go],
            ],
            axis=-1,
        )
        dx = np.linalg.solve(J, -F[go][..., None])[..., 0]
        step = xa[go] + np.clip(dx, -0.5 * m, 0.5 * m)
        fold = fold_parameter(gear, side, step[:, 0])
        # (1.1 u*: off the cusp, where the Jacobian is singular; the fillet's cut, where
        # the real flank starts, lay at 1.29 to 1.50 u* on 1180 undercut sections of
        # random blanks, tests/test_surface_undercut.py)
        step[:, 1] = np.where(fold > 0, np.maximum(step[:, 1], 1.1 * fold), step[:, 1])
        x[active[go]] = step
        active = active[go]
    return x, ok, it


def _start(gear, side, M2, O2, p, n, n_z=9, n_u=9):
    """Starting values (z2, u2, t) for :func:`_project`: the gear flank sample (a
    coarse n_z x n_u grid of its involute part, from its start: on an undercut gear
    above the folded branch) nearest to each pinion normal line."""
    from ..surface import involute_start, tip_parameter

    zs = np.linspace(gear.z_toe, gear.z_heel, n_z)
    ut, _ = tip_parameter(gear, side, zs)
    uf = involute_start(gear, side, zs)
    us = uf[:, None] + (ut - uf)[:, None] * np.linspace(0.0, 1.0, n_u)[None, :]
    zz = np.repeat(zs, n_u)
    r, _, _, _ = _jets(gear, side, zz, us.ravel())
    q = np.einsum("ij,kj->ki", M2[0], r) + O2  # (K, 3), same gear angle for all points
    d = q[None, :, :] - p[:, None, :]  # (N, K, 3)
    t = np.einsum("nkj,nj->nk", d, n)
    perp = np.linalg.norm(d - t[..., None] * n[:, None, :], axis=2)
    best = np.argmin(perp, axis=1)
    return np.stack([zz[best], us.ravel()[best], t[np.arange(p.shape[0]), best]], axis=1)


def _assembly(design, scene):
    from ..tca.assembly import Assembly, AssemblyErrors

    return Assembly.from_design(design, AssemblyErrors.from_scene(scene))


def _gear_phase(design, asm, pinion, gear, side, zc, uc):
    """Gear angle phi_2,0 at phi_1 = 0 at which the flanks ``side`` of pinion tooth 0
    and gear tooth 0 touch: the unloaded TCA's contact at the pitch point
    (:func:`gearbox.tca.local.centre_start`, :func:`gearbox.tca.contact.solve_contact`),
    or where the surfaces touch off the real flanks there, the border, corner or
    crossing that touches first (:func:`gearbox.tca.edge.edge_start`), carried back to phi_1 = 0 along the
    ideal ratio; where both fail, :func:`_gear_phase_search`.

    The separation field needs the touching phase: a gear turned by d phi_2 off it
    changes each separation along the pinion normal by a lever that varies over the
    flank, a shape error of first order in d phi_2 (case 01's coast flank: 0.5 to 1.1 %
    of mean stiffness per 2 mrad, and 18 % at the 49 mrad by which a phase searched at the
    pinion's phi_1 = 0, away from the mesh, was off).
    """
    from ..tca.contact import solve_contact
    from ..tca.edge import edge_start, on_flanks
    from ..tca.local import centre_start

    ratio = design.pinion.teeth / design.gear.teeth
    try:
        target = np.asarray(design.pitch_point, dtype=float)
        phi1c, x0 = centre_start(pinion, gear, asm, side, target)
        c = solve_contact(pinion, gear, asm, side, [phi1c], x0[None, :], max_iter=200)
        if c.converged[0] and c.opposed[0] and on_flanks(pinion, gear, side, c.x)[0]:
            return float(c.x[0, 4]) + ratio * phi1c
        # no surface contact near the pitch point (near line contact under
        # misalignment): what touches first there (a border, corner or crossing)
        start = edge_start(pinion, gear, asm, side, phi1c, x0)
        if start is not None:
            return float(start[0][4]) + ratio * phi1c
    except (ValueError, FloatingPointError, np.linalg.LinAlgError):
        pass
    return _gear_phase_search(design, asm, pinion, gear, side, zc, uc)


def _gear_phase_search(design, asm, pinion, gear, side, zc, uc):
    """Gear angle phi_2,0 at phi_1 = 0 that brings the flank ``side`` of gear tooth 0
    through the pinion's tooth 0 flank point (zc, uc).

    The separation t along the pinion normal is a smooth function of the gear angle
    (the flank's analytic continuation is used, so it exists far from contact too);
    its zero is found by the secant method from a bracket near phi_2 = 0. The normals
    must be opposed there (tooth bodies on either side); the partner point may lie on
    the continuation of the gear flank: the phase only needs to pair the right flanks,
    the rigid offset is taken up by the contact problem (phi_0).

    The search runs with the pinion turned so that the point lies at the pitch point's
    angle about its axis (``phi_ref``; the phase is then carried back to phi_1 = 0):
    away from the mesh its normal line may miss every gear flank within reach (case
    01's pair at a 224 mm offset, its pitch point 17 deg round the pinion from tooth 0,
    found no phase within two gear pitches).
    """
    p, _, _, n = _jets(pinion, side, np.array([zc]), np.array([uc]))
    P = np.asarray(design.pitch_point, dtype=float)
    q = asm.pinion_matrix(np.zeros(1))[0] @ p[0]
    phi_ref = math.atan2(P[1], P[0]) - math.atan2(q[1], q[0])
    ratio = design.pinion.teeth / design.gear.teeth
    M1 = asm.pinion_matrix(np.full(1, phi_ref))
    pf = np.einsum("nij,nj->ni", M1, p) + asm.pinion_origin
    nf = np.einsum("nij,nj->ni", M1, n)

    def gap(phase, x0=None):
        M2 = asm.gear_matrix(np.array([phase - ratio * phi_ref]))
        if x0 is None:
            x0 = _start(gear, side, M2, asm.gear_origin, pf, nf)
        x, ok, _ = _project(gear, side, M2, asm.gear_origin, pf, nf, x0)
        return x, bool(ok[0]), M2

    step = math.pi / (4 * design.gear.teeth)  # 1/8 gear pitch
    # first bracket: two neighbouring phases whose projections converge
    a = None
    for k in (0, 1, -1, 2, -2, 3, -3, 4, -4, 5, -5, 6, -6, 7, -7, 8, -8, 12, -12, 16, -16):
        xa, oka, _ = gap(k * step)
        if oka:
            xb, okb, _ = gap((k + 1) * step, xa)
            if okb:
                a, b = k * step, (k + 1) * step
                break
    if a is None:
        raise InputError(
            Problem(
                f"ltca.mesh_phase[{side}]",
                None,
                "the gear flank is not met along the pinion's normal at any phase within "
                "two gear pitches: the assembly does not mesh",
            )
        )
    it = 0
    for it in range(1, 61):  # noqa: B007 - reported in the error
        if not (oka and okb) or xb[0, 2] == xa[0, 2]:
            break
        c = b - xb[0, 2] * (b - a) / (xb[0, 2] - xa[0, 2])
        c = a + float(np.clip(c - a, -8 * step, 8 * step))
        a, xa, oka = b, xb, okb
        b = c
        xb, okb, M2 = gap(b, xa)
        if okb and abs(xb[0, 2]) < 1e-9:
            break
    ok = okb and abs(xb[0, 2]) < 1e-7
    if ok:
        _, _, _, n2 = _jets(gear, side, xb[:, 0], xb[:, 1])
        ok = float(np.einsum("ij,nj->ni", M2[0], n2)[0] @ nf[0]) < 0.0  # opposed
    if not ok:
        raise InputError(
            Problem(
                f"ltca.mesh_phase[{side}]",
                None,
                f"no gear tooth flank meets the pinion's reference flank point ({it} secant "
                "steps): the assembly does not mesh (check offset, shaft angle and axial "
                "positions)",
            )
        )
    return b


def separation_field(
    design,
    scene,
    side: str,
    *,
    n_profile: int,
    n_face: int,
    positions: int,
    pitches: tuple[int, int] = (-3, 3),
    relief: tuple[FlankModification | TipRelief, FlankModification | TipRelief] | None = None,
    edge_borders: bool = True,
) -> SeparationField:
    """Separation field of the reference tooth pair on flank ``side`` ("R" or "L")
    at ``positions`` per mesh cycle over ``pitches`` mesh cycles around phi_1 = 0.

    relief: (pinion, gear) :class:`FlankModification` (or :class:`TipRelief`); ``None``
    takes the scene's (:func:`modifications_from_scene`). Its removal is added to every
    separation. edge_borders: each edge point on the flank border itself
    (:func:`_edge_borders`, scene key ``ltca.edge_borders``), not on its last profile
    sample."""
    from ..surface import blanks_from_design, involute_start, tip_parameter

    pinion, gear = blanks_from_design(design)
    if relief is None:
        relief = modifications_from_scene(design, scene)
    mods = _Modification(design, pinion, gear, side, relief)
    asm = _assembly(design, scene)
    N1, N2 = design.pinion.teeth, design.gear.teeth
    pitch = 2 * math.pi / N1
    dz = pinion.face_width / n_face
    z = pinion.z_toe + dz * (np.arange(n_face) + 0.5)
    u_tip, _ = tip_parameter(pinion, side, z)
    u_form = involute_start(pinion, side, z)
    frac = (np.arange(n_profile) + 0.5) / n_profile
    # (S, U): form circle (u = 0, or an undercut flank's cut by the fillet) to tip
    u = u_form[:, None] + (u_tip - u_form)[:, None] * frac[None, :]
    zz = np.repeat(z, n_profile)
    uu = u.ravel()
    p1, _, _, n1 = _jets(pinion, side, zz, uu)
    relief1 = mods.pinion(p1)  # (npts,) removal on the pinion, fixed over the angles
    phase = _gear_phase(design, asm, pinion, gear, side, 0.0, 0.5 * float((u_form + u_tip).mean()))
    phi1 = np.arange(pitches[0] * positions, pitches[1] * positions + 1) * (pitch / positions)
    M = phi1.size
    npts = zz.size
    sep = np.full((M, npts), np.nan)
    sep_ext = np.full((M, npts), np.nan)  # on the flanks' continuation too
    grad = np.full((M, npts), np.nan)
    gz = np.full((M, npts), np.nan)
    z2_toe, z2_heel = gear.z_toe, gear.z_heel
    # the gear's tip parameter depends on z_2 only: tabulate it once (it is smooth,
    # linear interpolation on 201 points is exact to well below a micrometre)
    z2_tab = np.linspace(z2_toe, z2_heel, 201)
    u2_tab, _ = tip_parameter(gear, side, z2_tab)
    u2_form_tab = involute_start(gear, side, z2_tab)
    total_it = 0
    x = None
    # continuation from the middle of the engagement outwards
    order = np.argsort(np.abs(phi1))
    prev = {}
    for i in order:
        f1 = phi1[i]
        M1 = asm.pinion_matrix(np.full(npts, f1))
        pf = np.einsum("nij,nj->ni", M1, p1) + asm.pinion_origin
        nf = np.einsum("nij,nj->ni", M1, n1)
        f2 = phase - (N1 / N2) * f1
        M2 = asm.gear_matrix(np.full(npts, f2))
        near = min(prev, key=lambda j: abs(phi1[j] - f1)) if prev else None
        if near is None:
            x0 = _start(gear, side, M2, asm.gear_origin, pf, nf)
        else:
            x0 = prev[near]
        x, ok, it = _project(gear, side, M2, asm.gear_origin, pf, nf, x0)
        total_it += it
        prev[i] = np.where(ok[:, None], x, x0)
        u2_tip = np.interp(x[:, 0], z2_tab, u2_tab)
        u2_form = np.interp(x[:, 0], z2_tab, u2_form_tab)
        on = ok & (x[:, 0] >= z2_toe) & (x[:, 0] <= z2_heel)
        on &= (x[:, 1] >= u2_form) & (x[:, 1] <= u2_tip)
        r2, _, _, _ = _jets(gear, side, x[:, 0], x[:, 1])
        t = x[:, 2]
        if mods.active:
            t = t + relief1 + mods.gear(r2)
        sep[i] = np.where(on, t, np.nan)
        sep_ext[i] = np.where(ok, t, np.nan)
        grad[i] = np.hypot(r2[:, 0], r2[:, 1])
        gz[i] = x[:, 0]
    S, U = n_face, n_profile
    sep3 = sep.reshape(M, S, U)
    xs = np.stack([prev[i] for i in range(M)]).reshape(M, S, U, 3)
    line = _refine_lines(
        pinion,
        gear,
        asm,
        side,
        phase,
        N1 / N2,
        phi1,
        z,
        u,
        sep3,
        sep_ext.reshape(M, S, U),
        xs,
        p1.reshape(S, U, 3),
        n1.reshape(S, U, 3),
        grad.reshape(M, S, U),
        gz.reshape(M, S, U),
        mods,
        edge_borders,
    )
    return SeparationField(
        side=side,
        phi1=phi1,
        z=z,
        u=u,
        **line,
        separation=sep3,
        point=p1.reshape(n_face, n_profile, 3),
        normal=n1.reshape(n_face, n_profile, 3),
        gear_radius=grad.reshape(M, n_face, n_profile),
        gear_z=gz.reshape(M, n_face, n_profile),
        iterations=total_it,
    )


class _Modification:
    """Flank modifications of a pair on one flank side: material removed (m) at
    pinion and gear flank points given in their own frames (radius = hypot(x, y),
    axial position z; tip and form radii of the transverse section at z)."""

    def __init__(self, design, pinion, gear, side, relief):
        k = _SIDE_INDEX[side]
        self.parts = []
        for rel, blank, gd in zip(
            relief, (pinion, gear), (design.pinion, design.gear), strict=True
        ):
            mod = as_modification(rel)
            form = None
            if mod.profile_active:  # the form radius is smooth in z: tabulate it once
                zt = np.linspace(blank.z_toe, blank.z_heel, 41)
                form = (zt, _form_radius(blank, gd, zt)[k])
            self.parts.append((mod, blank, gd.base_radius[k], form, gd.reference_pitch_radius))
        self.active = any(part[0].active for part in self.parts)

    def _removal(self, k, points):
        mod, blank, rb, form, r_ref = self.parts[k]
        if not mod.active:
            return np.zeros(points.shape[0])
        radius = np.hypot(points[:, 0], points[:, 1])
        # the flank's continuation beyond the face keeps the end section's radii
        z = np.clip(points[:, 2], blank.z_toe, blank.z_heel)
        return mod.removal(
            radius,
            points[:, 2] - 0.5 * (blank.z_toe + blank.z_heel),
            tip_radius=blank.tip_radius(z),
            base_radius=rb,
            face_width=blank.face_width,
            form_radius=None if form is None else np.interp(z, *form),
            reference_radius=r_ref,
        )

    def pinion(self, points):
        return self._removal(0, points)

    def gear(self, points):
        return self._removal(1, points)


def _refine_lines(
    pinion,
    gear,
    asm,
    side,
    phase,
    ratio,
    phi1,
    z,
    u,
    sep,
    sep_ext,
    xs,
    p1,
    n1,
    grad,
    gz,
    mods,
    edge_borders=True,
):
    """Contact line of every (angle, slot): see :class:`SeparationField`.

    The vertex is sought on the flanks' continuation (``sep_ext``) so that a minimum
    just inside the border of the sampled range is found; it is an edge point only
    when the refined minimum lies off either real flank."""
    from ..surface import involute_start, tip_parameter

    M, S, U = sep.shape
    valid = np.isfinite(sep)
    has = np.any(valid, axis=2)
    big = np.where(valid, sep, np.inf)
    idx = np.argmin(big, axis=2)
    first = np.argmax(valid, axis=2)
    last = U - 1 - np.argmax(valid[:, :, ::-1], axis=2)
    edge = has & ((idx == first) | (idx == last))
    ii, ss = np.meshgrid(np.arange(M), np.arange(S), indexing="ij")
    s0 = np.where(has, big[ii, ss, idx], np.nan)
    ext = np.where(np.isfinite(sep_ext), sep_ext, np.inf)
    sm = ext[ii, ss, np.clip(idx - 1, 0, U - 1)]
    sp = ext[ii, ss, np.clip(idx + 1, 0, U - 1)]
    # a border minimum with a larger value beyond the border (on the continuation)
    # is an interior minimum of the continuous field: refine it as well
    edge = edge & ~(
        (idx > 0) & (idx < U - 1) & np.isfinite(sm) & np.isfinite(sp) & (sm > s0) & (sp > s0)
    )
    d, _, _ = _parabola(np.where(np.isfinite(sm), sm, s0), s0, np.where(np.isfinite(sp), sp, s0))
    du = u[:, 1] - u[:, 0]
    out = {
        "line_has": has,
        "line_edge": edge,
        "line_u": u[ss, idx],
        "line_separation": s0,
        "line_curvature": np.full((M, S), np.nan),
        "line_point": p1[ss, idx],
        "line_normal": n1[ss, idx],
        "line_gear_radius": grad[ii, ss, idx],
        "line_gear_z": gz[ii, ss, idx],
    }
    if edge_borders:
        geo = (pinion, gear, asm, side, phase, ratio, phi1, z)
        _edge_borders(out, edge, idx, first, u, sep_ext, xs, geo, mods)
    sel = has & ~edge
    ia, sa = ii[sel], ss[sel]
    if ia.size:
        h = 0.25 * du[sa]
        uv = u[sa, idx[sel]] + d[sel] * du[sa]
        x0 = xs[ia, sa, idx[sel]]
        M1 = asm.pinion_matrix(phi1[ia])
        M2 = asm.gear_matrix(phase - ratio * phi1[ia])
        vals, oks, xk0 = [], [], None
        for k in (-1, 0, 1):
            pk, _, _, nk = _jets(pinion, side, z[sa], uv + k * h)
            pf = np.einsum("nij,nj->ni", M1, pk) + asm.pinion_origin
            nf = np.einsum("nij,nj->ni", M1, nk)
            xk, okk, _ = _project(gear, side, M2, asm.gear_origin, pf, nf, x0)
            if mods.active:
                r2k, _, _, _ = _jets(gear, side, xk[:, 0], xk[:, 1])
                vals.append(xk[:, 2] + mods.pinion(pk) + mods.gear(r2k))
            else:
                vals.append(xk[:, 2])
            oks.append(okk)
            if k == 0:
                xk0 = xk
        good = oks[0] & oks[1] & oks[2]
        d2, smin, c2 = _parabola(vals[0], vals[1], vals[2])
        ustar = uv + d2 * h
        ps, rz, ru, ns = _jets(pinion, side, z[sa], ustar)
        dl = np.linalg.norm(ru, axis=1)  # arc length per unit u
        curv = c2 / (h * dl) ** 2
        good &= np.isfinite(smin) & (c2 > 0)
        # the refined minimum must lie on both real flanks
        u1_tip, _ = tip_parameter(pinion, side, z[sa])
        z2 = np.clip(xk0[:, 0], gear.z_toe, gear.z_heel)
        u2_tip, _ = tip_parameter(gear, side, z2)
        u1_form, u2_form = involute_start(pinion, side, z[sa]), involute_start(gear, side, z2)
        on = (ustar >= u1_form) & (ustar <= u1_tip)
        on &= (xk0[:, 1] >= u2_form) & (xk0[:, 1] <= u2_tip)
        on &= (xk0[:, 0] >= gear.z_toe) & (xk0[:, 0] <= gear.z_heel)
        edge[ia[good & ~on], sa[good & ~on]] = True
        good &= on
        sel_idx = (ia[good], sa[good])
        out["line_u"][sel_idx] = ustar[good]
        out["line_separation"][sel_idx] = smin[good]
        out["line_curvature"][sel_idx] = curv[good]
        out["line_point"][sel_idx] = ps[good]
        out["line_normal"][sel_idx] = ns[good]
        r2, _, _, _ = _jets(gear, side, xk0[good, 0], xk0[good, 1])
        out["line_gear_radius"][sel_idx] = np.hypot(r2[:, 0], r2[:, 1])
        out["line_gear_z"][sel_idx] = xk0[good, 0]
    curv = out["line_curvature"]
    fallback = np.nanmedian(curv) if np.any(np.isfinite(curv)) else 1.0 / pinion.normal_module
    out["line_curvature"] = np.where(np.isfinite(curv) & (curv > 0), curv, fallback)
    return out


def _edge_borders(out, edge, idx, first, u, sep_ext, xs, geo, mods):
    """Each border minimum of the sampled separation (an edge point) moved from its
    sample to the border itself, in ``out`` (:func:`_refine_lines`'s fields); ``geo``:
    (pinion, gear, asm, side, phase, ratio, phi1, z).

    The samples lie half a step inside the pinion's form and tip lines, and a border of
    the gear's flank (its tip or form line, a face end) crosses the pinion's profile
    between two samples. The point goes to the pinion's own line, or where the gear's
    violated limit, taken linearly between the two samples, is zero, and its separation
    is projected there as the field's (:func:`_project`, the flank modifications
    added); it is kept where the projection reaches the gear's flank within a tenth of
    the sample step beyond its border and lowers the separation (the sampled minimum
    bounds the border's). Without this, a gear edge that crosses the pinion's profile
    between two samples was found only at the angles where the sample next to it
    projected inside the gear's flank (case 03's coast flank at 96 positions: an edge
    point at every fourth position only, 0.1 to 1.6 um from contact, 6 to 9 um at the
    others), and the pinion's tip edge was read half a step short of the tip."""
    from ..surface import involute_start, tip_parameter

    pinion, gear, asm, side, phase, ratio, phi1, z = geo
    U = sep_ext.shape[2]
    ii, ss = np.nonzero(edge)
    if ii.size == 0:
        return
    a = idx[ii, ss]
    low = a == first[ii, ss]
    b = np.where(low, a - 1, a + 1)
    du = u[ss, 1] - u[ss, 0]
    beyond = (b >= 0) & (b < U)
    bc = np.clip(b, 0, U - 1)

    def limits(x):
        """The gear's four limits at its points x (z2, u2, .): > 0 beyond the border,
        in parts of its profile span or face width."""
        z2 = np.clip(x[:, 0], gear.z_toe, gear.z_heel)
        tip, _ = tip_parameter(gear, side, z2)
        form = involute_start(gear, side, z2)
        span = np.maximum(tip - form, 1e-12)
        face = gear.z_heel - gear.z_toe
        cols = [(x[:, 1] - tip) / span, (form - x[:, 1]) / span]
        cols += [(gear.z_toe - x[:, 0]) / face, (x[:, 0] - gear.z_heel) / face]
        return np.stack(cols, axis=1)

    # the pinion's own form or tip line half a step beyond a first or last sample
    u_new = np.where(low, u[ss, a] - 0.5 * du, u[ss, a] + 0.5 * du)
    gb = beyond & np.isfinite(sep_ext[ii, ss, bc])
    if gb.any():  # a gear border between samples a and b
        ga = limits(xs[ii[gb], ss[gb], a[gb]])
        gbv = limits(xs[ii[gb], ss[gb], bc[gb]])
        k = np.argmax(gbv, axis=1)
        r = np.arange(k.size)
        g0, g1 = ga[r, k], gbv[r, k]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where((g0 <= 0) & (g1 > 0), g0 / (g0 - g1), np.nan)
        u_new[gb] = u[ss[gb], a[gb]] + t * (u[ss[gb], bc[gb]] - u[ss[gb], a[gb]])
    u_new[beyond & ~gb] = np.nan  # the projection failed beyond: left as sampled
    go = np.isfinite(u_new)
    if not go.any():
        return
    ii, ss, a, u_new, du = ii[go], ss[go], a[go], u_new[go], du[go]
    pk, _, _, nk = _jets(pinion, side, z[ss], u_new)
    M1 = asm.pinion_matrix(phi1[ii])
    M2 = asm.gear_matrix(phase - ratio * phi1[ii])
    pf = np.einsum("nij,nj->ni", M1, pk) + asm.pinion_origin
    nf = np.einsum("nij,nj->ni", M1, nk)
    xk, okk, _ = _project(gear, side, M2, asm.gear_origin, pf, nf, xs[ii, ss, a])
    r2, _, _, _ = _jets(gear, side, xk[:, 0], xk[:, 1])
    sep = xk[:, 2] + (mods.pinion(pk) + mods.gear(r2) if mods.active else 0.0)
    # on the gear's flank, to a tenth of the sample step beyond a border (the linear
    # crossing's error), in the gear's own parameters
    reach = 0.1 * du / np.maximum(np.abs(u[ss, -1] - u[ss, 0]), 1e-12)
    near = np.max(limits(xk), axis=1) <= reach
    take = okk & near & np.isfinite(sep) & (sep < out["line_separation"][ii, ss])
    ii, ss = ii[take], ss[take]
    out["line_u"][ii, ss] = u_new[take]
    out["line_separation"][ii, ss] = sep[take]
    out["line_point"][ii, ss] = pk[take]
    out["line_normal"][ii, ss] = nk[take]
    out["line_gear_radius"][ii, ss] = np.hypot(r2[take, 0], r2[take, 1])
    out["line_gear_z"][ii, ss] = xk[take, 0]


def _parabola(sm, s0, sp):
    """Vertex offset (in steps, |d| <= 0.5 clipped) and value of the parabola through
    (-1, sm), (0, s0), (1, sp); also the second difference."""
    with np.errstate(invalid="ignore"):
        c2 = sm - 2 * s0 + sp
        d = np.where(c2 > 0, 0.5 * (sm - sp) / np.where(c2 > 0, c2, 1.0), 0.0)
        d = np.clip(np.nan_to_num(d), -0.5, 0.5)
        return d, s0 - 0.25 * (sm - sp) * d, c2


def _half_angle_base(gd, blank, side, z):
    """Half tooth-thickness angle at the base circle of flank ``side`` of a beveloid
    transverse section at axial position z (rad): the tilted rack shifted radially by
    X(z) widens the half tooth at r_p by X tan(alpha_P) (alpha_P the flank's transverse
    pressure angle, geometry conventions), so psi_b = (pi m_t / 4 + X tan alpha_P) / r_p
    + inv(alpha_P)."""
    ap = gd.transverse_pressure_angle[_SIDE_INDEX[side]]
    rp = blank.reference_pitch_radius
    X = blank.rack_shift(z)
    return (math.pi * blank.transverse_module / 4 + X * math.tan(ap)) / rp + inv(ap)


def _sections(gd, blank, side, radius, z):
    n = radius.size
    rb = gd.base_radius[_SIDE_INDEX[side]]
    root = blank.root_radius(z)
    return ToothSections.uniform(
        n,
        radius=np.maximum(radius, rb * (1 + 1e-6)),
        base_radius=rb,
        root_radius=root,
        tip_radius=np.maximum(blank.tip_radius(z), radius),
        bore_radius=0.5 * root,
        base_half_angle=_half_angle_base(gd, blank, side, z),
        teeth=blank.teeth,
        normal_module=blank.normal_module,
        normal_pressure_angle=blank.normal_pressure_angle,
        helix_angle=abs(blank.helix_angle),
        profile_shift=blank.rack_shift(z) * math.cos(blank.cone_angle) / blank.normal_module,
        rack_dedendum=blank.tool_addendum / blank.normal_module,
        rack_root_radius=blank.tool_tip_radius / blank.normal_module,
    )


_REACH = 2e-4  # m: points farther than this from first contact are left out


def _gear_widths(g_z, has, dz):
    """Extent along the gear's axis of each pinion slot of width dz on the contact
    lines: |d z_2 / d slot| from the gear-axial coordinates of neighbouring slots
    (one-sided at the ends of a line), the median ratio where a line has one slot."""
    gz = np.where(has, g_z, np.nan)
    d = np.full(gz.shape, np.nan)
    both = np.abs(gz[:, 2:] - gz[:, :-2]) / 2
    d[:, 1:-1] = both
    fwd = np.abs(gz[:, 1:] - gz[:, :-1])
    d[:, :-1] = np.where(np.isfinite(d[:, :-1]), d[:, :-1], fwd)
    d[:, 1:] = np.where(np.isfinite(d[:, 1:]), d[:, 1:], fwd)
    ratio = d / dz
    med = np.nanmedian(ratio[has]) if np.any(np.isfinite(ratio[has])) else 1.0
    ratio = np.where(np.isfinite(ratio) & (ratio > 0), ratio, med)
    return dz * ratio


def beveloid_grids(design, scene, field: SeparationField, positions: int, reach: float = _REACH):
    """Contact grids at ``positions`` per mesh cycle from a separation field.

    reach (m): points whose gap at first contact exceeds it are left out (the loaded
    approach is checked against it after the solve). Returns (grids, sense): a list of
    :class:`ContactGrid` and the sign of the pinion rotation that loads this flank.
    """
    from ..surface import blanks_from_design

    pinion, gear = blanks_from_design(design)
    asm = _assembly(design, scene)
    side = field.side
    M, S, U = field.separation.shape
    i_start = int(round(field.phi1[0] / (2 * math.pi / design.pinion.teeth) * positions))
    zaxis = np.array([0.0, 0.0, 1.0])
    E = scene["material"]["youngs_modulus_GPa"] * 1e9
    nu = scene["material"]["poisson_ratio"]
    dz = pinion.face_width / S
    # the active flank: profile parameters whose gear partner lies on the gear's flank
    # at some angle of the engagement
    uvalid = np.broadcast_to(field.u[None], field.separation.shape)[np.isfinite(field.separation)]
    if uvalid.size == 0:
        flank = "drive" if side == "R" else "coast"
        raise InputError(
            Problem(
                f"ltca.flanks[{flank}]",
                "no contact",
                "no pinion flank point's normal meets the gear's flank at any position: "
                "the flanks do not overlap (the design's contact ratio checks, the offset, "
                "the profile shifts)",
            ),
            "the loaded TCA found no contact",
        )
    u_lo, u_top = float(uvalid.min()), float(uvalid.max())
    has = field.line_has
    edge = field.line_edge
    smin = field.line_separation
    curv = field.line_curvature
    pt = field.line_point
    nr = field.line_normal / np.linalg.norm(field.line_normal, axis=-1, keepdims=True)
    g_rad = field.line_gear_radius
    g_z = field.line_gear_z
    uu = field.line_u
    # to Sf at each field angle, arms
    M1 = asm.pinion_matrix(field.phi1)  # (M, 3, 3)
    pf = np.einsum("mij,msj->msi", M1, pt) + asm.pinion_origin
    nf = np.einsum("mij,msj->msi", M1, nr)
    arm_raw = np.einsum("msi,msi->ms", nf, np.cross(zaxis, pf - asm.pinion_origin))
    sense = float(np.sign(np.nanmean(np.where(has, arm_raw, np.nan))))
    arm = sense * arm_raw
    proj = np.sqrt(np.maximum(1 - (nf @ zaxis) ** 2, 1e-12))
    # the gear's own: the normal against its transverse plane, and the slot's extent
    # along its axis (the gear-axial coordinate of the contact line per pinion slot)
    proj2 = np.sqrt(np.maximum(1 - (nf @ asm.gear_axis) ** 2, 1e-12))
    width2 = _gear_widths(g_z, has, dz)
    # first pass: the points of every position and their rigid rotation to contact
    picks = []
    for j in range(positions):
        ks, slots, fi = [], [], []
        for k in range(-8, 9):
            i = j + k * positions - i_start
            if 0 <= i < M and has[i].any():
                for s in np.flatnonzero(has[i]):
                    ks.append(k)
                    slots.append(s)
                    fi.append(i)
        if not ks:
            raise InputError(
                Problem(f"ltca.grid[{side}]", j, "no tooth pair reaches the active flank here")
            )
        ks, slots, fi = np.array(ks), np.array(slots), np.array(fi)
        s_i = smin[fi, slots]
        m_i = arm[fi, slots]
        keep = m_i > 0
        phi0 = np.min(s_i[keep] / m_i[keep])
        keep &= (s_i - m_i * phi0) < reach
        picks.append((ks[keep], slots[keep], fi[keep], s_i[keep], m_i[keep]))
    # one rigid rotation for all positions (the nominal phase is arbitrary): what is
    # left of each position's rotation to first contact is the unloaded TE
    phi_ref = min(float(np.min(p[3] / p[4])) for p in picks)
    k_side = _SIDE_INDEX[side]
    rb1, rb2 = design.pinion.base_radius[k_side], design.gear.base_radius[k_side]
    roll1_ref = math.sqrt(pinion.reference_pitch_radius**2 - rb1**2)
    roll2_ref = math.sqrt(gear.reference_pitch_radius**2 - rb2**2)
    mid1, mid2 = 0.5 * (pinion.z_toe + pinion.z_heel), 0.5 * (gear.z_toe + gear.z_heel)
    grids = []
    for ks, slots, fi, s_i, m_i in picks:
        z1 = field.z[slots]
        rad1 = np.hypot(pt[fi, slots, 0], pt[fi, slots, 1])
        rad2 = g_rad[fi, slots]
        flank = np.column_stack(
            [
                np.sqrt(np.maximum(rad1**2 - rb1**2, 0.0)) - roll1_ref,
                z1 - mid1,
                np.sqrt(np.maximum(rad2**2 - rb2**2, 0.0)) - roll2_ref,
                g_z[fi, slots] - mid2,
            ]
        )
        grids.append(
            ContactGrid(
                pair=ks,
                slot=slots,
                face=z1,
                width=np.full(ks.size, dz),
                line_length=dz / proj[fi, slots],
                separation=s_i - m_i * phi_ref,
                arm=m_i,
                transverse_projection=proj[fi, slots],
                width2=width2[fi, slots],
                transverse_projection2=proj2[fi, slots],
                curvature_radius=1.0 / curv[fi, slots],
                profile=uu[fi, slots],
                profile_range=(u_lo, u_top),
                face_range=(pinion.z_toe, pinion.z_heel),
                n_slots=S,
                edge=edge[fi, slots],
                position=pf[fi, slots],
                normal=nf[fi, slots],
                tooth1=_sections(design.pinion, pinion, side, rad1, z1),
                tooth2=_sections(design.gear, gear, side, g_rad[fi, slots], g_z[fi, slots]),
                youngs_modulus=E,
                poisson_ratio=nu,
                pinion_axis=np.array([zaxis, asm.pinion_origin]),
                gear_axis=np.array([asm.gear_axis, asm.gear_origin]),
                flank_coordinates=flank,
            )
        )
    return grids, sense


def scene_grids(design, scene, side: str, positions: int, *, relief=None):
    """Contact grids of one flank (``"R"`` drive, ``"L"`` coast) over a mesh cycle with
    the scene's grid counts and tip relief (``relief`` overrides it). Returns
    ``(grids, sense, field)``: :func:`beveloid_grids`'s two and the separation field."""
    lt = scene["ltca"]
    if relief is None:
        relief = modifications_from_scene(design, scene)
    field = separation_field(
        design,
        scene,
        side,
        n_profile=lt["grid_profile"],
        n_face=lt["grid_face"],
        positions=positions,
        relief=relief,
        edge_borders=lt["edge_borders"],
    )
    grids, sense = beveloid_grids(design, scene, field, positions)
    return grids, sense, field


def scene_compliance(design, scene):
    """The compliance level ``ltca.fidelity`` of a beveloid pair: the FE level meshes
    the generated teeth (their blanks), the fast level needs nothing of the pair."""
    fidelity = scene["ltca"]["fidelity"]
    if fidelity == "fe":
        from ..surface import blanks_from_design

        return compliance_for("fe", blanks=blanks_from_design(design))
    return compliance_for(fidelity, face_ends=scene["ltca"]["face_ends"])


def refuse_unmodelled_teeth(design) -> None:
    """InputError naming each gear with pointed teeth (a normal tip thickness below 0,
    design check ``*_topping``): the loaded TCA needs a tooth tip. Undercut flanks are
    taken from where the fillet cuts the regular involute
    (:func:`gearbox.surface.involute_start`; the slices' outline
    :func:`gearbox.ltca.slice_model.fillet_top`, the FE level's mesh
    :func:`gearbox.surface.form_point`); before, the grids had reached down the
    envelope's folded branch below that point."""
    p = Problems()
    for name, g in (("pinion", design.pinion), ("gear", design.gear)):
        top = design.checks.get(f"{name}_topping")
        if top is not None and top.margin + TOPPING_MIN_SAN * design.spec.normal_module < 0:
            s_an = top.margin + TOPPING_MIN_SAN * design.spec.normal_module
            p.add(
                f"{name}.profile_shift_xt",
                round(g.profile_shift_xt, 5),
                f"the {name}'s teeth are pointed (normal tip thickness {s_an * 1e3:.3f} mm, "
                f"design check {name}_topping): the loaded TCA needs a tooth tip; a smaller "
                "profile shift, or the offset for another backlash-free gear shift",
            )
    p.raise_if_any("the loaded TCA cannot take this design")


def interference_notes(design, flanks) -> tuple[str, ...]:
    """A note for each analysed flank whose mating tip meets a gear's flank below its
    root form circle (the design check ``*_active_root_*`` fails: meshing
    interference with the fillet or, on an undercut gear, with the involute just above
    the fillet's cut). The loaded TCA's flanks end at the form circles, so such a
    tip's contact is an edge contact at the form circle there, not a model of the
    interference: the unloaded TE and edge load it brings come from that edge (on
    case 03 with a 12-tooth pinion whose gear's tip reaches 10.2 mm of path below its
    form circle, 18.4 um of unloaded TE p-p)."""
    out = []
    for flank in flanks:
        name = "right" if _FLANK_SIDE[flank] == "R" else "left"
        for gear in ("pinion", "gear"):
            check = design.checks.get(f"{gear}_active_root_{name}")
            if check is None or check.ok:
                continue
            mate = "gear" if gear == "pinion" else "pinion"
            out.append(
                f"{flank} flank: the {mate}'s tip meets the {gear} "
                f"{-check.margin * 1e3:.3f} mm of path below its root form circle "
                f"(design check {gear}_active_root_{name}: meshing interference). The loaded "
                f"TCA's flanks end at the form circle, so that contact appears as edge "
                f"contact there: the unloaded TE and edge load it brings come from that "
                f"edge, not from a model of the interference; a larger {gear} profile shift "
                f"or a shorter {mate} tip clears it."
            )
    return tuple(out)


def refuse_no_overlap(design, flanks) -> None:
    """InputError for each analysed flank whose transverse contact ratio (the design
    check's) is below 0: the tips do not reach past each other's working pitch circles,
    so only tip edges would touch (case 04 with x_t2 = -1.5 and no backlash-free shift
    gave 85 MN/m and 370 um of LTE from edge contact, where the TCA finds no contact)."""
    p = Problems()
    for flank in flanks:
        name = "right" if _FLANK_SIDE[flank] == "R" else "left"
        check = design.checks.get(f"transverse_contact_ratio_{name}")
        if check is not None and check.margin < -1.0:
            p.add(
                f"ltca.flanks[{flank}]",
                flank,
                f"the transverse contact ratio is {1.0 + check.margin:.3f} (design check "
                f"transverse_contact_ratio_{name}): the tips do not reach past the working "
                "pitch circles, only tip edges would touch (the offset, the profile shifts, "
                "the addendum)",
            )
    p.raise_if_any("the loaded TCA cannot take this design")


def beveloid_ltca(
    design,
    scene,
    *,
    options: LTCAOptions | None = None,
    relief: tuple[FlankModification | TipRelief, FlankModification | TipRelief] | None = None,
):
    """Loaded TCA and mesh table of a crossed beveloid pair for the scene's torques and
    flanks (``drive`` = R, ``coast`` = L). Returns :class:`~gearbox.ltca.table.LTCAResult`.
    relief: (pinion, gear) tip reliefs; ``None`` takes the scene's ``[ltca]`` keys.
    """
    from .table import LTCAResult, mesh_table

    refuse_unmodelled_teeth(design)
    lt = scene["ltca"]
    refuse_no_overlap(design, lt["flanks"])
    options = options or LTCAOptions(positions=lt["positions"])
    P = options.positions
    compliance = scene_compliance(design, scene)
    torques = scene["load"]["torques_Nm"]
    if relief is None:
        relief = modifications_from_scene(design, scene)
    results, senses, fields = {}, {}, {}
    made = {f: scene_grids(design, scene, _FLANK_SIDE[f], P, relief=relief) for f in lt["flanks"]}
    reserve = getattr(compliance, "reserve", None)
    if callable(reserve):  # one model per gear for both flanks
        reserve([g for grids, _, _ in made.values() for g in grids])
    for flank in lt["flanks"]:
        grids, sense, field = made[flank]
        res = ltca_cycle(
            lambda f, g=grids: g[int(round(f * P)) % P],
            torques,
            options=options,
            compliance=compliance,
        )
        elastic = float(np.max(res.lte - res.lte_unloaded[None, :]))
        if elastic > 0.5 * _REACH:
            raise InputError(
                Problem(
                    "load.torques_Nm",
                    list(torques),
                    f"the loaded approach {elastic * 1e6:.0f} um exceeds half the contact "
                    f"grid's reach ({_REACH * 1e6:.0f} um): torques this high leave the "
                    "modelled contact zone",
                )
            )
        results[flank] = res
        senses[flank] = sense
        fields[flank] = field.iterations
    asm = _assembly(design, scene)
    first = next(iter(results))
    res0 = results[first]
    P0 = res0.mesh_point.reshape(-1, 3).mean(axis=0)
    n0 = res0.line_of_action.reshape(-1, 3).mean(axis=0)
    sgn = 1.0 if first == "drive" else -1.0
    a1 = np.array([0.0, 0.0, 1.0])
    a1 = a1 if sgn * a1 @ np.cross(P0 - asm.pinion_origin, n0) > 0 else -a1
    a2 = asm.gear_axis
    a2 = a2 if sgn * a2 @ np.cross(P0 - asm.gear_origin, n0) > 0 else -a2
    attrs = {
        "scene": scene.name,
        "method": "loaded TCA: separation field of the generated flanks (gearbox.surface), "
        f"{describe_compliance(compliance)}, active-set contact solver",
        "fidelity": lt["fidelity"],
        "root_stress": root_stress_method(compliance),
        "gearbox_version": __version__,
        "frame": "Sf of gearbox.tca.assembly (paper Fig. 11); drive = R flank, coast = L flank",
        "field_newton_iterations": int(sum(fields.values())),
        "edge_points": "flank border" if lt["edge_borders"] else "last profile sample",
        "flank_modifications": describe_pair(relief),
        "pinion_reference_pitch_radius_m": float(design.pinion.reference_pitch_radius),
        "gear_reference_pitch_radius_m": float(design.gear.reference_pitch_radius),
    }
    table = mesh_table(
        results,
        pinion_teeth=design.pinion.teeth,
        gear_teeth=design.gear.teeth,
        pinion_axis=[a1, asm.pinion_origin],
        gear_axis=[a2, asm.gear_origin],
        attrs=attrs,
    )
    notes = ()
    if lt["fidelity"] == "fast":
        from .validity import fast_level_notes

        notes = fast_level_notes(made[first][0][0])
    notes = tuple(notes) + topography_notes(relief) + interference_notes(design, lt["flanks"])
    return LTCAResult(
        flanks=results,
        table=table,
        attrs=attrs,
        notes=notes,
        modification_maps=modification_maps(design, relief, flanks=lt["flanks"]),
    )


def modification_maps(design, relief, n_face: int = 21, flanks=("drive",)) -> dict:
    """Per modified gear and analysed flank (``flanks``: ``"drive"`` R, ``"coast"`` L)
    the removal over that flank from its form circle to the tip at ``n_face`` axial
    positions (:func:`removal_map`, with the flank's own base and form radii), for the
    report; keys ``"<gear>, <flank> flank"``."""
    from ..surface import blanks_from_design

    maps = {}
    blanks = blanks_from_design(design)
    for flank in flanks:
        k = _SIDE_INDEX[_FLANK_SIDE[flank]]
        for name, rel, blank, gd in zip(
            ("pinion", "gear"), relief, blanks, (design.pinion, design.gear), strict=True
        ):
            mod = as_modification(rel)
            if not mod.active:
                continue
            z = np.linspace(blank.z_toe, blank.z_heel, n_face)
            maps[f"{name}, {flank} flank"] = removal_map(
                mod,
                z - 0.5 * (blank.z_toe + blank.z_heel),
                form_radius=_form_radius(blank, gd, z)[k],
                tip_radius=blank.tip_radius(z),
                base_radius=gd.base_radius[k],
                reference_radius=gd.reference_pitch_radius,
                face_width=blank.face_width,
            )
    return maps


_ = Problems
