"""ISO 6336-1 method B: single stiffness c' and mesh stiffness c_gamma of spur and
helical gear pairs.

All formulas from ISO 6336-1:2006, clause 9 ("Tooth stiffness parameters c' and
c_gamma"), method B; the 2019 edition keeps them (it averages the basic rack factor
over pinion and gear, which is what :func:`basic_rack_factor` does for two racks).
ISO states the stiffnesses in N/(mm um); here they are SI, N/m per m of face width
(N/m^2): 1 N/(mm um) = 1e9 N/m^2.

- theoretical single stiffness ``c'_th = 1 / q'`` with the flexibility ``q'`` of a
  tooth pair (mm um/N) from a polynomial in the virtual tooth numbers and the
  profile-shift coefficients (:func:`flexibility_q`);
- single stiffness ``c' = c'_th C_M C_R C_B cos(beta)``, times
  ``((F_t K_A / b) / (100 N/mm))^0.25`` below 100 N/mm of load per face width;
- mesh stiffness ``c_gamma_alpha = c' (0.75 eps_alpha + 0.25)`` (for
  ``eps_alpha >= 1.2``) and ``c_gamma_beta = 0.85 c_gamma_alpha``.

The implementation is checked against a published KISSsoft report (ISO 6336:2006
method B) in ``tests/test_ltca_iso.py``.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from ..errors import Problems

__all__ = [
    "IsoStiffness",
    "basic_rack_factor",
    "flexibility_q",
    "gear_blank_factor",
    "iso_mesh_stiffness",
    "virtual_teeth",
]

#: N/(mm um) -> N/m^2
N_PER_MM_UM = 1.0e9

# ISO 6336-1:2006 method B, coefficients C1..C9 of q' (mm um / N)
_Q = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)


def virtual_teeth(teeth: int, helix_angle: float, normal_pressure_angle: float) -> float:
    """Virtual number of teeth z_n = z / (cos^2(beta_b) cos(beta)) (ISO 6336-1 method B).

    helix_angle, normal_pressure_angle: beta, alpha_n (rad).
    """
    beta_b = math.asin(math.sin(helix_angle) * math.cos(normal_pressure_angle))
    return teeth / (math.cos(beta_b) ** 2 * math.cos(helix_angle))


def flexibility_q(zn1: float, zn2: float, x1: float, x2: float) -> float:
    """Minimum flexibility q' of a tooth pair (mm um/N), ISO 6336-1 method B.

    zn1, zn2: virtual numbers of teeth (zn2 = inf for a rack); x1, x2: normal
    profile-shift coefficients.
    """
    c1, c2, c3, c4, c5, c6, c7, c8, c9 = _Q
    return (
        c1
        + c2 / zn1
        + c3 / zn2
        + c4 * x1
        + c5 * x1 / zn1
        + c6 * x2
        + c7 * x2 / zn2
        + c8 * x1**2
        + c9 * x2**2
    )


def basic_rack_factor(dedendum_coefficient: float, pressure_angle: float) -> float:
    """Basic rack factor C_B (ISO 6336-1 method B) of one basic rack.

    C_B = (1 + 0.5 (1.2 - h_fP/m_n)) (1 - 0.02 (20 deg - alpha_Pn)), with the angle
    difference in degrees. dedendum_coefficient: h_fP/m_n; pressure_angle (rad).
    """
    return (1.0 + 0.5 * (1.2 - dedendum_coefficient)) * (
        1.0 - 0.02 * (20.0 - math.degrees(pressure_angle))
    )


def gear_blank_factor(rim_width_ratio: float | None, rim_thickness_ratio: float | None) -> float:
    """Gear blank factor C_R (ISO 6336-1 method B).

    1 for solid disc gears (``None``); otherwise
    ``C_R = 1 + ln(b_s/b) / (5 exp(s_R / (5 m_n)))`` with the web width ratio
    ``b_s/b`` clipped to [0.2, 1.2] and the rim thickness ratio ``s_R/m_n >= 1``.
    """
    if rim_width_ratio is None or rim_thickness_ratio is None:
        return 1.0
    bs = min(max(rim_width_ratio, 0.2), 1.2)
    sr = max(rim_thickness_ratio, 1.0)
    return 1.0 + math.log(bs) / (5.0 * math.exp(sr / 5.0))


@dataclass(frozen=True)
class IsoStiffness:
    """ISO 6336-1 method B tooth stiffness parameters of a pair (SI, N/m^2).

    Stiffnesses are per metre of face width: multiply by the face width (m) for N/m.
    """

    q_prime: float  #: flexibility q' (mm um/N), as ISO states it
    c_prime_th: float  #: theoretical single stiffness c'_th (N/m^2)
    c_prime: float  #: single stiffness c' (N/m^2)
    c_gamma_alpha: float  #: mesh stiffness c_gamma_alpha (N/m^2)
    c_gamma_beta: float  #: mesh stiffness c_gamma_beta (N/m^2)
    C_M: float
    C_R: float
    C_B: float
    load_factor: float  #: ((F_t K_A/b)/100 N/mm)^0.25 below 100 N/mm, else 1

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, d) -> IsoStiffness:
        return cls(**{k: float(d[k]) for k in cls.__dataclass_fields__})


def iso_mesh_stiffness(
    *,
    teeth: tuple[int, int],
    helix_angle: float,
    normal_pressure_angle: float,
    profile_shift: tuple[float, float],
    transverse_contact_ratio: float,
    load_per_width: float | None = None,
    dedendum_coefficient: tuple[float, float] = (1.25, 1.25),
    rack_pressure_angle: tuple[float, float] | None = None,
    rim_width_ratio: float | None = None,
    rim_thickness_ratio: float | None = None,
    C_M: float = 0.8,
    youngs_modulus: float = 206.0e9,
) -> IsoStiffness:
    """ISO 6336-1 method B single and mesh stiffness of an external pair.

    teeth: (z1, z2); helix_angle, normal_pressure_angle: beta, alpha_n (rad);
    profile_shift: (x1, x2); transverse_contact_ratio: eps_alpha;
    load_per_width: F_t K_A / b (N/m), ``None`` for "at least 100 N/mm";
    dedendum_coefficient: h_fP/m_n of each basic rack; rim_*: see
    :func:`gear_blank_factor`; C_M: theoretical correction factor (0.8 for solid
    gears); youngs_modulus (Pa): c' scales with E/E_steel, E_steel = 206 GPa.
    """
    p = Problems()
    p.in_range("teeth[0]", teeth[0], 5, None)
    p.in_range("teeth[1]", teeth[1], 5, None)
    p.in_range("helix_angle", helix_angle, -math.radians(45), math.radians(45))
    p.in_range("transverse_contact_ratio", transverse_contact_ratio, 1.0, None)
    if load_per_width is not None:
        p.in_range("load_per_width", load_per_width, 0.0, None, lo_open=True)
    p.raise_if_any("invalid ISO 6336-1 stiffness input")
    beta = abs(helix_angle)
    zn1 = virtual_teeth(teeth[0], beta, normal_pressure_angle)
    zn2 = virtual_teeth(teeth[1], beta, normal_pressure_angle)
    q = flexibility_q(zn1, zn2, profile_shift[0], profile_shift[1])
    c_th = N_PER_MM_UM / q
    ra = rack_pressure_angle or (normal_pressure_angle, normal_pressure_angle)
    c_b = 0.5 * (
        basic_rack_factor(dedendum_coefficient[0], ra[0])
        + basic_rack_factor(dedendum_coefficient[1], ra[1])
    )
    c_r = gear_blank_factor(rim_width_ratio, rim_thickness_ratio)
    lf = 1.0
    if load_per_width is not None and load_per_width < 1.0e5:
        lf = (load_per_width / 1.0e5) ** 0.25
    c_prime = c_th * C_M * c_r * c_b * math.cos(beta) * lf * youngs_modulus / 206.0e9
    eps = transverse_contact_ratio
    c_ga = c_prime * (0.75 * eps + 0.25)
    return IsoStiffness(
        q_prime=q,
        c_prime_th=c_th,
        c_prime=c_prime,
        c_gamma_alpha=c_ga,
        c_gamma_beta=0.85 * c_ga,
        C_M=C_M,
        C_R=c_r,
        C_B=c_b,
        load_factor=lf,
    )
