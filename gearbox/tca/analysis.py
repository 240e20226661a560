"""Unloaded tooth contact analysis over a sweep of pinion angles (drive and coast).

For each flank side the reference tooth pair (pinion tooth 0, gear tooth 0) is solved
at the pinion angles ``phi_1 + 2 pi j / N_1`` for ``j = -J..J``: pinion tooth j at
phi_1 is tooth 0 at that angle, so one batched solve covers every tooth pair that can
be in contact. The starting values come from the tangent of the contact path at the
pitch point (implicit function theorem), then :func:`gearbox.tca.contact.solve_contact`
iterates. A contact is *active* when it lies on both real flanks: inside the face
widths, above both form circles (start of the involute) and below both tip cones.

Per pinion angle the gear angle is set by the active pair that stops it first: on the
drive side (R, pinion turning +phi_1 about z_f pushes the gear towards -phi_2) the
smallest phi_2, on the coast side (L) the largest. Unloaded transmission error is the
gear angle minus the ideal ``phi_2c - (N_1/N_2)(phi_1 - phi_1c)``.

Measured FPD angle: the angle between the two flanks' zero-curvature principal
directions (their rulings, the contact lines with the common rack, paper Fig. 2) at
each contact point, from the generated surfaces.

Contact ellipse: the surfaces' curvature tensors in the common tangent plane are
added (both convex-positive), and the separation ``delta`` gives the semi-axes
``sqrt(2 delta / lambda_i)`` (Litvin & Fuentes, 2nd ed. 2004, ch. 8 "Mating
Surfaces: Curvature Relations, Contact Ellipse"; marking-compound thickness 6.35 um
by default).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, Problem
from ..surface import ToothBlank, flank_points
from .assembly import Assembly, AssemblyErrors
from .contact import solve_contact, tangent_predictor
from .edge import edge_contacts, edge_start, on_flanks
from .local import centre_start, contact_ellipse, far_outside, flank_limits, refine_path_ends
from .result import (
    LINE_CONTACT_FPD,
    SIDE_NAMES,
    FlankContact,
    TCAResult,
    TCASettings,
    _edge_tally,
)

__all__ = ["TCASettings", "FlankContact", "TCAResult", "run_tca", "tca_of_blanks", "SIDE_NAMES"]


#: Iterations allowed to the one contact solve at the pitch point (at least
#: ``tca.max_iter``). From its start at the working pitch radius it took 1 iteration on
#: the paper's cases and on case 03 with a 3.5 deg pinion cone, 20 on the drive flank
#: of a design for a 2 deg FPD angle; near line contact the conditions hardly fix the
#: face position, and the bound leaves room for such starts. The sweep's solves start
#: from the tangent predictor and keep ``tca.max_iter``.
CENTRE_MAX_ITER = 200


def _edge_counts(fc) -> str:
    """'the gear heel at 12 positions, the pinion toe at 3 positions' from a side's
    edge contacts."""
    return ", ".join(
        f"the {a} at {c} position{'s' if c > 1 else ''}" for a, c in _edge_tally(fc).items()
    )


def _no_centre_reason(asm, c, centre_iter) -> str:
    """Why neither the flanks' surfaces nor a border of a flank touch near the pitch point."""
    why = (
        "with no assembly errors" if asm.errors == AssemblyErrors() else "check the assembly errors"
    )
    borders = (
        "no border of either member's real flank (face end, tip or form line, their corners "
        "and crossings) touches the mate there"
    )
    if c.converged[0] and c.opposed[0]:  # the surfaces touch, but off the real flanks
        return (
            f"no tooth pair is in contact on the real flanks near the pitch point: the flanks' "
            f"surfaces touch only on their continuation (pinion z {c.x[0, 0] * 1e3:.4g} mm, "
            f"gear z {c.x[0, 2] * 1e3:.4g} mm), and {borders}; the assembly separates the "
            f"gears or the flanks do not overlap: {why}"
        )
    return (
        f"the contact conditions have no solution near the pitch point within {centre_iter} "
        f"iterations (residual {c.residual_position[0]:.3g} m), and {borders}: {why}"
    )


def _side(pinion, gear, asm, side, phi1_grid, settings, target):
    N1, N2 = pinion.teeth, gear.teeth
    # J pairs either side of the reference pair at every position: a sweep of c mesh
    # cycles about the pitch point moves the reference pair c / 2 pitches either way
    J = settings.pairs + int(np.ceil(0.5 * settings.mesh_cycles))
    pairs = np.arange(-J, J + 1)
    phi1c, x0 = centre_start(pinion, gear, asm, side, target)
    centre_iter = max(settings.max_iter, CENTRE_MAX_ITER)
    c = solve_contact(pinion, gear, asm, side, [phi1c], x0[None, :], max_iter=centre_iter)
    # the surfaces' contact near the pitch point, where it lies on the real flanks (a
    # misaligned near-line pair's can lie half a metre along the continued flanks)
    if c.converged[0] and c.opposed[0] and on_flanks(pinion, gear, side, c.x)[0]:
        xc = c.x[0]
        tan = tangent_predictor(pinion, gear, asm, side, [phi1c], c.x)[0]
    else:  # no surface contact near the pitch point: start from what touches first
        start = edge_start(pinion, gear, asm, side, phi1c, x0)
        if start is None:
            raise InputError(
                Problem(
                    f"tca[{SIDE_NAMES[side]}]",
                    "pitch-point contact",
                    _no_centre_reason(asm, c, centre_iter),
                ),
                "tooth contact analysis failed",
            )
        xc, tan = start
    phi_ref = (phi1_grid[:, None] + 2 * np.pi * pairs[None, :] / N1).ravel()
    X0 = xc + np.outer(phi_ref - phi1c, tan)
    s = solve_contact(pinion, gear, asm, side, phi_ref, X0, max_iter=settings.max_iter)
    n, P = len(phi1_grid), len(pairs)
    x = s.x
    M1 = asm.pinion_matrix(phi_ref)
    M2 = asm.gear_matrix(x[:, 4])
    fp1 = flank_points(pinion, side, x[:, 0], x[:, 1], involute_only=True)
    fp2 = flank_points(gear, side, x[:, 2], x[:, 3], involute_only=True)
    lim1, fl1 = flank_limits(pinion, side, x[:, 0], x[:, 1], fp1.radius, "pinion")
    lim2, fl2 = flank_limits(gear, side, x[:, 2], x[:, 3], fp2.radius, "gear")
    ok = s.converged & s.opposed
    limit = np.where(lim1 != "", lim1, lim2)
    # a problem that did not converge is reported as such; when its last iterate is far
    # outside the flanks (more than one module beyond a limit: involute continuation
    # near the base cylinder, where the surface is singular) it is also named by that limit
    far = far_outside(pinion, x[:, 0], x[:, 1], fp1.radius) | far_outside(
        gear, x[:, 2], x[:, 3], fp2.radius
    )
    named = np.char.add(limit.astype(str), " (not converged)")
    limit = np.where(ok, limit, np.where(far & (limit != ""), named, "not converged"))
    active = ok & (limit == "")
    # rulings (zero-curvature directions) and curvature tensors in Sf
    d1 = np.einsum("nij,nkj->nki", M1, fp1.directions)
    d2 = np.einsum("nij,nkj->nki", M2, fp2.directions)
    r1 = d1[:, 0, :] * np.sign(d1[:, 0, 2])[:, None]
    a2 = asm.gear_axis
    r2 = d2[:, 0, :] * np.sign(d2[:, 0, :] @ a2)[:, None]
    nrm = s.normal
    fpd_signed = np.arctan2(
        np.einsum("ni,ni->n", nrm, np.cross(r1, r2)), np.einsum("ni,ni->n", r1, r2)
    )
    fpd = np.arccos(np.clip(np.abs(np.einsum("ni,ni->n", r1, r2)), 0.0, 1.0))
    axes, major = contact_ellipse(
        fp1.curvatures, d1, fp2.curvatures, d2, nrm, settings.marking_compound
    )
    e_face = np.array([0.0, 0.0, 1.0]) - nrm[:, 2:3] * nrm
    e_face /= np.linalg.norm(e_face, axis=1, keepdims=True)
    e_prof = np.cross(nrm, e_face)
    # towards the pinion's tip: the radial direction away from the pinion axis
    radial = s.point - asm.pinion_origin
    radial[:, 2] = 0.0
    e_prof *= np.sign(np.einsum("ni,ni->n", e_prof, radial))[:, None]
    ang = np.arctan2(np.einsum("ni,ni->n", major, e_prof), np.einsum("ni,ni->n", major, e_face))
    ang = np.where(ang > np.pi / 2, ang - np.pi, np.where(ang <= -np.pi / 2, ang + np.pi, ang))
    # gear angle of each pair at the sweep's pinion angles
    g_pairs = x[:, 4].reshape(n, P) + 2 * np.pi * pairs[None, :] / N2
    act = active.reshape(n, P)
    gp = np.where(act, g_pairs, np.nan)
    with np.errstate(all="ignore"):
        if side == "R":
            gear_angle = np.where(act.any(1), np.nanmin(np.where(act, gp, np.inf), axis=1), np.nan)
        else:
            gear_angle = np.where(act.any(1), np.nanmax(np.where(act, gp, -np.inf), axis=1), np.nan)
    # positions without a surface contact on the real flanks: the border, corner or
    # crossing of borders that touches first (gearbox.tca.edge) sets the gear angle
    edge_name = np.full(n, "", dtype=object)
    edge_point = np.full((n, 3), np.nan)
    edge_x = np.full((n, 5), np.nan)
    need = ~act.any(axis=1)
    if need.any():
        got = edge_contacts(pinion, gear, asm, side, phi1_grid[need], pairs, phi1c, xc, settings)
        gear_angle[need], edge_name[need], edge_point[need], edge_x[need] = got
    corner = np.char.find(np.asarray(edge_name, dtype=str), "/") >= 0
    edge_fl = [np.full((n, 2), np.nan), np.full((n, 2), np.nan)]
    on = np.isfinite(edge_x).all(axis=1)
    edge_pair = np.zeros(n, dtype=int)  # the touching pair's offset j
    edge_pair[on] = np.round((gear_angle[on] - edge_x[on, 4]) * N2 / (2 * np.pi)).astype(int)
    if on.any():
        for k, (blank, who) in enumerate(((pinion, "pinion"), (gear, "gear"))):
            z, u = edge_x[on, 2 * k], edge_x[on, 2 * k + 1]
            radius = flank_points(blank, side, z, u, involute_only=True).radius
            edge_fl[k][on] = flank_limits(blank, side, z, u, radius, who)[1]
    te = gear_angle - (xc[4] - (N1 / N2) * (phi1_grid - phi1c))
    # path limits and contact ratio of the reference pair (sorted by its pinion angle);
    # the ends of its active interval are refined by bisection in phi_1
    order = np.argsort(phi_ref)
    a_sorted = active[order]
    lim_sorted = limit[order]
    if a_sorted.any():
        first, last = np.flatnonzero(a_sorted)[[0, -1]]
        start = lim_sorted[first - 1] if first > 0 else "beyond the examined pairs"
        end = lim_sorted[last + 1] if last + 1 < len(order) else "beyond the examined pairs"
        ph = phi_ref[order]
        if 0 < first and last + 1 < len(order):
            ends, by = refine_path_ends(
                pinion,
                gear,
                asm,
                side,
                ph[[first, last]],
                x[order][[first, last]],
                ph[[first - 1, last + 1]],
                x[order][[first - 1, last + 1]],
                settings,
                tan,
            )
            ratio = (ends[1] - ends[0]) / (2 * np.pi / N1)
            start, end = by  # the limits at the refined ends
        else:
            ratio = float("nan")
    else:
        start = end = "no contact"
        ratio = 0.0
    r = lambda a: a.reshape((n, P) + a.shape[1:])  # noqa: E731
    return FlankContact(
        side=side,
        name=SIDE_NAMES[side],
        pinion_angle=phi1_grid,
        gear_angle=gear_angle,
        transmission_error=te,
        pairs_in_contact=act.sum(axis=1),
        pair=pairs,
        active=act,
        converged=r(s.converged),
        iterations=r(s.iterations),
        limit=r(np.asarray(limit, dtype=str)),
        point=r(s.point),
        normal=r(nrm),
        pinion_zu=r(x[:, :2]),
        gear_zu=r(x[:, 2:4]),
        pinion_flank=r(fl1),
        gear_flank=r(fl2),
        fpd_angle=r(fpd),
        fpd_angle_signed=r(fpd_signed),
        ellipse_axes=r(axes),
        ellipse_direction=r(major),
        ellipse_angle=r(ang),
        gear_angle_pairs=g_pairs,
        path_limits=(str(start), str(end)),
        contact_ratio=float(ratio),
        edge=np.asarray(edge_name, dtype=str),
        edge_point=edge_point,
        edge_pair=edge_pair,
        edge_pinion_flank=edge_fl[0],
        edge_gear_flank=edge_fl[1],
        edge_corner=corner,
    ), phi1c


def tca_of_blanks(
    pinion: ToothBlank,
    gear: ToothBlank,
    assembly: Assembly,
    settings: TCASettings | None = None,
    *,
    pitch_point=None,
    designed_fpd=None,
    pinion_angles=None,
) -> TCAResult:
    """Unloaded TCA of both flank sides over a sweep of pinion angles.

    Args:
        pinion, gear: :class:`gearbox.surface.ToothBlank` of both members.
        assembly: :class:`Assembly` in Sf.
        settings: :class:`TCASettings` (defaults: 61 positions over 1.5 mesh cycles).
        pitch_point: a point of Sf near which the contact passes (m), shape (3,);
            default: the point at the pinion's reference pitch radius on x_f.
        designed_fpd: (xi_R, xi_L) of the design (rad), stored for comparison.
        pinion_angles: explicit pinion angles phi_1 of the sweep (rad), shape (n,),
            instead of the range centred on the pitch-point passage.

    Raises:
        InputError: when no contact is found near the pitch point, or when no tooth
            pair is in contact anywhere on the flanks.
    """
    settings = (settings or TCASettings()).validate()
    target = np.asarray(
        pitch_point
        if pitch_point is not None
        else (pinion.reference_pitch_radius, 0.0, assembly.pinion_axial),
        dtype=float,
    )
    N1 = pinion.teeth
    # the sweep is centred on the drive side's pitch-point passage
    phi1c, _ = centre_start(pinion, gear, assembly, "R", target)
    half = 0.5 * settings.mesh_cycles * 2 * np.pi / N1
    if pinion_angles is None:
        grid = phi1c + np.linspace(-half, half, settings.positions)
    else:
        grid = np.atleast_1d(np.asarray(pinion_angles, dtype=float))
    drive, _ = _side(pinion, gear, assembly, "R", grid, settings, target)
    coast, _ = _side(pinion, gear, assembly, "L", grid, settings, target)
    pitch2 = 2 * np.pi / gear.teeth
    play = drive.gear_angle - coast.gear_angle
    play = np.mod(play + 0.5 * pitch2, pitch2) - 0.5 * pitch2
    msgs = []
    status = "ok"
    for fc in (drive, coast):
        if not (fc.active.any() or np.isfinite(fc.gear_angle).any()):
            raise InputError(
                Problem(
                    f"tca[{fc.name}]",
                    "no contact",
                    "no tooth pair is in contact on the real flanks anywhere: the assembly separates the "
                    "gears (offset or axial errors too large) or the flanks do not overlap",
                ),
                "tooth contact analysis failed",
            )
        gaps = int(np.sum(fc.pairs_in_contact == 0))
        if gaps:
            status = "edge contact"
            edges = _edge_counts(fc)
            where = (
                f"; a border of a real flank (a face end, tip or form line, a corner of "
                f"two, or one crossing a border of the mate's) touches the mate there "
                f"({edges}), and sets the gear angle and TE"
                if edges
                else ""
            )
            ratio = (
                f" (contact ratio {fc.contact_ratio:.3f} < 1)"
                if np.isfinite(fc.contact_ratio) and fc.active.any()
                else ""
            )
            msgs.append(
                f"{fc.name}: {gaps} of {len(grid)} positions have no contact of the flanks' "
                f"surfaces on the real flanks{ratio}{where}"
            )
        roots = [lim for lim in fc.path_limits if lim.endswith(" root")]
        if roots:
            who = roots[0].split()[0]
            mate = "gear" if who == "pinion" else "pinion"
            msgs.append(
                f"{fc.name}: the contact path ends at the {who}'s root form circle, before "
                f"the {mate}'s tip: beyond it the {mate}'s tip meets the {who}'s fillet "
                f"(meshing interference, design check {who}_active_root_"
                f"{'right' if fc.side == 'R' else 'left'}); the TCA keeps to the involute flanks"
            )
        f_act = fc.fpd_angle[fc.active]
        if f_act.size and np.max(f_act) < LINE_CONTACT_FPD:
            msgs.append(
                f"{fc.name}: line contact (measured FPD angle {np.degrees(np.max(f_act)):.2g} deg): each "
                "contact point is one point of the instantaneous contact line, so the path position "
                "on the face is not defined by the flanks"
            )
        near = fc.limit == "not converged"
        if near.any():
            msgs.append(
                f"{fc.name}: {int(near.sum())} contact solves on or near the flanks did not converge "
                f"in {settings.max_iter} iterations (flagged 'not converged', excluded)"
            )
    r2 = gear.reference_pitch_radius
    if not np.isfinite(play).any():  # no position has both flanks in contact
        msgs.append(
            "backlash not measured: no position has contact on both the drive and the coast flank"
        )
    elif np.nanmin(play) * r2 < -1e-9:
        status = "interference"
        msgs.append(
            f"drive and coast flanks overlap by up to {-np.nanmin(play) * r2 * 1e6:.3f} um (circumferential, "
            f"gear pitch circle): the gears interfere in this assembly"
        )
    elif np.nanmax(play) * r2 > 1e-9:
        msgs.append(
            f"backlash up to {np.nanmax(play) * r2 * 1e6:.3f} um (circumferential, gear pitch circle)"
        )
    return TCAResult(
        pinion, gear, assembly, settings, drive, coast, play, designed_fpd, status, tuple(msgs)
    )


def _expect_design(design, name: str) -> None:
    """TypeError unless ``design`` is a designed pair (it has a spec and a pitch point)."""
    if not (hasattr(design, "spec") and hasattr(design, "pitch_point")):
        from ..errors import expect_type
        from ..geometry import PairDesign

        expect_type(design, PairDesign, name, "design_pair(PairSpec.from_scene(scene))")


def run_tca(
    design, scene=None, *, settings: TCASettings | None = None, errors=None, pinion_angles=None
) -> TCAResult:
    """Unloaded TCA of a designed pair (:class:`gearbox.geometry.PairDesign`).

    The blanks come from the design and its tool profile
    (:func:`gearbox.surface.blanks_from_design`), the assembly from its pitch point
    (:meth:`Assembly.from_design`). With a ``scene``, its ``[tca]`` section gives the
    settings and its ``[assembly]`` section the assembly errors, unless ``settings``
    or ``errors`` (:class:`AssemblyErrors`) are given.
    """
    from ..errors import expect_scene, expect_type
    from ..surface import blanks_from_design

    _expect_design(design, "run_tca: design")
    if settings is not None:
        expect_type(settings, TCASettings, "run_tca: settings", "TCASettings(positions=...)")
    if errors is not None:
        expect_type(errors, AssemblyErrors, "run_tca: errors", "AssemblyErrors(offset=...)")
    if scene is not None:
        expect_scene(scene, "run_tca: scene")
        settings = settings or TCASettings.from_scene(scene)
        errors = errors or AssemblyErrors.from_scene(scene)
    pinion, gear = blanks_from_design(design)
    asm = Assembly.from_design(design, errors)
    return tca_of_blanks(
        pinion,
        gear,
        asm,
        settings,
        pitch_point=design.pitch_point,
        designed_fpd=(design.fpd_angle_right, design.fpd_angle_left),
        pinion_angles=pinion_angles,
    )
