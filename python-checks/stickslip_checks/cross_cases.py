"""The cases of the cross-platform comparison (stickslip_checks.cross_platform): what each
run sets, steps and records, as a plan for the C driver `fmu-build/cross-driver/fmi_driver.c`.

- StickSlipBeam on the paper scene's breakaway and first slip at each structural fidelity
  with each law (the analytical, the network, LuGre, rate-and-state, the learned law with
  memory), every output recorded, the law state's outputs among them;
- NeuralFriction with either memoryless law over a grid of inputs (one step each: the
  outputs depend on the inputs only);
- NeuralFriction with each law with state (LuGre, rate-and-state with the aging and the
  slip evolution, the learned law with either evolution) over a stepped history of
  sliding velocity and normal force (`HISTORY`): the state is integrated over each
  communication step, so the comparison covers the state's exact step (its exp, expm1,
  ln) and the force at the committed state (asinh, the correction network).

Every input is written as the hex bits of its double, so no C library's decimal parser
decides an input.
"""

from __future__ import annotations

import json
import struct
from dataclasses import dataclass
from pathlib import Path

from .artifacts import BEAM, FRICTION, Model, fidelities

# The paper scene's breakaway (about 0.4 s) and first slip, at the communication step of
# the other FMU tests; Wine and qemu are slow, so no longer (docs/cross-platform.md).
STOP = 0.7
STEP = 1e-3
# NeuralFriction: sliding velocities through zero and past the network's training range,
# at three normal forces.
VELOCITIES = tuple(v * 1e-3 for v in range(-120, 121, 8)) + (1e-9, -1e-9)
NORMAL_FORCES = (50.0, 100.0, 150.0)

# StickSlipBeam's laws: (label, friction.law, friction.weights or None for the default).
BEAM_LAWS = (
    ("analytical", "exponential", None),
    ("neural", "neural", None),
    ("lugre", "lugre", None),
    ("rate-and-state", "rate-and-state", None),
    ("learned with memory", "neural", "rate-and-state-learned.json"),
)

# The shipped learned law with memory (aging), and the same parameters with the slip
# evolution: no such file is shipped, so run_all writes it into each unzipped
# NeuralFriction's resources (`write_slip_weights`).
LEARNED_WEIGHTS = "rate-and-state-learned.json"
LEARNED_SLIP_WEIGHTS = "rate-and-state-learned-slip.json"

# NeuralFriction's laws with state: (label, law, further parameters {name: value}).
HISTORY_LAWS = (
    ("lugre", "lugre", {}),
    ("rate-and-state, aging", "rate-and-state",
     {"friction.rate_and_state.state_evolution": "aging"}),
    ("rate-and-state, slip", "rate-and-state",
     {"friction.rate_and_state.state_evolution": "slip"}),
    ("learned with memory, aging", "neural", {"weights": LEARNED_WEIGHTS}),
    ("learned with memory, slip", "neural", {"weights": LEARNED_SLIP_WEIGHTS}),
)

# The stepped history: (sliding velocity m/s, normal force N, step s, steps). Steady
# sliding at 1 mm/s, a step up to 10 mm/s (rate-and-state's direct effect, then its
# relaxation over D_c / V = 1 ms), a stop (aging heals theta, the slip law freezes it,
# LuGre's bristles hold), the reversal to -5 mm/s, a normal-force step, a creep at 1 nm/s,
# a fast slide past the learned law's training range with shorter steps, and longer
# steps at 2 mm/s; 330 steps in all. The step sizes and the state's time scales
# (LuGre's g / (sigma0 |v|) = 0.5 ms at 10 mm/s, D_c / V = 1 to 10 ms) put the exact
# steps' exponentials over several decades of argument.
HISTORY = (
    (1e-3, 100.0, 1e-3, 60),
    (1e-2, 100.0, 1e-3, 40),
    (0.0, 100.0, 1e-3, 40),
    (-5e-3, 100.0, 1e-3, 50),
    (-5e-3, 140.0, 1e-3, 30),
    (1e-9, 140.0, 1e-3, 20),
    (0.1, 60.0, 1e-4, 60),
    (2e-3, 100.0, 1e-2, 30),
)


def history_steps() -> int:
    return sum(n for *_, n in HISTORY)


def history_duration() -> float:
    return sum(h * n for *_, h, n in HISTORY)


def bits(value: float) -> str:
    return "0x%016x" % struct.unpack("<Q", struct.pack("<d", value))[0]


@dataclass(frozen=True)
class Case:
    """One model at one setting, its driver plan and the names of the outputs the driver
    prints after the time on each line, in order."""

    model: str
    setting: str
    plan: str
    outputs: tuple[str, ...] = ()

    def column(self, line: str, name: str) -> str:
        """The printed value of output `name` on a line of this case's driver output."""
        return line.split()[1 + self.outputs.index(name)]


def _setter(model: Model, name: str, value) -> str:
    vr, kind = model.vr[name], model.kind(name)
    if name in model.choices:
        return f"int {vr} {model.code(name, value)}"
    if kind == "Real":
        return f"real {vr} {bits(float(value))}"
    if kind == "Integer":
        return f"int {vr} {int(value)}"
    if kind == "Boolean":
        return f"bool {vr} {int(bool(value))}"
    return f"string {vr} {value}"


def _outputs(model: Model) -> tuple[list[str], tuple[str, ...]]:
    """The driver's output lines for every output of `model`, and their names."""
    kinds = {"Real": "real", "Integer": "int", "Boolean": "bool"}
    variables = [v for v in model.description.modelVariables if v.causality == "output"]
    lines = [f"output {kinds[model.kind(v.name)]} {v.valueReference}" for v in variables]
    return lines, tuple(v.name for v in variables)


def _case(model: Model, name: str, setting: str, settings: list[str], steps: list[str]) -> Case:
    output_lines, names = _outputs(model)
    plan = "\n".join([*settings, *output_lines, *steps]) + "\n"
    return Case(name, setting, plan, names)


def beam_cases(beam: Model) -> list[Case]:
    """StickSlipBeam at each fidelity with each law (the analytical law is the
    exponential one; the neural law reads the packaged default weights; the laws with
    state, LuGre, rate-and-state and the learned one, carry their state through the
    step)."""
    out = []
    for fidelity in fidelities(beam):
        for law, code, weights in BEAM_LAWS:
            settings = [
                _setter(beam, "fidelity.level", fidelity),
                _setter(beam, "friction.law", code),
            ]
            if weights is not None:
                settings.append(_setter(beam, "friction.weights", weights))
            steps = [f"init {bits(0.0)} {bits(STOP)}", f"step {bits(STEP)} {round(STOP / STEP)}"]
            out.append(_case(beam, BEAM, f"{fidelity}, {law}", settings, steps))
    return out


def grid_cases(friction: Model) -> list[Case]:
    """NeuralFriction with either memoryless law over the input grid."""
    out = []
    for law, code in (("analytical", "exponential"), ("neural", "neural")):
        steps = [f"init {bits(0.0)} {bits(1.0)}"]
        for force in NORMAL_FORCES:
            for velocity in VELOCITIES:
                steps.append(_setter(friction, "sliding_velocity", velocity))
                steps.append(_setter(friction, "normal_force", force))
                steps.append(f"step {bits(1e-3)} 1")
        settings = [_setter(friction, "law", code)]
        out.append(_case(friction, FRICTION, f"input grid, {law}", settings, steps))
    return out


def history_cases(friction: Model) -> list[Case]:
    """NeuralFriction with each law with state over the stepped history."""
    out = []
    for label, law, parameters in HISTORY_LAWS:
        settings = [_setter(friction, "law", law)]
        settings += [_setter(friction, name, value) for name, value in parameters.items()]
        # The stop time only bounds the run; the driver's own t += h reaches about it.
        steps = [f"init {bits(0.0)} {bits(2.0 * history_duration())}"]
        for velocity, force, h, n in HISTORY:
            steps.append(_setter(friction, "sliding_velocity", velocity))
            steps.append(_setter(friction, "normal_force", force))
            steps.append(f"step {bits(h)} {n}")
        out.append(_case(friction, FRICTION, f"history, {label}", settings, steps))
    return out


def cases(beam: Model, friction: Model) -> list[Case]:
    """Every case: the beam's, NeuralFriction's grid and its histories."""
    return beam_cases(beam) + grid_cases(friction) + history_cases(friction)


def write_slip_weights(resources: Path) -> None:
    """Writes LEARNED_SLIP_WEIGHTS next to the shipped learned law: its parameters and
    correction with `law.state_evolution = "slip"` (the field the slip evolution added;
    a file without it is aging)."""
    weights = json.loads((resources / LEARNED_WEIGHTS).read_text())
    weights["law"]["state_evolution"] = "slip"
    weights["state"] = ("psi = ln(theta V_0 / D_c); slip law (the shipped file's parameters "
                        "with state_evolution = slip, written by the cross-platform test)")
    (resources / LEARNED_SLIP_WEIGHTS).write_text(json.dumps(weights, indent=2))
