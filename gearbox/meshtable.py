"""Mesh tables: mesh stiffness, loaded transmission error, mesh point and line of action.

A :class:`MeshTable` holds, per flank (``drive`` = the paper's R flank, ``coast`` = L),
per pinion torque level and per pinion position over one mesh cycle (period
``2 pi / N_1``, positions uniform, the end point excluded):

- ``stiffness``          secant mesh stiffness F_n / LTE (N/m)
- ``tangent_stiffness``  dF_n / d(LTE) (N/m); the dynamics uses this one
- ``lte``                loaded transmission error along the line of action (m)
- ``mesh_point``         load-weighted mesh point P in Sf (m), last axis x, y, z
- ``line_of_action``     unit line of action n in Sf (force of the pinion on the gear)
- ``extra``              optional fields of the same shape (``max_contact_pressure_Pa``,
  ``pattern_area_fraction``, ``load_sharing`` ...)

and the pinion and gear axes (unit vector in the driving sense, a point) in Sf.
Arrays are shaped ``(n_flanks, n_torques, n_positions)`` (and ``(..., 3)`` for vectors).

Interpolation is smooth and periodic in the pinion angle (a truncated Fourier series,
exact at the table positions when all harmonics are kept) and linear in torque: an
adaptive ODE solver needs a smooth right-hand side (linear interpolation in angle
puts a derivative jump into every table cell). :func:`fourier_eval` evaluates the
series with numpy or jax.numpy (``xp``), so it is jittable.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from ._pickling import PicklesReadOnly
from .errors import InputError, Problems

__all__ = [
    "FLANKS",
    "FRICTION_ARMS",
    "TORQUE_ARM",
    "FourierSeries",
    "MeshTable",
    "fourier_eval",
    "fourier_fit",
    "form_weight_fields",
    "form_weight_name",
    "pair_weight_fields",
    "pair_weight_name",
]

FLANKS = ("drive", "coast")

#: The optional fields of the sliding friction's moment arms about the pinion's and the
#: gear's axis (m), rows of ``extra`` (docs/drivetrain.md §3a).
FRICTION_ARMS = ("friction_arm_pinion_m", "friction_arm_gear_m")

#: The optional field of the torque arm T / sum F_n (m): the loaded TCA's normal load
#: per unit pinion torque, inverted.
TORQUE_ARM = "torque_arm_m"


def pair_weight_name(k: int) -> str:
    """Name of the optional field of tooth pair k's weight (the share of a normal
    offset of the pair that the loaded rotation takes up, docs/ltca.md "Pitch
    deviations"): ``pair_weight_0``, ``pair_weight_p1``, ``pair_weight_m1``."""
    k = int(k)
    return f"pair_weight_{'p' if k > 0 else 'm' if k < 0 else ''}{abs(k)}"


def pair_weight_fields(table) -> dict[int, str]:
    """Tooth pair index -> field name of the table's pair weights (empty if none)."""
    out = {}
    for k in range(-16, 17):
        name = pair_weight_name(k)
        if name in table.extra:
            out[k] = name
    return out


#: The form deviations' offset shapes, in their order (``ContactGrid.form_bases``'s
#: columns, the loaded TCA's form weights, the mesh table's fields): the slopes (linear
#: in the flank coordinate), then the crownings (its square).
FORM_BASES = (
    "pinion_profile",
    "pinion_helix",
    "gear_profile",
    "gear_helix",
    "pinion_profile_crowning",
    "pinion_helix_crowning",
    "gear_profile_crowning",
    "gear_helix_crowning",
)

#: The attrs of the lengths the loaded contact covers on the drive flanks (m): roll
#: length and axial length, pinion and gear; the form deviations' default evaluation lengths.
CONTACT_LENGTHS = (
    "pinion_contact_roll_length_m",
    "gear_contact_roll_length_m",
    "pinion_contact_face_length_m",
    "gear_contact_face_length_m",
)

#: The attrs of the middles of those ranges (m, from the reference circle and the face
#: middle): the crownings' default vertices.
CONTACT_CENTRES = (
    "pinion_contact_roll_centre_m",
    "gear_contact_roll_centre_m",
    "pinion_contact_face_centre_m",
    "gear_contact_face_centre_m",
)


def form_weight_name(basis: str, k: int) -> str:
    """Name of the optional field of tooth pair k's weight for the offset shape
    ``basis`` (one of FORM_BASES, docs/ltca.md "Form deviations": a unit slope, or a
    unit coefficient of a flank coordinate's square): ``form_weight_pinion_profile_0``,
    ``form_weight_gear_helix_crowning_m1``."""
    return "form_" + pair_weight_name(k).replace("pair_weight_", f"weight_{basis}_")


def form_weight_fields(table) -> dict[int, list[str]]:
    """Tooth pair index -> the field names of its form weights in the order of
    FORM_BASES (empty if the table has none)."""
    out = {}
    for k in range(-16, 17):
        names = [form_weight_name(b, k) for b in FORM_BASES]
        if all(n in table.extra for n in names):
            out[k] = names
    return out


_FIELDS = ("stiffness", "tangent_stiffness", "lte")
_UNITS = {
    "angle": "rad",
    "torque": "N m",
    "stiffness": "N/m",
    "tangent_stiffness": "N/m",
    "lte": "m",
    "mesh_point": "m",
    "line_of_action": "1",
}
_EXTRA_UNITS = {
    "max_contact_pressure_Pa": "Pa",
    "pattern_area_fraction": "1",
    "load_sharing": "1",
    **dict.fromkeys(FRICTION_ARMS, "m"),
    TORQUE_ARM: "m",
}


@dataclass(frozen=True)
class FourierSeries:
    """Truncated real Fourier series of period ``2 pi / teeth`` in the pinion angle.

    ``f(theta) = a0 + sum_k a_k cos(k N theta') + b_k sin(k N theta')`` with
    ``theta' = theta - angle0``, ``k = 1 .. len(a)``.

    a0: float; a, b: ndarray, shape (n_harmonics,).
    """

    a0: float
    a: np.ndarray
    b: np.ndarray
    teeth: int
    angle0: float = 0.0

    def __call__(self, theta, xp=np):
        return fourier_eval(self.a0, self.a, self.b, self.teeth, theta - self.angle0, xp=xp)[0]

    def derivative(self, theta, xp=np):
        """d f / d theta (unit of f per rad)."""
        return fourier_eval(self.a0, self.a, self.b, self.teeth, theta - self.angle0, xp=xp)[1]

    @property
    def mean(self) -> float:
        return float(self.a0)

    def peak_to_peak(self, samples: int = 512) -> float:
        th = self.angle0 + np.arange(samples) * (2 * np.pi / self.teeth / samples)
        v = self(th)
        return float(v.max() - v.min())


def fourier_fit(values: np.ndarray, harmonics: int = 0) -> tuple[float, np.ndarray, np.ndarray]:
    """Fourier coefficients of samples at uniform positions over one period.

    values: ndarray, shape (n,), samples at ``j/n`` of the period, j = 0..n-1.
    harmonics: number kept (0 = all up to the Nyquist one: the series then
    interpolates the samples exactly). Returns (a0, a, b), a and b of shape (h,).
    """
    v = np.asarray(values, dtype=float)
    n = v.size
    c = np.fft.rfft(v) / n
    hmax = n // 2
    h = hmax if harmonics <= 0 else min(harmonics, hmax)
    a = 2.0 * c[1 : h + 1].real
    b = -2.0 * c[1 : h + 1].imag
    if n % 2 == 0 and h == hmax:
        # Nyquist bin appears once in the inverse transform, not twice.
        a[-1] *= 0.5
        b[-1] = 0.0
    return float(c[0].real), a, b


def fourier_eval(a0, a, b, teeth, theta, xp=np):
    """Value and derivative of a Fourier series in the pinion angle.

    a0: float; a, b: array, shape (h,) (or broadcastable (..., h));
    theta: pinion angle (rad), scalar. Returns (f, df/dtheta).
    Works with ``xp = numpy`` and ``xp = jax.numpy`` (jittable, differentiable).
    """
    k = xp.arange(1, a.shape[-1] + 1) * teeth
    arg = k * theta
    c = xp.cos(arg)
    s = xp.sin(arg)
    f = a0 + xp.sum(a * c + b * s, axis=-1)
    df = xp.sum(k * (b * c - a * s), axis=-1)
    return f, df


@dataclass(frozen=True)
class MeshTable(PicklesReadOnly):
    """Mesh tables over one mesh cycle x torque levels x flanks (SI).

    pinion_teeth, gear_teeth: N_1, N_2.
    angle: ndarray, shape (n_positions,), pinion angle (rad), uniform with step
        ``2 pi / (N_1 n_positions)``, end point excluded.
    torque: ndarray, shape (n_torques,), pinion torque levels (N m), increasing.
    flanks: tuple of flank names, a subset of ``("drive", "coast")``.
    stiffness, tangent_stiffness, lte: ndarray, shape (n_flanks, n_torques, n_positions),
        N/m, N/m, m.
    mesh_point, line_of_action: ndarray, shape (n_flanks, n_torques, n_positions, 3),
        m and unit vectors, in Sf.
    pinion_axis, gear_axis: ndarray, shape (2, 3): [unit axis in the driving sense,
        a point on the axis (m)], in Sf.
    extra: mapping name -> ndarray, shape (n_flanks, n_torques, n_positions).
    attrs: provenance: ``scene``, ``method``, ``fidelity``, ``gearbox_version``, ``frame``.
    """

    pinion_teeth: int
    gear_teeth: int
    angle: np.ndarray
    torque: np.ndarray
    flanks: tuple[str, ...]
    stiffness: np.ndarray
    tangent_stiffness: np.ndarray
    lte: np.ndarray
    mesh_point: np.ndarray
    line_of_action: np.ndarray
    pinion_axis: np.ndarray
    gear_axis: np.ndarray
    extra: Mapping[str, np.ndarray] = field(default_factory=dict)
    attrs: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self):
        for name in (
            "angle",
            "torque",
            "stiffness",
            "tangent_stiffness",
            "lte",
            "mesh_point",
            "line_of_action",
            "pinion_axis",
            "gear_axis",
        ):
            arr = np.array(getattr(self, name), dtype=float)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        ex = {}
        for k, v in dict(self.extra).items():
            arr = np.array(v, dtype=float)
            arr.setflags(write=False)
            ex[k] = arr
        object.__setattr__(self, "extra", MappingProxyType(ex))
        object.__setattr__(self, "attrs", MappingProxyType(dict(self.attrs)))
        object.__setattr__(self, "flanks", tuple(self.flanks))
        validate_table(self)

    # ----------------------------------------------------------------- basics
    @property
    def mesh_period(self) -> float:
        """Pinion angle of one mesh cycle, 2 pi / N_1 (rad)."""
        return 2.0 * math.pi / self.pinion_teeth

    @property
    def n_positions(self) -> int:
        return self.angle.size

    def flank_index(self, flank: str) -> int:
        if flank not in self.flanks:
            raise InputError(
                [], f"flank {flank!r} is not in the mesh table (it has {', '.join(self.flanks)})"
            )
        return self.flanks.index(flank)

    def _torque_weights(self, torque: float) -> tuple[int, int, float]:
        tq = self.torque
        lo, hi = float(tq[0]), float(tq[-1])
        tol = 1e-9 * max(1.0, hi)
        if not (lo - tol <= torque <= hi + tol):
            p = Problems()
            p.add(
                "torque_Nm",
                torque,
                f"must be within the mesh table's torque range [{lo:g}, {hi:g}] N m",
            )
            p.raise_if_any("operating point outside the mesh table")
        if tq.size == 1:
            return 0, 0, 0.0
        j = int(np.clip(np.searchsorted(tq, torque) - 1, 0, tq.size - 2))
        w = (torque - tq[j]) / (tq[j + 1] - tq[j])
        return j, j + 1, float(np.clip(w, 0.0, 1.0))

    def values_at(self, name: str, flank: str, torque: float) -> np.ndarray:
        """Table column ``name`` at ``torque`` (linear in torque), shape (n_positions, ...)."""
        i = self.flank_index(flank)
        arr = getattr(self, name) if name in _UNITS else self.extra[name]
        j0, j1, w = self._torque_weights(float(torque))
        return (1.0 - w) * arr[i, j0] + w * arr[i, j1]

    def series(self, name: str, flank: str, torque: float, harmonics: int = 0) -> FourierSeries:
        """Smooth periodic interpolant of a scalar field in pinion angle at ``torque``."""
        v = self.values_at(name, flank, torque)
        a0, a, b = fourier_fit(v, harmonics)
        return FourierSeries(a0, a, b, self.pinion_teeth, float(self.angle[0]))

    def coefficients(self, name: str, flank: str, harmonics: int = 0) -> np.ndarray:
        """Fourier coefficients per torque level, shape (n_torques, 1 + 2 h): [a0, a, b].

        Linear interpolation in torque commutes with the Fourier fit, so interpolating
        these rows in torque (e.g. ``jnp.interp`` per column) is the jittable form of
        :meth:`series`.
        """
        i = self.flank_index(flank)
        arr = getattr(self, name) if name in _UNITS else self.extra[name]
        rows = []
        for j in range(self.torque.size):
            a0, a, b = fourier_fit(arr[i, j], harmonics)
            rows.append(np.concatenate([[a0], a, b]))
        return np.array(rows)

    def rotation_radii(self, flank: str, torque: float) -> tuple[float, float]:
        """Mean directional rotation radii (lambda_1, lambda_2) of a flank (m).

        lambda_i = a_i . ((P - O_i) x n), averaged over the mesh cycle (docs/drivetrain.md §2).
        """
        P = self.values_at("mesh_point", flank, torque)
        n = self.values_at("line_of_action", flank, torque)
        out = []
        for ax in (self.pinion_axis, self.gear_axis):
            lam = np.einsum("j,ij->i", ax[0], np.cross(P - ax[1], n))
            out.append(float(lam.mean()))
        return out[0], out[1]

    def mean_direction(self, flank: str, torque: float) -> np.ndarray:
        n = self.values_at("line_of_action", flank, torque).mean(axis=0)
        return n / np.linalg.norm(n)

    def scaled(self, *, stiffness: float = 1.0, lte: float = 1.0) -> MeshTable:
        """A copy with stiffnesses and LTE multiplied by factors (stress tests, studies)."""
        import dataclasses

        return dataclasses.replace(
            self,
            stiffness=self.stiffness * stiffness,
            tangent_stiffness=self.tangent_stiffness * stiffness,
            lte=self.lte * lte,
        )

    def summary(self, harmonics: int = 3) -> dict[str, Any]:
        """Mean and peak-to-peak stiffness and LTE per flank and torque, and the peak
        amplitudes of the LTE's first ``harmonics`` mesh-order harmonics (the orders
        N_1, 2 N_1, ... of the pinion; what excites gear whine) (SI, JSON-ready)."""
        out: dict[str, Any] = {}
        for i, f in enumerate(self.flanks):
            rows = {}
            for j, t in enumerate(self.torque):
                k = self.stiffness[i, j]
                e = self.lte[i, j]
                _, a, b = fourier_fit(e, harmonics)
                amp = np.zeros(harmonics)
                amp[: a.size] = np.hypot(a, b)
                rows[f"{t:g}"] = {
                    "mean_mesh_stiffness_N_per_m": float(k.mean()),
                    "mesh_stiffness_peak_to_peak_N_per_m": float(k.max() - k.min()),
                    "lte_mean_m": float(e.mean()),
                    "lte_peak_to_peak_m": float(e.max() - e.min()),
                    "lte_harmonics_m": amp.tolist(),
                    "mesh_point_m": self.mesh_point[i, j].mean(axis=0).tolist(),
                    "line_of_action": self.line_of_action[i, j].mean(axis=0).tolist(),
                }
            out[f] = rows
        return out

    # ------------------------------------------------------------ persistence
    def to_dataset(self):
        """An ``xarray.Dataset`` (dims flank, torque, angle, xyz) with units and provenance."""
        import xarray as xr

        dims = ("flank", "torque", "angle")
        data = {}
        for name in _FIELDS:
            data[name] = xr.Variable(dims, getattr(self, name), {"units": _UNITS[name]})
        for name in ("mesh_point", "line_of_action"):
            data[name] = xr.Variable(dims + ("xyz",), getattr(self, name), {"units": _UNITS[name]})
        for name, arr in self.extra.items():
            data[f"extra_{name}"] = xr.Variable(dims, arr, {"units": _EXTRA_UNITS.get(name, "")})
        data["pinion_axis"] = xr.Variable(("axis_row", "xyz"), self.pinion_axis, {"units": "1 | m"})
        data["gear_axis"] = xr.Variable(("axis_row", "xyz"), self.gear_axis, {"units": "1 | m"})
        coords = {
            "flank": list(self.flanks),
            "torque": xr.Variable("torque", self.torque, {"units": "N m"}),
            "angle": xr.Variable("angle", self.angle, {"units": "rad"}),
            "xyz": ["x", "y", "z"],
            "axis_row": ["direction", "point"],
        }
        attrs = {
            k: (v if isinstance(v, (int, float, str)) else str(v)) for k, v in self.attrs.items()
        }
        attrs.update(pinion_teeth=int(self.pinion_teeth), gear_teeth=int(self.gear_teeth))
        return xr.Dataset(data, coords=coords, attrs=attrs)

    @classmethod
    def from_dataset(cls, ds) -> MeshTable:
        attrs = dict(ds.attrs)
        n1 = int(attrs.pop("pinion_teeth"))
        n2 = int(attrs.pop("gear_teeth"))
        extra = {k[len("extra_") :]: ds[k].values for k in ds.data_vars if k.startswith("extra_")}
        return cls(
            pinion_teeth=n1,
            gear_teeth=n2,
            angle=ds["angle"].values,
            torque=ds["torque"].values,
            flanks=tuple(str(f) for f in ds["flank"].values),
            stiffness=ds["stiffness"].values,
            tangent_stiffness=ds["tangent_stiffness"].values,
            lte=ds["lte"].values,
            mesh_point=ds["mesh_point"].values,
            line_of_action=ds["line_of_action"].values,
            pinion_axis=ds["pinion_axis"].values,
            gear_axis=ds["gear_axis"].values,
            extra=extra,
            attrs=attrs,
        )

    def to_netcdf(self, path: str | Path) -> Path:
        """Write a netCDF-4 file atomically (see :func:`write_netcdf_atomic`)."""
        return write_netcdf_atomic(self.to_dataset(), path)

    @classmethod
    def from_netcdf(cls, path: str | Path) -> MeshTable:
        import xarray as xr

        try:
            with xr.open_dataset(path) as ds:
                ds.load()
                return cls.from_dataset(ds)
        except (OSError, KeyError, ValueError) as exc:
            if isinstance(exc, InputError):
                raise
            raise InputError([], f"cannot read mesh table {path}: {exc}") from None

    def to_csv(self, path: str | Path | None = None) -> str:
        """CSV, one row per (angle, flank, torque), angle first; SI units in the header."""
        cols = [
            "angle_rad",
            "flank",
            "torque_Nm",
            "stiffness_N_per_m",
            "tangent_stiffness_N_per_m",
            "lte_m",
            "P_x_m",
            "P_y_m",
            "P_z_m",
            "n_x",
            "n_y",
            "n_z",
        ]
        cols += [f"{k}" for k in self.extra]
        lines = [",".join(cols)]
        for a_i, a in enumerate(self.angle):
            for i, f in enumerate(self.flanks):
                for j, t in enumerate(self.torque):
                    row = [repr(float(a)), f, repr(float(t))]
                    row += [repr(float(getattr(self, n)[i, j, a_i])) for n in _FIELDS]
                    row += [repr(float(v)) for v in self.mesh_point[i, j, a_i]]
                    row += [repr(float(v)) for v in self.line_of_action[i, j, a_i]]
                    row += [repr(float(v[i, j, a_i])) for v in self.extra.values()]
                    lines.append(",".join(row))
        text = "\n".join(lines) + "\n"
        if path is not None:
            from .commands._common import write_atomic

            write_atomic(path, text)
        return text


def write_netcdf_atomic(ds, path: str | Path) -> Path:
    """Write an ``xarray.Dataset`` as netCDF-4 to a temporary file, then rename.

    Uses the netCDF4 engine where installed, else h5netcdf (which needs h5py).
    """
    from .commands._common import atomic_target

    try:
        import netCDF4  # noqa: F401

        engine = "netcdf4"
    except ImportError:
        engine = "h5netcdf"
    path = Path(path)
    with atomic_target(path) as tmp:
        ds.to_netcdf(tmp, engine=engine)
    return path


def validate_table(t: MeshTable) -> None:
    """Shapes, uniform periodic angle grid, positivity, unit directions; raise once."""
    p = Problems()
    n1 = t.pinion_teeth
    p.check(
        isinstance(n1, (int, np.integer)) and n1 >= 1, "pinion_teeth", n1, "must be an integer >= 1"
    )
    p.check(
        isinstance(t.gear_teeth, (int, np.integer)) and t.gear_teeth >= 1,
        "gear_teeth",
        t.gear_teeth,
        "must be an integer >= 1",
    )
    npos = t.angle.size
    p.check(
        t.angle.ndim == 1 and npos >= 4, "angle", f"{npos} positions", "must have >= 4 positions"
    )
    p.check(
        len(t.flanks) >= 1
        and all(f in FLANKS for f in t.flanks)
        and len(set(t.flanks)) == len(t.flanks),
        "flanks",
        t.flanks,
        "must be distinct names from ('drive', 'coast')",
    )
    tq = t.torque
    p.check(tq.ndim == 1 and tq.size >= 1, "torque", tq.tolist(), "must have >= 1 level")
    if tq.size:
        p.check(bool(np.all(tq > 0)), "torque", tq.tolist(), "must be > 0 N m")
        p.check(bool(np.all(np.diff(tq) > 0)), "torque", tq.tolist(), "must be strictly increasing")
    if p.items:
        p.raise_if_any("invalid mesh table")
    if n1 >= 1 and npos >= 4:
        step = 2 * math.pi / n1 / npos
        dev = np.abs(np.diff(t.angle) - step).max() if npos > 1 else 0.0
        p.check(
            dev <= 1e-9 * step + 1e-12,
            "angle",
            f"steps {np.diff(t.angle).min():.6g}..{np.diff(t.angle).max():.6g} rad",
            f"must be uniform with step 2 pi/(N_1 n_positions) = {step:.6g} rad over one mesh "
            f"cycle, end point excluded (periodic table)",
        )
    shape = (len(t.flanks), tq.size, npos)
    for name in _FIELDS:
        arr = getattr(t, name)
        if not p.check(arr.shape == shape, name, f"shape {arr.shape}", f"must have shape {shape}"):
            continue
        p.check(bool(np.all(np.isfinite(arr))), name, "non-finite entries", "must be finite")
    for name in ("mesh_point", "line_of_action"):
        arr = getattr(t, name)
        if p.check(
            arr.shape == shape + (3,), name, f"shape {arr.shape}", f"must have shape {shape + (3,)}"
        ):
            p.check(bool(np.all(np.isfinite(arr))), name, "non-finite entries", "must be finite")
    for name in ("pinion_axis", "gear_axis"):
        arr = getattr(t, name)
        if p.check(arr.shape == (2, 3), name, f"shape {arr.shape}", "must have shape (2, 3)"):
            p.check(
                abs(np.linalg.norm(arr[0]) - 1) < 1e-6,
                name,
                arr[0].tolist(),
                "direction must be a unit vector",
            )
    for k, arr in t.extra.items():
        p.check(arr.shape == shape, f"extra.{k}", f"shape {arr.shape}", f"must have shape {shape}")
    if p.items:
        p.raise_if_any("invalid mesh table")
    for name in ("stiffness", "tangent_stiffness"):
        arr = getattr(t, name)
        if not np.all(arr > 0):
            idx = np.unravel_index(np.argmin(arr), arr.shape)
            p.add(
                f"{name}[{t.flanks[idx[0]]}, {tq[idx[1]]:g} N m, position {idx[2]}]",
                float(arr[idx]),
                "must be > 0 N/m",
            )
    nn = np.linalg.norm(t.line_of_action, axis=-1)
    p.check(
        bool(np.all(np.abs(nn - 1) < 1e-6)),
        "line_of_action",
        f"norms {nn.min():.6g}..{nn.max():.6g}",
        "must be unit vectors",
    )
    p.raise_if_any("invalid mesh table")


def check_periodic_samples(values: np.ndarray, name: str, rtol: float = 1e-6) -> None:
    """For tables given with the period's end point included: first row must equal last.

    values: ndarray, shape (n_positions + 1, ...). Raises naming ``name``.
    """
    v = np.asarray(values, dtype=float)
    scale = max(np.abs(v).max(), 1e-300)
    err = float(np.abs(v[0] - v[-1]).max())
    if err > rtol * scale:
        p = Problems()
        p.add(
            name,
            f"first {v[0]!r} vs last {v[-1]!r}",
            f"is not periodic over the mesh cycle (relative mismatch {err / scale:.3g} > {rtol:g})",
        )
        p.raise_if_any("invalid mesh table")


def from_periodic_samples(angle_with_end: np.ndarray, **kw) -> MeshTable:
    """Build a table from samples that include the period's end point (checked, dropped).

    ``angle_with_end``: shape (n + 1,), from theta_0 to theta_0 + 2 pi / N_1. Every
    array in ``kw`` named in ``stiffness, tangent_stiffness, lte, mesh_point,
    line_of_action`` has the position axis third with n + 1 entries; the last entry
    must repeat the first.
    """
    a = np.asarray(angle_with_end, dtype=float)
    n1 = kw["pinion_teeth"]
    if abs((a[-1] - a[0]) - 2 * math.pi / n1) > 1e-9:
        p = Problems()
        p.add(
            "angle",
            f"{a[0]:.6g}..{a[-1]:.6g} rad",
            f"must span one mesh cycle 2 pi/N_1 = {2 * math.pi / n1:.6g} rad",
        )
        p.raise_if_any("invalid mesh table")
    out = dict(kw)
    for name in _FIELDS + ("mesh_point", "line_of_action"):
        arr = np.asarray(kw[name], dtype=float)
        check_periodic_samples(np.moveaxis(arr, 2, 0), name)
        out[name] = arr[:, :, :-1]
    if "extra" in kw:
        out["extra"] = {}
        for k, arr in kw["extra"].items():
            arr = np.asarray(arr, dtype=float)
            check_periodic_samples(np.moveaxis(arr, 2, 0), f"extra.{k}")
            out["extra"][k] = arr[:, :, :-1]
    return MeshTable(angle=a[:-1], **out)
