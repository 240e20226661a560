"""Textbook tooth loss factors of a parallel involute pair (ISO/TR 14179-2), written
out from the formulas for the tests that hold the mesh friction to them."""

import math


def loss_factor(h) -> float:
    """Tooth loss factor H of a :class:`gearbox.mesh_analytical.HelicalPair` with the
    load spread evenly over its path of contact: for a spur pair Ohlendorf's
    H_V = pi (u + 1) / (z_1 u) (1 - eps_a + eps_1^2 + eps_2^2) (halves in double
    contact, ISO/TR 14179-2:2001 eq. 8), for a helical pair the mean transverse
    distance from the pitch point over the path, pi (u + 1) / (z_1 u cos(beta_b))
    (eps_1^2 + eps_2^2) / eps_a; eps_1 / eps_2 the addendum contact ratios of pinion /
    gear."""
    z1, z2 = h.teeth
    u = z2 / z1
    aw = h.working_pressure_angle
    rb1, rb2 = h.base_radius(0), h.base_radius(1)
    xc = rb1 * math.tan(aw)  # the pitch point's roll distance from T_1
    line = h.centre_distance * math.sin(aw)  # T_1 T_2
    e1 = (math.sqrt(h.tip_radius(0) ** 2 - rb1**2) - xc) / h.base_pitch
    e2 = (math.sqrt(h.tip_radius(1) ** 2 - rb2**2) - (line - xc)) / h.base_pitch
    eps = h.contact_ratio
    if h.base_helix_angle == 0.0:
        return math.pi * (u + 1) / (z1 * u) * (1 - eps + e1**2 + e2**2)
    return math.pi * (u + 1) / (z1 * u * math.cos(h.base_helix_angle)) * (e1**2 + e2**2) / eps
