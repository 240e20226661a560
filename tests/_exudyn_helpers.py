"""Helpers shared by the exudyn backend's tests (tests/test_drivetrain_exudyn*.py): random
states about the operating point, and the force functions' deviation from the model's
right-hand side."""

import numpy as np

from gearbox.drivetrain import exudyn_backend as xb
from gearbox.drivetrain.exudyn_backend import ExudynSolver, build_exudyn_system
from gearbox.drivetrain.model import mesh_forces, rhs


def rel(a, b):
    return abs(a - b) / abs(b)


def random_state(model, rng, i):
    """The i-th random state near the operating point (2 x the state scale); every fourth
    (i % 4 == 3) pushed back through the backlash onto the coast flank."""
    y0 = model.static_state()
    y = y0 + model.params()["scale"] * rng.normal(0.0, 2.0, 2 * model.n_dof)
    if i % 4 == 3:
        y[1] -= y0[1] + 1.5 * model.coast.backlash / model.drive.lambda1
    return y


def random_states(model, rng, count):
    """``count`` states of :func:`random_state`."""
    return [random_state(model, rng, i) for i in range(count)]


def random_cases(model, rng, count):
    """``count`` pairs (t, y): a state of :func:`random_state`, then a time in [0, 0.05) s."""
    cases = []
    for i in range(count):
        y = random_state(model, rng, i)
        cases.append((float(rng.uniform(0.0, 0.05)), y))
    return cases


def force_function_errors(model, cases, strip=None):
    """How far the generic layout's force functions are from the model's ``rhs``.

    M a = f_user(t, q, v) - K q - C v against M times the model's accelerations at each
    (t, y) of ``cases``, for the recorded symbolic function and the plain Python one.
    Returns (errors, contact, stripped): errors, {"symbolic": e, "python": e}, the
    largest difference over the cases relative to the largest term of each case
    (max |a| + max |K x| / min inertia); contact, shape (len(cases), 2), whether each
    flank carries load; stripped, the same error of the Python function of
    ``strip(plan)`` (the plan with a term taken out, to show that the comparison sees
    it), None without ``strip``.
    """
    plan = xb._plan_from_model(model)
    K, C = xb._structural(plan)
    p = model.params()
    n = model.n_dof
    sysm = build_exudyn_system(model, ExudynSolver(layout="generic"))
    symbolic = sysm.keepalive[0]
    python = xb._all_forces(plan, False)
    functions = {
        "symbolic": lambda t, x, v: symbolic.Evaluate(sysm.mbs, t, 0, x, v),
        "python": lambda t, x, v: python(sysm.mbs, t, 0, x, v),
    }
    if strip is not None:
        bare = xb._all_forces(strip(plan), False)
        functions["stripped"] = lambda t, x, v: bare(sysm.mbs, t, 0, x, v)
    errors = dict.fromkeys(functions, 0.0)
    contact = []
    for t, y in cases:
        x, v = y[:n], y[n:]
        want = (rhs(t, y / p["scale"], p) * p["scale"])[n:]
        big = np.abs(want).max() + np.abs(K @ x).max() / plan.inertia.min()
        for name, fn in functions.items():
            f = np.array(fn(t, x.tolist(), v.tolist()))
            got = (f - K @ x - C @ v) / plan.inertia
            errors[name] = max(errors[name], float(np.abs(got - want).max() / big))
        contact.append(mesh_forces(t, x, v, p)[0] > 0)
    stripped = errors.pop("stripped", None)
    return errors, np.array(contact), stripped
