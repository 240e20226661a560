"""Finite-element compliance level of the loaded TCA (``fidelity = "fe"``).

Influence coefficients of each gear from a 3-D linear-elastic model of a few teeth and
the rim (:mod:`gearbox.fe.mesh`, :mod:`gearbox.fe.model`), joined to the elastic
half-space near the load by a matching depth, the combined surface-integral / finite
element approach of Vijayakar, S.M., "A combined surface integral and finite element
solution for a three-dimensional contact problem", Int. J. Numer. Meth. Engng 31
(1991) 525-545:

``c_ij = m_i . u_FE(x_i - d n_i | load j) + [w_B(x_i | j) - w_B(x_i - d n_i | j)]``

for each gear: the finite-element model gives the displacement of the point at
depth d below the contact point i (where a mesh of a few elements across the tooth
is accurate), the half-space gives the displacement of the surface point relative to
that depth point. ``m_i = -n_i`` is the inward normal, ``w_B`` the Boussinesq normal
displacement (:mod:`gearbox.fe.boussinesq`) in the tangent plane of the load j.
The FE's own local part near the load (the mesh-dependent flattening under a
concentrated load) never enters: the FE is read only at depth d, and the part of
the half-space solution down to depth d replaces it. The correction is applied
between points of the same tooth pair; points of other teeth lie a base pitch away,
many times d, where it decays as d^2 / r^3, and it is left out there.

- the depth term is load-independent; the surface self-term depends on the Hertz
  half-width across the contact line (the cell is the contact-line length of the
  slice times the Hertz width 2a, uniform pressure), so the level is load dependent
  and its diagonal is re-evaluated by the contact solver's fixed-point iteration
  (:meth:`FECompliance.contact_diagonal`);
- one factorisation per gear; unit loads on a lattice of the loaded flank (spacing
  ``lattice_spacing`` m_n in face and profile), solved once, and interpolated
  bilinearly onto every contact grid: a mesh cycle costs one factorisation and a
  lattice of solves per gear and flank.

Load and response: a unit force along the inward normal spread uniformly over a
square patch of side ``lattice_spacing m_n`` on the flank (3 x 3 Gauss points,
consistent nodal loads); the response is the inward-normal displacement at depth d.

Far field (``FEOptions(far_field="extrapolated")``, the default): the segment (loaded
teeth plus ``neighbours`` each side, cut faces clamped) is stiffer than the whole gear,
whose rim and body carry a tooth load far round the gear. Per gear and flank, coarse
segments of growing extent (``far_field_mesh``; clamped cut faces with ``neighbours``
.. 5 neighbours, free ones with 3 .. 5) take unit loads at a 3 x 3 sub-lattice of every
loadable tooth (one factorisation and a few solves each); the mean depth response of
each is extrapolated to the whole gear (:func:`gearbox.fe.extent.extent_limit`), and
the difference to the coarse segment that matches the level's own is added to every
entry of that gear's block (rank one: a series compliance; see
:meth:`FECompliance.far_field` for why it is not a full matrix).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from ..errors import InputError, Problem, Problems
from ..ltca.grid import ContactGrid
from ..ltca.slice_model import hertz_half_width
from ..surface.blank import ToothBlank
from ..surface.generation import flank_jets, flank_points, involute_start
from ..surface.sample import SolveFailure, parameter_at_radius, tip_parameter
from .boussinesq import depth_deflection, surface_deflection
from .extent import extent_limit
from .mesh import FEBuildError, MeshOptions, build_tooth_mesh, locate
from .model import ToothModel, build_model, thread_map

__all__ = ["FEOptions", "FECompliance", "FarField", "GearLoads", "beveloid_loads", "gear_loads"]

# load columns solved together (ToothModel.solve shares them over the cores)
_BLOCK = 32


@dataclass(frozen=True)
class FEOptions:
    """Options of the finite-element level.

    mesh: element counts (:class:`~gearbox.fe.mesh.MeshOptions`); matching_depth:
    depth d of the matching points below the flank, over m_n; lattice_spacing: unit
    load lattice spacing on the flank (face and profile), over m_n; neighbours: extra
    unloaded teeth meshed on each side of the loaded ones; cut_faces: boundary condition
    of the segment's two radial cut faces, ``"clamped"`` or ``"free"`` (the bore is
    clamped in both); far_field: ``"extrapolated"`` adds the compliance the segment
    misses against the whole gear (:meth:`FECompliance.far_field`), ``"none"`` gives the
    segment alone; far_field_mesh: the (coarse) mesh of that extent study.
    """

    mesh: MeshOptions = MeshOptions()
    matching_depth: float = 0.25
    lattice_spacing: float = 0.25
    neighbours: int = 1
    cut_faces: str = "clamped"
    far_field: str = "extrapolated"
    far_field_mesh: MeshOptions = MeshOptions().refined(0.5)

    def __post_init__(self):
        p = Problems()
        p.in_range("fe.matching_depth", self.matching_depth, 0.05, 0.6)
        p.in_range("fe.lattice_spacing", self.lattice_spacing, 0.05, 1.0)
        p.check(
            isinstance(self.neighbours, int) and self.neighbours >= 0,
            "fe.neighbours",
            self.neighbours,
            "must be an integer >= 0",
        )
        p.check(
            self.cut_faces in ("clamped", "free"),
            "fe.cut_faces",
            self.cut_faces,
            "must be 'clamped' or 'free'",
        )
        p.check(
            self.far_field in ("extrapolated", "none"),
            "fe.far_field",
            self.far_field,
            "must be 'extrapolated' or 'none'",
        )
        p.raise_if_any("invalid FE options")

    def to_dict(self) -> dict:
        d = asdict(self)
        return d

    @classmethod
    def from_dict(cls, d: dict) -> FEOptions:
        d = dict(d)
        d["mesh"] = MeshOptions.from_dict(d["mesh"])
        if "far_field_mesh" in d:
            d["far_field_mesh"] = MeshOptions.from_dict(d["far_field_mesh"])
        return cls(**d)


@dataclass(frozen=True)
class GearLoads:
    """Where the grid points of one gear sit on its flanks (gear frame, SI).

    blank: generating data of the gear; side: loaded flank ("R" or "L"); tooth:
    tooth offset of every point, shape (n,); z, u: flank parameters (m), shape (n,);
    bore_radius (m).
    """

    blank: ToothBlank
    side: str
    tooth: np.ndarray
    z: np.ndarray
    u: np.ndarray
    bore_radius: float


def _blank_of(sections, face_range) -> ToothBlank:
    """Generating data of a cylindrical gear from a grid's tooth sections (point 0)."""
    mn = float(sections.normal_module[0])
    beta = float(sections.helix_angle[0])
    x = float(sections.profile_shift[0])
    z = int(sections.teeth[0])
    rp = 0.5 * mn * z / math.cos(beta)
    return ToothBlank(
        teeth=z,
        normal_module=mn,
        normal_pressure_angle=float(sections.normal_pressure_angle[0]),
        helix_angle=beta,
        cone_angle=0.0,
        profile_shift_xt=x * math.cos(beta),
        face_width=float(face_range[1] - face_range[0]),
        reference_section=-0.5 * float(face_range[0] + face_range[1]),
        tool_addendum=float(sections.rack_dedendum[0]) * mn,
        tool_tip_radius=float(sections.rack_root_radius[0]) * mn,
        addendum=float(sections.tip_radius[0]) - rp - x * mn,
    )


def _u_at_radius(blank, side, z, r):
    """Rack-profile parameter u of the flank point at radius r in section z
    (:func:`gearbox.surface.sample.parameter_at_radius`, its failure as an FE build error)."""
    try:
        u, _ = parameter_at_radius(blank, side, z, r)
    except SolveFailure as exc:
        raise FEBuildError(
            Problem(
                "grid.radius",
                np.asarray(r).tolist(),
                f"no point of the generated {side} flank there: {exc}",
            ),
            "a contact grid point lies off the generated flank",
        ) from None
    return u


def _slope_sign(blank, side):
    """Sign of d(radius)/dz along the involute helicoid's straight generator."""
    P = flank_points(blank, side, np.array(0.0), np.array(0.8 * blank.normal_module))
    n = P.normal
    ez = np.array([0.0, 0.0, 1.0])
    g = n * n[2] - ez
    er = P.position * np.array([1.0, 1.0, 0.0])
    er = er / np.linalg.norm(er)
    return float(np.sign(np.dot(er, g) / g[2]))


def beveloid_loads(grid: ContactGrid, gear: int, blanks) -> GearLoads:
    """Locate the grid points of a beveloid grid (:mod:`gearbox.ltca.beveloid`) on gear
    ``gear`` with its generating data ``blanks = (pinion, gear)``.

    Pinion: the grid's face position and profile parameter are the pinion's own flank
    parameters (z, u); the flank is the one whose radius there is the grid's. Gear:
    its axial position follows from the local profile shift the grid carries,
    ``x(z) m_n / cos(gamma) = x_t m_t + z tan(gamma)`` (the tilted rack's shift,
    :meth:`~gearbox.surface.blank.ToothBlank.rack_shift`, needs gamma != 0), and u
    from the radius. Pair k sits k teeth ahead in the gear's sense of rotation, as in
    :func:`gear_loads`.
    """
    blank = blanks[gear]
    sections = grid.tooth1 if gear == 0 else grid.tooth2
    p = Problems()
    if gear == 1:
        p.check(
            abs(blank.cone_angle) > 1e-9,
            "gear.cone_angle",
            blank.cone_angle,
            "must be != 0 for the FE level to place beveloid grid points on the gear",
        )
    p.raise_if_any("the FE level cannot place this contact grid on its teeth")
    r = np.asarray(sections.radius, dtype=float)
    if gear == 0:
        z = np.asarray(grid.face, dtype=float)
        u = np.asarray(grid.profile, dtype=float)
        err = {}
        for s in ("R", "L"):
            P, _, _ = flank_jets(blank, s, z, u)
            err[s] = float(np.max(np.abs(np.hypot(P[0].val, P[1].val) - r)))
        side = min(err, key=err.get)
        if err[side] > 1e-6 * blank.normal_module:
            raise FEBuildError(
                Problem(
                    "grid.profile",
                    f"radius mismatch {err[side]:.3g} m",
                    "the grid's pinion profile parameters must be those of the pinion blank",
                ),
                "the FE level cannot place this contact grid on its teeth",
            )
    else:
        X = np.asarray(sections.profile_shift) * blank.normal_module / math.cos(blank.cone_angle)
        z = (X - blank.profile_shift_xt * blank.transverse_module) / math.tan(blank.cone_angle)
        side = beveloid_loads(grid, 0, blanks).side
        u = _u_at_radius(blank, side, z, r)
    fp = flank_points(blank, side, z[:1], u[:1])
    ez = np.array([0.0, 0.0, 1.0])
    sense = float(np.sign(np.dot(np.cross(ez, fp.position[0]), fp.normal[0])))
    if gear == 1:
        sense = -sense
    tooth = (sense * grid.pair).astype(int)
    return GearLoads(blank, side, tooth, z, u, float(np.min(sections.bore_radius)))


def gear_loads(grid: ContactGrid, gear: int) -> GearLoads:
    """Locate the grid points of a parallel-axis grid on gear ``gear`` (0 pinion, 1 gear).

    The flank is built with the hand for which the grid's contact lines (pinion radius
    rising along +face, gear radius falling) are the straight generators of the
    involute helicoid; a mirror image of a gear has the mirrored compliance, so the
    hand of the grid's own gear pair does not change the result. Pair k sits on the
    tooth that is k teeth ahead in the gear's sense of rotation (the driving pinion's
    flank moves along its outward normal, the driven gear's against it), behind it
    where the grid's ``pair_sense`` is -1.
    """
    sections = grid.tooth1 if gear == 0 else grid.tooth2
    _require_cylindrical(grid, sections, gear)
    blank = _blank_of(sections, grid.face_range)
    side = "R"
    if abs(blank.helix_angle) > 0:
        want = 1.0 if gear == 0 else -1.0
        beta = abs(blank.helix_angle)
        for h in (beta, -beta):
            b = _replace_helix(blank, h)
            if _slope_sign(b, side) == want:
                blank = b
                break
    z = np.asarray(grid.face, dtype=float)
    u = _u_at_radius(blank, side, z, sections.radius)
    fp = flank_points(blank, side, np.array(0.0), np.array(0.8 * blank.normal_module))
    ez = np.array([0.0, 0.0, 1.0])
    sense = float(np.sign(np.dot(np.cross(ez, fp.position), fp.normal)))
    if gear == 1:
        sense = -sense
    tooth = (sense * grid.pair_sense * grid.pair).astype(int)
    return GearLoads(blank, side, tooth, z, u, float(sections.bore_radius[0]))


def _require_cylindrical(grid, sections, gear):
    """Raise unless the grid is a parallel-axis one (uniform sections, one normal)."""
    p = Problems()
    for name in (
        "root_radius",
        "tip_radius",
        "bore_radius",
        "teeth",
        "normal_module",
        "normal_pressure_angle",
        "helix_angle",
        "profile_shift",
        "rack_dedendum",
        "rack_root_radius",
    ):
        a = getattr(sections, name)
        if np.ptp(a) > 1e-9 * max(1.0, float(np.max(np.abs(a)))):
            p.add(
                f"grid.tooth{gear + 1}.{name}",
                f"varies over the grid ({float(np.min(a)):.6g} .. {float(np.max(a)):.6g})",
                "the FE level rebuilds only cylindrical (parallel-axis) gears from a grid's "
                "tooth sections; for a beveloid grid pass the pair's generating data: "
                "FECompliance(blanks=...) or compliance_for('fe', blanks=...)",
            )
            break
    if np.max(np.ptp(grid.normal, axis=0)) > 1e-9:
        p.add(
            "grid.normal",
            "varies over the grid",
            "a parallel-axis grid has one plane of action (one normal); this grid is not "
            "one the FE level can place on cylindrical teeth",
        )
    p.raise_if_any("the FE level cannot place this contact grid on its teeth")


def _replace_helix(blank, beta):
    d = blank.to_dict()
    d["helix_angle"] = beta
    return ToothBlank.from_dict(d)


@dataclass(frozen=True)
class _Lattice:
    """Unit-load lattice of one loaded flank: axial positions z (m), shape (nz,), and
    rack-profile parameters u (m), shape (nu,); lattice point ``i nu + j``."""

    z: np.ndarray
    u: np.ndarray


@dataclass(frozen=True)
class _Solved:
    """What is kept of the solutions for the lattice unit loads on one tooth.

    depth: loadable tooth -> inward-normal displacement at its lattice depth points,
    (n_lat, n_lat) m/N; dofs: unknowns of the fillet elements; fillet: their values,
    (dofs, n_lat) m/N.
    """

    depth: dict
    dofs: np.ndarray
    fillet: np.ndarray


@dataclass(frozen=True)
class FarField:
    """Far-field correction of one gear and loaded flank (see
    :meth:`FECompliance.far_field`).

    compliance: the constant added to every entry of the gear's block (m/N);
    uncertainty: its extent uncertainty (m/N, half the difference of the clamped and
    free extrapolations); segment: the mean depth response of the coarse segment that
    matches the level's own (m/N); spread: standard deviation over mean of the
    entry-wise extrapolated correction over the depth points of the loadable teeth and
    the sub-lattice loads (its non-uniformity); sequence: mean depth responses of the
    coarse segments, ``{(cut faces, neighbours): m/N}``; seconds: wall time.
    """

    compliance: float
    uncertainty: float
    segment: float
    spread: float
    sequence: dict
    seconds: float


@dataclass
class _GearModel:
    model: ToothModel
    key: tuple
    bore: float = 0.0
    lattices: dict = field(default_factory=dict)  # (side) -> lattice geometry
    # (side, loaded tooth) -> _Solved; ("depth", side, tooth) -> depth operator;
    # ("fillet", side, tooth) -> fillet points; ("far", side) -> FarField
    responses: dict = field(default_factory=dict)


class FECompliance:
    """Finite-element compliance level (see the module docstring).

    options: :class:`FEOptions`; blanks: ``(pinion, gear)``
    :class:`~gearbox.surface.blank.ToothBlank` of a beveloid pair, whose grids
    (:mod:`gearbox.ltca.beveloid`) are then placed by :func:`beveloid_loads`;
    ``None`` for parallel-axis grids (:func:`gear_loads`); teeth: optional
    ``{gear: (first, last)}`` loaded tooth offsets (see :meth:`reserve`). The
    factorised models and the lattice responses are cached on the instance, keyed by
    the gear's generating data, so one instance serves a whole mesh cycle (and both
    flanks) with one factorisation per gear. ``stats`` counts factorisations and
    solves and their wall times (s).
    """

    name = "fe"
    load_dependent = True

    def __init__(self, options: FEOptions = FEOptions(), *, blanks=None, teeth: dict | None = None):
        from ..errors import expect_type
        from ..surface.blank import ToothBlank

        expect_type(options, FEOptions, "FECompliance: options", "FEOptions(...)")
        if blanks is not None:
            pair = isinstance(blanks, tuple | list) and len(blanks) == 2
            if not (pair and all(isinstance(b, ToothBlank) for b in blanks)):
                got = f"{type(blanks).__name__} {blanks!r}"
                raise TypeError(
                    "FECompliance: blanks must be (pinion, gear) ToothBlank "
                    f"(gearbox.surface.blanks_from_design(design)), or None; got {got[:80]}"
                )
            blanks = tuple(blanks)
        if teeth is not None:
            expect_type(teeth, dict, "FECompliance: teeth", "{gear: (first, last)}")
        self.options = options
        self.blanks = blanks
        self._teeth_hint = teeth or {}
        self._bore: dict = {}
        self._models: dict = {}
        self.stats = {
            "factorisations": 0,
            "solves": 0,
            "build_s": 0.0,
            "solve_s": 0.0,
            "far_field_factorisations": 0,
            "far_field_s": 0.0,
        }

    # ------------------------------------------------------------------ models
    def _model(self, loads: GearLoads, gear: int, E: float, nu: float) -> _GearModel:
        # one model per gear: the bore of the first grid (or of reserve()) is kept
        key = (tuple(sorted(loads.blank.to_dict().items())), E, nu)
        lo, hi = self._teeth_hint.get(gear, (int(loads.tooth.min()), int(loads.tooth.max())))
        gm = self._models.get(key)
        if gm is not None:
            t = gm.model.mesh.teeth
            nb = self.options.neighbours
            if t[0] + nb <= int(loads.tooth.min()) and int(loads.tooth.max()) <= t[-1] - nb:
                return gm
            lo = min(lo, t[0] + nb)
            hi = max(hi, t[-1] - nb)
        import time

        t0 = time.perf_counter()
        nb = self.options.neighbours
        mesh = build_tooth_mesh(
            loads.blank,
            tuple(range(lo - nb, hi + nb + 1)),
            bore_radius=self._bore.get(gear, loads.bore_radius),
            options=self.options.mesh,
            clamp_cut_faces=self.options.cut_faces == "clamped",
        )
        model = build_model(mesh, E, nu)
        self.stats["factorisations"] += 1
        self.stats["build_s"] += time.perf_counter() - t0
        gm = _GearModel(model=model, key=key, bore=mesh.bore_radius)
        self._models[key] = gm
        return gm

    def _lattice(self, gm: _GearModel, side: str) -> _Lattice:
        lat = gm.lattices.get(side)
        if lat is not None:
            return lat
        blank = gm.model.mesh.blank
        h = self.options.lattice_spacing * blank.normal_module
        nz = max(2, int(math.ceil(blank.face_width / h)) + 1)
        z = np.linspace(blank.z_toe, blank.z_heel, nz)
        u_tip = float(np.min(tip_parameter(blank, side, z)[0]))
        u_form = float(np.max(involute_start(blank, side, z)))  # 0 without undercut
        nu = max(2, int(math.ceil((u_tip - u_form) / h)) + 1)
        u = np.linspace(u_form, u_tip, nu)
        lat = _Lattice(z=z, u=u)
        gm.lattices[side] = lat
        return lat

    def _candidates(self, mesh, tooth, side, z, u):
        """Elements that may hold points near flank ``side`` of a tooth at flank
        parameters (z, u): the layer and profile row of (z, u) and their neighbours,
        the tooth-block columns of the flank's half of the tooth (at least two: a
        matching point 0.25 m_n deep lies beyond the second column of a mesh with six
        or more elements across), and the rim's top row."""
        zl = mesh.z_layers[0::2]
        layer = np.clip(np.searchsorted(zl, z) - 1, 0, zl.size - 2)
        ul = mesh.flank_u[side][0][0::2]
        row = np.clip(np.searchsorted(ul, u) - 1, 0, ul.size - 2)
        nc = mesh.options.across
        col = mesh.element_col
        blk = mesh.element_block
        k = max(2, (nc + 1) // 2)
        near = (blk == 0) & ((col < k) if side == "L" else (col >= nc - k))
        rim = (blk == 1) & (mesh.element_row == mesh.options.rim - 1)
        base = np.flatnonzero((mesh.element_tooth == tooth) & (near | rim))
        el = mesh.element_layer[base]
        er = np.where(mesh.element_block[base] == 0, mesh.element_row[base], -1)
        out = []
        for ly, rw in zip(np.atleast_1d(layer), np.atleast_1d(row), strict=True):
            ok = (np.abs(el - ly) <= 1) & ((np.abs(er - rw) <= 1) | ((er == -1) & (rw <= 1)))
            out.append(base[ok])
        return out

    def _surface(self, blank, side, tooth, z, u):
        """Points, outward normals and tangents of flank points of tooth ``tooth``."""
        fp = flank_points(blank, side, z, u)
        a = 2 * math.pi * tooth / blank.teeth
        R = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
        P = fp.position @ R.T
        n = fp.normal @ R.T
        t1 = fp.dr_dz @ R.T
        t1 = t1 - np.sum(t1 * n, -1, keepdims=True) * n
        t1 /= np.linalg.norm(t1, axis=-1, keepdims=True)
        t2 = np.cross(n, t1)
        return P, n, t1, t2

    def _unit_loads(self, gm: _GearModel, side: str, tooth: int, Z, U):
        """Nodal loads of unit forces along the inward normal, each spread over a square
        patch of side ``lattice_spacing m_n`` centred at flank point (Z, U) of tooth
        ``tooth`` (3 x 3 Gauss points, consistent nodal loads): sparse (n_dofs, Z.size)."""
        import scipy.sparse as sp

        model = gm.model
        mesh = model.mesh
        blank = mesh.blank
        P, n, t1, t2 = self._surface(blank, side, tooth, Z, U)
        half = 0.5 * self.options.lattice_spacing * blank.normal_module
        g = np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)])
        w = np.array([5.0, 8.0, 5.0]) / 9.0
        pts, wts, owner = [], [], []
        for i, gi in enumerate(g):
            for j, gj in enumerate(g):
                pts.append(P + half * (gi * t1 + gj * t2))
                wts.append(np.full(Z.size, 0.25 * w[i] * w[j]))
                owner.append(np.arange(Z.size))
        pts = np.concatenate(pts)
        wts = np.concatenate(wts)
        owner = np.concatenate(owner)
        cands = self._candidates(mesh, tooth, side, pts[:, 2], U[owner])
        cells, X, _ = locate(mesh, pts, cands)
        Op = model.point_operator(cells, X)  # (3 q, n_dofs)
        # unit force along the inward normal -n, weights of the patch quadrature
        f = -(n[owner] * wts[:, None])  # (q, 3)
        S = sp.csr_matrix(
            (
                f.ravel(),
                (np.arange(3 * pts.shape[0]), np.repeat(owner, 3)),
            ),
            shape=(3 * pts.shape[0], Z.size),
        )
        return (Op.T @ S).tocsc()

    def _lattice_unit_loads(self, gm: _GearModel, side: str, tooth: int):
        """Nodal loads of all lattice unit loads on one tooth, sparse (n_dofs, n_lat);
        cached on the gear model."""
        key = ("unit", side, tooth)
        if key not in gm.responses:
            lat = self._lattice(gm, side)
            Z, U = np.meshgrid(lat.z, lat.u, indexing="ij")
            gm.responses[key] = self._unit_loads(gm, side, tooth, Z.ravel(), U.ravel())
        return gm.responses[key]

    def _responses(self, gm: _GearModel, side: str, tooth: int) -> _Solved:
        """Responses to the lattice unit loads on one tooth (one solve per load)."""
        key = (side, tooth)
        if key in gm.responses:
            return gm.responses[key]
        import time

        import scipy.sparse as sp

        t0 = time.perf_counter()
        model = gm.model
        mesh = model.mesh
        F = self._lattice_unit_loads(gm, side, tooth)
        n_lat = F.shape[1]
        # only what the compliance and the fillet stresses need is kept: the depth
        # responses on every loadable tooth and the unknowns of the fillet elements
        from .stress import fillet_points

        nb = self.options.neighbours
        loadable = mesh.teeth[nb : len(mesh.teeth) - nb] or mesh.teeth
        D = [self._depth_operator(gm, side, tb) for tb in loadable]
        Dall = sp.vstack(D).tocsr()
        fil = [fillet_points(self, gm, side, tb) for tb in loadable]
        union = np.unique(np.concatenate([model.element_dofs(f[2]).ravel() for f in fil]))
        depth = np.empty((Dall.shape[0], n_lat))
        usub = np.empty((union.size, n_lat))
        # blocks of columns: the solves of a block share the cores (ToothModel.solve),
        # the block bounds the memory of the full displacement columns
        for j in range(0, n_lat, _BLOCK):
            u = model.solve(F[:, j : j + _BLOCK])
            depth[:, j : j + _BLOCK] = Dall @ u
            usub[:, j : j + _BLOCK] = u[union]
        sizes = np.cumsum([0] + [d.shape[0] for d in D])
        solved = _Solved(
            depth={tb: depth[sizes[i] : sizes[i + 1]] for i, tb in enumerate(loadable)},
            dofs=union,
            fillet=usub,
        )
        gm.responses[key] = solved
        self.stats["solves"] += n_lat
        self.stats["solve_s"] += time.perf_counter() - t0
        return solved

    def _depth_operator(self, gm: _GearModel, side: str, tooth: int):
        """(n_lat, n_dofs) inward-normal displacement at the lattice depth points."""
        key = ("depth", side, tooth)
        if key in gm.responses:
            return gm.responses[key]
        mesh = gm.model.mesh
        blank = mesh.blank
        lat = self._lattice(gm, side)
        Z, U = np.meshgrid(lat.z, lat.u, indexing="ij")
        P, n, _, _ = self._surface(blank, side, tooth, Z.ravel(), U.ravel())
        d = self.options.matching_depth * blank.normal_module
        Q = P - d * n
        # a helical flank's normal leans along the axis: near the face ends the depth
        # point is kept inside the face (the matching point moves by at most d sin(beta_b))
        Q[:, 2] = np.clip(Q[:, 2], blank.z_toe, blank.z_heel)
        cands = self._candidates(mesh, tooth, side, Q[:, 2], U.ravel())
        cells, X, miss = locate(mesh, Q, cands)
        if np.max(miss) > 1e-6:
            raise FEBuildError(
                Problem(
                    "fe.matching_depth",
                    self.options.matching_depth,
                    f"matching points at depth {d:g} m leave the meshed tooth: reduce it",
                ),
                "the FE level cannot place its matching points",
            )
        Op = gm.model.point_operator(cells, X)
        m = -n
        import scipy.sparse as sp

        S = sp.csr_matrix(
            (m.ravel(), (np.repeat(np.arange(Z.size), 3), np.arange(3 * Z.size))),
            shape=(Z.size, 3 * Z.size),
        )
        D = (S @ Op).tocsr()
        gm.responses[key] = D
        return D

    def _far_field_runs(self):
        """Segments of the extent study: (cut faces, neighbours), clamped first."""
        nb = self.options.neighbours
        last = max(5, nb + 2)
        runs = [("clamped", k) for k in range(nb, last + 1)]
        runs += [("free", k) for k in range(last - 2, last + 1)]
        return runs

    def _far_field_study(self, gm: _GearModel, side: str):
        """Depth responses of coarse segments of growing extent to unit loads on a
        sub-lattice of each loadable tooth: {(cut faces, neighbours): (n_resp, n_load)}
        m/N."""
        import scipy.sparse as sp

        mesh0 = gm.model.mesh
        blank = mesh0.blank
        nb = self.options.neighbours
        loadable = mesh0.teeth[nb : len(mesh0.teeth) - nb] or mesh0.teeth
        lo, hi = loadable[0], loadable[-1]
        lat = self._lattice(gm, side)
        sub = _Lattice(
            z=lat.z[np.unique([0, lat.z.size // 2, lat.z.size - 1])],
            u=lat.u[np.unique([0, lat.u.size // 2, lat.u.size - 1])],
        )
        Zs, Us = np.meshgrid(sub.z, sub.u, indexing="ij")
        Zs, Us = Zs.ravel(), Us.ravel()
        _, E, nu = gm.key
        runs = self._far_field_runs()
        widest = hi - lo + 1 + 2 * max(k for _, k in runs)
        if widest >= blank.teeth:
            raise FEBuildError(
                Problem(
                    "fe.far_field",
                    self.options.far_field,
                    f"the extent study needs segments of {widest} teeth, the gear has "
                    f"{blank.teeth}: use far_field='none' (or fewer neighbours)",
                ),
                "the FE level cannot extrapolate its segment to the whole gear",
            )
        if (self.options.cut_faces, nb) not in runs:
            runs.append((self.options.cut_faces, nb))

        def segment(run):
            bc, k = run
            mesh = build_tooth_mesh(
                blank,
                tuple(range(lo - k, hi + k + 1)),
                bore_radius=gm.bore,
                options=self.options.far_field_mesh,
                clamp_cut_faces=bc == "clamped",
            )
            cg = _GearModel(model=build_model(mesh, E, nu), key=gm.key, bore=gm.bore)
            cg.lattices[side] = lat
            D = sp.vstack([self._depth_operator(cg, side, tb) for tb in loadable]).tocsr()
            cols = []
            for ta in loadable:
                F = self._unit_loads(cg, side, ta, Zs, Us)
                for j in range(0, Zs.size, _BLOCK):
                    cols.append(D @ cg.model.solve(F[:, j : j + _BLOCK]))
            return np.concatenate(cols, axis=1)

        # the segments are independent: built, factorised and solved on the cores at
        # once (SuperLU releases the GIL; each segment's state is its own)
        done = thread_map(segment, runs)
        self.stats["far_field_factorisations"] += len(runs)
        return dict(zip(runs, done, strict=True))

    def far_field(self, grid: ContactGrid, gear: int) -> FarField:
        """Far-field correction of gear ``gear`` for the flank ``grid`` loads (cached per
        gear model and flank: a table pays it once per gear and flank).

        The whole gear's compliance minus the segment's, at the depth points: coarse
        segments of the same loaded teeth with clamped cut faces and ``neighbours``
        .. 5 neighbours, and free cut faces with 3 .. 5, each factorised once and loaded
        by unit loads at a 3 x 3 sub-lattice (toe, middle, heel x root, middle, tip of
        the lattice) of every loadable tooth; responses at the full lattice's depth
        points on every loadable tooth. The mean response of each segment is
        extrapolated (Aitken on the clamped and the free sequence, their mean) and the
        coarse base segment's subtracted.

        Rank one, measured: the entry-wise extrapolated correction is not uniform (its
        standard deviation over its mean, :attr:`FarField.spread`, is 0.12 / 0.17 on the
        spur pair z 20/40 b 16, pinion / gear, 0.23 / 0.18 on case 03 drive), but the
        mean stiffness hardly sees its shape: on the coarse mesh, 8 positions, a smooth
        matrix (that shape interpolated bilinearly over the sub-lattice) instead of the
        constant moved the mean stiffness by -0.1 % (spur, 400 N m) and -0.6 to -0.8 %
        (case 03 drive, 150-450 N m), and the constant came closer to the extent-
        extrapolated whole gear of ``benchmarks/fe_extent.py`` on case 03 (-0.8 to
        -1.2 % against -1.4 to -2.0 %, uncertainty +-0.9 to 1.0 %). A constant is a
        series compliance: for a parallel pair it leaves the load distribution unchanged
        and adds (c_pinion + c_gear) times the total normal load to the approach.
        """
        loads = self.loads(grid, gear)
        gm = self._model(loads, gear, grid.youngs_modulus, grid.poisson_ratio)
        return self._far_field(gm, loads.side)

    def _far_field(self, gm: _GearModel, side: str) -> FarField:
        key = ("far", side)
        if key in gm.responses:
            return gm.responses[key]
        import time

        t0 = time.perf_counter()
        out = self._far_field_study(gm, side)
        runs = self._far_field_runs()
        mean = {r: float(np.mean(v)) for r, v in out.items()}
        cl = np.array([out[r] for r in runs if r[0] == "clamped"])
        fr = np.array([out[r] for r in runs if r[0] == "free"])
        lim, err = extent_limit(
            [mean[r] for r in runs if r[0] == "clamped"],
            [mean[r] for r in runs if r[0] == "free"],
        )
        base = mean[(self.options.cut_faces, self.options.neighbours)]
        try:
            d = extent_limit(cl, fr)[0] - out[(self.options.cut_faces, self.options.neighbours)]
            spread = float(np.std(d) / np.mean(d))
        except InputError:
            spread = float("nan")  # some entries do not converge monotonically
        ff = FarField(
            compliance=float(lim) - base,
            uncertainty=float(err),
            segment=base,
            spread=spread,
            sequence=mean,
            seconds=time.perf_counter() - t0,
        )
        gm.responses[key] = ff
        self.stats["far_field_s"] += ff.seconds
        return ff

    def _tooth_weights(self, lat: _Lattice, loads: GearLoads) -> dict:
        """Per loaded tooth: the indices of its grid points and their interpolation
        weights onto the lattice, ``{tooth: (idx, W (n_t, n_lat))}``."""
        out = {}
        for t in np.unique(loads.tooth):
            idx = np.flatnonzero(loads.tooth == t)
            out[int(t)] = (idx, self._weights(lat, loads.z[idx], loads.u[idx]))
        return out

    def _weights(self, lat: _Lattice, z, u):
        """Bilinear interpolation weights onto the lattice, shape (n, n_lat)."""
        nz, nu = lat.z.size, lat.u.size
        iz = np.clip(np.searchsorted(lat.z, z) - 1, 0, nz - 2)
        iu = np.clip(np.searchsorted(lat.u, u) - 1, 0, nu - 2)
        fz = np.clip((z - lat.z[iz]) / (lat.z[iz + 1] - lat.z[iz]), 0.0, 1.0)
        fu = np.clip((u - lat.u[iu]) / (lat.u[iu + 1] - lat.u[iu]), 0.0, 1.0)
        W = np.zeros((z.size, nz * nu))
        r = np.arange(z.size)
        for dz, wz in ((0, 1 - fz), (1, fz)):
            for du, wu in ((0, 1 - fu), (1, fu)):
                np.add.at(W, (r, (iz + dz) * nu + iu + du), wz * wu)
        return W

    # --------------------------------------------------------------- interface
    def reserve(self, grids) -> None:
        """Size the tooth models for all grids of a cycle (or of both flanks) at once:
        one factorisation per gear, none repeated when a later position loads another
        tooth, and every position solved on the same segment. Hints only grow: a
        later call widens them to its grids as well (``ltca_cycle`` calls it)."""
        for gear in (0, 1):
            teeth = [self.loads(g, gear).tooth for g in grids]
            lo = min(int(t.min()) for t in teeth)
            hi = max(int(t.max()) for t in teeth)
            bore = min(float(np.min(self.loads(g, gear).bore_radius)) for g in grids)
            if gear in self._teeth_hint:
                lo = min(lo, self._teeth_hint[gear][0])
                hi = max(hi, self._teeth_hint[gear][1])
                bore = min(bore, self._bore[gear])
            self._teeth_hint[gear] = (lo, hi)
            self._bore[gear] = bore

    def loads(self, grid: ContactGrid, gear: int) -> GearLoads:
        """Where the grid points sit on gear ``gear``'s teeth (0 pinion, 1 gear)."""
        if self.blanks is not None:
            return beveloid_loads(grid, gear, self.blanks)
        return gear_loads(grid, gear)

    def gear_matrix(self, grid: ContactGrid, gear: int) -> np.ndarray:
        """FE part of one gear's compliance at the matching depth, shape (n, n), m/N."""
        loads = self.loads(grid, gear)
        gm = self._model(loads, gear, grid.youngs_modulus, grid.poisson_ratio)
        lat = self._lattice(gm, loads.side)
        n = grid.size
        C = np.zeros((n, n))
        W = self._tooth_weights(lat, loads)
        for ta, (ia, Wa) in W.items():
            solved = self._responses(gm, loads.side, ta)
            for tb, (ib, Wb) in W.items():
                Clat = solved.depth[tb]  # (n_lat responses on tb, n_lat loads on ta)
                C[np.ix_(ib, ia)] = Wb @ Clat @ Wa.T
        if self.options.far_field == "extrapolated":
            # rank one: a series compliance of the gear body, the same for every pair
            # of points (the choice is measured: FECompliance.far_field)
            C += self._far_field(gm, loads.side).compliance
        return 0.5 * (C + C.T)

    def _frames(self, grid: ContactGrid):
        """Contact-line direction t and across direction c at every point (pair frame)."""
        n = grid.normal
        t = np.zeros_like(n)
        for k in grid.pairs():
            idx = np.flatnonzero(grid.pair == k)
            idx = idx[np.argsort(grid.slot[idx])]
            if idx.size > 1:
                d = np.gradient(grid.position[idx], axis=0)
                t[idx] = d
            else:
                t[idx] = np.cross(n[idx], np.cross(np.array([0.0, 0.0, 1.0]), n[idx]))
        t = t - np.sum(t * n, -1, keepdims=True) * n
        t /= np.linalg.norm(t, axis=-1, keepdims=True)
        c = np.cross(n, t)
        return t, c

    def local_matrix(self, grid: ContactGrid) -> np.ndarray:
        """Half-space part between points of one tooth pair, both gears, without the
        surface self-terms (m/N), shape (n, n). The surface coupling between two
        cells uses the Hertz half-width of a 200 N/mm line load (cells a slice apart
        see the cell's width only to second order)."""
        E, nu = grid.youngs_modulus, grid.poisson_ratio
        mn = float(grid.tooth1.normal_module[0])
        d = self.options.matching_depth * mn
        half = 0.5 * self.options.lattice_spacing * mn
        t, c = self._frames(grid)
        n = grid.size
        C = np.zeros((n, n))
        a0 = hertz_half_width(2.0e5, grid.curvature_radius, E, nu)
        for k in grid.pairs():
            idx = np.flatnonzero(grid.pair == k)
            dP = grid.position[idx][:, None, :] - grid.position[idx][None, :, :]  # i - j
            x = np.sum(dP * t[idx][None, :, :], -1)
            y = np.sum(dP * c[idx][None, :, :], -1)
            lj = 0.5 * grid.line_length[idx][None, :]
            aj = a0[idx][None, :]
            ws = surface_deflection(x, y, lj, aj, E, nu)
            np.fill_diagonal(ws, 0.0)
            wd = depth_deflection(x, y, d, half, half, E, nu)
            C[np.ix_(idx, idx)] = 2.0 * (ws - wd)  # both gears, equal materials
        return 0.5 * (C + C.T)

    def tooth_matrix(self, grid: ContactGrid) -> np.ndarray:
        """FE part of both gears plus the half-space coupling (m/N), shape (n, n)."""
        C = self.gear_matrix(grid, 0) + self.gear_matrix(grid, 1)
        return C + self.local_matrix(grid)

    def contact_diagonal(self, grid: ContactGrid, line_load: np.ndarray) -> np.ndarray:
        """Surface self-term of the half-space, both gears (m/N), shape (n,): a uniform
        pressure over the contact-line length of the slice times the Hertz width.
        Line loads (N/m) below 1 N/mm take the width of 1 N/mm: under a vanishing
        width the surface displacement of a line load diverges logarithmically."""
        E, nu = grid.youngs_modulus, grid.poisson_ratio
        q = np.maximum(np.asarray(line_load, dtype=float), 1.0e3)
        a = hertz_half_width(q, grid.curvature_radius, E, nu)
        return 2.0 * surface_deflection(0.0, 0.0, 0.5 * grid.line_length, a, E, nu)

    def describe(self) -> str:
        """One line naming the level's choices, for provenance (table attributes, the
        report)."""
        far = {"extrapolated": "far field extrapolated", "none": "the segment alone"}
        return (
            f"finite-element teeth ({far.get(self.options.far_field, self.options.far_field)}), "
            f"half-space contact to {self.options.matching_depth:g} m_n, root stress from "
            "the FE fillet"
        )

    def grid_root_stress(self, grid: ContactGrid, load) -> tuple:
        """Root stress of pinion and gear under the grid loads, from the FE fillet
        (:func:`gearbox.fe.stress.fillet_stress`), in place of the fast level's ISO
        6336-3 slices (:func:`gearbox.ltca.stress.grid_root_stress`).

        Returns ``((at1, at2), (top1, top2))``, arrays of shape (n,): ``at`` the largest
        principal stress over the fillet profile of each point's tooth at the point's
        face position (linear between the fillet's element middles along the face,
        held at the outermost beyond them), ``top`` the largest over that tooth's
        whole fillet (its face ends included, which the grid's slot middles may not
        reach). The lattice responses the contact solve computed are superposed: no
        new solve.
        """
        from .stress import fillet_stress

        load = np.asarray(load, dtype=float)
        at, top = [], []
        for gear in (0, 1):
            loads = self.loads(grid, gear)
            fs = fillet_stress(self, grid, load, gear)
            rs = fs.root_stress  # (teeth, face positions)
            a = np.zeros(grid.size)
            m = np.zeros(grid.size)
            for k, tooth in enumerate(fs.teeth):
                on = loads.tooth == tooth
                a[on] = np.interp(loads.z[on], fs.z, rs[k])
                m[on] = rs[k].max()
            at.append(a)
            top.append(m)
        return (at[0], at[1]), (top[0], top[1])

    def matrix(self, grid: ContactGrid, line_load: np.ndarray | None = None) -> np.ndarray:
        C = self.tooth_matrix(grid)
        if line_load is None:
            line_load = np.full(grid.size, 1.0e5)
        C[np.diag_indices_from(C)] += self.contact_diagonal(grid, line_load)
        return C
