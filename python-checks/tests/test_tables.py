"""The one table writer (tables) and the DataFrame/Dataset views of the results: the
text layout the entry points print, the CSV cells, and that a DataFrame holds what the
CSV file holds. No FMU needed; runs in about a second."""

from __future__ import annotations

import csv

import numpy as np

from stickslip_checks import study, tables

from test_plot_entry_points import STUDY_COLUMNS, study_rows, write_rows


def test_columns_are_as_wide_as_their_widest_cell_and_aligned_as_asked():
    text = tables.format_table(["run", "wall [s]"], [["a", "0.05"], ["longer", "12.00"]])
    assert text.splitlines() == [
        "run     wall [s]",
        "------  --------",
        "a           0.05",
        "longer     12.00",
    ]
    left = tables.format_table([["x", "y"], ["", "[m]"]], [["1", "2"]], left=None)
    assert left.splitlines() == ["x  y", "   [m]", "-  ---", "1  2"]


def test_a_frame_holds_the_cells_of_the_csv_file(tmp_path):
    headers, rows = ["name", "value [m]", "note"], [["a", repr(0.1), ""], ["b", repr(2e-3), "x"]]
    path = tmp_path / "t.csv"
    tables.write_csv(path, headers, rows)
    with path.open(newline="") as handle:
        assert list(csv.reader(handle)) == [headers] + rows
    frame = tables.frame(headers, rows).astype({"value [m]": float})
    assert list(frame.columns) == headers
    assert frame["value [m]"].tolist() == [0.1, 2e-3]
    assert frame["note"].isna().tolist() == [True, False]


def test_the_study_grid_as_a_dataset(tmp_path):
    write_rows(tmp_path / "study.csv", STUDY_COLUMNS, study_rows("1"))
    data = study.to_dataset(tmp_path / "study.csv")
    other = study.resolution({"level": "other-level", "element_size_m": ""})
    assert sorted(data["resolution"].values) == ["modal 4 modes", other]
    # A study.csv without the law and inference columns (before issue 24) reads as one
    # law and one inference, both "".
    assert dict(data.sizes) == {
        "law": 1, "resolution": 2, "dt_s": 2, "integrator": 2, "inference": 1}
    # Three runs on a grid of 8 points: the rest are missing.
    assert int(data["err_rms_m"].count()) == 3
    run = data["wall_s"].sel(resolution=other, dt_s=1e-4, integrator="scheme-b")
    assert float(run.squeeze()) == 0.1
    assert np.isnan(data["wall_s"].sel(resolution="modal 4 modes", dt_s=1e-4)).all()
