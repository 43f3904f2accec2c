"""The Dask parameter sweep (sweep, sweep_engine, stick_slip_map): distributed = serial,
one FMU load per worker, the stick-slip map's physics, and clear errors for bad parameter
names and grids.

Needs the FMUs built by `cargo run --release -p fmu-build` (found by artifacts);
without them every test here FAILS and says how to build them. Starts two small
LocalClusters on 127.0.0.1; runs in about 15 s on two cores.
"""

from __future__ import annotations

import math

import pytest
from conftest import need

from stickslip_checks import sweep, sweep_study
from stickslip_checks.artifacts import AUTO, BEAM
from stickslip_checks.parameters import Catalogue, SweepError
from stickslip_checks.stick_slip_map import (
    FAILED,
    MAP_SPEEDS,
    SLIDING,
    STICK_SLIP,
    beam_estimates,
    default_cases,
    sliding_stability_speed,
)
from stickslip_checks.sweep_engine import beam_fmu, run_serial, run_sweep

# Fields that say where and how fast a run went, not what it computed.
PLACE = {"wall_s", "worker", "worker_loads", "process_loads"}

# A small sweep that covers both regimes and both dampings: stick-slip at 0.02 and
# 0.3 m/s, steady sliding at 8 m/s (2 % Rayleigh) and an Integer parameter.
RAYLEIGH = {"damping.mass_proportional": 1.3577, "damping.stiffness_proportional": 6.0097e-5}
RAYLEIGH_CASE = ",".join(f"{name}={value}" for name, value in RAYLEIGH.items())
SMALL = [
    {"belt_speed": 0.02},
    {"loading.belt_speed": 0.3, "friction.static_coefficient": 0.6},
    {"belt_speed": 8.0, **RAYLEIGH},
    {"belt_speed": 1.5, "normal_force": 80.0},
    {"belt_speed": 0.05, "fidelity.modes": 6},
    {"belt_speed": 0.02, "contact.initial_state": "at-rest", **RAYLEIGH},
]
SMALL_T_END = 3.0  # s: enough for several stick-slip cycles at 0.02 m/s (breakaway 0.4 s)


def computed(row: dict) -> dict:
    return {k: v for k, v in row.items() if k not in PLACE}


@pytest.fixture(scope="module")
def serial(built):
    """SMALL run one after the other in this process: the reference of the Dask runs."""
    need(built)
    return run_serial(SMALL, fidelity="modal", t_end=SMALL_T_END)


def test_local_cluster_equals_serial_and_loads_once_per_worker(serial):
    results = run_sweep(SMALL, fidelity="modal", t_end=SMALL_T_END, workers=2)
    assert len(results) == len(SMALL)
    for params, got, want in zip(SMALL, results, serial):
        # Same FMU, same inputs, same arithmetic: the worker's runs (after fmi2Reset, in
        # whatever order Dask chose) must equal the serial ones bit for bit, down to the
        # hash of the sampled tip deflection, stick and transition series.
        assert computed(got) == computed(want), params
        assert got["regime"] != FAILED, got.get("error")
    # Two worker processes, each loaded the FMU exactly once for six tasks.
    assert len(results.loads) == 2, results.loads
    assert all(n == 1 for n in results.loads.values()), results.loads
    assert {r["worker"] for r in results} <= set(results.loads)
    assert all(r["worker_loads"] == 1 and r["process_loads"] == 1 for r in results)
    assert serial.loads == {"in-process": 1}


def test_existing_scheduler_equals_serial(serial):
    """--scheduler: the tasks go to a cluster the sweep did not start (and does not close)."""
    from distributed import LocalCluster

    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None
    ) as cluster:
        results = run_sweep(SMALL[:3], t_end=SMALL_T_END, scheduler=cluster.scheduler_address)
        assert len(cluster.workers) == 2  # still running
    assert [computed(r) for r in results] == [computed(r) for r in serial[:3]]
    assert sorted(results.loads.values()) == [1, 1]


def test_map_stick_slip_at_paper_speed_and_sliding_at_top(built):
    """The map's cases at 0.02 m/s, 0.508 m/s and the top speed (10.24 m/s).

    - 0.02 m/s: steady sliding there is unstable (Stribeck slope -150 N s/m against a few
      N s/m of damping), so every case must be in stick-slip. From the quasi-static start
      the tip sticks until k delta = mu_s F_n: delta = 8 mm, t = 8 mm / 0.02 m/s = 0.400 s.
    - 0.508 m/s, 2 % Rayleigh: below the mode-1 estimate of where steady sliding becomes
      stable (0.61 m/s), so it cannot be the end state from either start.
    - 10.24 m/s: far above where stick-slip stops (measured ~1.1 and ~6 m/s for the two
      dampings). The tip slides without sticking again; on average it rests where the
      spring holds kinetic friction: mu(v) F_n / k = 0.2 * 100 N / 6250 N/m = 3.2 mm,
      with mu(v) = mu_k at this speed (exp(-alpha v) < 1e-22), mu_k and F_n the FMU's
      start values and k = 3 EI / L^3 from `stickslip estimates` (tip_stiffness).
    """
    need(built)
    catalogue = Catalogue(beam_fmu())
    cases = default_cases(catalogue)
    top, paper, below = MAP_SPEEDS[-1], 0.02, MAP_SPEEDS[20]
    assert paper in MAP_SPEEDS and top > 10.0 and 0.5 < below < 0.52
    sets, labels = [], []
    for label, values in cases:
        speeds = (paper, below, top) if values else (paper, top)
        for v in speeds:
            sets.append({**values, "belt_speed": v})
            labels.append((label, v))
    rows = dict(zip(labels, run_serial(sets)))  # the map's defaults: modal, 20 s
    defaults = catalogue.defaults()
    static_stiffness = beam_estimates(defaults)["tip_stiffness"]  # 3 EI / L^3, N/m
    kinetic_force = defaults["friction.kinetic_coefficient"] * defaults["normal_force"]  # N
    for (label, v), row in rows.items():
        assert row["regime"] != FAILED, row.get("error")
        if v == paper:
            assert row["regime"] == STICK_SLIP, (label, row)
            assert row["window_stick_to_slip"] >= 3, (label, row)
            if "at rest" not in label:
                assert abs(row["breakaway_s"] - 0.400) <= 1e-3, (label, row)
        elif v == below:
            assert row["regime"] == STICK_SLIP, (label, row)
        else:
            assert row["regime"] == SLIDING, (label, row)
            assert row["stick_fraction"] == 0.0 and row["window_stick_to_slip"] == 0
            mean = 1e-3 * row["mean_mm"]
            # 2 % damping has decayed the oscillation after breakaway; the default 0.09 %
            # has not (it is still ~+-0.18 m), so its window mean is only close.
            tol = 0.02 if "Rayleigh" in label else 0.3
            assert mean == pytest.approx(kinetic_force / static_stiffness, rel=tol), (label, row)
    # The linear estimate the map draws: 2 % damping gives the notes' ~0.6 m/s.
    speed = sliding_stability_speed({**defaults, **cases[1][1]})
    assert 0.55 < speed < 0.65


def test_paper_scene_metrics_match_the_library(built):
    """0.02 m/s for 1.2 s: docs/measurements.md's modal row (breakaway 0.400 s, 17 slip
    phases, corridor 4.836 - 8.434 mm after breakaway), here from the 1 ms samples. (16
    before issue 37: a slip step without solution then took the wrong side's force and
    skipped one re-stick; the beam and plane-stress rows had 17 already.)"""
    need(built)
    (row,) = run_serial([{"belt_speed": 0.02}], t_end=1.2)
    assert row["breakaway_s"] == pytest.approx(0.400, abs=1e-9)
    assert row["stick_to_slip"] == 17
    assert row["corridor_min_mm"] == pytest.approx(4.836, abs=1e-3)
    assert row["corridor_max_mm"] == pytest.approx(8.434, abs=1e-3)


def test_refused_value_is_an_error_row_and_the_instance_recovers(built):
    need(built)
    rows = run_serial([{"material.youngs_modulus": -1.0}, {"belt_speed": 0.02}], t_end=0.6)
    assert rows[0]["regime"] == FAILED
    assert "youngs_modulus" in rows[0]["error"]
    # fmi2Reset leaves the error state: the next run on the same instance is normal.
    assert rows[1]["regime"] == STICK_SLIP and math.isclose(rows[1]["breakaway_s"], 0.4)
    assert rows.loads == {"in-process": 1}


@pytest.mark.parametrize(
    "argv, message",
    [
        (
            ["--grid", "belt_sped=0.1:1:3"],
            "unknown parameter 'belt_sped'; close matches: belt_speed",
        ),
        (["--set", "static_coefficient=0.6"], "friction.static_coefficient"),
        (["--set", "damping.mass=1"], "damping.mass_proportional"),
        (["--grid", "belt_speed=0.1:1"], "bad --grid 'belt_speed=0.1:1'"),
        (["--grid", "belt_speed=0.1:1:three"], "count an integer"),
        (["--grid", "belt_speed=0:1:5:log"], "log grid needs start > 0"),
        (["--grid", "belt_speed=0.1:1:5:lin"], "bad --grid"),
        (["--grid", "belt_speed=0.1:1:0"], "count must be >= 1"),
        (["--grid", "friction.law=1:3:3"], "is Choice"),
        (["--grid", "fidelity.modes=4:5:5"], "repeats values"),
        (["--set", "belt_speed=fast"], "bad value 'fast' for belt_speed"),
        (["--set", "friction.law=dahl"], "not one of exponential, coulomb"),
        (["--grid", "belt_speed=0.1,0.2", "--set", "belt_speed=1"], "both swept"),
        (["--set", "fidelity.level=beam"], "--fidelity"),
        (["--t-end", "1.0005", "--step", "0.001"], "multiple"),
    ],
)
def test_bad_names_and_grids_exit_with_a_message(built, argv, message, capsys):
    need(built)
    with pytest.raises(SystemExit) as exit_info:
        sweep.main(argv + ["--workers", "0", "--out", "/nonexistent/never-written"])
    text = str(exit_info.value.code)
    assert text.startswith("stickslip-sweep: ") and message in text, text
    assert "Traceback" not in capsys.readouterr().err


def test_fidelity_choices_are_the_model_descriptions_levels_without_auto(built, capsys):
    """--fidelity and the engine accept the structural models the FMU declares
    (fidelity.level's items in code order) and refuse auto, which picks one itself."""
    fmus = need(built)
    items = fmus.models[BEAM].choices["fidelity.level"]
    levels = Catalogue(beam_fmu()).fidelities
    assert AUTO in items and len(levels) == len(items) - 1
    assert list(levels) == sorted(set(items) - {AUTO}, key=items.get)
    with pytest.raises(SystemExit) as exit_info:
        sweep.main(["--fidelity", AUTO, "--workers", "0", "--out", "/nonexistent/never-written"])
    assert exit_info.value.code == 2  # argparse: not one of the choices
    refusal = capsys.readouterr().err
    assert f"invalid choice: '{AUTO}'" in refusal, refusal
    assert all(f"'{level}'" in refusal for level in levels), refusal
    with pytest.raises(SweepError, match=f"unknown fidelity '{AUTO}'"):
        run_serial([{"belt_speed": 0.02}], fidelity=AUTO, t_end=0.003)


def test_a_grid_sweep_as_a_dataset_with_progress(built):
    """Two cases over two belt speeds, in process, 1 s each: progress once per run, and
    the Dataset over (case, belt speed) holds the CSV's metrics where the runs put them."""
    need(built)
    catalogue = Catalogue(beam_fmu())
    runs, swept, log_x, default_map = sweep_study.build_runs(
        catalogue, [], ["belt_speed=0.3,8"], ["default:", f"rayleigh:{RAYLEIGH_CASE}"]
    )
    seen = []
    results = run_serial(
        [p for _, p in runs], fidelity="modal", t_end=1.0,
        progress=lambda done, total, row: seen.append((done, total, row["regime"])),
    )
    assert [(d, t) for d, t, _ in seen] == [(k, 4) for k in range(1, 5)]
    result = sweep_study.Sweep(
        catalogue, runs, swept, log_x, default_map, "modal", 1.0, 1 / 3, results
    )
    frame = sweep_study.to_frame(result)
    assert len(frame) == 4 and frame.columns[1] == "belt_speed [m/s]"
    data = sweep_study.to_dataset(result)
    assert dict(data.sizes) == {"case": 2, "belt_speed [m/s]": 2}
    p2p = data["peak-to-peak tip deflection [mm]"]
    for (label, params), row in zip(runs, results):
        got = p2p.sel({"case": label, "belt_speed [m/s]": params["belt_speed"]})
        assert float(got) == row["p2p_mm"], (label, params)
