"""The results file of a study (`out=`): a CSV that grows by one block of rows per
finished batch, so a crash loses no finished variant, and that a resumed study reads to
skip the variants it holds."""

from __future__ import annotations

import csv
import io
import os
from pathlib import Path
from typing import TYPE_CHECKING, List, Sequence, Union

if TYPE_CHECKING:
    import pandas as pd

STATUSES = ("ok", "failed")


class ResultsFile:
    """A CSV file of a study's rows with the columns `columns` (the first is `variant`)."""

    def __init__(self, path: Union[str, "os.PathLike[str]"], columns: Sequence[str]) -> None:
        self.path = Path(path)
        if self.path.suffix.lower() != ".csv":
            raise ValueError(f"out= is a .csv file (rows are appended as they finish), not {self.path}")
        self.columns = list(columns)

    def start(self, resume: bool) -> "pd.DataFrame":
        """The rows already finished: those in the file when resuming (after dropping a
        row a crash cut short), else none, the file begun anew."""
        import pandas as pd

        if not resume or not self.path.exists() or self.path.stat().st_size == 0:
            self._write_text(_csv_line(self.columns))
            return pd.DataFrame(columns=self.columns)
        self._keep_complete_rows()
        frame = pd.read_csv(self.path, dtype={"message": "str"})
        frame["message"] = frame["message"].fillna("")
        return frame

    def append(self, rows: "pd.DataFrame") -> None:
        """Adds `rows` at the end and flushes them to the operating system."""
        with open(self.path, "a", newline="", encoding="utf-8") as f:
            rows[self.columns].to_csv(f, header=False, index=False, lineterminator="\n")
            f.flush()

    def _keep_complete_rows(self) -> None:
        """Rewrites the file without incomplete or repeated rows, if it has any; raises
        ValueError when it holds another study's columns."""
        text = self.path.read_text(encoding="utf-8")
        records = list(csv.reader(io.StringIO(text)))
        if records[0] != self.columns:
            raise ValueError(
                f"{self.path} holds other columns ({records[0]}) than this study's ({self.columns}): "
                "pass resume=False to overwrite it, or another out="
            )
        whole = text.endswith("\n")  # else a crash interrupted the last write
        rows = records[1:] if whole else records[1:-1]
        kept = _complete(rows, self.columns)
        if not whole or len(kept) < len(rows):
            self._write_text("".join(_csv_line(r) for r in [self.columns, *kept]))

    def _write_text(self, text: str) -> None:
        """Replaces the file's contents with `text` in one step (a crash leaves the old)."""
        partial = self.path.with_name(self.path.name + ".partial")
        partial.write_text(text, encoding="utf-8", newline="")
        os.replace(partial, self.path)


def _complete(records: List[List[str]], columns: Sequence[str]) -> List[List[str]]:
    """The records with every column and a status, each variant's first only."""
    status = list(columns).index("status")
    seen, kept = set(), []
    for record in records:
        if len(record) == len(columns) and record[status] in STATUSES and record[0] not in seen:
            seen.add(record[0])
            kept.append(record)
    return kept


def _csv_line(values: Sequence[str]) -> str:
    """One CSV record, quoted as pandas writes them, ending in a newline."""
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerow(values)
    return out.getvalue()
