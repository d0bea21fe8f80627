"""The paper's whole analysis as a library call: :func:`reproduce` returns a :class:`Report`.

>>> import bouncelab as bl
>>> report = bl.reproduce(["A"], out="report")  # doctest: +SKIP
>>> report.complete, report.skipped, report.left_out  # doctest: +SKIP

* :mod:`~bouncelab.report.steps` — one function per step of one campaign's analysis (Table 3,
  Table 2, cross-validation, assessment, lever arm, bootstrap, repeatability, tangential
  velocities, prediction intervals, the reload check) and what to trust where figures disagree;
* :mod:`~bouncelab.report.figures` — one function per figure (the paper's Figs. 3 and 6-10, the lever arm);
* :mod:`~bouncelab.report.model` — what a report holds (:class:`Report`, :class:`Section`,
  :class:`Inputs`, :class:`Skipped`, tables, figures, laws);
* :mod:`~bouncelab.report.markdown`, :mod:`~bouncelab.report.page` — its tables as markdown, its page as
  HTML (``index.html`` and the report's own view in a notebook);
* :mod:`~bouncelab.report.folder` — the output folder: refused before any work when unsafe, built beside
  it and swapped in only when complete;
* :mod:`~bouncelab.report.pipeline` — :func:`reproduce`, which runs them.

The ``bouncelab reproduce`` command parses its arguments, calls :func:`reproduce` and words the result.
"""

from __future__ import annotations

from bouncelab.report.folder import MANIFEST, remove_stale_staging
from bouncelab.report.model import Figure, Inputs, LawFile, Report, Section, Skipped, Table
from bouncelab.report.pipeline import reproduce
from bouncelab.report.steps import campaign_file_name, default_laws

__all__ = ["MANIFEST", "Figure", "Inputs", "LawFile", "Report", "Section", "Skipped", "Table", "campaign_file_name",
           "default_laws", "remove_stale_staging", "reproduce"]
