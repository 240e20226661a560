"""Why the fast level's drive flanks are stiffer than its coast flanks, against the FE.

    python3 benchmarks/ltca_flank_gap.py [--cases 01 02 03 04] [--only WORD...] [--no-split]

The fast level's mean mesh stiffness against the whole-gear FE level (stored:
``tests/data/fe_reference_paper_cases.json``, as ``benchmarks/ltca_ripple.py``) is
higher on the drive flank than on the coast flank of every paper case. This script
tries the candidate causes as variants of :class:`~gearbox.ltca.FastCompliance` and
prints, per variant, the error per case and flank at 150 / 300 / 450 N m, the drive
minus coast gap at 300 N m, the parallel pairs against their whole-gear FE
(``tests/data/fe_parallel_whole_gear.json``) and K_Hbeta of the misaligned spur pair
of ``benchmarks/ltca_misalignment.py`` against its whole-gear FE
(``tests/data/fe_khbeta_spur.json``), which measures the load's spread along the face:

- ``default``: the fast level as it is;
- ``face ends``: with the helical face ends (``helix_ends=HELIX_ENDS``);
- ``foundation L``: the slices' foundation (Sainsot's term less the shared torsion and
  far field) coupled along the face over L tooth depths, the tooth above the root
  circle over the default 0.6 (two shear layers in place of one);
- ``rocking c``: each gear's body rocking about the radial axis under the tangential
  load's offset along the face, ``c (y_i t_i)(y_j t_j) / (E b^3)`` added to the
  pinion's block (y the face coordinate from the face middle, t the normal's
  tangential component); zero for a load even along the face;
- ``pairs even``: between different tooth pairs the body torsion and the far field
  shared evenly (``between_pairs="even"``, the default before the plane-strain whole
  gear's couplings); ``pairs plane x 1.0``: those couplings without the factor
  ``PAIR_COUPLING_SCALE``.

- ``contact along the line``: Weber's contact approach (a line load, even and
  endless along the line) corrected for the load's actual run along the contact line
  by Boussinesq's half-space: each point's approach less what an even line load beyond
  its own strip adds, plus what the loads of the same pair's other strips add
  (:class:`LineContact`; an even endless load gives Weber's again). A short contact, as
  on the coast flanks, loses the approach of the load it lacks.
- ``contact to the matching depth``: the FE level's split (``contact="matching_depth"``):
  Weber's approach to the FE's matching depth, the slices' tooth read there, with that
  split's own body coefficient.

``--only`` keeps the variants whose name has one of the words. Then the split at 300
N m into what the FE's segment holds and its far field (``1/k_whole - 1/k_segment``),
against the fast level (pairs even) without its shared terms and what its far field
and tilt add, in 1e-10 m/N of mesh compliance (``--no-split`` leaves it out). About
70 s here.

``--own-terms CASE [--positions 0 8 16] [--refine 1.0] [--contact matching_depth]``
runs the FE level's segment (minutes) at those positions of both flanks and splits one
tooth pair's own compliance under the FE's contact loads at 300 N m, ``F^T C F /
F_n^2`` summed over the pairs that carry 5 % or more, into the pinion's and the gear's
tooth (the fast level's slices and rim torsion) and the contact (the FE level's
half-space cells and their couplings; Weber's approach in the fast level, to the
centre line or with ``--contact matching_depth`` to the FE's matching depth, the tooth
then read there), each level against the other.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import ltca_misalignment as mis  # noqa: E402
import ltca_ripple as rip  # noqa: E402

from gearbox.ltca import FastCompliance  # noqa: E402
from gearbox.ltca import compliance as cm  # noqa: E402
from gearbox.ltca.slice_fe import fe_tooth_compliance  # noqa: E402
from gearbox.ltca.slice_model import normal_section  # noqa: E402

KHBETA = ROOT / "tests" / "data" / "fe_khbeta_spur.json"
FLANKS = ("drive", "coast")


@dataclass(frozen=True)
class FoundationCoupled(FastCompliance):
    """The slices' tooth coupled over ``coupling_length``, their foundation over
    ``foundation_length`` tooth depths (normal section, plane-strain tooth, the shared
    far field: the default's other options)."""

    foundation_length: float = 0.6

    def slice_matrix(self, grid, gear, parts=None, acute=None):
        # the default's slices, less the plane-strain tooth: Sainsot's foundation less
        # the shared torsion and far field; each part through the default's coupling
        E, nu = grid.youngs_modulus, grid.poisson_ratio
        total = self.slice_parts(grid) if parts is None else parts
        tooth = []
        for teeth in (grid.tooth1, grid.tooth2):
            section, factor = normal_section(teeth)
            tooth.append(fe_tooth_compliance(section, E, nu, normal=True, depth=None) * factor)
        found = tuple(t - c for t, c in zip(total, tooth, strict=True))
        wide = replace(self, coupling_length=self.foundation_length)
        return FastCompliance.slice_matrix(
            self, grid, gear, tuple(tooth), acute
        ) + FastCompliance.slice_matrix(wide, grid, gear, found, acute)


@dataclass(frozen=True)
class Rocking(FastCompliance):
    """The pinion body's rocking under the tangential load's offset along the face."""

    rocking: float = 0.0

    def body_matrix(self, grid):
        b = cm._face(grid, 0)
        v = grid.face * grid.arm / grid.tooth1.radius  # y times the tangential component
        return super().body_matrix(grid) + self.rocking / (grid.youngs_modulus * b**3) * np.outer(
            v, v
        )


@dataclass(frozen=True)
class Unshared(FastCompliance):
    """The fast level without the far field and tilt it shares (what the FE's segment
    holds)."""

    def body_matrix(self, grid):
        return np.zeros((grid.size, grid.size))


def _beyond(a, h, E, nu):
    """Integral from ``a`` to infinity along the surface of Boussinesq's approach of the
    surface point over a point at depth ``h`` below the observed point, per unit force
    (m/N per m of line): a point force P at distance s moves the surface by P (1 -
    nu^2) / (pi E s) and the point at depth by P (1 + nu) / (2 pi E) (2 (1 - nu) / r +
    h^2 / r^3), r = sqrt(s^2 + h^2)."""
    c = (1.0 - nu**2) / (np.pi * E)
    return c * (np.arcsinh(a / h) - np.log(2.0 * a / h)) - (1.0 + nu) / (2.0 * np.pi * E) * (
        1.0 - a / np.sqrt(a**2 + h**2)
    )


@dataclass(frozen=True)
class LineContact(FastCompliance):
    """Weber's contact approach corrected for the load's run along the contact line:
    within each tooth pair, point i's approach loses ``2 I(l_i / 2) q_i`` (an even
    line load beyond its own strip of length l_i, which Weber's line formula holds)
    and gains ``sum_j F_j (I(s_ij - l_j / 2) - I(s_ij + l_j / 2)) / l_j`` (the other
    strips' loads), I = :func:`_beyond` for each gear's reference depth; load
    independent, so it goes with the tooth matrix. One point per face slot and pair
    (the beveloid and parallel grids)."""

    def tooth_matrix(self, grid):
        E, nu = grid.youngs_modulus, grid.poisson_ratio
        C = super().tooth_matrix(grid)
        depths = self.contact_reference(grid)
        for k in grid.pairs():
            idx = np.flatnonzero(grid.pair == k)
            d = grid.position[idx, None, :] - grid.position[None, idx, :]
            s = np.linalg.norm(d, axis=-1)
            strip = grid.line_length[idx]
            near = np.maximum(s - strip[None, :] / 2, 0.25 * strip[None, :])
            for h in depths:
                hi = h[idx][:, None]
                K = (_beyond(near, hi, E, nu) - _beyond(s + strip[None, :] / 2, hi, E, nu)) / strip
                np.fill_diagonal(K, -2.0 * _beyond(strip / 2, h[idx], E, nu) / strip)
                C[np.ix_(idx, idx)] += K
        return C


def own_terms(case: str, positions: list[int], refine: float, contact: str) -> None:
    """One tooth pair's own compliance by term, FE segment against the fast level (its
    contact term to ``contact``: the centre line or the FE's matching depth)."""
    from gearbox.fe import FECompliance, FEOptions, MeshOptions
    from gearbox.ltca import solve_contact
    from gearbox.surface import blanks_from_design

    fast = FastCompliance(contact=contact)
    print(
        f"case {case}, positions {positions}, FE mesh refined {refine:g}, 300 N m, fast contact "
        f"{contact}: one pair's own F^T C F / F_n^2 (1e-10 m/N), summed over the positions"
    )
    print(f"{'flank':>5} {'term':>8} {'FE':>8} {'fast':>8} {'fast/FE':>8}")
    for flank in FLANKS:
        _, design, grids = rip.case_grids(case, flank)
        grids = [grids[p] for p in positions]
        fe = FECompliance(
            FEOptions(mesh=MeshOptions().refined(refine), far_field="none"),
            blanks=blanks_from_design(design),
        )
        fe.reserve(grids)
        sums = {t: np.zeros(2) for t in ("pinion", "gear", "contact")}
        for g in grids:
            tooth = [fe.gear_matrix(g, 0), fe.gear_matrix(g, 1)]
            local = fe.local_matrix(g)
            seg = rip.Frozen([g], [tooth[0] + tooth[1] + local], fe.contact_diagonal)
            F = solve_contact(g, seg, 300.0).load
            q = F / g.line_length
            ours = [fast.slice_matrix(g, k) + fast.torsion_matrix(g, k) for k in (0, 1)]
            fe_contact = np.diag(fe.contact_diagonal(g, q)) + local
            weber = np.diag(fast.contact_diagonal(g, q))
            for k in g.pairs():
                i = g.pair == k
                if F[i].sum() < 0.05 * F.sum():
                    continue
                f, norm = F[i], F.sum() ** 2 * 1e-10
                for term, a, b in (
                    ("pinion", tooth[0], ours[0]),
                    ("gear", tooth[1], ours[1]),
                    ("contact", fe_contact, weber),
                ):
                    sums[term] += [f @ a[np.ix_(i, i)] @ f / norm, f @ b[np.ix_(i, i)] @ f / norm]
        sums["all"] = sum(sums.values())
        for term, (x, y) in sums.items():
            print(f"{flank:>5} {term:>8} {x:8.3f} {y:8.3f} {y / x:8.3f}", flush=True)


def k_hbeta_errors(compliance) -> list[float]:
    """K_Hbeta of the misaligned spur pair over the stored whole-gear FE's - 1, per
    misalignment (10, 20 um), mean of the two positions."""
    data = json.loads(KHBETA.read_text())["levels"]["FE (whole gear)"]
    out = []
    for entry in data:
        fe = np.mean([r["k_hbeta"] for r in entry["rows"]])
        fast = np.mean(
            [r["k_hbeta"] for r in mis.k_hbeta(compliance, entry["misalignment_um"])["rows"]]
        )
        out.append(float(fast / fe - 1))
    return out


def variant_table(cases, variants) -> None:
    print("mean stiffness / whole-gear FE - 1 (%), 150 / 300 / 450 N m; gap: drive - coast at 300")
    for name, comp in variants.items():
        err = 100 * rip.calibration_errors(cases, FLANKS, comp).reshape(len(cases), 2, 3)
        par = rip.parallel_errors(comp)
        khb = k_hbeta_errors(comp)
        print(f"\n{name}")
        for i, case in enumerate(cases):
            d, c = (" / ".join(f"{v:+5.1f}" for v in err[i, j]) for j in (0, 1))
            print(f"  {case}  drive {d}   coast {c}   gap {err[i, 0, 1] - err[i, 1, 1]:4.1f}")
        print(
            "  parallel pairs: "
            + ", ".join(f"{k} {100 * v:+.1f} %" for k, v in par.items())
            + f"; K_Hbeta at 10 / 20 um: {100 * khb[0]:+.1f} / {100 * khb[1]:+.1f} %",
            flush=True,
        )


def split_table(cases) -> None:
    print(
        "\nat 300 N m, mesh compliance 1/k in 1e-10 m/N: FE segment + FE far field = FE whole;"
        " fast unshared + fast far field and tilt = fast"
    )
    print(
        f"{'case':>4} {'flank':>5} {'FE seg':>7} {'FE far':>7} {'FE whole':>8} "
        f"{'fast uns.':>9} {'fast far':>8} {'fast':>7} {'uns./seg':>8} {'far/far':>8}"
    )
    for case in cases:
        for flank in FLANKS:
            _, _, grids = rip.case_grids(case, flank)
            run = rip.stored_fe(case, flank)
            i = run["torques_Nm"].index(300.0)
            seg = 1e10 / run["mean_stiffness_N_per_m"][i]
            whole = 1e10 / rip.whole_gear_stiffness(case, flank)[i]
            even = FastCompliance(between_pairs="even")
            fast = 1e10 / rip.cycle(grids, [300.0], even).stiffness.mean()
            uns = 1e10 / rip.cycle(grids, [300.0], Unshared(between_pairs="even")).stiffness.mean()
            print(
                f"{case:>4} {flank:>5} {seg:7.2f} {whole - seg:7.2f} {whole:8.2f} "
                f"{uns:9.2f} {fast - uns:8.2f} {fast:7.2f} {uns / seg:8.3f} "
                f"{(fast - uns) / (whole - seg):8.3f}",
                flush=True,
            )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="+", default=["01", "02", "03", "04"])
    ap.add_argument("--only", nargs="+", metavar="WORD", help="the variants whose name has one")
    ap.add_argument("--no-split", action="store_true", help="leave out the split at 300 N m")
    ap.add_argument("--own-terms", metavar="CASE", help="only the FE level's own terms (minutes)")
    ap.add_argument("--positions", nargs="+", type=int, default=[0, 8, 16])
    ap.add_argument("--refine", type=float, default=1.0, help="FE mesh refinement (--own-terms)")
    ap.add_argument(
        "--contact",
        choices=["centre_line", "matching_depth"],
        default="centre_line",
        help="the fast level's contact reference (--own-terms)",
    )
    a = ap.parse_args(argv)
    if a.own_terms:
        own_terms(a.own_terms, a.positions, a.refine, a.contact)
        return 0
    variants = {
        "default": FastCompliance(),
        "face ends": FastCompliance(helix_ends=cm.HELIX_ENDS),
        "foundation 1.0": FoundationCoupled(foundation_length=1.0),
        "foundation 1.5": FoundationCoupled(foundation_length=1.5),
        "rocking 10": Rocking(rocking=10.0),
        "rocking 30": Rocking(rocking=30.0),
        "pairs even (the earlier default)": FastCompliance(between_pairs="even"),
        "pairs plane x 1.0": FastCompliance(pair_coupling_scale=1.0),
        "contact along the line": LineContact(),
        "contact to the matching depth": FastCompliance(contact="matching_depth"),
    }
    if a.only:
        variants = {k: v for k, v in variants.items() if any(w in k for w in a.only)}
    variant_table(a.cases, variants)
    if not a.no_split:
        split_table(a.cases)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
