"""The results file of a study (`out=`): a CSV that grows by one block of rows per
finished batch, so a crash loses no finished variant, and that a resumed study reads to
skip the variants it holds; or a Parquet file, written whole when the study ends, whose
rows stream meanwhile to a CSV beside it (`NAME.parquet.rows.csv`) for the same reason."""

from __future__ import annotations

import csv
import io
import os
from pathlib import Path
from typing import TYPE_CHECKING, List, Sequence, Union

if TYPE_CHECKING:
    import pandas as pd

STATUSES = ("ok", "failed")


def results_file(path: Union[str, "os.PathLike[str]"], columns: Sequence[str]) -> "Union[ResultsFile, ParquetResults]":
    """The results file for `out=`: by its suffix, a CSV (.csv) or Parquet (.parquet) file."""
    suffix = Path(path).suffix.lower()
    if suffix == ".parquet":
        return ParquetResults(path, columns)
    if suffix != ".csv":
        raise ValueError(f"out= is a .csv or .parquet file, not {path}")
    return ResultsFile(path, columns)


class ResultsFile:
    """A CSV file of a study's rows with the columns `columns` (the first is `variant`)."""

    def __init__(self, path: Union[str, "os.PathLike[str]"], columns: Sequence[str]) -> None:
        self.path = Path(path)
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

    def finish(self, table: "pd.DataFrame") -> None:
        """The study has ended with `table`: the rows are all in the file already."""

    def keep_only(self, rows: "pd.DataFrame") -> None:
        """Rewrites the file to hold `rows` only (retry_failed drops the failed ones)."""
        body = rows[self.columns].to_csv(header=False, index=False, lineterminator="\n")
        self._write_text(_csv_line(self.columns) + body)

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


class ParquetResults:
    """A Parquet file of a study's rows: the finished rows stream to a CSV beside it
    (`NAME.parquet.rows.csv`, a [`ResultsFile`]) and the whole table is written to the
    Parquet file when the study ends, replacing it in one step, the CSV then removed. A
    resumed study reads both: the Parquet file of an earlier study that ended, and the
    CSV of one that did not."""

    def __init__(self, path: Union[str, "os.PathLike[str]"], columns: Sequence[str]) -> None:
        try:
            import pyarrow  # noqa: F401  (pandas writes Parquet through it)
        except ImportError:
            raise ImportError("out=*.parquet needs pyarrow: pip install mbfx[parquet]") from None
        self.path = Path(path)
        self.columns = list(columns)
        self.rows = ResultsFile(self.path.with_name(self.path.name + ".rows.csv"), columns)

    def start(self, resume: bool) -> "pd.DataFrame":
        """The rows already finished: the Parquet file's and the streamed CSV's when
        resuming (each variant once), else none."""
        import pandas as pd

        streamed = self.rows.start(resume)
        if not resume or not self.path.exists():
            return streamed
        ended = pd.read_parquet(self.path)
        if list(ended.columns) != self.columns:
            raise ValueError(
                f"{self.path} holds other columns ({list(ended.columns)}) than this study's ({self.columns}): "
                "pass resume=False to overwrite it, or another out="
            )
        # The streamed rows are the newer (a failed row run again by retry_failed).
        both = pd.concat([streamed, ended], ignore_index=True) if len(streamed) else ended
        return both.drop_duplicates("variant").reset_index(drop=True)

    def append(self, rows: "pd.DataFrame") -> None:
        """Adds `rows` to the streamed CSV."""
        self.rows.append(rows)

    def keep_only(self, rows: "pd.DataFrame") -> None:
        """Keeps `rows` only: the streamed CSV holds them (newer than the Parquet file's),
        the Parquet file is rewritten whole when the study ends."""
        self.rows.keep_only(rows)

    def finish(self, table: "pd.DataFrame") -> None:
        """Writes `table` (every row of the study) to the Parquet file in one step."""
        partial = self.path.with_name(self.path.name + ".partial")
        table[self.columns].to_parquet(partial, index=False)
        os.replace(partial, self.path)
        self.rows.path.unlink(missing_ok=True)


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
