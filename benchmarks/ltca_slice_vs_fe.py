"""The slice model of the fast level against the FE tooth under uniform line loads.

One tooth, a unit force along the flank normal spread evenly over the whole face at
``--heights`` heights of the active profile (so that every transverse section of the
3-D tooth carries the same line load, as a 2-D slice does), per unit face width:

- FE (``gearbox.fe.line_load``): the segment of the FE level (loaded tooth and one
  neighbour each side, bore and cut faces clamped), read along the load at the
  tooth's mid-surface ("centre") and at the matching depth 0.25 m_n ("depth"); the
  same with every tooth clamped at the root circle (the tooth alone on a rigid body:
  "tooth"); "foundation" = segment - tooth; "far field" = the whole gear - the
  segment, from coarse segments of 1-5 clamped and 3-5 free neighbours extrapolated
  as the FE level does (``gearbox.fe.extent.extent_limit``); "d -> centre" = depth -
  centre, the compression between the matching depth and the mid-surface;
- slice model (``gearbox.ltca.slice_model``): bending, shear, axial compression (the
  beam, clamped at the root circle), Sainsot's fillet foundation (body torsion
  included) and the body torsion alone, and Weber's half-plane compression between
  the same two depths, ``2 (1 - nu^2) / (pi E) ln(h / d)`` per unit line load;
  and the tooth as a plane-strain FE body clamped at the root circle
  (``gearbox.ltca.slice_fe``, ``FastCompliance(tooth="fe")``), read at the centre
  line and at the matching depth (``FastCompliance(contact="matching_depth")``)
  against the FE tooth read there, and the whole virtual spur gear in plane strain
  (``slice_fe.whole_gear_compliance``, its number of teeth rounded) against the FE's
  whole gear (segment + far field).

    python benchmarks/ltca_slice_vs_fe.py                    # spur z 30/45 and case 03
    python benchmarks/ltca_slice_vs_fe.py --refine 1.0 --json tests/data/fe_slice_line_load.json
    python benchmarks/ltca_slice_vs_fe.py --stored tests/data/fe_slice_line_load.json \
        --beam-at centre_line                                # no FE run
    python benchmarks/ltca_slice_vs_fe.py --pairs case03_beta0 case03_beta10 case03_beta30 \
        --refine 1.0 --beam-at centre_line --json tests/data/fe_slice_line_load_helix.json

``--beam-at`` picks where the slice beam's deflection is taken
(``slice_compliance(beam_at=...)``: the load point or where the load's line crosses
the tooth's centre line, the point the FE's "centre" is read at); ``--stored`` takes
the FE numbers of a stored run instead of running the FE level.

Compliances in 1e-11 m per N/m of face width (m^2/N). ``--refine`` is the mesh
(``MeshOptions().refined(REFINE)``, 1.0 the FE level's default); the far field is
always from the coarse extent mesh of the FE level (``refined(0.5)``).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from gearbox.fe import MeshOptions  # noqa: E402
from gearbox.fe.compliance import gear_loads  # noqa: E402
from gearbox.fe.extent import extent_limit  # noqa: E402
from gearbox.fe.line_load import line_load_compliance  # noqa: E402
from gearbox.ltca import ParallelPair, parallel_grid  # noqa: E402
from gearbox.ltca.slice_fe import fe_tooth_compliance, whole_gear_compliance  # noqa: E402
from gearbox.ltca.slice_model import body_torsion, normal_section, slice_compliance  # noqa: E402

#: The two teeth of the experiment: the spur pinion z 30 of docs/fe.md's pair z 30/45,
#: m 4, b 30, and case 03's pinion as a cylindrical helical gear (the paper's cone
#: angle of 1 deg left out: a uniform line load needs the same height along the face).
PAIRS = {
    "spur": ParallelPair(4e-3, math.radians(20.0), 0.0, (30, 45), face_width=0.03),
    "case03": ParallelPair(
        6e-3,
        math.radians(20.0),
        math.radians(20.0),
        (29, 45),
        profile_shift=(0.16 / math.cos(math.radians(20.0)), 0.0),
        face_width=0.04,
        root_radius_coefficient=0.25,
        youngs_modulus=206e9,
    ),
}
# case 03's pinion at other helix angles (the same normal module, profile shift, face
# and number of teeth): how the 3-D whole gear departs from its normal section's 2-D
# virtual spur gear as the helix angle grows
for _deg in (0, 10, 30):
    PAIRS[f"case03_beta{_deg}"] = replace(PAIRS["case03"], helix_angle=math.radians(_deg))
UNIT = 1e-11


def heights(pair: ParallelPair, n: int) -> np.ndarray:
    """n load radii (m) evenly spaced in roll length over the pinion's flank from the
    form circle to the tip, 5 % of it kept clear at both ends."""
    rb = pair.base_radius(0)
    xf = math.sqrt(max(pair.form_radius(0) ** 2 - rb**2, 0.0))
    xa = math.sqrt(pair.tip_radius(0) ** 2 - rb**2)
    x = xf + (xa - xf) * np.linspace(0.05, 0.95, n)
    return np.sqrt(rb**2 + x**2)


def slice_terms(
    pair: ParallelPair, radii, contact_depths, matching_depth, beam_at: str = "load_point"
) -> dict:
    """The slice model's terms per unit face width along the flank normal (m^2/N);
    beam_at: ``slice_compliance(beam_at=...)``."""
    g = parallel_grid(pair, 0.0, 8)
    s = replace(g.tooth1.take(np.zeros(radii.size, int)), radius=np.asarray(radii))
    v, factor = normal_section(s)
    E, nu = g.youngs_modulus, g.poisson_ratio
    cb = math.cos(pair.base_helix_angle)
    weber = 2 * (1 - nu**2) / (math.pi * E) * np.log(contact_depths / matching_depth) * cb
    out = {
        "torsion": body_torsion(v, E / (2 * (1 + nu))) * factor,
        "weber_d_to_centre": weber,
    }
    out["plane strain tooth"] = fe_tooth_compliance(v, E, nu) * factor
    depth = matching_depth / pair.normal_module  # read at the FE level's matching depth
    out["plane strain tooth at d"] = fe_tooth_compliance(v, E, nu, depth=depth) * factor
    # the whole (virtual spur) gear in plane strain, its number of teeth rounded
    zv = int(round(float(v.teeth[0])))
    out["plane strain gear"] = whole_gear_compliance(v, E, nu, zv) * factor
    for root, pre in (("radial", ""), ("fillet", "fillet ")):
        c = slice_compliance(v, E, nu, root=root, beam_at=beam_at)
        for k, part in enumerate(("bending", "shear", "axial", "foundation")):
            out[pre + part] = c[k] * factor
    return out


def fe_terms(pair: ParallelPair, radii, refine: float, extent: bool) -> dict:
    g = parallel_grid(pair, 0.0, 8)
    L = gear_loads(g, 0)
    kw = dict(
        bore_radius=L.bore_radius,
        youngs_modulus=g.youngs_modulus,
        poisson_ratio=g.poisson_ratio,
    )
    mesh = MeshOptions().refined(refine)
    t0 = time.perf_counter()
    seg = line_load_compliance(L.blank, L.side, radii, options=mesh, **kw)
    tooth = line_load_compliance(L.blank, L.side, radii, options=mesh, clamp_root=True, **kw)
    out = {
        "segment_centre": seg.centre,
        "segment_depth": seg.depth,
        "tooth_centre": tooth.centre,
        "tooth_depth": tooth.depth,
        "centre_depth_m": seg.centre_depth,
        "matching_depth_m": seg.matching_depth,
        "n_dofs": seg.n_dofs,
    }
    if extent:
        coarse = MeshOptions().refined(0.5)
        seq = {}
        for bc, ks in (("clamped", range(1, 6)), ("free", range(3, 6))):
            seq[bc] = [
                line_load_compliance(
                    L.blank,
                    L.side,
                    radii,
                    options=coarse,
                    neighbours=k,
                    clamp_cut_faces=bc == "clamped",
                    **kw,
                ).centre
                for k in ks
            ]
        lim, err = extent_limit(np.array(seq["clamped"]), np.array(seq["free"]))
        out["far_field"] = lim - seq["clamped"][0]
        out["far_field_uncertainty"] = err
    out["seconds"] = time.perf_counter() - t0
    return out


def table(name: str, pair: ParallelPair, radii, fe: dict, sl: dict) -> None:
    rf = pair.root_radius(0)
    print(f"\n{name}: compliance per unit face width (1e-11 m^2/N), load height above the root")
    head = (
        f"{'h (mm)':>7} | {'FE tooth':>8} {'beam':>6} {'ratio':>5} | {'bend':>6} {'shear':>6} "
        f"{'axial':>6} | {'FE fdn':>6} {'Sainsot':>7} {'ratio':>5} {'tors':>5} | "
        f"{'FE far':>6} | {'FE d->c':>7} {'Weber':>6} | {'FE seg':>6} {'slices':>6} {'ratio':>5}"
    )
    print(head)
    print("  whole-gear foundation (FE: foundation + far field) and the fillet root:")
    for i, r in enumerate(radii):
        beam = sl["bending"][i] + sl["shear"][i] + sl["axial"][i]
        fdn = fe["segment_centre"][i] - fe["tooth_centre"][i]
        far = fe.get("far_field", np.full(radii.size, np.nan))[i]
        dc = fe["segment_depth"][i] - fe["segment_centre"][i]
        tot = beam + sl["foundation"][i]
        print(
            f"{(r - rf) * 1e3:7.2f} | {fe['tooth_centre'][i] / UNIT:8.3f} {beam / UNIT:6.3f} "
            f"{beam / fe['tooth_centre'][i]:5.2f} | {sl['bending'][i] / UNIT:6.3f} "
            f"{sl['shear'][i] / UNIT:6.3f} {sl['axial'][i] / UNIT:6.3f} | {fdn / UNIT:6.3f} "
            f"{sl['foundation'][i] / UNIT:7.3f} {sl['foundation'][i] / fdn:5.2f} "
            f"{sl['torsion'][i] / UNIT:5.3f} | {far / UNIT:6.3f} | {dc / UNIT:7.3f} "
            f"{sl['weber_d_to_centre'][i] / UNIT:6.3f} | {fe['segment_centre'][i] / UNIT:6.3f} "
            f"{tot / UNIT:6.3f} {tot / fe['segment_centre'][i]:5.2f}"
        )
    print(
        f"{'h (mm)':>7} | {'FE fdn+far':>10} {'Sainsot':>7} {'ratio':>5} {'fillet':>6} {'ratio':>5} "
        f"| {'FE tooth':>8} {'beam, fillet':>12} {'ratio':>5} | {'plane strain':>12} {'ratio':>5} "
        f"| {'FE whole':>8} {'2-D gear':>8} {'ratio':>5}"
    )
    whole_fe = fe["segment_centre"] + fe.get("far_field", np.full(radii.size, np.nan))
    for i, r in enumerate(radii):
        whole = fe["segment_centre"][i] - fe["tooth_centre"][i]
        whole = whole + fe.get("far_field", np.full(radii.size, np.nan))[i]
        beam = sl["fillet bending"][i] + sl["fillet shear"][i] + sl["fillet axial"][i]
        print(
            f"{(r - rf) * 1e3:7.2f} | {whole / UNIT:10.3f} {sl['foundation'][i] / UNIT:7.3f} "
            f"{sl['foundation'][i] / whole:5.2f} {sl['fillet foundation'][i] / UNIT:6.3f} "
            f"{sl['fillet foundation'][i] / whole:5.2f} | {fe['tooth_centre'][i] / UNIT:8.3f} "
            f"{beam / UNIT:12.3f} {beam / fe['tooth_centre'][i]:5.2f} | "
            f"{sl['plane strain tooth'][i] / UNIT:12.3f} "
            f"{sl['plane strain tooth'][i] / fe['tooth_centre'][i]:5.2f} | "
            f"{whole_fe[i] / UNIT:8.3f} {sl['plane strain gear'][i] / UNIT:8.3f} "
            f"{sl['plane strain gear'][i] / whole_fe[i]:5.2f}"
        )
    print(
        f"{'h (mm)':>7} | {'FE tooth at d':>13} {'plane strain at d':>17} {'ratio':>5} | "
        f"compression d -> centre over Weber's: {'FE tooth':>8} {'plane strain':>12}"
    )
    for i, r in enumerate(radii):
        at_d = sl["plane strain tooth at d"][i]
        w = sl["weber_d_to_centre"][i]
        print(
            f"{(r - rf) * 1e3:7.2f} | {fe['tooth_depth'][i] / UNIT:13.3f} {at_d / UNIT:17.3f} "
            f"{at_d / fe['tooth_depth'][i]:5.2f} | {'':>38}"
            f"{(fe['tooth_depth'][i] - fe['tooth_centre'][i]) / w:8.2f} "
            f"{(at_d - sl['plane strain tooth'][i]) / w:12.2f}"
        )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pairs", nargs="+", default=["spur", "case03"], choices=list(PAIRS))
    ap.add_argument("--heights", type=int, default=6)
    ap.add_argument("--refine", type=float, default=0.5, help="FE mesh refinement")
    ap.add_argument("--no-extent", action="store_true", help="skip the far-field study")
    ap.add_argument("--json", type=Path)
    ap.add_argument("--beam-at", default="load_point", choices=("load_point", "centre_line"))
    ap.add_argument("--stored", type=Path, help="the FE numbers of a stored --json run")
    a = ap.parse_args(argv)
    out = {"command": "python benchmarks/ltca_slice_vs_fe.py " + " ".join(argv or sys.argv[1:])}
    out["runs"] = []
    stored = {}
    if a.stored is not None:
        for run in json.loads(a.stored.read_text())["runs"]:
            stored[run["pair"]] = run
    print(f"slice beam read at the {a.beam_at.replace('_', ' ')}")
    for name in a.pairs:
        pair = PAIRS[name]
        if name in stored:
            radii = np.asarray(stored[name]["radius_m"])
            fe = {k: np.asarray(v) for k, v in stored[name]["fe_m2_per_N"].items()}
        else:
            radii = heights(pair, a.heights)
            fe = fe_terms(pair, radii, a.refine, not a.no_extent)
        depths = fe["centre_depth_m"]
        sl = slice_terms(pair, radii, depths, float(fe["matching_depth_m"]), a.beam_at)
        table(name, pair, radii, fe, sl)
        print(f"  FE: {int(fe['n_dofs'])} unknowns, {float(fe['seconds']):.0f} s")
        out["runs"].append(
            {
                "pair": name,
                "refine": a.refine,
                "radius_m": radii.tolist(),
                "fe_m2_per_N": {
                    k: (np.asarray(v).tolist() if np.ndim(v) else v) for k, v in fe.items()
                },
                "slice_m2_per_N": {k: np.asarray(v).tolist() for k, v in sl.items()},
            }
        )
    if a.json is not None:
        a.json.write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
