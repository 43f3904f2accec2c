"""NeuralFriction with the laws with state (law = lugre, rate-and-state) under fmpy:
sliding at constant velocity, each reaches its closed-form steady state, written out
here from the papers' formulas with the model description's start values (an oracle
independent of the Rust code).

Needs the FMUs built by `cargo run --release -p fmu-build` (see test_fmu.py).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import need

from stickslip_checks.artifacts import FRICTION
from stickslip_checks.scene import exponential_law

VELOCITY = 0.02  # m/s
STEP = 1e-3  # s
STEPS = 100


def slide(fmus, law: str, reals: dict[str, float]) -> dict[str, float]:
    """NeuralFriction with `law` and the Real parameters `reals`, slid at VELOCITY for
    STEPS steps of STEP; returns the outputs by name."""
    model = fmus.models[FRICTION]
    vr = fmus.vr[FRICTION]
    slave = fmus.slave(FRICTION, law)
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.setInteger([vr["law"]], [model.code("law", law)])
    if reals:
        slave.setReal([vr[k] for k in reals], list(reals.values()))
    slave.exitInitializationMode()
    slave.setReal([vr["sliding_velocity"]], [VELOCITY])
    for k in range(STEPS):
        slave.doStep(currentCommunicationPoint=k * STEP, communicationStepSize=STEP)
    names = ["friction_force", "bristle_deflection", "state_theta", "state_psi"]
    values = slave.getReal([vr[n] for n in names])
    slave.terminate()
    slave.freeInstance()
    return dict(zip(names, values))


def test_lugre_slides_to_g_plus_viscous_force(built):
    """LuGre (Canudas de Wit et al. 1995) at constant v: z -> g(v) / sigma0 and
    F -> g(v) + sigma2 v, g the exponential law (paper Eq. 6). The bristles relax in
    g / (sigma0 v) = 2.3e-4 s, so after 0.1 s only rounding is left: rtol 1e-9."""
    fmus = need(built)
    friction = fmus.models[FRICTION]
    sigma2 = 5.0
    out = slide(fmus, "lugre", {"friction.lugre.viscous_damping": sigma2})
    g = float(exponential_law(np.array([VELOCITY]), friction)[0])
    sigma0 = friction.real_start("friction.lugre.bristle_stiffness")
    assert out["friction_force"] == pytest.approx(g + sigma2 * VELOCITY, rel=1e-9)
    assert out["bristle_deflection"] == pytest.approx(g / sigma0, rel=1e-9)
    assert out["state_theta"] == 0.0 and out["state_psi"] == 0.0


def test_rate_and_state_slides_to_its_steady_coefficient(built):
    """Rate-and-state (Dieterich 1979, Ruina 1983) at constant V: theta -> D_c / V and
    F -> F_n (mu_0 + (a - b) ln(V / V_0)). The state relaxes over D_c = 1e-5 m, 200 D_c
    in 0.1 s: rtol 1e-9."""
    fmus = need(built)
    friction = fmus.models[FRICTION]
    start = {
        name: friction.real_start(f"friction.rate_and_state.{name}")
        for name in (
            "direct_effect",
            "evolution_effect",
            "characteristic_slip",
            "reference_velocity",
            "reference_coefficient",
        )
    }
    out = slide(fmus, "rate-and-state", {})
    mu = start["reference_coefficient"] + (
        start["direct_effect"] - start["evolution_effect"]
    ) * np.log(VELOCITY / start["reference_velocity"])
    normal_force = friction.real_start("normal_force")
    assert out["friction_force"] == pytest.approx(normal_force * mu, rel=1e-9)
    theta = start["characteristic_slip"] / VELOCITY
    assert out["state_theta"] == pytest.approx(theta, rel=1e-9)
    assert out["bristle_deflection"] == 0.0
