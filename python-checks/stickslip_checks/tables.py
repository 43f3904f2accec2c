"""The one table writer of the package: the aligned text tables the entry points print,
the CSV files beside them, and the same rows as a pandas DataFrame (how fmpy users read
results; pandas is imported only when a DataFrame is asked for)."""

from __future__ import annotations

import csv
from collections.abc import Collection, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import pandas as pd

GAP = "  "  # between columns


def format_table(
    headers: Sequence[str] | Sequence[Sequence[str]],
    rows: Sequence[Sequence[str]],
    left: Collection[int] | None = (0,),
) -> str:
    """Header line(s), a line of dashes, then the rows; every column as wide as its
    widest cell, columns GAP apart, the columns in `left` (None: all) left-aligned and
    the others right-aligned, trailing blanks stripped. `headers` is one line of names or
    several lines (e.g. names, then units)."""
    lines = [list(headers)] if isinstance(headers[0], str) else [list(h) for h in headers]
    widths = [max(len(cells[i]) for cells in lines + list(rows)) for i in range(len(lines[0]))]

    def line(cells: Sequence[str]) -> str:
        return GAP.join(
            c.ljust(w) if left is None or i in left else c.rjust(w)
            for i, (c, w) in enumerate(zip(cells, widths))
        ).rstrip()

    return "\n".join(
        [line(h) for h in lines] + [GAP.join("-" * w for w in widths)] + [line(r) for r in rows]
    )


def write_csv(path: Path, headers: Sequence[str], rows: Sequence[Sequence[object]]) -> None:
    """The rows under one header line, with the csv module's default dialect."""
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(headers)
        writer.writerows(rows)


def frame(headers: Sequence[str], rows: Sequence[Sequence[object]]) -> pd.DataFrame:
    """The rows of a CSV file (before it is written) as a DataFrame; empty cells ("")
    become missing values."""
    import pandas as pd

    return pd.DataFrame(
        [[None if v == "" else v for v in row] for row in rows], columns=list(headers)
    )
