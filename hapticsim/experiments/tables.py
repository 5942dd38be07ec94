"""CSV and Markdown tables of experiment summaries (atomic writes)."""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from hapticsim.data.io import write_text_atomic


def csv_text(rows: Sequence[dict[str, Any]], columns: Sequence[str] | None = None) -> str:
    """CSV text of `rows` (header from `columns` or the first row's keys); floats in repr form."""
    if columns is None:
        columns = list(rows[0]) if rows else []
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(columns), lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({c: row[c] for c in columns})
    return buf.getvalue()


def write_csv(
    path: str | Path, rows: Sequence[dict[str, Any]], columns: Sequence[str] | None = None
) -> Path:
    """Write `rows` as CSV to `path` (atomic); returns the path."""
    return write_text_atomic(path, csv_text(rows, columns))


def format_value(value: float, digits: int = 3) -> str:
    """`value` with `digits` significant digits; scientific notation below 1e-3."""
    if value != 0 and abs(value) < 1e-3:
        return f"{value:.{digits - 1}e}"
    return f"{value:.{digits}g}" if abs(value) >= 10**digits else f"{value:.{digits}f}"


def mean_spread(row: dict[str, Any], metric: str, digits: int = 3) -> str:
    """``"mean ± std"`` of `metric` in a :func:`~hapticsim.experiments.stats.summarize` row."""
    return (
        f"{format_value(row[f'{metric}_mean'], digits)} ± "
        f"{format_value(row[f'{metric}_std'], digits)}"
    )


def markdown_table(header: Sequence[str], body: Sequence[Sequence[str]]) -> str:
    """A GitHub Markdown table; the first column left-aligned, the others right-aligned."""
    lines = [
        "| " + " | ".join(header) + " |",
        "|" + "|".join([":---"] + ["---:"] * (len(header) - 1)) + "|",
    ]
    lines += ["| " + " | ".join(cells) + " |" for cells in body]
    return "\n".join(lines) + "\n"
