"""Code generation: ``config.h``, ``model.c`` and ``modelDescription.xml`` from an
:class:`~gearbox.fmu.spec.FmuModel` (plain string templates, no template engine).

The XML follows the FMI 2.0.4 standard (sections 2.2 and 3.3: ModelVariables,
ModelStructure with Outputs, Derivatives and InitialUnknowns); units are declared in
UnitDefinitions with their SI base-unit exponents.
"""

from __future__ import annotations

import hashlib
import math
import uuid
from dataclasses import replace
from xml.sax.saxutils import quoteattr

from .spec import KINDS, FmuModel, Variable

__all__ = [
    "SOLVER_VARIABLES",
    "config_h",
    "guid",
    "model_c",
    "model_description",
    "model_description_fmi3",
    "variables_markdown",
    "with_solver",
]

#: Parameters of the internal Co-Simulation integrator, added to every FMU.
SOLVER_VARIABLES = (
    Variable(
        "solver.rtol",
        "parameter",
        "1",
        "Relative tolerance of the internal DOPRI5 integrator (Co-Simulation, solver.method "
        "= 0); the "
        "absolute tolerance of each state is rtol times its nominal value.",
        start=1e-8,
        min=1e-14,
        max=0.1,
    ),
    Variable(
        "solver.max_step",
        "parameter",
        "s",
        "Largest internal step of the DOPRI5 integrator (Co-Simulation) (s, > 0).",
        start=1e-3,
        min=0.0,
        max=1.0,
        min_open=True,
    ),
    Variable(
        "solver.method",
        "parameter",
        "1",
        "Co-Simulation integrator: 1 = fixed-step Tsit5 (step from the model, solver.fixed_step), "
        "handing intervals that end out of the nominal mesh contact to adaptive DOPRI5 steps at "
        "solver.contact_rtol; 0 = adaptive DOPRI5 at solver.rtol.",
        start=1.0,
        min=0.0,
        max=1.0,
    ),
    Variable(
        "solver.fixed_step",
        "parameter",
        "s",
        "Step of the fixed-step integrator (s): 0 = automatic, 1 / (solver.steps_per_period "
        "f_max) with f_max the larger of the highest eigenfrequency of the model linearised "
        "with the mesh at its largest stiffness and the mesh frequency, at most 1 / "
        "(solver.steps_per_mesh_period f_mesh) and 0.8 x the stability limit; > 0: this "
        "step (at most the stability limit).",
        start=0.0,
        min=0.0,
        max=1.0,
    ),
    Variable(
        "solver.steps_per_period",
        "parameter",
        "1",
        "Fixed steps per period of f_max for the automatic step (>= 2).",
        start=12.0,
        min=2.0,
        max=1e4,
    ),
    Variable(
        "solver.steps_per_mesh_period",
        "parameter",
        "1",
        "The automatic fixed step is also at most 1 / (this x the mesh frequency) (the "
        "forcing frequency of engine and propeller FMUs): the mesh laws' higher harmonics "
        "(>= 2).",
        start=32.0,
        min=2.0,
        max=1e4,
    ),
    Variable(
        "solver.contact_rtol",
        "parameter",
        "1",
        "Relative tolerance of the adaptive DOPRI5 steps that replace fixed steps out of the "
        "nominal mesh contact.",
        start=1e-9,
        min=1e-14,
        max=0.1,
    ),
    Variable(
        "solver.step_size",
        "output",
        "s",
        "Step of the fixed-step integrator in use (s; a communication step gets equal steps "
        "no longer than this).",
    ),
    Variable(
        "solver.stability_limit",
        "output",
        "s",
        "Largest stable fixed Tsit5 step on the model linearised at peak mesh stiffness (s).",
    ),
    Variable(
        "solver.handed_over",
        "output",
        "1",
        "Fixed-step intervals integrated with adaptive steps after contact loss, since "
        "instantiation.",
    ),
    Variable(
        "solver.steps",
        "output",
        "1",
        "Accepted integrator steps since instantiation (Model Exchange: completed steps of the importer's integrator).",
    ),
    Variable(
        "solver.rejected",
        "output",
        "1",
        "Rejected internal integrator steps since instantiation (Co-Simulation).",
    ),
    Variable(
        "solver.rhs_evaluations",
        "output",
        "1",
        "Right-hand side evaluations since instantiation.",
    ),
)

#: unit -> SI base-unit exponents (FMI 2.0.4 section 2.2.2) and optional display unit.
UNITS: dict[str, tuple[dict[str, int], tuple[str, float] | None]] = {
    "1": ({}, None),
    "s": ({"s": 1}, None),
    "rad": ({"rad": 1}, None),
    "rad/s": ({"rad": 1, "s": -1}, ("rpm", 60.0 / (2.0 * math.pi))),
    "rad/s2": ({"rad": 1, "s": -2}, None),
    "m": ({"m": 1}, None),
    "m/s": ({"m": 1, "s": -1}, None),
    "N": ({"kg": 1, "m": 1, "s": -2}, None),
    "N/m": ({"kg": 1, "s": -2}, None),
    "N.s/m": ({"kg": 1, "s": -1}, None),
    "N.m": ({"kg": 1, "m": 2, "s": -2}, None),
    "N.m/s": ({"kg": 1, "m": 2, "s": -3}, None),
    "W": ({"kg": 1, "m": 2, "s": -3}, None),
    "N.m/rad": ({"kg": 1, "m": 2, "s": -2, "rad": -1}, None),
    "N.m.s/rad": ({"kg": 1, "m": 2, "s": -1, "rad": -1}, None),
    "N.m.s2/rad2": ({"kg": 1, "m": 2, "rad": -2}, None),
    "kg.m2": ({"kg": 1, "m": 2}, None),
    "kg": ({"kg": 1}, None),
}


def with_solver(model: FmuModel) -> FmuModel:
    """The model with the integrator parameters appended (once)."""
    names = {v.name for v in model.variables}
    extra = tuple(v for v in SOLVER_VARIABLES if v.name not in names)
    return replace(model, variables=model.variables + extra)


def guid(model: FmuModel) -> str:
    """A GUID that changes whenever the variables, the code or the tables change."""
    h = hashlib.sha256()
    h.update(model.identifier.encode())
    h.update(repr(model.variables).encode())
    h.update(model.c_data.encode())
    h.update(model.c_code.encode())
    for name in sorted(model.resources):
        h.update(name.encode())
        h.update(model.resources[name].encode())
    return "{" + str(uuid.UUID(h.hexdigest()[:32])) + "}"


def _c_double(x: float) -> str:
    if math.isinf(x):
        return "HUGE_VAL" if x > 0 else "-HUGE_VAL"
    return repr(float(x))


def config_h(model: FmuModel) -> str:
    """``config.h``: identifier, GUID, sizes, value references, model data struct."""
    lines = [
        f"/* config.h of {model.identifier}: generated by gearbox.fmu.codegen; do not edit. */",
        "#ifndef config_h",
        "#define config_h",
        "",
        f"#define MODEL_IDENTIFIER {model.identifier}",
        f'#define MODEL_GUID "{guid(model)}"',
        "",
        "/* capability flags (the same as in modelDescription.xml) */",
        "#define GBX_MODEL_EXCHANGE 1",
        "#define GBX_CO_SIMULATION 1",
        "#define GBX_CAN_GET_SET_FMU_STATE 0",
        "",
        f"#define GBX_NR {len(model.variables)}",
        f"#define GBX_NX {len(model.states)}",
        "#define NUMBER_OF_EVENT_INDICATORS 0",
        "",
        "/* value references */",
    ]
    for i, v in enumerate(model.variables):
        lines.append(f"#define VR_{v.c_name} {i}")
    lines += ["", "/* state indices */"]
    for i, v in enumerate(model.states):
        lines.append(f"#define X_{v.c_name} {i}")
    lines += [
        "",
        "#define GBX_VR_SOLVER_RTOL VR_solver_rtol",
        "#define GBX_VR_SOLVER_MAX_STEP VR_solver_max_step",
        "#define GBX_VR_SOLVER_STEPS VR_solver_steps",
        "#define GBX_VR_SOLVER_REJECTED VR_solver_rejected",
        "#define GBX_VR_SOLVER_RHS VR_solver_rhs_evaluations",
        "#define GBX_VR_SOLVER_METHOD VR_solver_method",
        "#define GBX_VR_SOLVER_FIXED_STEP VR_solver_fixed_step",
        "#define GBX_VR_SOLVER_STEPS_PER_PERIOD VR_solver_steps_per_period",
        "#define GBX_VR_SOLVER_CONTACT_RTOL VR_solver_contact_rtol",
        "#define GBX_VR_SOLVER_STEPS_PER_FORCING VR_solver_steps_per_mesh_period",
        "#define GBX_VR_SOLVER_STEP_SIZE VR_solver_step_size",
        "#define GBX_VR_SOLVER_STABILITY_LIMIT VR_solver_stability_limit",
        "#define GBX_VR_SOLVER_HANDED_OVER VR_solver_handed_over",
        "",
        "typedef struct {",
        model.c_data.rstrip() or "    int unused;",
        "} GbxModelData;",
        "",
        "#endif /* config_h */",
        "",
    ]
    return "\n".join(lines)


def _vars_table(model: FmuModel) -> str:
    state_index = {v.name: i for i, v in enumerate(model.states)}
    vr = {v.name: i for i, v in enumerate(model.variables)}
    rows = []
    for v in model.variables:
        if v.kind == "state":
            index = state_index[v.name]
        elif v.kind == "derivative":
            index = state_index[v.derivative_of]
        elif v.kind == "input" and v.rate:
            index = vr[v.rate]
        else:
            index = -1
        start = 0.0 if v.start is None else v.start
        rows.append(
            f'    {{"{v.name}", {KINDS.index(v.kind)}, {index}, {_c_double(start)}, '
            f"{_c_double(v.min)}, {_c_double(v.max)}, {int(v.min_open)}, {int(v.max_open)}, "
            f"{_c_double(v.nominal)}, {int(v.fixed)}}}, /* vr {vr[v.name]} {v.kind} */"
        )
    return "const gbx_var GBX_VARS[GBX_NR] = {\n" + "\n".join(rows) + "\n};\n"


def model_c(model: FmuModel) -> str:
    """``model.c``: the variable table and the model hooks."""
    head = (
        f"/* model.c of {model.identifier}: generated by gearbox.fmu.codegen; do not edit.\n"
        f" * {model.description}\n"
        " * Equations: see readme.md in this folder. */\n"
        "#include <math.h>\n#include <stdio.h>\n#include <string.h>\n\n"
        '#include "gbx_model.h"\n\n'
        "#define P(name) (m->r[VR_##name])\n\n"
    )
    return head + _vars_table(model) + "\n" + model.c_code.strip() + "\n"


def _unit_definitions(units: set[str]) -> list[str]:
    out = ["  <UnitDefinitions>"]
    for u in sorted(units):
        if u not in UNITS:
            raise ValueError(f"unit {u!r} has no definition in gearbox.fmu.codegen.UNITS")
        base, display = UNITS[u]
        attrs = " ".join(f'{k}="{e}"' for k, e in base.items())
        out.append(f"    <Unit name={quoteattr(u)}>")
        out.append(f"      <BaseUnit {attrs}/>" if attrs else "      <BaseUnit/>")
        if display:
            out.append(f'      <DisplayUnit name="{display[0]}" factor="{display[1]!r}"/>')
        out.append("    </Unit>")
    out.append("  </UnitDefinitions>")
    return out


_SOURCE_FILES = (
    "    <SourceFiles>",
    '      <File name="fmi2_runtime.c"/>',
    '      <File name="model.c"/>',
    "    </SourceFiles>",
)


def _num(x: float) -> str:
    return repr(float(x))


def _causality(v: Variable, fmi_version: int) -> list[str]:
    """causality, variability, initial of a variable (FMI 2.0 section 2.2.7, FMI 3.0
    section 2.4.7; FMI 3.0 takes no ``initial`` on parameters here)."""
    if v.kind == "parameter":
        out = ['causality="parameter"', f'variability="{"fixed" if v.fixed else "tunable"}"']
        return out + (['initial="exact"'] if fmi_version == 2 else [])
    if v.kind == "input":
        return ['causality="input"', 'variability="continuous"']
    causality = "output" if v.kind == "output" else "local"
    return [f'causality="{causality}"', 'variability="continuous"', 'initial="calculated"']


def _value_attrs(v: Variable, derivative_of: int | None) -> list[str]:
    """unit, displayUnit, derivative (index or value reference of the state), nominal,
    start, min, max of a real variable."""
    out = []
    if v.unit:
        out.append(f"unit={quoteattr(v.unit)}")
        if UNITS[v.unit][1]:
            out.append(f'displayUnit="{UNITS[v.unit][1][0]}"')
    if v.kind == "derivative":
        out.append(f'derivative="{derivative_of}"')
    if v.kind == "state":
        out.append(f'nominal="{_num(v.nominal)}"')
    if v.kind in ("parameter", "input"):
        out.append(f'start="{_num(v.start)}"')
        if math.isfinite(v.min):
            out.append(f'min="{_num(v.min)}"')
        if math.isfinite(v.max):
            out.append(f'max="{_num(v.max)}"')
    return out


def model_description(model: FmuModel, *, generation_tool: str = "gearbox") -> str:
    """``modelDescription.xml`` for FMI 2.0, Model Exchange and Co-Simulation."""
    ident = model.identifier
    units = {v.unit for v in model.variables if v.unit}
    index = {v.name: i + 1 for i, v in enumerate(model.variables)}  # 1-based (FMI 2.0)
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        "<fmiModelDescription",
        '  fmiVersion="2.0"',
        f"  modelName={quoteattr(ident)}",
        f'  guid="{guid(model)}"',
        f"  description={quoteattr(model.description)}",
        f"  generationTool={quoteattr(generation_tool)}",
        '  variableNamingConvention="structured"',
        '  numberOfEventIndicators="0">',
        f'  <ModelExchange modelIdentifier="{ident}" canNotUseMemoryManagementFunctions="true"'
        ' canGetAndSetFMUstate="false" canSerializeFMUstate="false">',
        *_SOURCE_FILES,
        "  </ModelExchange>",
        f'  <CoSimulation modelIdentifier="{ident}" canHandleVariableCommunicationStepSize="true"'
        ' canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="false"'
        ' canSerializeFMUstate="false">',
        *_SOURCE_FILES,
        "  </CoSimulation>",
    ]
    lines += _unit_definitions(units)
    lines += [
        "  <LogCategories>",
        '    <Category name="logEvents" description="Instantiation, termination, solver work"/>',
        '    <Category name="logStatusError" description="Errors: invalid arguments, parameters,'
        ' resources, integration failures"/>',
        "  </LogCategories>",
        f'  <DefaultExperiment startTime="0" stopTime="{_num(model.stop_time)}"'
        f' stepSize="{_num(model.step_size)}"/>',
        "  <ModelVariables>",
    ]
    for i, v in enumerate(model.variables):
        desc = v.description
        attrs = [f"name={quoteattr(v.name)}", f'valueReference="{i}"']
        if desc:
            attrs.append(f"description={quoteattr(desc)}")
        attrs += _causality(v, 2)
        real = _value_attrs(v, index.get(v.derivative_of))
        lines.append(f"    <!-- {i + 1} -->")
        lines.append(f"    <ScalarVariable {' '.join(attrs)}>")
        lines.append(f"      <Real {' '.join(real)}/>")
        lines.append("    </ScalarVariable>")
    lines += ["  </ModelVariables>", "  <ModelStructure>"]
    outputs = [index[v.name] for v in model.by_kind("output")]
    derivs = [index[v.name] for v in model.by_kind("derivative")]
    states = [index[v.name] for v in model.states]
    if outputs:
        lines.append("    <Outputs>")
        lines += [f'      <Unknown index="{k}"/>' for k in outputs]
        lines.append("    </Outputs>")
    if derivs:
        lines.append("    <Derivatives>")
        lines += [f'      <Unknown index="{k}"/>' for k in derivs]
        lines.append("    </Derivatives>")
    initial = sorted(outputs + derivs + states)
    if initial:
        lines.append("    <InitialUnknowns>")
        lines += [f'      <Unknown index="{k}"/>' for k in initial]
        lines.append("    </InitialUnknowns>")
    lines += ["  </ModelStructure>", "</fmiModelDescription>", ""]
    return "\n".join(lines)


def variables_markdown(model: FmuModel) -> str:
    """The FMU's variables as a Markdown table (value reference, causality, unit,
    start, accepted range, description)."""
    lines = [
        "## Variables",
        "",
        "| vr | name | kind | unit | start | accepted values | description |",
        "|---|---|---|---|---|---|---|",
    ]
    for i, v in enumerate(model.variables):
        if v.kind in ("parameter", "input"):
            lo = "(" if v.min_open or math.isinf(v.min) else "["
            hi = ")" if v.max_open or math.isinf(v.max) else "]"
            rng = f"{lo}{v.min:g}, {v.max:g}{hi}"
            start = f"{v.start:.6g}"
        else:
            rng = start = ""
        kind = (
            f"{v.kind} ({'fixed' if v.fixed else 'tunable'})" if v.kind == "parameter" else v.kind
        )
        lines.append(
            f"| {i} | `{v.name}` | {kind} | {v.unit} | {start} | {rng} | {v.description} |"
        )
    return "\n".join(lines) + "\n"


def model_description_fmi3(model: FmuModel, *, generation_tool: str = "gearbox") -> str:
    """``modelDescription.xml`` for FMI 3.0 (Model Exchange and Co-Simulation).

    The same variables and value references as FMI 2.0, plus the independent variable
    ``time`` (value reference = number of variables); derivatives refer to their
    state by value reference (FMI 3.0 section 2.4.7).
    """
    ident = model.identifier
    units = {v.unit for v in model.variables if v.unit} | {"s"}
    vr = {v.name: i for i, v in enumerate(model.variables)}
    common = ' canGetAndSetFMUState="false" canSerializeFMUState="false"'
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        "<fmiModelDescription",
        '  fmiVersion="3.0"',
        f"  modelName={quoteattr(ident)}",
        f'  instantiationToken="{guid(model)}"',
        f"  description={quoteattr(model.description)}",
        f"  generationTool={quoteattr(generation_tool)}",
        '  variableNamingConvention="structured">',
        f'  <ModelExchange modelIdentifier="{ident}"{common}/>',
        f'  <CoSimulation modelIdentifier="{ident}"{common}'
        ' canHandleVariableCommunicationStepSize="true" hasEventMode="false"/>',
    ]
    lines += _unit_definitions(units)
    lines += [
        "  <LogCategories>",
        '    <Category name="logEvents" description="Instantiation, termination, solver work"/>',
        '    <Category name="logStatusError" description="Errors: invalid arguments, parameters,'
        ' resources, integration failures"/>',
        "  </LogCategories>",
        f'  <DefaultExperiment startTime="0" stopTime="{_num(model.stop_time)}"'
        f' stepSize="{_num(model.step_size)}"/>',
        "  <ModelVariables>",
        f'    <Float64 name="time" valueReference="{len(model.variables)}" causality="independent"'
        ' variability="continuous" unit="s" description="Simulation time"/>',
    ]
    for i, v in enumerate(model.variables):
        attrs = [f"name={quoteattr(v.name)}", f'valueReference="{i}"']
        if v.description:
            attrs.append(f"description={quoteattr(v.description)}")
        attrs += _causality(v, 3) + _value_attrs(v, vr.get(v.derivative_of))
        lines.append(f"    <Float64 {' '.join(attrs)}/>")
    lines += ["  </ModelVariables>", "  <ModelStructure>"]
    outputs = [vr[v.name] for v in model.by_kind("output")]
    derivs = [vr[v.name] for v in model.by_kind("derivative")]
    states = [vr[v.name] for v in model.states]
    lines += [f'    <Output valueReference="{k}"/>' for k in outputs]
    lines += [f'    <ContinuousStateDerivative valueReference="{k}"/>' for k in derivs]
    lines += [
        f'    <InitialUnknown valueReference="{k}"/>' for k in sorted(outputs + derivs + states)
    ]
    lines += ["  </ModelStructure>", "</fmiModelDescription>", ""]
    return "\n".join(lines)
