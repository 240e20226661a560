"""Half-space solutions of gearbox.fe.boussinesq against independent references."""

import math

import numpy as np
import pytest
from scipy import integrate

from gearbox.fe import depth_deflection, surface_deflection

E, NU = 206e9, 0.3


def _quad_surface(x, y, a, b):
    # direct numerical integral of Johnson eq. (3.21) over the rectangle (singular
    # only at an interior point, handled by splitting the rectangle there)
    def f(yy, xx):
        return 1.0 / math.hypot(x - xx, y - yy)

    xs = sorted({-a, a, *([x] if -a < x < a else [])})
    ys = sorted({-b, b, *([y] if -b < y < b else [])})
    tot = 0.0
    for x0, x1 in zip(xs, xs[1:], strict=False):
        for y0, y1 in zip(ys, ys[1:], strict=False):
            tot += integrate.dblquad(f, x0, x1, y0, y1, epsabs=1e-13, epsrel=1e-10)[0]
    return (1 - NU**2) / (math.pi * E) * tot / (4 * a * b)


@pytest.mark.parametrize(
    "x,y,a,b",
    [(0.0, 0.0, 1e-3, 1e-3), (0.3e-3, -0.2e-3, 1e-3, 0.25e-3), (3e-3, 1e-3, 0.5e-3, 0.1e-3)],
)
def test_surface_closed_form_matches_quadrature(x, y, a, b):
    # the closed form is exact; 1e-7 relative is the quadrature's own accuracy
    assert surface_deflection(x, y, a, b, E, NU) == pytest.approx(
        _quad_surface(x, y, a, b), rel=1e-7
    )


def test_square_centre_matches_the_textbook_value():
    # centre of a uniformly loaded square of side 2a: w = (8/pi) ln(1 + sqrt 2) p a (1-nu^2)/E
    # (Johnson, Contact Mechanics, 1985, section 3.3; 2.244 p a (1 - nu^2) / E)
    a = 1e-3
    p = 1.0 / (4 * a * a)
    ref = 8 / math.pi * math.log(1 + math.sqrt(2)) * p * a * (1 - NU**2) / E
    assert surface_deflection(0.0, 0.0, a, a, E, NU) == pytest.approx(ref, rel=1e-12)


def test_far_field_is_the_point_load():
    # far from the rectangle the load acts as a point load: w = (1 - nu^2) / (pi E r)
    r = 0.2
    w = surface_deflection(r, 0.0, 1e-3, 1e-3, E, NU)
    assert w == pytest.approx((1 - NU**2) / (math.pi * E * r), rel=1e-4)


@pytest.mark.parametrize("depth", [0.5e-3, 1e-3, 3e-3])
def test_depth_deflection_matches_quadrature(depth):
    # Johnson eq. (3.22c) integrated by scipy over the rectangle: the 8 x 8 Gauss rule
    # must agree to 1e-4 relative for depth >= half the larger side
    a, b = 1e-3, 0.5e-3
    G = E / (2 * (1 + NU))

    def uz(yy, xx):
        rho = math.sqrt((0.2e-3 - xx) ** 2 + (0.1e-3 - yy) ** 2 + depth**2)
        return (depth**2 / rho**3 + 2 * (1 - NU) / rho) / (4 * math.pi * G)

    ref = integrate.dblquad(uz, -a, a, -b, b, epsrel=1e-11)[0] / (4 * a * b)
    got = depth_deflection(0.2e-3, 0.1e-3, depth, a, b, E, NU)
    assert got == pytest.approx(ref, rel=1e-4)


def test_depth_deflection_tends_to_the_surface_value():
    # continuity of the half-space solution: at a depth 1e-4 of the patch size the
    # displacement under the patch centre is the surface value to 1e-3 relative
    a = 1e-3
    xs = np.linspace(-a, a, 801)
    # fine midpoint sum of the point-load formula (independent of the 8 x 8 rule)
    d = 1e-7
    G = E / (2 * (1 + NU))
    X, Y = np.meshgrid(0.5 * (xs[1:] + xs[:-1]), 0.5 * (xs[1:] + xs[:-1]))
    rho = np.sqrt(X**2 + Y**2 + d**2)
    uz = (d**2 / rho**3 + 2 * (1 - NU) / rho) / (4 * math.pi * G)
    mid = float(np.sum(uz) * (xs[1] - xs[0]) ** 2 / (4 * a * a))
    assert mid == pytest.approx(surface_deflection(0.0, 0.0, a, a, E, NU), rel=1e-3)
