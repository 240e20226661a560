"""Mesh tables from the loaded TCA: :class:`~gearbox.meshtable.MeshTable` and the
scene-level entry points.

``drive`` is the paper's R flank and ``coast`` its L flank (project convention, see
docs/ltca.md); a table holds both when the scene asks for both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from .. import __version__
from ..errors import Problems
from ..meshtable import (
    CONTACT_CENTRES,
    CONTACT_LENGTHS,
    FORM_BASES,
    FRICTION_ARMS,
    TORQUE_ARM,
    MeshTable,
    form_weight_name,
    pair_weight_name,
)
from .analysis import (
    PER_POSITION,
    CycleResult,
    LTCAOptions,
    cycle_summary,
    ltca_cycle,
    root_stress_method,
)
from .compliance import compliance_for, describe_compliance
from .parallel import ParallelPair, parallel_grid
from .pitch import covered_centres, covered_lengths
from .validity import fast_level_notes

__all__ = [
    "LTCAResult",
    "mesh_table",
    "parallel_ltca",
    "parallel_pair_from_design",
    "scene_ltca",
]


@dataclass(frozen=True)
class LTCAResult:
    """Loaded TCA of a pair: per flank a :class:`CycleResult`, and the mesh table.

    flanks: mapping flank name -> CycleResult; table: the MeshTable (SI); attrs:
    provenance (scene, method, fidelity, gearbox version, frame); notes: where the pair
    lies outside the range the fast level was checked on, one line per quantity naming
    the gears (:func:`gearbox.ltca.validity.fast_level_notes`; empty inside it and at
    the FE level); modification_maps: per modified gear and flank (``"pinion, drive
    flank"``, ...) the
    removal over its drive flank (:func:`gearbox.ltca.modification.removal_map`), for
    the report's map; empty without flank modifications.
    """

    flanks: dict
    table: MeshTable
    attrs: dict = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    modification_maps: dict = field(default_factory=dict)

    def summary(self) -> dict:
        """JSON-ready summary: the notes, and per flank, per torque (N m as key), the
        mean and peak-to-peak mesh stiffness and LTE, mean P and n, pattern area
        fraction, edge-contact flag and solver status."""
        out = {"attrs": dict(self.attrs), "notes": list(self.notes), "flanks": {}}
        for name, res in self.flanks.items():
            rows = cycle_summary(res)["torques"]
            out["flanks"][name] = dict(
                zip(torque_keys([r["torque_Nm"] for r in rows]), rows, strict=True)
            )
        return out


def torque_keys(torques) -> list[str]:
    """Keys of torque levels (N m) in the summary: the shortest ``%g`` form of 6 to 17
    digits that tells every level apart (300 and 300.0004 need 7: "300", "300.0004")."""
    for digits in range(6, 18):
        keys = [f"{float(t):.{digits}g}" for t in torques]
        if len(set(keys)) == len(keys):
            return keys
    return [repr(float(t)) for t in torques]  # pragma: no cover - equal levels


def mesh_table(
    flanks: dict,
    *,
    pinion_teeth: int,
    gear_teeth: int,
    pinion_axis,
    gear_axis,
    attrs: dict,
    angle0: float = 0.0,
) -> MeshTable:
    """Assemble a MeshTable from per-flank :class:`CycleResult` (same torques and positions).

    pinion_axis, gear_axis: shape (2, 3) [unit axis in the driving sense, point] in Sf.
    """
    names = [f for f in ("drive", "coast") if f in flanks]
    first = flanks[names[0]]
    P = first.fraction.size
    angle = angle0 + first.fraction * (2 * math.pi / pinion_teeth)

    def stack(attr):
        return np.stack([getattr(flanks[f], attr) for f in names])

    share_max = np.stack([flanks[f].pair_share.max(axis=2) for f in names])
    area = np.stack([np.repeat(flanks[f].pattern_area_fraction[:, None], P, axis=1) for f in names])
    extra = {
        "max_contact_pressure_Pa": stack("max_pressure"),
        "pattern_area_fraction": area,
        "load_sharing": share_max,
        "root_stress_pinion_Pa": stack("root_stress_pinion"),
        "root_stress_gear_Pa": stack("root_stress_gear"),
        "edge_load_fraction": stack("edge_load_fraction"),
    }
    if all(flanks[f].loss_factor is not None for f in names):
        extra["mesh_loss_factor"] = stack("loss_factor")
        extra["sliding_speed_per_pinion_speed_m"] = stack("sliding_speed")
    if all(flanks[f].friction_arm is not None for f in names):
        arms = stack("friction_arm")
        extra.update(zip(FRICTION_ARMS, (arms[..., 0], arms[..., 1]), strict=True))
    if all(flanks[f].pair_weight is not None for f in names):
        # each tooth pair's weight (docs/ltca.md "Pitch deviations"), 0 where a flank
        # does not track the pair; and the torque arm T / sum F_n
        ks = sorted({int(k) for f in names for k in flanks[f].pair_index})
        for k in ks:
            w = np.zeros((len(names), first.torque.size, P))
            for i, f in enumerate(names):
                hit = np.flatnonzero(flanks[f].pair_index == k)
                if hit.size:
                    w[i] = flanks[f].pair_weight[:, :, hit[0]]
            extra[pair_weight_name(k)] = w
        extra[TORQUE_ARM] = np.stack(
            [flanks[f].torque[:, None] / flanks[f].normal_load for f in names]
        )
    if all(flanks[f].pair_form_weight is not None for f in names):
        # each pair's weights for its teeth's slopes and crownings (docs/ltca.md "Form
        # deviations"), and the lengths and middles of what the drive flank's contact
        # covers
        ks = sorted({int(k) for f in names for k in flanks[f].pair_index})
        for k in ks:
            for b, basis in enumerate(FORM_BASES):
                w = np.zeros((len(names), first.torque.size, P))
                for i, f in enumerate(names):
                    hit = np.flatnonzero(flanks[f].pair_index == k)
                    if hit.size:
                        w[i] = flanks[f].pair_form_weight[:, :, hit[0], b]
                extra[form_weight_name(basis, k)] = w
        if "drive" in flanks:
            rng = flanks["drive"].flank_range
            (r1, r2), (f1, f2) = covered_lengths(rng)
            (c1, c2), (d1, d2) = covered_centres(rng)
            attrs = {
                **attrs,
                **dict(zip(CONTACT_LENGTHS, (r1, r2, f1, f2), strict=True)),
                **dict(zip(CONTACT_CENTRES, (c1, c2, d1, d2), strict=True)),
            }
    return MeshTable(
        pinion_teeth=pinion_teeth,
        gear_teeth=gear_teeth,
        angle=angle,
        torque=first.torque,
        flanks=tuple(names),
        stiffness=stack("stiffness"),
        tangent_stiffness=stack("tangent_stiffness"),
        lte=stack("lte"),
        mesh_point=stack("mesh_point"),
        line_of_action=stack("line_of_action"),
        pinion_axis=np.asarray(pinion_axis, dtype=float),
        gear_axis=np.asarray(gear_axis, dtype=float),
        extra=extra,
        attrs=attrs,
    )


def parallel_pair_from_design(design, scene) -> ParallelPair:
    """The :class:`ParallelPair` of a design with shaft angle 0 and cone angles 0, with
    the scene's assembly errors: the offset error changes the centre distance, the
    shaft-angle error is the pair's ``misalignment``; axial shifts must be 0."""
    from .parallel import MIN_TEETH as PARALLEL_MIN_TEETH

    p = Problems()
    p.check(
        abs(design.shaft_angle) < 1e-12,
        "pair.shaft_angle_deg",
        math.degrees(design.shaft_angle),
        "must be 0 for a parallel-axis pair",
    )
    for name, g in (("pinion", design.pinion), ("gear", design.gear)):
        p.check(
            abs(g.cone_angle) < 1e-12,
            f"{name}.cone_angle_deg",
            math.degrees(g.cone_angle),
            "must be 0 for a parallel-axis pair",
        )
    p.raise_if_any("not a parallel-axis pair")
    tool = scene["tool"]
    mat = scene["material"]
    asm = scene["assembly"]
    for key in ("pinion_axial_error_mm", "gear_axial_error_mm"):
        p.check(
            asm[key] == 0.0,
            f"assembly.{key}",
            asm[key],
            "must be 0 for a parallel-axis pair (the parallel path does not model the "
            "face overlap an axial shift changes)",
        )
    for name, g in (("pinion", design.pinion), ("gear", design.gear)):
        p.check(
            g.teeth >= PARALLEL_MIN_TEETH,
            f"{name}.teeth",
            g.teeth,
            f"must be >= {PARALLEL_MIN_TEETH} for a parallel-axis pair (its slices)",
        )
    p.raise_if_any("the parallel-axis path cannot take this pair")
    return ParallelPair(
        normal_module=design.normal_module,
        normal_pressure_angle=design.normal_pressure_angle,
        helix_angle=design.pinion.helix_angle,
        teeth=(design.pinion.teeth, design.gear.teeth),
        profile_shift=(design.pinion.normal_profile_shift, design.gear.normal_profile_shift),
        face_width=min(design.pinion.face_width, design.gear.face_width),
        center_distance=design.offset + asm["offset_error_mm"] * 1e-3,
        misalignment=math.radians(asm["shaft_angle_error_deg"]),
        addendum_coefficient=tool["gear_addendum_coefficient"],
        dedendum_coefficient=tool["addendum_coefficient"],
        root_radius_coefficient=tool["tip_radius_coefficient"],
        youngs_modulus=mat["youngs_modulus_GPa"] * 1e9,
        poisson_ratio=mat["poisson_ratio"],
    )


def right_handed(pair: ParallelPair, relief=None):
    """The pair the closed-form grid models and the modifications on it: the grid
    (:func:`~gearbox.ltca.parallel.parallel_grid`) is built for a pinion of positive
    helix angle; a pinion of negative helix angle is its mirror image in the
    transverse plane (z -> -z), which keeps each gear's sense of rotation and flank
    side. So the mirrored pair has the helix angle |beta|, the shaft-angle error -g
    (the gear axis (0, sin g, cos g) mirrors to the line of (0, -sin g, cos g)) and
    the helix slopes -f_H, the flank twists -S and the topographies turned end for end
    (the face coordinate turns, :meth:`FlankModification.reflected`). Returns (pair, relief, hand):
    hand -1 where the results are to be mirrored back (:func:`_end_for_end` with
    ``y=False``, :func:`mirrored_grids`), else +1 and the inputs as they are."""
    from .modification import as_modification

    mods = None if relief is None else tuple(as_modification(r) for r in relief)
    if pair.helix_angle >= 0:
        return pair, mods, 1
    base = replace(pair, helix_angle=-pair.helix_angle, misalignment=-pair.misalignment)
    if mods is not None:
        mods = tuple(m.reflected() for m in mods)
    return base, mods, -1


def _coast_order(positions: int) -> np.ndarray:
    """Where the coast flank's positions lie among the drive flank's: position j of the
    coast is the drive flank's position -j (the half turn about the centre line
    reverses each gear's rotation), ``(-j) mod P``."""
    return (-np.arange(positions)) % positions


def mirrored_grids(grids: list) -> list:
    """Grids with the faces end for end (the axial flank coordinates' sign changed):
    a left-hand pair's from its right-hand mirror image (:func:`right_handed`). The
    contact and its compliance are the mirror image's."""
    out = []
    for g in grids:
        if g.flank_coordinates is None:
            out.append(g)
            continue
        c = g.flank_coordinates.copy()
        c[:, [1, 3]] *= -1.0
        out.append(replace(g, flank_coordinates=c))
    return out


def coast_grids(grids: list) -> list:
    """A symmetric parallel pair's drive grids at positions ``j / P`` as its coast
    flank's (:func:`_mirror`): the coast flank at position j is the drive contact of
    position -j turned half a turn about the centre line, the pair labels counting the
    other way (``pair -> -pair``, and one less where -j wraps into the cycle before,
    j > 0: a label counts cycles, tooth = cycle - label; ``pair_sense`` -1) and the
    faces end for end (the
    axial flank coordinates change sign). The contact and its compliance are the drive
    grid's: the geometry is left in the drive frame."""
    turned = [grids[j] for j in _coast_order(len(grids))]
    return mirrored_grids(
        [
            replace(g, pair=-g.pair - (1 if jc else 0), pair_sense=-g.pair_sense)
            for jc, g in enumerate(turned)
        ]
    )


def _reversed_in_time(res: CycleResult) -> CycleResult:
    """A result at positions -j with the pair labels counting the other way (the tooth
    pairs' arrays reversed along their pair axes): the time of a contact turned half a
    turn about the centre line, which reverses each gear's rotation."""
    j = _coast_order(res.fraction.size)
    out = {}
    for name in PER_POSITION + (
        "iterations",
        "converged",
        "loss_factor",
        "sliding_speed",
        "friction_arm",
        "mesh_point",
        "line_of_action",
    ):
        v = getattr(res, name)
        if v is not None:
            out[name] = v[:, j]
    out["lte_unloaded"] = res.lte_unloaded[j]
    # pair k of the drive at position -j is the coast's -k, one less where -j wraps
    # into the cycle before (j > 0): the label of a tooth pair counts the cycles
    # (tooth = cycle - label, gearbox.ltca.pitch)
    src = res.pair_index
    labels = np.arange(-int(src.max()) - 1, -int(src.min()) + 1)
    K = labels.size
    pair_axes = {
        "pair_share": (2,),
        "pair_root_stress": (2,),
        "pair_weight": (2,),
        "pair_load_sensitivity": (2, 3),
        "pair_form_weight": (2,),
        "pair_form_load_sensitivity": (2, 3),
    }
    for name, axes in pair_axes.items():
        v = getattr(res, name)
        if v is None:
            continue
        shape = list(v.shape)
        for a in axes:
            shape[a] = K
        w = np.zeros(shape, dtype=v.dtype)
        for jc, jd in enumerate(j):
            at = np.searchsorted(labels, -src - (1 if jc else 0))
            idx = (slice(None), jc) + tuple(
                at if a in axes else slice(None) for a in range(2, 2 + len(axes))
            )
            if len(axes) == 2:
                w[:, jc][np.ix_(np.arange(v.shape[0]), at, at)] = v[:, jd]
            else:
                w[:, jc][:, at] = v[:, jd]
            del idx
        out[name] = w
    out["pair_index"] = labels
    return replace(res, **out)


def _end_for_end(res: CycleResult, *, y: bool) -> CycleResult:
    """A result with the faces turned end for end (z -> -z, and y -> -y as well for a
    half turn about the centre line, ``y=True``; else the mirror image in the
    transverse plane): the points and the normal (rack flank normals n_L of the
    surfaces convention) turn, the face slots and the pattern's face cells reverse,
    the helix slopes' offsets change sign (their crownings', even in the axial
    position, do not), the axial flank coordinates' range mirrors. The faces' range
    is symmetric about the face middle."""
    P = res.mesh_point.copy()
    n = res.line_of_action.copy()
    for v in (P, n):
        v[..., 2] *= -1
        if y:
            v[..., 1] *= -1
    out = dict(
        mesh_point=P,
        line_of_action=n,
        root_stress_face_pinion=res.root_stress_face_pinion[:, ::-1],
        root_stress_face_gear=res.root_stress_face_gear[:, ::-1],
        pattern_pressure=res.pattern_pressure[:, :, ::-1],
    )
    if res.pair_form_weight is not None:
        flip = np.array([-1.0 if b.endswith("_helix") else 1.0 for b in FORM_BASES])
        out["pair_form_weight"] = res.pair_form_weight * flip
        out["pair_form_load_sensitivity"] = res.pair_form_load_sensitivity * flip
    if res.flank_range is not None:
        rng = res.flank_range.copy()
        rng[[1, 3]] = -rng[[1, 3]][:, ::-1]
        out["flank_range"] = rng
    return replace(res, **out)


def _mirror(res: CycleResult) -> CycleResult:
    """The coast flank of a symmetric parallel pair from its drive flank's result: the
    drive contact turned half a turn about the centre line (the x axis through both
    axes: y -> -y, z -> -z), which maps the pair onto itself and its drive flanks onto
    its coast flanks, and reverses each gear's rotation, so the coast at position j is
    the drive at position -j, the pair labels counting the other way
    (:func:`coast_grids`, whose loaded TCA it equals, tested), the faces end for end."""
    return _end_for_end(_reversed_in_time(res), y=True)


def _in_sf(res: CycleResult) -> CycleResult:
    """A closed-form result in the surface path's frame Sf: the grid's frame is Sf
    with y -> -y (a mirror: its drive contact at y < 0), its normals carrying the
    line of action's axial part with the sign of the table (``parallel_grid``), so the
    points go to Sf by y -> -y and the normals by y, z -> -y, -z (the half turn about
    x that the table's earlier frame was). The same pair then reads the same in both
    paths (mesh point and line of action, tested)."""
    P = res.mesh_point.copy()
    n = res.line_of_action.copy()
    P[..., 1] *= -1
    n[..., 1] *= -1
    n[..., 2] *= -1
    return replace(res, mesh_point=P, line_of_action=n)


def _sloped(mods) -> bool:
    """Whether the modifications are not even in the face coordinate (helix slope,
    flank twist, an uneven topography): the coast flank then needs its own run."""
    return mods is not None and not all(m.face_symmetric for m in mods)


def parallel_ltca(
    pair: ParallelPair,
    torques,
    *,
    flanks=("drive", "coast"),
    options: LTCAOptions | None = None,
    fidelity: str = "fast",
    n_face: int = 40,
    scene_name: str = "",
    relief=None,
    face_ends: bool = False,
) -> LTCAResult:
    """Loaded TCA and mesh table of a parallel-axis pair.

    Frame: the surface path's Sf (:class:`gearbox.tca.assembly.Assembly`): pinion axis
    along z through the origin, gear axis through (a, 0, 0), the driving senses +z and
    -z; the grid's own frame is Sf with y -> -y (:func:`_in_sf`). Symmetric tooth
    profiles (the flank modifications ``relief`` = (pinion, gear)
    :class:`~gearbox.ltca.modification.FlankModification` act on both flanks alike): the
    coast flank is the drive flank turned half a turn about the centre line (axial
    position w -> -w), so it is the drive flank's analysis with the modifications
    reflected in w (:meth:`FlankModification.reflected`: a helix slope, a flank twist
    and a topography change) and then turned. ``fidelity`` and
    ``face_ends``: the compliance level, as :func:`compliance_for` takes them.
    """
    from .modification import as_modification, describe_pair, removal_map, topography_notes

    options = options or LTCAOptions()
    compliance = compliance_for(fidelity, face_ends=face_ends)
    base, mods, hand = right_handed(pair, relief)

    def cycle(mods):
        return ltca_cycle(
            lambda f: parallel_grid(base, f, n_face, relief=mods),
            torques,
            options=options,
            compliance=compliance,
        )

    res = {}
    drive = cycle(mods) if "drive" in flanks or not _sloped(mods) else None
    if "drive" in flanks:
        res["drive"] = drive
    if "coast" in flanks:
        if _sloped(mods):
            turned = tuple(m.reflected() for m in mods)
            res["coast"] = _mirror(cycle(turned))
        else:
            res["coast"] = _mirror(drive)
    if hand < 0:  # the right-hand mirror image's results mirrored back
        res = {k: _end_for_end(v, y=False) for k, v in res.items()}
    res = {k: _in_sf(v) for k, v in res.items()}
    a, g = pair.working_center_distance, pair.misalignment
    attrs = {
        "scene": scene_name,
        "method": "loaded TCA, parallel-axis involute pair (plane of action, closed form), "
        f"{describe_compliance(compliance)}",
        "fidelity": fidelity,
        "root_stress": root_stress_method(compliance),
        "gearbox_version": __version__,
        "frame": "Sf of gearbox.tca.assembly: pinion axis z through origin, gear axis "
        "through (a, 0, 0); drive = R flank",
        "flank_modifications": describe_pair(
            None if relief is None else tuple(as_modification(r) for r in relief)
        ),
        "pinion_reference_pitch_radius_m": float(pair.pitch_radius(0)),
        "gear_reference_pitch_radius_m": float(pair.pitch_radius(1)),
    }
    table = mesh_table(
        res,
        pinion_teeth=pair.teeth[0],
        gear_teeth=pair.teeth[1],
        pinion_axis=[[0.0, 0.0, 1.0], [0.0, 0.0, 0.0]],
        # Sf's gear axis (0, sin g, cos g) of the shaft-angle error, driving sense -
        gear_axis=[[0.0, -math.sin(g), -math.cos(g)], [a, 0.0, 0.0]],
        attrs=attrs,
    )
    notes = fast_level_notes(parallel_grid(base, 0.0, n_face)) if fidelity == "fast" else ()
    notes = tuple(notes) + topography_notes(relief)
    maps = {}
    for i, (name, rel) in enumerate(zip(("pinion", "gear"), relief or (None, None), strict=True)):
        mod = as_modification(rel)
        if mod.active:
            b = pair.face_width
            # a parallel pair's flanks are alike: the coast flank's map is the drive's
            maps[f"{name}, drive flank"] = removal_map(
                mod,
                np.linspace(-0.5 * b, 0.5 * b, 21),
                form_radius=pair.form_radius(i),
                tip_radius=pair.tip_radius(i),
                base_radius=pair.base_radius(i),
                reference_radius=pair.pitch_radius(i),
                face_width=b,
            )
    return LTCAResult(flanks=res, table=table, attrs=attrs, notes=notes, modification_maps=maps)


def is_parallel(design) -> bool:
    """Whether a design is a parallel-axis pair (shaft angle and cone angles 0): the
    loaded TCA then takes the closed-form grid (:func:`parallel_ltca`)."""
    return abs(design.shaft_angle) < 1e-12 and all(
        abs(g.cone_angle) < 1e-12 for g in (design.pinion, design.gear)
    )


def scene_ltca(design, scene, *, options: LTCAOptions | None = None) -> LTCAResult:
    """Loaded TCA of a scene's pair: parallel-axis pairs (shaft angle and cone angles
    0) in closed form; crossed beveloid pairs through :func:`beveloid_ltca`."""
    from ..errors import expect_scene

    expect_scene(scene, "scene_ltca: scene")
    lt = scene["ltca"]
    options = options or LTCAOptions(positions=lt["positions"])
    if is_parallel(design):
        from .beveloid import interference_notes, modifications_from_scene

        res = parallel_ltca(
            parallel_pair_from_design(design, scene),
            scene["load"]["torques_Nm"],
            flanks=tuple(lt["flanks"]),
            options=options,
            fidelity=lt["fidelity"],
            n_face=lt["grid_face"],
            scene_name=scene.name,
            relief=modifications_from_scene(design, scene),
            face_ends=lt["face_ends"],
        )
        extra = interference_notes(design, lt["flanks"])
        return replace(res, notes=tuple(res.notes) + extra) if extra else res
    from .beveloid import beveloid_ltca

    return beveloid_ltca(design, scene, options=options)
