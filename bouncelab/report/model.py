"""What :func:`bouncelab.reproduce` returns: a :class:`Report` of one :class:`Section` per campaign.

Everything the report holds is here, in memory: its tables (as DataFrames and markdown), its
figures (as PNG bytes), the fitted laws, what each campaign's analysis read (:class:`Inputs`),
what it could not make or left out, with the reason (:class:`Skipped`), and what to trust where
two of its figures disagree. Writing it to a folder (:mod:`bouncelab.report.folder`) and showing
it (:mod:`bouncelab.report.page`) read it and change nothing.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

    from bouncelab.laws import BounceModel

__all__ = ["Figure", "Inputs", "LawFile", "Report", "Section", "Skipped", "Table"]


class Skipped(NamedTuple):
    """A table, figure or step of the report that was not made, and why.

    A plain tuple ``(campaign, step, reason)``: ``step`` names what it would have made (``"Fig. 6"``,
    ``"Table 2: paper's SVM plane"``), ``reason`` says why in words.
    """

    campaign: str
    step: str
    reason: str


@dataclass(frozen=True)
class Inputs:
    """What one campaign's analysis read.

    ``source`` is the campaign as asked for (``"A"``, or the path given); ``origin`` the file read
    (its absolute path) or, for data bouncelab made, how it made them (None: not said); ``kind`` whether
    the bounces are measured or synthetic; ``units`` the units the values were read in;
    ``dropped_rows`` the file's data rows left out for a missing value (1-based, the first row
    under the header is 1); ``settings`` how the launcher settings were known; ``intervals`` what
    the prediction-interval columns held (None: the data have none).
    """

    source: str
    origin: str | None
    kind: str
    units: str
    bounces: int
    dropped_rows: tuple[int, ...] = ()
    settings: str = ""
    intervals: str | None = None

    def lines(self) -> list[tuple[str, str]]:
        """(what, text) pairs describing the inputs, for the page and the console."""
        rows = [("source", self.source if self.origin in (None, self.source) else f"{self.source} ({self.origin})"),
                ("data", self.kind), ("units read", self.units), ("bounces", str(self.bounces))]
        if self.dropped_rows:
            rows.append(("rows dropped", f"{len(self.dropped_rows)} (a missing value), data rows "
                                         + ", ".join(map(str, self.dropped_rows))))
        if self.settings:
            rows.append(("launcher settings", self.settings))
        rows.append(("prediction intervals", self.intervals or "none in the data"))
        return rows


@dataclass
class Table:
    """One table: ``frame`` written as ``tables/CAMPAIGN_STEM.csv``, ``markdown`` as ``.md`` and shown on the
    page. A table without ``frame`` is a section whose step was skipped (its markdown says why); one without
    ``markdown`` is data only (a CSV beside a table that summarises it)."""

    title: str
    stem: str
    markdown: str | None = field(repr=False)
    frame: pd.DataFrame | None = field(default=None, repr=False)

    def files(self, campaign: str) -> list[str]:
        """The files the table is written to, relative to the report folder."""
        base = f"tables/{campaign}_{self.stem}"
        return [f"{base}.csv"] * (self.frame is not None) + [f"{base}.md"] * (self.markdown is not None)


@dataclass
class Figure:
    """One figure, ``png`` written as ``figures/CAMPAIGN_STEM.png``; ``png`` None: not drawn, ``reason`` says
    why. ``label`` is its short name (``"Fig. 3"``)."""

    caption: str
    stem: str
    label: str
    png: bytes | None = field(default=None, repr=False)
    reason: str | None = None

    def files(self, campaign: str) -> list[str]:
        return [] if self.png is None else [f"figures/{campaign}_{self.stem}.png"]


@dataclass
class LawFile:
    """A fitted law written as ``laws/CAMPAIGN_STEM.json``; ``listed``: linked on the page as one of Table 3's."""

    name: str
    stem: str
    model: BounceModel
    listed: bool = True

    def files(self, campaign: str) -> list[str]:
        return [f"laws/{campaign}_{self.stem}.json"]


@dataclass
class Section:
    """One campaign's analysis.

    ``tables``, ``figures`` and ``laws`` are keyed by their file stems; ``skipped`` lists the steps that
    could not run on these data (the report is then partial), ``left_out`` those not made by choice or
    for want of an optional input (no interval columns, ``figures=False``...), each with its reason;
    ``caveats`` says where two of the report's figures disagree and which to trust, and which laws have
    more parameters than these data support. The analysis objects themselves are kept for further work:
    ``comparison`` (:class:`~bouncelab.fitting.Comparison`, Table 3), ``piecewise`` (Table 2's fits),
    ``assessments`` (:class:`~bouncelab.fitting.assessment.Assessment` per law), ``repeatability``.
    """

    name: str
    inputs: Inputs
    data: xr.Dataset | None = None
    notes: list[str] = field(default_factory=list)
    tables: dict[str, Table] = field(default_factory=dict)
    figures: dict[str, Figure] = field(default_factory=dict)
    laws: dict[str, LawFile] = field(default_factory=dict)
    skipped: list[Skipped] = field(default_factory=list)
    left_out: list[Skipped] = field(default_factory=list)
    caveats: list[str] = field(default_factory=list)
    law_names: list[str] = field(default_factory=list)
    synthetic: bool = False
    generator: str | None = None
    paper_campaign: str | None = None
    comparison: Any = None
    piecewise: dict[str, Any] = field(default_factory=dict)
    assessments: dict[str, Any] = field(default_factory=dict)
    not_assessed: dict[str, str] = field(default_factory=dict)
    repeatability: Any = None

    def files(self) -> list[str]:
        """Every file of this campaign, relative to the report folder."""
        items = [*self.tables.values(), *self.laws.values(), *self.figures.values()]
        return [f for item in items for f in item.files(self.name)]

    def __repr__(self) -> str:
        drawn = sum(f.png is not None for f in self.figures.values())
        return (f"<Section {self.name}: {self.inputs.bounces} bounces, {len(self.tables)} tables, {drawn} figures, "
                f"{len(self.laws)} laws, {len(self.skipped)} skipped, {len(self.left_out)} not made>")


@dataclass
class Report:
    """The paper's analysis of one or more campaigns (:func:`bouncelab.reproduce`).

    ``sections`` holds one :class:`Section` per campaign, by name. ``out`` is the folder the report
    was written to (None: kept in memory only) and ``files`` every file written there.
    ``skipped`` lists, as ``(campaign, step, reason)``, the steps that could not run on the data (too
    few bounces for a law, one slip/roll class for the SVM, no repeated launcher setting, a figure
    that cannot be drawn); ``complete`` is True when there are none. ``left_out`` lists what was not
    made by choice or for want of an optional input, with the reason: these do not make the report
    partial. In a notebook the report shows itself: its page, tables and figures inline.
    """

    out: Path | None
    sections: dict[str, Section] = field(default_factory=dict)
    seed: int = 0
    laws: tuple[str, ...] = ()
    bootstrap: int = 0
    elapsed: float = 0.0
    #: Units of the figures (``{"velocity": ..., "spin": ...}``); None for the scaled units.
    figure_units: dict[str, str] | None = None
    files: list[Path] = field(default_factory=list)

    @property
    def index(self) -> Path | None:
        """The report's page, ``out/index.html`` (None for a report kept in memory)."""
        return None if self.out is None else self.out / "index.html"

    @property
    def skipped(self) -> list[Skipped]:
        """The steps that could not run on the data, every campaign's, in order."""
        return [s for sec in self.sections.values() for s in sec.skipped]

    @property
    def left_out(self) -> list[Skipped]:
        """What was not made by choice or for want of an optional input, with the reason."""
        return [s for sec in self.sections.values() for s in sec.left_out]

    @property
    def caveats(self) -> list[tuple[str, str]]:
        """``(campaign, text)``: where the report's figures disagree and which to trust; laws with more
        parameters than the data support."""
        return [(name, text) for name, sec in self.sections.items() for text in sec.caveats]

    @property
    def inputs(self) -> dict[str, Inputs]:
        """What each campaign's analysis read, by campaign."""
        return {name: sec.inputs for name, sec in self.sections.items()}

    @property
    def complete(self) -> bool:
        """Whether every step ran (nothing in :attr:`skipped`)."""
        return not self.skipped

    def to_html(self, *, inline: bool = True) -> str:
        """The report's page as one HTML document; ``inline``: its figures inside it (base64 PNGs), else
        linked to the files of :attr:`out` (as ``index.html`` does)."""
        from bouncelab.report.page import report_html

        return report_html(self, inline=inline, standalone=True)

    def _repr_html_(self) -> str:
        from bouncelab.report.page import report_html

        return report_html(self, inline=True, standalone=False)

    def __repr__(self) -> str:
        where = "in memory" if self.out is None else f"in {str(self.out)!r}"
        state = "complete" if self.complete else f"partial, {len(self.skipped)} step(s) skipped"
        return f"<bouncelab Report of {', '.join(self.sections) or 'no campaign'} {where}: {state}>"
