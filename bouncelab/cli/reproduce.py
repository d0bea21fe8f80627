"""``bouncelab reproduce`` in the command line's words.

The analysis is the library's (:func:`bouncelab.reproduce`, in :mod:`bouncelab.report`); the command
(``cli/main.py``) turns its flags into that call, and :func:`summarise` words the
:class:`~bouncelab.report.Report` it returns: where it was written, what each campaign read (file,
units, rows dropped, settings, intervals), the seed, what was not made and why, what to trust where
figures disagree, and the steps skipped, which make the exit code 5.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from bouncelab.cli.messages import EXIT_OK, EXIT_PARTIAL
from bouncelab.core.errors import OutputError
from bouncelab.report import reproduce

__all__ = ["OutputError", "check_output_file", "reproduce", "summarise", "summary_lines"]


def check_output_file(path: str, flag: str, example: str, suffix: str | None = None) -> None:
    """Refuse, before a possibly long job, an output file path that cannot be written (OutputError naming
    ``flag``): a folder, a missing parent folder, or (when ``suffix`` is given) another file type."""
    p = Path(path).expanduser()
    if p.is_dir():
        raise OutputError(f"{flag} {path!r} is a folder; give a file name such as {example}", path=path,
                          reason="a folder")
    if suffix is not None and p.suffix.lower() != suffix:
        raise OutputError(f"{flag} {path!r}: give the file a {suffix} suffix, e.g. {example}", path=path,
                          reason=f"not a {suffix} file")
    if not p.parent.is_dir():
        raise OutputError(f"{flag} {path!r}: the folder {str(p.parent)!r} does not exist", path=path,
                          reason="no such folder")


def summary_lines(report: Any, out: str | Path) -> list[str]:
    """The run summary: the report's page, each campaign's inputs, the run's seed and laws, what was not
    made, what to trust, and (last) the steps skipped."""
    lines = [f"report written to {Path(out) / report.index.name}"]
    sections = getattr(report, "sections", {})
    for name, sec in sections.items():
        facts = dict(sec.inputs.lines())
        lines.append(f"campaign {name}: {facts.pop('source')}, {facts.pop('data')}, {facts.pop('bounces')} bounces")
        lines += [f"  {what}: {text}" for what, text in facts.items()]
    if sections:
        lines.append(f"seed {report.seed}; laws: {', '.join(report.laws)}; bootstrap: "
                     + (f"{report.bootstrap} resamples" if report.bootstrap else "left out (0)"))
    left_out = getattr(report, "left_out", [])
    if left_out:
        lines.append(f"not made ({len(left_out)}, by choice or for want of what they need in the data):")
        lines += [f"  {campaign}: {what}: {why}" for campaign, what, why in left_out]
    caveats = getattr(report, "caveats", [])
    if caveats:
        lines.append("what to trust:")
        lines += [f"  {campaign}: {text}" for campaign, text in caveats]
    if not report.complete:
        lines.append(f"partial report: {len(report.skipped)} step(s) could not run on the data and were skipped "
                     f"(exit code {EXIT_PARTIAL}):")
        lines += [f"  {campaign}: {what}: {why}" for campaign, what, why in report.skipped]
    return lines


def summarise(report: Any, out: str | Path) -> int:
    """Print the run summary (:func:`summary_lines`) on standard output; returns the exit code (0 complete,
    5 partial)."""
    print("\n".join(summary_lines(report, out)))
    return EXIT_OK if report.complete else EXIT_PARTIAL
