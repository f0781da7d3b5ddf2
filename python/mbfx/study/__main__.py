"""`python -m mbfx.study STUDY.toml`: runs the design study a study file describes
(`mbfx.study.config`) and prints a summary: the variants that ran and failed, where the
table went, and each response's quadratic surface (R², main effects). `mbfx study` runs
this same command.

Exit codes, as every mbfx command's: 0 when the study ran (failed variants are rows of
the table, with their messages), 1 for a study file or arguments that cannot be run, or
when every variant failed.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import List, Optional

from . import config
from .runner import run


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(
        prog="mbfx study",
        description="Run the design study of a study file (TOML) on Dask.",
    )
    ap.add_argument("study", type=Path, help="the study file (TOML)")
    ap.add_argument("--scheduler", help="an existing Dask cluster's address (default: the file's, else a LocalCluster)")
    ap.add_argument("--out", type=Path, help="the results file, .csv or .parquet (default: the file's)")
    ap.add_argument("--plots", type=Path, help="a folder for each response's plots (PNG; needs matplotlib)")
    ap.add_argument("--no-resume", action="store_true", help="run every variant again, even those the results file holds")
    ap.add_argument("--retry-failed", action="store_true",
                    help="run again the variants the results file holds as failed (their rows replaced)")
    ap.add_argument("--progress", action="store_true", help="show a progress bar")
    try:
        args = ap.parse_args(argv)
    except SystemExit as e:  # argparse's 2 for a usage error: 1, as every mbfx command
        return 0 if e.code in (0, None) else 1
    try:
        study_file = config.read(args.study)
    except config.StudyFileError as e:
        print(f"mbfx study: error: {e}", file=sys.stderr)
        return 1
    kwargs = study_file.run_kwargs()
    if args.out is not None:
        kwargs["out"] = args.out
    if args.no_resume:
        kwargs["resume"] = False
    if args.retry_failed:
        kwargs["retry_failed"] = True
    scheduler = args.scheduler or study_file.scheduler
    try:
        with _client(scheduler) as client:
            study = run(str(study_file.model), client=client, progress=args.progress, **kwargs)
    except ValueError as e:
        # The study's own checks (a template naming no factor, a table's columns, ...).
        print(f"mbfx study: error: {study_file.path}: {e}", file=sys.stderr)
        return 1
    _report(study, kwargs.get("out"), args.plots)
    return 0 if len(study.ok) or not len(study.table) else 1


def _client(address: Optional[str]):
    """A client of the cluster at `address`, or None (the study starts a LocalCluster)."""
    from contextlib import nullcontext

    if address is None:
        return nullcontext(None)
    from distributed import Client

    return Client(address)


def _report(study, out: Optional[Path], plots: Optional[Path]) -> None:
    n, ok = len(study.table), len(study.ok)
    print(f"{n} variants: {ok} ok, {n - ok} failed")
    for message, count in study.failed["message"].value_counts().head(5).items():
        print(f"  {count} failed: {message}")
    if out is not None:
        print(f"table: {out}")
    for response, text in config.responses_summary(study):
        print(f"{response}: {text}")
    if plots is not None:
        plots.mkdir(parents=True, exist_ok=True)
        for response in study.responses:
            study.plot(response, plots / f"{response}.png")
            try:
                study.plot_sensitivity(response, plots / f"{response}_sensitivity.png")
            except (ValueError, ArithmeticError):
                pass  # no surface: the summary above says why
        print(f"plots: {plots}")


if __name__ == "__main__":
    raise SystemExit(main())
