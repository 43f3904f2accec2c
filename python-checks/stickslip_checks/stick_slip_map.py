"""The stick-slip map: what one sweep run reduces to (regime, transitions, deflection
window), where stick-slip stops along the swept parameter, and the map's default cases.

A run is reduced over the last `window` of its samples: breakaway, stick -> slip
transitions (from the FMU's `transitions` counter), peak-to-peak, min, max and mean tip
deflection, the stick fraction and the regime: "stick-slip" if the tip sticks again after
a slip within the window, "steady sliding" if it slips and does not stick again, "stuck"
if it sticks through the whole window.

The map (stickslip-sweep without --grid) runs MAP_SPEEDS for three cases: the FMU's default
damping, 2 % Rayleigh damping at modes 1 and 3, and the same from rest.

The beam-theory numbers the map needs (the Rayleigh coefficients of the 2 % case and the
linear estimate of where steady sliding becomes stable) come from `stickslip estimates`,
which computes them in Rust (`stickslip::stability`); nothing here re-derives the beam.
"""

from __future__ import annotations

import json
import math
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from .artifacts import find_binary

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
        # The corridor of the whole run after breakaway, as in scene.py and docs/measurements.md.
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

# The sections of the scene file that the estimates read; the FMU names its parameters
# after the scene file's fields, so these carry over by name.
_ESTIMATE_SECTIONS = ("geometry", "material", "friction", "contact", "damping")


def _scene_of(params: dict) -> dict:
    """The scene file (as a dict) that the FMU parameters and inputs `params` describe."""
    scene: dict = {"loading": {}}
    for name, value in params.items():
        if name in ("belt_speed", "normal_force"):
            scene["loading"][name] = value
            continue
        section, *path = name.split(".")
        if section not in _ESTIMATE_SECTIONS or name == "friction.weights":
            continue
        # Nested tables (friction.lugre.bristle_stiffness) are nested in the file too.
        table = scene.setdefault(section, {})
        for key in path[:-1]:
            table = table.setdefault(key, {})
        table[path[-1]] = value
    return scene


def beam_estimates(params: dict, rayleigh_ratio: float | None = None) -> dict:
    """`stickslip estimates` for the scene of `params`: bending frequencies `omega`
    (rad/s), `mass` (kg), the static tip stiffness `tip_stiffness` (3 EI / L^3, N/m), the
    Rayleigh `mass_proportional` (1/s) and `stiffness_proportional` (s) in use, and
    `sliding_stability_speed` (m/s, None where it does not apply). With `rayleigh_ratio`,
    the damping is Rayleigh damping with that ratio at modes 1 and 3. Raises ValueError
    with the binary's message for a bad scene."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "scene.json"
        path.write_text(json.dumps(_scene_of(params)))
        command = [str(find_binary()), "estimates", "--scene", str(path)]
        if rayleigh_ratio is not None:
            command += ["--rayleigh-ratio", repr(rayleigh_ratio)]
        done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        message = done.stderr.strip() or f"stickslip estimates failed ({done.returncode})"
        raise ValueError(message)
    return json.loads(done.stdout)


def rayleigh_damping(params: dict, ratio: float = RAYLEIGH_RATIO) -> dict:
    """Rayleigh a (1/s), b (s) giving `ratio` at modes 1 and 3: zeta(w) = a/(2w) + b w/2."""
    estimates = beam_estimates(params, rayleigh_ratio=ratio)
    return {
        "damping.mass_proportional": estimates["mass_proportional"],
        "damping.stiffness_proportional": estimates["stiffness_proportional"],
    }


def sliding_stability_speed(params: dict) -> float | None:
    """Belt speed (m/s) above which steady sliding is linearly stable in mode 1, or None
    where the estimate does not apply (see `stickslip::stability::sliding_stability_speed`
    for the derivation). Raises ValueError for a scene the binary refuses."""
    speed = beam_estimates(params)["sliding_stability_speed"]
    if speed == "inf":
        return math.inf
    return speed
