"""What an FMU is made of, before any C is written: variables, equations, tables.

An :class:`FmuModel` is the single source of the generated ``config.h``, ``model.c``
and ``modelDescription.xml``: the min/max of a parameter in the XML and the range the
C code enforces in ``fmi2SetReal`` come from the same :class:`Variable`.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

__all__ = ["KINDS", "FmuModel", "Variable"]

#: Variable kinds, in the order of the C enumeration ``gbx_kind`` (gbx_model.h).
KINDS = ("parameter", "input", "output", "state", "derivative")

_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*(\.[A-Za-z][A-Za-z0-9_]*)*$")
_DER = re.compile(r"^der\(([A-Za-z][A-Za-z0-9_]*(\.[A-Za-z][A-Za-z0-9_]*)*)\)$")


@dataclass(frozen=True)
class Variable:
    """One real FMU variable.

    ``name`` is structured (``engine.inertia``); its C macro is ``VR_engine_inertia``.
    ``start`` is required for parameters and inputs. ``min``/``max`` bound the values
    accepted through the FMI API; ``min_open`` excludes the bound itself (the XML can
    only state the closed bound, the description says "> 0"). ``nominal`` scales the
    absolute tolerance of a state. ``rate`` (inputs only) names the input that is its
    time derivative: in Co-Simulation the input is extrapolated linearly with it over
    a communication step (an angle with its speed). ``derivative_of`` names the state
    of a derivative variable. ``fixed`` parameters (variability "fixed") can be set
    only before initialization ends (the operating point: speed, mean torque); the
    others are "tunable" during the run.
    """

    name: str
    kind: str
    unit: str = ""
    description: str = ""
    start: float | None = None
    min: float = -math.inf
    max: float = math.inf
    min_open: bool = False
    max_open: bool = False
    nominal: float = 1.0
    rate: str | None = None
    derivative_of: str | None = None
    fixed: bool = False

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"Variable {self.name!r}: kind {self.kind!r} not in {KINDS}")
        if not (_NAME.match(self.name) or (self.kind == "derivative" and _DER.match(self.name))):
            raise ValueError(f"Variable name {self.name!r} is not a structured identifier")
        if self.kind in ("parameter", "input") and self.start is None:
            raise ValueError(f"Variable {self.name!r}: a {self.kind} needs a start value")
        if self.kind == "derivative" and not self.derivative_of:
            raise ValueError(f"Variable {self.name!r}: a derivative needs derivative_of")

    @property
    def c_name(self) -> str:
        """C identifier part: ``der(q.x)`` becomes ``der_q_x``, dots become underscores."""
        return self.name.replace("der(", "der_").replace(")", "").replace(".", "_")


@dataclass(frozen=True)
class FmuModel:
    """An FMU before code generation.

    ``c_data`` is the body of ``struct GbxModelData`` (tables read at instantiation);
    ``c_code`` defines the model hooks declared in ``gbx_model.h``
    (``gbx_model_load``, ``gbx_model_free``, ``gbx_model_check``,
    ``gbx_model_initial_state``, ``gbx_model_derivatives``, ``gbx_model_outputs``);
    ``resources`` maps file names under ``resources/`` to their text; ``readme`` is
    the Markdown of the FMU folder (equations, variables); ``stop_time`` and
    ``step_size`` make the DefaultExperiment (s).
    """

    identifier: str
    description: str
    variables: tuple[Variable, ...]
    c_data: str
    c_code: str
    resources: dict[str, str] = field(default_factory=dict)
    readme: str = ""
    stop_time: float = 1.0
    step_size: float = 1e-4

    def __post_init__(self) -> None:
        names = [v.name for v in self.variables]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ValueError(f"FmuModel {self.identifier}: duplicate variables {sorted(dup)}")
        if not re.match(r"^[A-Za-z_][A-Za-z0-9_]*$", self.identifier):
            raise ValueError(f"FmuModel identifier {self.identifier!r} is not a C identifier")
        known = set(names)
        for v in self.variables:
            for ref in (v.rate, v.derivative_of):
                if ref is not None and ref not in known:
                    raise ValueError(f"Variable {v.name!r} refers to unknown {ref!r}")

    def by_kind(self, kind: str) -> list[Variable]:
        return [v for v in self.variables if v.kind == kind]

    def vr(self, name: str) -> int:
        """Value reference of a variable (its index)."""
        for i, v in enumerate(self.variables):
            if v.name == name:
                return i
        raise KeyError(name)

    @property
    def states(self) -> list[Variable]:
        return self.by_kind("state")
