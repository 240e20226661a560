"""Compliance levels of the loaded TCA behind one interface.

A compliance level turns a :class:`~gearbox.ltca.grid.ContactGrid` into the
influence-coefficient matrix along the common normal: ``C[i, j]`` is the normal
approach at point i per newton of normal load at point j (m/N), symmetric and
positive definite. The contact solver needs nothing else, so the finite-element
level (``fidelity = "fe"``) plugs in by implementing :class:`Compliance`.

:class:`FastCompliance` is the semi-analytical level:

- each face slice of each tooth is a thin slice of the tooth's normal section (the
  virtual spur tooth, :func:`~gearbox.ltca.slice_model.normal_section`): the tooth as
  a plane-strain finite-element body clamped at the root circle
  (:func:`~gearbox.ltca.slice_fe.fe_tooth_compliance`, the default; or the beam of
  :func:`~gearbox.ltca.slice_model.slice_compliance`: bending, shear, axial
  compression) on Sainsot's fillet foundation;
- neighbouring slices of one tooth are coupled by a shear layer: the slices are the
  springs of a Pasternak foundation (Pasternak, P.L., "On a new method of analysis of
  an elastic foundation by means of two foundation constants", Gosudarstvennoe
  Izdatelstvo Literatury po Stroitelstvu i Arkhitekture, Moscow, 1954), the form used
  for gear teeth by Ajmi, M., Velex, P., "A model for simulating the quasi-static
  and dynamic behaviour of solid wide-faced spur and helical gears", Mech. Mach.
  Theory 40 (2005) 173-190. Its Green's function on a long tooth is the
  exponential influence function ``exp(-|y - y'| / lambda) / (2 lambda)``; a uniform
  line load gives exactly the slice deflection, so the coupling redistributes load
  without changing the stiffness of a uniformly loaded tooth. The decay length
  ``lambda`` is ``coupling_length`` times the whole depth of the tooth (default 0.6,
  :data:`COUPLING_LENGTH`, chosen on the FE level: with the plane-strain tooth and the
  shared far field, 0.5 / 0.6 / 0.75 / 1.0 tooth depths give the face load factor
  K_Hbeta of a misaligned spur pair -4.6 .. -4.1 / -2.4 .. -0.9 / +0.9 .. +4.0 /
  +6.4 .. +11.9 % against the whole-gear FE, the beveloid cases' mean stiffness
  -6.1 .. +9.0 / -2.7 .. +8.9 / +1.2 .. +9.9 / +5.4 .. +11.2 % and their LTE
  peak-to-peak -1.5 .. +8.0 % at 0.6; 0.6 has the smallest largest error);
- the torsion of each gear's body (bore to root circle), a rigid rotation of its rim
  that every tooth in mesh shares: Sainsot's foundation term holds it for a single
  loaded tooth (:func:`~gearbox.ltca.slice_model.body_torsion`), so it is taken out of
  the slices and added once per gear, ``C_ij += rho_i rho_j / K_t`` (rho the arm of the
  normal about the gear's axis, K_t the annulus' torsional stiffness). Counted per
  slice, it was halved wherever two tooth pairs share the load and made the loaded
  TE ripple too large (docs/ltca.md, "LTE peak-to-peak against the FE level");
- the far field of each gear's body, common to all its loaded points: Sainsot's
  foundation is the whole 2-D gear's, and the part of it beyond the loaded tooth and
  its neighbours (``FAR_FIELD``) is taken out of the slices and added once per gear,
  with the body's tilt under the axial load of helical teeth (``BODY_TILT``, growing
  with the gear's root radius over its face width, as measured on the FE level's whole
  gear), which the 2-D foundation does not hold
  (``foundation="split"``, the default; ``"normal"`` keeps it in the slices with the
  body coefficient ``BODY_COMPLIANCE`` calibrated on the FE level, the first version);
- between points on different tooth pairs, in place of the rim torsion and that far
  field shared evenly, the plane-strain whole gear's couplings by the teeth's distance
  (one to three pitches) and the points' load heights, times ``PAIR_COUPLING_SCALE``
  (``between_pairs="plane"``, the default with the split foundation;
  :func:`~gearbox.ltca.slice_fe.neighbour_influence`): the FE level's whole gear
  shares between neighbouring pairs more the larger the gear (less the rim torsion,
  0.83 / 1.07 / 1.34 / 1.48 over ``1 / E`` for z 20 / 29 / 40 / 45 at beta 0), which
  one constant far field does not hold (docs/ltca.md, "The drive flanks against the
  coast flanks");
- the local contact flattening of each slice is Weber's line-load approach (diagonal,
  load dependent) down to a reference depth in each tooth: the tooth's centre line
  (``contact="centre_line"``, Weber & Banaschek's own choice and the default) or the
  FE level's matching depth (``contact="matching_depth"``), the split of
  :mod:`gearbox.fe.compliance`, whose half-space part above that depth is the same
  quantity in three dimensions (docs/ltca.md, "The contact term"); with the
  plane-strain tooth read at the same depth this is the FE level's split throughout
  (docs/ltca.md, "The FE level's split in the slices": against the FE level the load
  along the contact lines and the LTE ripple come nearer, the mean stiffness of the
  paper's cases +1.2 .. +8.9 % against the default's -2.7 .. +8.9 %);
- optionally (``helix_ends``, off by default) the helical tooth's face ends: each
  slice's compliance times a factor of its distances to the acute and the obtuse face
  end (:data:`HELIX_ENDS`, fitted on the FE level's tooth), which the slices of the
  normal section do not hold (docs/ltca.md, "The face ends in the compliance").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from ..errors import InputError, Problem, Problems
from .grid import ContactGrid
from .slice_model import (
    body_torsion,
    foundation_compliance,
    normal_section,
    slice_compliance,
    weber_approach,
)
from .stress import HelixEnds, acute_end, end_distances, load_height

__all__ = [
    "BODY_COMPLIANCE",
    "BODY_COMPLIANCE_MATCHING_DEPTH",
    "BODY_TILT",
    "CALIBRATED_BEAM",
    "CONTACT_DEPTH",
    "COUPLING_LENGTH",
    "FAR_FIELD",
    "HELIX_ENDS",
    "PAIR_COUPLING_SCALE",
    "Compliance",
    "FastCompliance",
    "compliance_for",
    "describe_compliance",
]

#: Body compliance of :class:`FastCompliance` over 1/(E b), fitted on the FE level
#: (docs/fe.md, "Calibration of the fast level"): the minimax fit of the mean mesh
#: stiffness of the paper's cases 01-04, both flanks, 150/300/450 N m, against the FE
#: level at its default mesh with the segment-extent correction. With the body torsion
#: shared (``shared_torsion``, the default) the fit is 0.30 (errors -4.2 .. +4.2 %,
#: ``benchmarks/ltca_ripple.py --coupling-length 1.0 --root radial --beam-at load_point
#: --tooth beam --foundation normal --fit-body``); 0.24 (-4.3 .. +4.3 %) before the
#: loaded TCA took the touching gear phase (2026-12, docs/ltca.md "Method"), which
#: raised the coast flanks' stiffness at both levels; with the torsion in the slices it
#: was 0.41 (-4.7 .. +4.6 %) before that.
BODY_COMPLIANCE = 0.30

#: The same fit with the contact term down to the matching depth
#: (``FastCompliance(contact="matching_depth")``, ``--contact matching_depth``):
#: errors -5.1 .. +5.2 % (0.91 and -4.2 .. +4.2 % before the touching gear phase).
BODY_COMPLIANCE_MATCHING_DEPTH = 0.99

#: Reference depth of the contact term for ``contact="matching_depth"``, over m_n: the
#: FE level's default matching depth (``gearbox.fe.FEOptions().matching_depth``, tested
#: equal), below which that level reads the tooth from its mesh.
CONTACT_DEPTH = 0.25


#: The far field of a gear's body over ``1 / E`` per unit face width
#: (``FastCompliance(foundation="split")``): what the FE level's whole gear adds to its
#: three-tooth segment under a line load along the face, less the body torsion, at
#: beta = 0: 0.92 .. 1.10 (case 03's pinion as a spur gear) and 0.99 .. 1.17 (spur
#: z 30, m 4), lowest to highest load (``benchmarks/ltca_slice_vs_fe.py``, stored in
#: ``tests/data/fe_slice_line_load*.json``; tested).
FAR_FIELD = 1.0

#: The tilt of a gear's body under the axial component of its tooth loads, shared by
#: all its loaded points: ``BODY_TILT sin(beta_b)^2 (r_f / b)^2`` over ``E`` per unit
#: face width, added to :data:`FAR_FIELD` (beta_b the angle between the flank normal
#: and the gear's transverse plane, r_f the root radius, b the face width along the
#: gear's axis). The axial load ``F sin(beta_b)`` at the arm r_f tilts the body, a plate
#: of thickness b, by ``F sin(beta_b) r_f / (E b^3 / BODY_TILT)``, which moves every
#: loaded point by ``r_f sin(beta_b)`` times that along its normal. Fitted on the FE
#: level's whole gear (``benchmarks/fe_independent.py --pair-couplings``): the growth of
#: what it shares between tooth pairs from beta 0 to 15 / 30 deg on z 20 / 40, m_n 4,
#: b 30 mm (the segment, its far field, less the rim torsion), and of case 03's pinion's
#: far field less the torsion at 10 / 20 / 30 deg; at 30 deg the pinion z 20 grows by
#: 0.37 / E (r_f / b 1.4), the gear z 40 by 1.41 / E (r_f / b 2.9), the law 0.31 / 1.39
#: (tested). Before it the growth was ``cos(beta)^-4.5`` for every gear, fitted on case
#: 03's pinion alone: 2.5 times the FE's on the pinion z 20 at 30 deg, 0.65 times on
#: the gear z 40.
BODY_TILT = 0.74

#: Between different tooth pairs (``FastCompliance(between_pairs="plane")``, the
#: default), the plane-strain whole gear's couplings by distance and load height
#: (:func:`~gearbox.ltca.slice_fe.neighbour_influence`) times this factor: the FE
#: level's whole gear over the plane-strain one at one pitch, mean over three load
#: heights at beta = 0, is 1.06 / 1.13 on z 20 / 40 (m_n 4, b 30 mm) and 1.07 / 1.16 on
#: the paper's z 29 / 45 (m_n 6, b 40 mm) (``tests/data/fe_pair_couplings*.json``,
#: ``benchmarks/fe_independent.py --pair-couplings``); their mean, 1.1. The plate of
#: finite width is softer than the plane-strain disc by about that much.
PAIR_COUPLING_SCALE = 1.1

#: The helical tooth's face ends in the fast compliance (``FastCompliance(helix_ends=
#: HELIX_ENDS)``; off by default): a factor on each slice's compliance before the
#: coupling along the face, by its distances to the acute and the obtuse face end, its
#: load height, the helix angle and the face width
#: (:class:`~gearbox.ltca.stress.HelixEnds`, the harmonic mean across each slot). Fitted
#: on the FE level's one-tooth blocks under loads even along a line of constant radius
#: (z 20/40, m_n 4, helix 10 / 20 / 30 deg over the spur tooth, b 12 / 24 / 40 mm, 1 mm
#: slices, both gears, three heights: ``python3 benchmarks/fe_independent.py
#: --fit-face-ends``): rms 0.037 in ln of the deflection along the face, the mean within
#: -3.9 .. +4.8 %. What it does and why it is off: docs/ltca.md, "The face ends in the
#: compliance".
HELIX_ENDS = HelixEnds(
    height=(0.34, 0.61, 0.88),
    acute=(2.958, 2.549, 2.218),
    acute_decay=(0.335, 0.378, 0.345),
    obtuse=(0.875, 0.687, 0.655),
    obtuse_decay=(0.208, 0.309, 0.254),
    middle=(-0.028, -0.03, -0.043),
    narrow=(0.559, 0.521, 0.474),
    quadratic=2.375,
    key="ltca.helix_ends",
)

#: Default decay length of the slices' coupling along the face, over the tooth's whole
#: depth (module docstring: chosen on the FE level).
COUPLING_LENGTH = 0.6

_CALIBRATED = {"centre_line": BODY_COMPLIANCE, "matching_depth": BODY_COMPLIANCE_MATCHING_DEPTH}


@runtime_checkable
class Compliance(Protocol):
    """Interface of a compliance level.

    ``matrix(grid, line_load)`` returns the influence matrix, shape (n, n), m/N,
    along the common normal at the grid points. ``line_load`` (N/m of contact line,
    shape (n,)) is the current load estimate; levels whose matrix depends on the
    load (``load_dependent = True``, e.g. contact flattening) use it, the solver
    iterates them to a fixed point. A load-dependent level splits its matrix into
    ``tooth_matrix(grid)`` (load independent, shape (n, n), computed once per
    position) and ``contact_diagonal(grid, line_load)`` (shape (n,), m/N, the local
    flattening), so that ``matrix = tooth_matrix + diag(contact_diagonal)``.
    """

    name: str
    load_dependent: bool

    def matrix(self, grid: ContactGrid, line_load: np.ndarray | None = None) -> np.ndarray: ...

    def tooth_matrix(self, grid: ContactGrid) -> np.ndarray: ...

    def contact_diagonal(self, grid: ContactGrid, line_load: np.ndarray) -> np.ndarray: ...


def _pasternak_block(c_slot, width, lam):
    """Compliance matrix of one tooth's slices coupled by a shear layer.

    c_slot: normal compliance per unit face width of every slot (m per N/m), shape
    (m,); width: slot width (m); lam: decay length (m). Free ends (no shear at the
    face ends). Returns shape (m, m), m/N.
    """
    k = width / c_slot  # spring of each slice (N/m)
    kw = 1.0 / np.mean(c_slot)  # foundation modulus per unit width (N/m^2)
    g = lam**2 * kw  # shear-layer stiffness (N)
    m = c_slot.size
    K = np.diag(k)
    if m > 1:
        kc = g / width
        i = np.arange(m - 1)
        K[i, i] += kc
        K[i + 1, i + 1] += kc
        K[i, i + 1] -= kc
        K[i + 1, i] -= kc
    return np.linalg.inv(K)


@dataclass(frozen=True)
class FastCompliance:
    """Semi-analytical compliance: thin slices, shear-layer coupling, Weber contact.

    coupling_length: slice-coupling decay length over the tooth's whole depth (-);
    0 turns the coupling off (independent slices). section: where the slices are cut,
    ``"normal"`` (the virtual spur tooth of the normal section per unit tooth length,
    as ISO 6336-1 takes a helical tooth; :func:`~gearbox.ltca.slice_model.normal_section`)
    or ``"transverse"`` (the transverse section per unit face width with the load's
    transverse component, the first version). body_compliance: compliance of each
    gear's body common to all its loaded points, over ``1 / (E b)`` (b the face width
    along that gear's axis): a rank-one term ``body_compliance / (E b)`` added to every
    entry of each gear's block (all tooth pairs), the far-field deflection of the rim
    that a two-dimensional slice foundation does not hold. shared_torsion: the body
    torsion held in Sainsot's foundation term is a rotation of the whole rim, one per
    gear (True), or each slice's own (False, the first version). contact: the
    reference depth of Weber's contact flattening in each tooth, ``"centre_line"`` (the
    distance of the contact from the tooth's centre line, Weber & Banaschek) or
    ``"matching_depth"`` (``contact_depth`` times m_n below the flank, the FE level's
    split: :func:`~gearbox.ltca.slice_model.weber_approach`; with ``tooth="fe"`` the
    plane-strain tooth is then read at that depth too, so the compression between it
    and the centre line sits in the coupled slice, as in the FE level's teeth); ``None`` for
    body_compliance takes the value calibrated for that contact term
    (:data:`BODY_COMPLIANCE`, :data:`BODY_COMPLIANCE_MATCHING_DEPTH`). root: the
    tooth below its involute, ``"radial"`` (a radial flank from the base to the root
    circle, and Sainsot's root thickness from it: the first version) or ``"fillet"``
    (the generated fillet, in the beam and in Sainsot's root thickness:
    :func:`~gearbox.ltca.slice_model.slice_compliance`). beam_at: where the tooth's
    beam deflection is taken, ``"load_point"`` (the first version) or
    ``"centre_line"`` (where the load's line crosses the tooth's centre line, down to
    which Weber's contact term runs: ``slice_compliance(beam_at=...)``). tooth: the
    tooth above the root circle, ``"beam"`` (bending, shear and axial compression of
    :func:`~gearbox.ltca.slice_model.slice_compliance`, read at ``beam_at``) or
    ``"fe"`` (the slice's tooth as a plane-strain finite-element body clamped at the
    root circle, read at the centre line:
    :func:`~gearbox.ltca.slice_fe.fe_tooth_compliance`; Sainsot's foundation as with
    the beam). The FE tooth holds the generated fillet and is read at the centre line
    whatever ``root`` and ``beam_at`` say; ``root`` still picks Sainsot's root thickness,
    so ``tooth="fe"`` goes with ``root="fillet"`` (measured so: docs/ltca.md).
    foundation: where Sainsot's foundation term (the whole 2-D gear under one tooth's
    load) is kept: ``"normal"`` all in each slice (the first version), or ``"split"``
    (the default): the body's far field, :data:`FAR_FIELD` over ``E`` per unit face
    width, taken out of every slice, and the body's tilt under the axial load
    (:data:`BODY_TILT`), shared by every loaded point of the gear (``(FAR_FIELD + tilt)
    / (E b)`` in every entry of its block, as the FE level's rank-one far field), so a
    tooth pair's own compliance holds only what the FE level's three-tooth segment
    holds; ``body_compliance`` is then what is added to it (default 0: nothing
    fitted). helix_ends: a factor on each slice's compliance by its distances to the
    helical tooth's acute and obtuse face ends (:data:`HELIX_ENDS`, the FE level's
    softer acute end and stiffer obtuse end; the acute end from the grid's contact
    lines, :func:`~gearbox.ltca.stress.acute_end`), or None (the default: the slices'
    compliance is even along the face). between_pairs: between points on different
    tooth pairs, ``"even"`` (the rim torsion and the far field shared by every loaded
    point alike, the tilt too) or ``"plane"`` (the plane-strain whole gear's couplings
    by distance and load height times ``pair_coupling_scale`` in place of the torsion
    and the far field, the tilt kept: :meth:`pair_matrix`); None takes ``"plane"`` with
    the split foundation, ``"even"`` with the normal one. Within a tooth pair both
    are the same.

    The default (the plane-strain tooth, the fillet root, the split foundation, the
    plane couplings between pairs, the coupling length :data:`COUPLING_LENGTH`, no
    body term) against the FE level (``python benchmarks/ltca_ripple.py --parallel``,
    docs/ltca.md): LTE peak-to-peak of the paper's cases within -4.4 .. +4.1 %, mean
    stiffness of spur pairs -2.2 / -2.4 %, of a 15 degree helical pair +0.2 % and of
    the beveloid cases -4.5 .. +4.8 % (with ``between_pairs="even"``: -1.2 / -0.2 %,
    +2.8 % and -3.4 .. +7.1 %); :data:`CALIBRATED_BEAM` +10.2 .. +31.6 %, -22.7 /
    -18.6 %, -9.3 % and -4.2 .. +4.2 % (fitted there). Measured with the touching gear
    phase (2026-12) against the FE level's runs remade with it.
    """

    coupling_length: float = COUPLING_LENGTH
    body_compliance: float | None = None
    section: str = "normal"
    shared_torsion: bool = True
    contact: str = "centre_line"
    contact_depth: float = CONTACT_DEPTH
    root: str = "fillet"
    beam_at: str = "centre_line"
    tooth: str = "fe"
    foundation: str = "split"
    helix_ends: HelixEnds | None = None
    between_pairs: str | None = None
    pair_coupling_scale: float = PAIR_COUPLING_SCALE
    name: str = "fast"
    load_dependent: bool = True

    def __post_init__(self):
        p = Problems()
        p.in_range("coupling_length", self.coupling_length, 0.0, 20.0)
        if self.body_compliance is not None:
            p.in_range("body_compliance", self.body_compliance, 0.0, 100.0)
        p.check(
            self.section in ("normal", "transverse"),
            "section",
            self.section,
            "must be 'normal' or 'transverse'",
        )
        p.check(
            self.contact in _CALIBRATED,
            "contact",
            self.contact,
            "must be 'centre_line' or 'matching_depth'",
        )
        p.in_range("contact_depth", self.contact_depth, 0.05, 0.6)
        p.check(
            self.root in ("radial", "fillet"), "root", self.root, "must be 'radial' or 'fillet'"
        )
        p.check(
            self.beam_at in ("load_point", "centre_line"),
            "beam_at",
            self.beam_at,
            "must be 'load_point' or 'centre_line'",
        )
        p.check(self.tooth in ("beam", "fe"), "tooth", self.tooth, "must be 'beam' or 'fe'")
        p.check(
            self.foundation in ("normal", "split"),
            "foundation",
            self.foundation,
            "must be 'normal' or 'split'",
        )
        p.check(
            self.between_pairs in (None, "even", "plane"),
            "between_pairs",
            self.between_pairs,
            "must be 'even' or 'plane'",
        )
        p.check(
            self.between_pairs != "plane" or self.foundation == "split",
            "between_pairs",
            self.between_pairs,
            "'plane' replaces the shared far field: it needs foundation='split'",
        )
        p.in_range("pair_coupling_scale", self.pair_coupling_scale, 0.5, 2.0)
        p.raise_if_any("invalid fast compliance")
        if self.body_compliance is None:
            body = 0.0 if self.foundation == "split" else _CALIBRATED[self.contact]
            object.__setattr__(self, "body_compliance", body)
        if self.between_pairs is None:
            between = "plane" if self.foundation == "split" else "even"
            object.__setattr__(self, "between_pairs", between)

    def describe(self) -> str:
        """One line naming the model's choices, for provenance (table attributes, the
        report)."""
        read = "centre line" if self.contact == "centre_line" else "matching depth"
        tooth = {
            "fe": f"plane-strain FE tooth read at the {read}",
            "beam": f"slice beam read at the {self.beam_at.replace('_', ' ')}",
        }[self.tooth]
        shared = "far field shared" if self.foundation == "split" else "foundation in the slices"
        body = f", body term {self.body_compliance:g}" if self.body_compliance else ""
        ends = ", helical face ends" if self.helix_ends is not None else ""
        pairs = (
            f", pairs coupled by the plane-strain whole gear x {self.pair_coupling_scale:g}"
            if self.between_pairs == "plane"
            else ""
        )
        return (
            f"thin {self.section} slices: {tooth}, {self.root} root, Sainsot foundation "
            f"({shared}{body}{pairs}), coupled over {self.coupling_length:g} tooth depths"
            f"{ends}, Weber contact to the {self.contact.replace('_', ' ')}"
        )

    def slice_parts(self, grid: ContactGrid):
        """Normal compliance per unit face width of pinion and gear slices (m per N/m):
        the tooth above the root circle and Sainsot's foundation less what the gear
        shares (the body torsion and, for ``foundation="split"``, the far field)."""
        E, nu = grid.youngs_modulus, grid.poisson_ratio
        G = E / (2.0 * (1.0 + nu))
        out = []
        for teeth, proj in (
            (grid.tooth1, grid.transverse_projection),
            (grid.tooth2, grid.transverse_projection2),
        ):
            # the section the slice is cut in, and its factor to the flank normal
            section, factor = (
                normal_section(teeth) if self.section == "normal" else (teeth, proj**2)
            )
            normal = self.section == "normal"
            if self.tooth == "fe":  # the beam's integrals are not needed
                from .slice_fe import fe_tooth_compliance

                depth = self.contact_depth if self.contact == "matching_depth" else None
                c = fe_tooth_compliance(
                    section, E, nu, normal=normal, depth=depth
                ) + foundation_compliance(section, E, root=self.root, normal=normal)
            else:
                c = slice_compliance(
                    section, E, nu, root=self.root, normal=normal, beam_at=self.beam_at
                ).total
            if self.shared_torsion:
                c = c - body_torsion(section, G)
            if self.foundation == "split":
                c = c - FAR_FIELD / (E * factor)
                if np.any(c <= 0.0):  # a far field larger than the slice's own foundation
                    raise InputError(
                        Problem(
                            "ltca.fidelity",
                            "fast",
                            "the body's far field exceeds a slice's foundation for these "
                            "teeth: a tooth thin at its root or a large gear on a narrow "
                            "face (the design's topping checks; docs/ltca.md, Limits); "
                            "in Python, FastCompliance(foundation='normal') keeps the far "
                            "field in the slices",
                        )
                    )
            out.append(c * factor)
        return tuple(out)

    def torsion_matrix(self, grid: ContactGrid, gear: int | None = None) -> np.ndarray:
        """The bodies' torsion, shared by all loaded points of each gear (m/N), shape
        (n, n): ``rho_i rho_j (1/r_i^2 - 1/r_f^2) / (4 pi G b)`` per gear, rho the base
        radius times the cosine between the normal and the gear's transverse plane
        (the arm of the normal about the gear's axis), r_i, r_f the mean bore and
        root radii and b the face width along that gear's axis; zero when
        ``shared_torsion`` is off. gear: 0 or 1 for the pinion's or the gear's term
        alone, None for both."""
        n = grid.size
        C = np.zeros((n, n))
        if not self.shared_torsion:
            return C
        G = grid.youngs_modulus / (2.0 * (1.0 + grid.poisson_ratio))
        both = (
            (grid.tooth1, grid.transverse_projection, grid.width),
            (grid.tooth2, grid.transverse_projection2, grid.width2),
        )
        for teeth, proj, widths in both if gear is None else both[gear : gear + 1]:
            rho = teeth.base_radius * proj
            ri, rf = float(np.mean(teeth.bore_radius)), float(np.mean(teeth.root_radius))
            face = float(grid.n_slots * np.mean(widths))
            C += np.outer(rho, rho) * (1.0 / ri**2 - 1.0 / rf**2) / (4.0 * np.pi * G * face)
        return C

    def slice_matrix(
        self, grid: ContactGrid, gear: int, parts=None, acute: float | None = None
    ) -> np.ndarray:
        """The slices of one gear (0 pinion, 1 gear), coupled along each tooth (m/N),
        shape (n, n): block diagonal over the tooth pairs. parts: ``slice_parts(grid)``
        if already computed; acute: the face direction (+1 / -1) of the gear's acute
        face end, by default :func:`~gearbox.ltca.stress.acute_end` of the grid's
        contact lines (0: no helical face-end factor)."""
        n = grid.size
        C = np.zeros((n, n))
        c = (self.slice_parts(grid) if parts is None else parts)[gear]
        teeth, widths = (grid.tooth1, grid.width) if gear == 0 else (grid.tooth2, grid.width2)
        depth = teeth.tip_radius - teeth.root_radius
        ends = self._end_factor(grid, teeth, acute)
        for k in grid.pairs():
            idx = np.flatnonzero(grid.pair == k)
            idx = idx[np.argsort(grid.slot[idx])]
            slots = grid.slot[idx]
            width = float(np.mean(widths[idx]))
            if self.coupling_length == 0.0 or idx.size == 1:
                C[idx, idx] += c[idx] * ends(idx, slots) / widths[idx]
                continue
            # every slot of the face: occupied ones carry their own slice, the
            # others (no contact line there) the nearest occupied slice's
            all_slots = np.arange(grid.n_slots)
            nearest = np.clip(np.searchsorted(slots, all_slots), 0, slots.size - 1)
            left = np.clip(nearest - 1, 0, slots.size - 1)
            use_left = np.abs(slots[left] - all_slots) < np.abs(slots[nearest] - all_slots)
            nearest = np.where(use_left, left, nearest)
            c_slot = c[idx][nearest] * ends(idx[nearest], all_slots)
            lam = self.coupling_length * float(np.mean(depth[idx]))
            block = _pasternak_block(c_slot, width, lam)
            C[np.ix_(idx, idx)] += block[np.ix_(slots, slots)]
        return C

    def _end_factor(self, grid: ContactGrid, teeth, acute: float | None):
        """``f(points, slots)``: the :attr:`helix_ends` factor on the compliance of the
        given face slots, each with the helix angle and load height of the given grid
        point (its own, or the nearest loaded one's), shape of ``slots``; ones without
        the factor or where the contact lines show no acute end."""

        def ones(points, slots):
            return np.ones(np.shape(slots))

        if self.helix_ends is None:
            return ones
        sign = acute_end(grid, teeth) if acute is None else float(np.sign(acute))
        if sign == 0.0:
            return ones
        a, b = grid.face_range
        w = (b - a) / grid.n_slots
        eta, t, mn = load_height(teeth), np.tan(teeth.helix_angle), teeth.normal_module

        def f(points, slots):
            centre = a + (np.asarray(slots) + 0.5) * w
            m = mn[points]
            u_a, u_o = end_distances(grid, teeth, sign, centre, m)
            return self.helix_ends.slot_factor(t[points], eta[points], u_a, u_o, w / m, (b - a) / m)

        return f

    def body_matrix(self, grid: ContactGrid) -> np.ndarray:
        """The terms every loaded point of a gear shares, in every entry (m/N), shape
        (n, n): ``body_compliance / (E b)`` per gear and, for ``foundation="split"``, the
        far field and the body's tilt ``(FAR_FIELD + body_tilt) / (E b)`` (b the face
        width along that gear's axis: :func:`body_tilt`)."""
        c = 0.0
        for gear in (0, 1):
            k, face = self.body_compliance, _face(grid, gear)
            if self.foundation == "split":
                k = k + FAR_FIELD + body_tilt(grid, gear)
            c += k / face
        return np.full((grid.size, grid.size), c / grid.youngs_modulus)

    def pair_matrix(self, grid: ContactGrid, gear: int) -> np.ndarray:
        """The plane-strain whole gear's couplings between the points of gear ``gear``
        on different tooth pairs (m/N), shape (n, n), zero within a pair:
        :func:`~gearbox.ltca.slice_fe.neighbour_influence` of the normal section at the
        face middle, read at each point's roll fraction (linear between its radii),
        the entry of two points ``k`` pitches apart (beyond 3: 3) the displacement of
        the one on the tooth in front of the loaded flank under a load on the other
        (symmetric, Maxwell-Betti), over the face width along the gear's axis. The
        tooth in front carries its contact at the larger radius of that gear: the
        line of action leads away from the gear's base circle in the direction its
        flank's normal points."""
        from .slice_fe import NEIGHBOUR_ROLL, neighbour_influence

        n = grid.size
        out = np.zeros((n, n))
        d = grid.pair[:, None] - grid.pair[None, :]
        if not d.any():
            return out
        teeth = grid.tooth1 if gear == 0 else grid.tooth2
        a, b = grid.face_range
        mid = int(np.argmin(np.abs(grid.face - 0.5 * (a + b))))
        section, factor = normal_section(teeth.take(np.array([mid])))
        _, c = neighbour_influence(section, grid.poisson_ratio)
        rb, rf, ra = teeth.base_radius, teeth.root_radius, teeth.tip_radius
        x0 = np.sqrt(np.maximum(rf**2 - rb**2, 0.0))
        roll = (np.sqrt(np.maximum(teeth.radius**2 - rb**2, 0.0)) - x0) / (
            np.sqrt(ra**2 - rb**2) - x0
        )
        x = np.interp(roll, NEIGHBOUR_ROLL, np.arange(len(NEIGHBOUR_ROLL)))
        i0 = np.minimum(np.floor(x).astype(int), len(NEIGHBOUR_ROLL) - 2)
        W = np.zeros((n, len(NEIGHBOUR_ROLL)))
        W[np.arange(n), i0] = 1.0 - (x - i0)
        W[np.arange(n), i0 + 1] = x - i0
        # the direction of the pair index in which the teeth in front lie
        order = np.lexsort((grid.pair, grid.slot))
        same = (np.diff(grid.slot[order]) == 0) & (np.diff(grid.pair[order]) == 1)
        step = np.diff(teeth.radius[order])[same]
        if step.size:
            ahead = 1 if np.sum(np.sign(step)) >= 0 else -1
        else:  # no slot holds two neighbouring pairs: the trend of the radius with the pair
            lean = np.sum((grid.pair - grid.pair.mean()) * (teeth.radius - teeth.radius.mean()))
            ahead = 1 if lean >= 0 else -1
        d = np.clip(ahead * d, -c.shape[0], c.shape[0])
        for k in range(1, c.shape[0] + 1):
            B = W @ c[k - 1] @ W.T  # [front, back]
            out = np.where(d == k, B, out)
            out = np.where(d == -k, B.T, out)
        scale = float(np.mean(factor)) / (grid.youngs_modulus * _face(grid, gear))
        return out * scale

    def tooth_matrix(self, grid: ContactGrid) -> np.ndarray:
        parts = self.slice_parts(grid)
        C = self.slice_matrix(grid, 0, parts) + self.slice_matrix(grid, 1, parts)
        C += self.body_matrix(grid)
        other = grid.pair[:, None] != grid.pair[None, :]
        for gear in (0, 1):
            torsion = self.torsion_matrix(grid, gear)
            if self.between_pairs == "plane" and other.any():
                # between pairs: the plane couplings in place of the torsion and far field
                even = torsion + FAR_FIELD / (grid.youngs_modulus * _face(grid, gear))
                plane = self.pair_coupling_scale * self.pair_matrix(grid, gear)
                torsion = torsion + np.where(other, plane - even, 0.0)
            C += torsion
        return C

    def contact_diagonal(self, grid: ContactGrid, line_load: np.ndarray) -> np.ndarray:
        """Secant compliance of the local flattening, shape (n,), m/N: Weber's approach
        of the two flanks relative to the reference depth of ``contact`` in each tooth."""
        E, nu = grid.youngs_modulus, grid.poisson_ratio
        h1, h2 = self.contact_reference(grid)
        q = np.maximum(line_load, 1e-6)
        w = weber_approach(q, grid.curvature_radius, h1, h2, E, nu)
        return w / (q * grid.line_length)

    def contact_reference(self, grid: ContactGrid):
        """Depth of the contact flattening's reference point below each flank (m),
        pinion and gear, shape (n,) each: the distance of the contact point from the
        tooth's centre line in its transverse section (``"centre_line"``), or
        ``contact_depth`` m_n, at most that distance (``"matching_depth"``)."""
        h = (_half_thickness(grid.tooth1), _half_thickness(grid.tooth2))
        if self.contact == "centre_line":
            return h
        return tuple(
            np.minimum(self.contact_depth * t.normal_module, hi)
            for t, hi in zip((grid.tooth1, grid.tooth2), h, strict=True)
        )

    def matrix(self, grid: ContactGrid, line_load: np.ndarray | None = None) -> np.ndarray:
        C = self.tooth_matrix(grid)
        if line_load is None:
            line_load = np.full(grid.size, 1.0e5)
        C[np.diag_indices_from(C)] += self.contact_diagonal(grid, line_load)
        return C


#: The fast level's default until the plane-strain tooth and the shared far field: the
#: slice beam read at the load point on the radial root, Sainsot's whole foundation in
#: every slice, slices coupled over one tooth depth and the body coefficient
#: :data:`BODY_COMPLIANCE` fitted on the FE level (docs/ltca.md keeps its measurements
#: beside the default's).
CALIBRATED_BEAM = FastCompliance(
    coupling_length=1.0, root="radial", beam_at="load_point", tooth="beam", foundation="normal"
)


def _face(grid: ContactGrid, gear: int) -> float:
    """Face width along gear ``gear``'s axis (m)."""
    return float(grid.n_slots * np.mean(grid.width if gear == 0 else grid.width2))


def body_tilt(grid: ContactGrid, gear: int) -> float:
    """The body's tilt shared by gear ``gear``'s loaded points, over ``1 / E`` per unit
    face width: ``BODY_TILT sin(beta_b)^2 (r_f / b)^2`` (:data:`BODY_TILT`), with the
    grid's mean angle between the normal and the gear's transverse plane, the mean root
    radius and the face width along the gear's axis; 0 for spur teeth."""
    teeth, proj = (
        (grid.tooth1, grid.transverse_projection)
        if gear == 0
        else (grid.tooth2, grid.transverse_projection2)
    )
    sin2 = max(1.0 - float(np.mean(proj)) ** 2, 0.0)
    return BODY_TILT * sin2 * (float(np.mean(teeth.root_radius)) / _face(grid, gear)) ** 2


def _half_thickness(teeth) -> np.ndarray:
    """Distance of the load point from the tooth centre line (m), transverse section."""
    from ..geometry.involute import inv

    alpha = np.arccos(np.clip(teeth.base_radius / teeth.radius, -1, 1))
    psi = teeth.base_half_angle - inv(alpha)
    return np.maximum(teeth.radius * np.sin(psi), 1e-6)


def describe_compliance(compliance) -> str:
    """A compliance level in words: its ``describe()`` where it has one, else its name."""
    describe = getattr(compliance, "describe", None)
    return describe() if callable(describe) else f"{compliance.name} compliance"


def compliance_for(fidelity: str, *, blanks=None, face_ends: bool = False) -> Compliance:
    """The compliance level named by ``ltca.fidelity``: ``fast`` (:class:`FastCompliance`,
    with ``face_ends`` (``ltca.face_ends``) the helical face ends, :data:`HELIX_ENDS`)
    or ``fe`` (``gearbox.fe.compliance.FECompliance``, where installed; ``face_ends``
    does not apply: its mesh holds the face ends). ``blanks``: ``(pinion, gear)``
    generating data of a beveloid pair, which the FE level needs to place beveloid
    grids on its teeth (parallel-axis grids carry what it needs)."""
    if fidelity == "fast":
        return FastCompliance(helix_ends=HELIX_ENDS if face_ends else None)
    p = Problems()
    if fidelity == "fe":
        try:
            from ..fe.compliance import FECompliance
        except ImportError as exc:
            p.add("ltca.fidelity", fidelity, f"the finite-element level is not available ({exc})")
        else:
            return FECompliance(blanks=blanks)
    else:
        p.add("ltca.fidelity", fidelity, "must be 'fast' or 'fe'")
    p.raise_if_any("invalid loaded TCA fidelity")
    raise AssertionError  # pragma: no cover
