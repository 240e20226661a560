"""The contact grids of the stored FE reference runs in ``tests/data/fe_*.json`` and
``ltca_root_stress_fe_*.json``: made before ``ltca.edge_borders`` became the default,
with each edge point on the last profile sample inside the flank border. A test that
compares the fast level with those runs builds its grids the same way
(``scene.replaced(ltca=SAMPLE_EDGES)``). The FE runs on the default grids, edge points
on the borders, are ``tests/data/fe_edge_borders_paper_cases.json``."""

SAMPLE_EDGES = {"edge_borders": False}
