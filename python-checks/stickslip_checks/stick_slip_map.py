"""The stick-slip map: what one sweep run reduces to (regime, transitions, deflection
window), where stick-slip stops along the swept parameter, and the map's default cases.

A run is reduced over the last `window` of its samples: breakaway, stick -> slip
transitions (from the FMU's `transitions` counter), peak-to-peak, min, max and mean tip
deflection, the stick fraction and the regime: "stick-slip" if the tip sticks again after
a slip within the window, "steady sliding" if it slips and does not stick again, "stuck"
if it sticks through the whole window.

The map (sweep.py without --grid) runs MAP_SPEEDS for three cases: the FMU's default
damping, 2 % Rayleigh damping at modes 1 and 3, and the same from rest.

Beam physics left here, because neither the FMU nor the command line reports it (see
euler_bernoulli_modes): the Euler-Bernoulli frequencies of modes 1 and 3 and the beam's
mass, for the Rayleigh coefficients of the 2 % case and for the linear estimate of where
steady sliding becomes stable.
"""

from __future__ import annotations

import math

import numpy as np

DEFAULT_WINDOW = 1.0 / 3.0  # metrics over the last third of the run (after transients)

# Belt speeds of the map (m/s): three per octave from 0.005 to 10.24 m/s, so that the
# paper's 0.02 m/s is a grid point (0.005 * 2^2, exact in binary). The top speed is well
# above where stick-slip stops with either damping case of the map (measured: ~1.1 m/s
# with 2 % Rayleigh damping, ~6 m/s with the FMU's default b = 5e-5 s).
MAP_SPEEDS = tuple(0.005 * 2.0 ** (k / 3) for k in range(34))
MAP_PARAMETER = "belt_speed"
RAYLEIGH_RATIO = 0.02  # damping ratio at modes 1 and 3 of the "2 % Rayleigh" case

# Regimes over the metrics window.
STICK_SLIP = "stick-slip"
SLIDING = "steady sliding"
STUCK = "stuck"
FAILED = "error"

# ----------------------------------------------------------------------------- one run


def _stick_to_slip(count: int, starts_in_stick: bool) -> int:
    """Stick -> slip transitions among `count` alternating transitions."""
    return (count + 1) // 2 if starts_in_stick else count // 2


def run_metrics(
    times: np.ndarray,
    u: np.ndarray,
    stick: np.ndarray,
    transitions: np.ndarray,
    window: float = DEFAULT_WINDOW,
) -> dict:
    """Metrics of one run sampled at the communication points.

    The transition counts come from the FMU's `transitions` counter, so they include
    stick or slip phases shorter than a sample. The stick fraction and the deflections are
    from the samples. The metrics window is the last `window` of the run. The regime is
    "stick-slip" if the tip sticks again after a slip within the window, "steady sliding"
    if it slips and does not stick again, "stuck" if it sticks through the whole window.
    """
    t_end = float(times[-1])
    i0 = int(np.searchsorted(times, (1.0 - window) * t_end - 1e-12))
    slipped = np.flatnonzero(~stick)
    # Sample times rounded to 1e-12 s: k * step carries binary noise (1.2750000000000001).
    breakaway = round(float(times[slipped[0]]), 12) if slipped.size else None
    n_total = int(transitions[-1] - transitions[0])
    n_window = int(transitions[-1] - transitions[i0])
    s2s_window = _stick_to_slip(n_window, bool(stick[i0]))
    resticks_window = n_window - s2s_window  # slip -> stick within the window
    if resticks_window > 0:
        regime = STICK_SLIP
    elif n_window == 0 and stick[i0]:
        regime = STUCK
    else:
        regime = SLIDING
    w = u[i0:]
    after = u[slipped[0] :] if slipped.size else u[:0]
    note = ""
    if breakaway is not None and breakaway > times[i0]:
        note = "breakaway inside the metrics window: lengthen --t-end"
    return {
        "regime": regime,
        "breakaway_s": breakaway,
        "stick_to_slip": _stick_to_slip(n_total, bool(stick[0])),
        "window_start_s": round(float(times[i0]), 12),
        "window_stick_to_slip": s2s_window,
        "p2p_mm": 1e3 * float(w.max() - w.min()),
        "min_mm": 1e3 * float(w.min()),
        "max_mm": 1e3 * float(w.max()),
        "mean_mm": 1e3 * float(w.mean()),
        "stick_fraction": float(stick[i0:].mean()),
        # The corridor of the whole run after breakaway, as in fmu_scene.py / README.
        "corridor_min_mm": 1e3 * float(after.min()) if after.size else None,
        "corridor_max_mm": 1e3 * float(after.max()) if after.size else None,
        "note": note,
    }


def stick_slip_stop(xs, regimes) -> tuple[float, float] | None:
    """(last x with stick-slip, next x) if every point above the last stick-slip one slides."""
    pairs = sorted(zip(xs, regimes))
    last = max((i for i, (_, r) in enumerate(pairs) if r == STICK_SLIP), default=None)
    if last is None or last == len(pairs) - 1:
        return None
    if any(r != SLIDING for _, r in pairs[last + 1 :]):
        return None
    return pairs[last][0], pairs[last + 1][0]


# ----------------------------------------------------------------------------- the map's cases


def default_cases(catalogue) -> list[tuple[str, dict]]:
    """The map's cases: two dampings from the quasi-static start, and 2 % from rest.

    The FMU's default damping (b = 5e-5 s, stiffness-proportional only) damps mode 1 by
    0.09 %; the physics notes' 2 % Rayleigh damping at modes 1 and 3 is the other case.
    Stick-slip and steady sliding can both be stable at one belt speed, so the start
    matters: the quasi-static start (tip moving with the belt, paper scene) begins in
    stick and breaks away at 8 mm. The start at rest (beam at rest, belt moving) breaks
    away in the first step above ~0.03 m/s and slides from zero deflection, only
    mu(v_b) F_n / k = 3.2 mm from the steady-sliding state. The CSV holds each case's
    parameter values.
    """
    defaults = catalogue.defaults()
    b = defaults["damping.stiffness_proportional"]
    rayleigh = rayleigh_damping(defaults)
    percent = f"{100 * RAYLEIGH_RATIO:g} % Rayleigh"
    return [
        (f"default damping b = {b:g} s", {}),
        (percent, rayleigh),
        (f"{percent}, start at rest", {**rayleigh, "contact.initial_state": "at-rest"}),
    ]


# ----------------------------------------------------------------------------- beam estimates

# Euler-Bernoulli cantilever: beta_n L of modes 1 and 3;
# omega_n = (beta_n L)^2 sqrt(EI / (rho A L^4)).
BETA_L = {1: 1.875104, 3: 7.854757}


def euler_bernoulli_modes(params: dict) -> tuple[float, float, float]:
    """(omega_1 (rad/s), omega_3 (rad/s), total mass M (kg)) of the Euler-Bernoulli
    cantilever with the geometry and material of `params` (the FMU's parameter names).

    Neither StickSlipBeam.fmu nor `stickslip` reports these numbers. `stickslip simulate
    --damping-ratio Z` computes Rayleigh damping from the same two frequencies inside the
    binary, but with beta_n L rounded to 1.8751 and 7.8548 and without printing a or b.
    What would remove this function: StickSlipBeam.fmu calculated parameters (or a
    command that prints them for a scene) for the natural frequencies of its structural
    model and the Rayleigh a, b of a damping ratio at modes 1 and 3 (e.g. a parameter
    damping.ratio), plus the modal mass at the tip for sliding_stability_speed.
    """
    length = params["geometry.length"]
    area = params["geometry.width"] * params["geometry.height"]  # m^2
    ei = (
        params["material.youngs_modulus"]
        * params["geometry.width"]
        * params["geometry.height"] ** 3
        / 12
    )
    rho_a = params["material.density"] * area  # kg/m
    scale = math.sqrt(ei / (rho_a * length**4))
    return BETA_L[1] ** 2 * scale, BETA_L[3] ** 2 * scale, rho_a * length


def rayleigh_damping(params: dict, ratio: float = RAYLEIGH_RATIO) -> dict:
    """Rayleigh a (1/s), b (s) giving `ratio` at modes 1 and 3: zeta(w) = a/(2w) + b w/2."""
    w1, w3, _ = euler_bernoulli_modes(params)
    return {
        "damping.mass_proportional": 2 * ratio * w1 * w3 / (w1 + w3),
        "damping.stiffness_proportional": 2 * ratio / (w1 + w3),
    }


def sliding_stability_speed(params: dict) -> float | None:
    """Belt speed (m/s) above which steady sliding is linearly stable (mode 1), or None.

    Linearised about steady sliding, the exponential law's slope dF/dv_rel =
    -alpha (mu_s - mu_k) F_n exp(-alpha v_b) feeds the tip velocity back as negative
    damping. A cantilever's mass-normalised modes all have phi_n(L)^2 = 4 / M at the tip,
    so mode 1 (the least damped: 2 zeta_1 omega_1 = a + b omega_1^2) is stable when
    (4 / M) alpha (mu_s - mu_k) F_n exp(-alpha v_b) < a + b omega_1^2. Only for the
    exponential law with the relative sliding velocity; the higher modes and the coupling
    through the static correction are ignored.
    """
    if (
        params.get("friction.model") != "exponential"
        or params.get("contact.sliding_velocity") != "relative"
    ):
        return None
    w1, _, mass = euler_bernoulli_modes(params)
    damping = params["damping.mass_proportional"] + params["damping.stiffness_proportional"] * w1**2
    alpha = params["friction.decay"]
    slope = alpha * (params["friction.static_coefficient"] - params["friction.kinetic_coefficient"])
    gain = 4.0 / mass * slope * params["normal_force"]  # 1/s at v_b = 0
    if alpha <= 0 or gain <= 0:
        return 0.0
    if damping <= 0:
        return math.inf
    return max(0.0, math.log(gain / damping) / alpha)
