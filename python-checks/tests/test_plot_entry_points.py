"""plot_cli and study_plot as entry points: the folder comes from the command line
(runner.out_dir), the exit status says whether there was something to plot, and the
words in the figures (clamps, fidelity levels, integrators) are taken from the CSV files.

No FMU or binary needed; runs in a few seconds (matplotlib).
"""

from __future__ import annotations

import csv

import pytest

from stickslip_checks import plot_cli, study, study_plot

# matplotlib 3.10 calls pyparsing names that pyparsing 3.3 deprecates (fonts, mathtext of
# the log axes); that is between those two packages, not a finding of these tests.
pytestmark = pytest.mark.filterwarnings("ignore:.*deprecated:DeprecationWarning")

STUDY_COLUMNS = [
    "level", "modes", "beam_elements", "element_size_m", "dt_s", "integrator", "wall_s",
    "err_rms_m", "pareto",
]


def write_rows(path, header, rows):
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        writer.writerows(rows)


def test_plot_cli_fails_without_csv_files(tmp_path, capsys):
    assert plot_cli.main([str(tmp_path)]) == 1
    assert "no paper_*_*.csv or mesh_convergence.csv" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_plot_cli_plots_every_clamp_the_csv_names(tmp_path, capsys):
    header = ["clamp", "element_size", "nodes", "error_euler_bernoulli"]
    # Clamp words the plot has never seen: they must still be drawn, not dropped.
    rows = [[clamp, h, n, e] for clamp in ("first-kind", "second-kind")
            for h, n, e in ((0.08, 128, -3e-4), (0.04, 253, -4e-5))]
    write_rows(tmp_path / "mesh_convergence.csv", header, rows)
    assert plot_cli.main([str(tmp_path)]) == 0
    assert (tmp_path / "mesh_convergence.png").stat().st_size > 0
    assert f"wrote {tmp_path / 'mesh_convergence.png'}" in capsys.readouterr().out


def study_rows(pareto_of_slow: str):
    """A fast coarse run, a slow accurate one (both on the front) and a dominated one."""
    return [
        ["modal", 4, "", "", "1e-3", "scheme-a", 0.001, 1e-3, 1],
        ["other-level", "", 10, "", "1e-4", "scheme-b", 0.1, 1e-5, pareto_of_slow],
        ["other-level", "", 5, "", "1e-3", "scheme-a", 0.2, 1e-4, 0],
    ]


def test_study_plot_checks_the_pareto_column_and_returns_a_status(tmp_path, capsys):
    assert study_plot.main([str(tmp_path)]) == 1  # no study.csv
    assert "no " in capsys.readouterr().err

    write_rows(tmp_path / "study.csv", STUDY_COLUMNS, study_rows("1"))
    assert study_plot.main([str(tmp_path)]) == 0
    assert (tmp_path / "pareto.png").stat().st_size > 0
    assert "3 runs, 2 on the Pareto front" in capsys.readouterr().out

    write_rows(tmp_path / "study.csv", STUDY_COLUMNS, study_rows("0"))
    assert study_plot.main([str(tmp_path)]) == 1
    assert "pareto column disagrees" in capsys.readouterr().err


def test_a_modal_row_of_the_mesh_is_labelled_apart_from_the_beam_modal_row():
    # Same modes, step and integrator: only the level and the element size tell the
    # beam's modal model from the mesh's, and the front check compares these labels.
    common = {"modes": "10", "beam_elements": "", "dt_s": "1e-4",
              "integrator": "generalized-alpha", "inference": ""}
    beam = study.label({**common, "level": "modal", "element_size_m": ""})
    mesh = study.label({**common, "level": "plane-stress-modal", "element_size_m": "0.02"})
    assert beam == "modal 10 modes, dt 0.0001 s, generalized-alpha"
    assert mesh == "modal 10 modes of plane stress 0.02 m, dt 0.0001 s, generalized-alpha"


def test_study_plot_draws_one_front_per_law(tmp_path, capsys):
    # Two laws with the same configurations: the slow accurate exponential run does not
    # dominate the LuGre run, because each law's errors are against its own reference.
    header = STUDY_COLUMNS + ["law"]
    rows = [
        ["modal", 4, "", "", "1e-3", "scheme-a", 0.001, 2e-5, 1, "exponential"],
        ["modal", 4, "", "", "1e-4", "scheme-a", 0.01, 5e-7, 1, "exponential"],
        ["modal", 4, "", "", "1e-3", "scheme-a", 0.02, 3e-6, 1, "lugre"],
        ["modal", 4, "", "", "1e-4", "scheme-a", 0.03, 4e-6, 0, "lugre"],
    ]
    write_rows(tmp_path / "study.csv", header, rows)
    assert study_plot.main([str(tmp_path)]) == 0
    assert (tmp_path / "fronts.png").stat().st_size > 0
    assert not (tmp_path / "pareto.png").exists()
    out = capsys.readouterr().out
    assert "3 on the Pareto fronts of 2 laws" in out
    assert "exponential: 2 on its front; under 1e-05 m: modal 4 modes, dt 0.0001 s" in out
    assert "lugre: 1 on its front; under 1e-05 m: modal 4 modes, dt 0.001 s" in out
    assert "under 1e-06 m: none" in out

    # A pareto column that compares across laws (LuGre's run marked off the front by
    # the exponential run) disagrees with the per-law front.
    rows[2][8] = 0
    write_rows(tmp_path / "study.csv", header, rows)
    assert study_plot.main([str(tmp_path)]) == 1
    assert "pareto column disagrees" in capsys.readouterr().err
