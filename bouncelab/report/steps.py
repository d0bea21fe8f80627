"""The paper's analysis of one campaign, one function per step.

Each step reads the campaign and what earlier steps made (a :class:`Run`), and adds to the
campaign's :class:`~bouncelab.report.model.Section`: its tables, fitted laws, notes, and, when it
cannot run on these data, a :class:`~bouncelab.report.model.Skipped` record with the reason (the
report is then partial) or, when it is not made by choice or for want of an optional input, a
``left_out`` record. A step returns the few words the progress display shows after it (None:
"done"). Only the typed errors of :data:`bouncelab.fitting.comparison.SKIPPABLE` (FitError,
DataError, ParameterError: "not on these data") become skips; anything else is a bug and stops the run.

The figures are steps too (:mod:`bouncelab.report.figures`).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from inspect import signature
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.report.markdown import assessment_markdown, frame_markdown, table2_markdown
from bouncelab.report.model import Inputs, LawFile, Section, Skipped, Table

__all__ = ["ASSESSED", "ASSESS_OPTIONS", "BEYOND_PAPER_LAWS", "BOOTSTRAPPED", "BOOTSTRAP_RESAMPLES",
           "NOT_ASSESSED", "NOT_ASSESSED_OTHER", "NOT_CROSS_VALIDATED", "NOT_CROSS_VALIDATED_REASON", "STAGES",
           "Run", "assessment", "bootstrap", "campaign_file_name", "caveats", "cross_validation", "default_laws",
           "inputs_of", "lever_arm", "prediction_intervals", "reload_check", "repeatability", "start",
           "table2", "table3", "tangential"]

#: Resamples of the parameter bootstrap in the report (3 to 4 s per campaign here; the refits run one after another).
BOOTSTRAP_RESAMPLES = 100
#: Laws fitted beside the paper's in every report: Walton's tangential restitution and the physics-based laws.
BEYOND_PAPER_LAWS = ("TangentialRestitution", "CompliantImpact", "TurfContact")
#: Laws left out of the report's cross-validation because each fit takes seconds (they integrate every bounce).
NOT_CROSS_VALIDATED = frozenset({"TurfContact", "CraterContact"})
#: Why (the report says so beside Table 3's held-out rows).
NOT_CROSS_VALIDATED_REASON = ("left out to keep the report quick: each fit integrates every bounce through the contact "
                              "and takes seconds to minutes; bouncelab.compare(data, [law]) gives them")
#: The laws whose parameters the report bootstraps (the paper's rigid family).
BOOTSTRAPPED = ("Rigid", "PennerVarying", "PennerFixed")
#: The laws the report assesses (:func:`bouncelab.assess`): the rigid family, whose fits take milliseconds.
ASSESSED = ("Rigid", "PennerVarying", "PennerFixed", "TangentialRestitution")


def _assess_defaults() -> dict[str, int]:
    from bouncelab.fitting.assessment import assess

    params = signature(assess).parameters
    return {name: params[name].default for name in ("k", "starts", "profile_points", "local_points")}


#: The assessment's counts in the report: :func:`bouncelab.assess`'s defaults (its bootstrap resamples are the
#: report's ``bootstrap``, and its folds at most the launcher settings); about 1 to 3 s per law on 693 bounces.
ASSESS_OPTIONS = _assess_defaults()
#: Why a law is not assessed in the report, by law (others: :data:`NOT_ASSESSED_OTHER`).
NOT_ASSESSED = {
    "PiecewiseAffine": "28 numbers in array parameters: an assessment profiles each with about 17 refits by the "
                       "generic global search, hundreds in all, and its plane search has no held parameters",
    "CompliantImpact": "each fit integrates every bounce through the contact (one to a few seconds); an assessment "
                       "refits it about 160 times",
    "TurfContact": "each fit integrates every bounce through the contact (seconds to a minute); an assessment refits "
                   "it some 200 times",
    "CraterContact": "each fit integrates every bounce through the contact (half a minute to a minute or more); an "
                     "assessment refits it some 300 times (docs/physics_laws.md gives one, with reduced counts)",
}
NOT_ASSESSED_OTHER = "not one of the rigid family assessed in the report; an assessment refits a law some 150 times"

_UNSAFE = re.compile(r"[^A-Za-z0-9_-]+")


def campaign_file_name(text: str) -> str:
    """``text`` made safe as the start of a file name: runs of anything but letters, digits, ``_``
    and ``-`` become one ``_`` (so no ``/``, ``..`` or leading dot survives); "campaign" if nothing is left.

    >>> campaign_file_name("../../x"), campaign_file_name("turf B (2024)"), campaign_file_name("/")
    ('x', 'turf_B_2024', 'campaign')
    """
    return _UNSAFE.sub("_", str(text)).strip("_") or "campaign"


def default_laws() -> tuple[str, ...]:
    """The laws of a report unless chosen: the paper's four and :data:`BEYOND_PAPER_LAWS`."""
    from bouncelab.fitting.comparison import PAPER_LAWS

    return (*PAPER_LAWS, *BEYOND_PAPER_LAWS)


def _first_line(exc: BaseException) -> str:
    return str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__


@dataclass
class Run:
    """One campaign's analysis in progress: its options, its section, and what the steps pass on."""

    section: Section
    data: xr.Dataset
    seed: int
    laws: list[Any]
    bootstrap: int
    units: Any = None
    train: xr.Dataset | None = None
    test: xr.Dataset | None = None
    split_error: str | None = None
    repeatability_error: str | None = None

    @property
    def name(self) -> str:
        return self.section.name

    def skip(self, step: str, reason: str) -> None:
        """``step`` could not run on these data (the report is partial)."""
        self.section.skipped.append(Skipped(self.name, step, reason))

    def leave_out(self, step: str, reason: str) -> None:
        """``step`` is not made, by choice or for want of an optional input (the report stays complete)."""
        self.section.left_out.append(Skipped(self.name, step, reason))

    def table(self, df: pd.DataFrame, stem: str, title: str, *, percent: bool = False,
              shown: pd.DataFrame | None = None, missing: str = "nan", note: str = "", marked: bool = False) -> None:
        """A table of numbers, shown under ``title``; ``marked``: its rows are laws, and the one that generated
        synthetic data is marked."""
        from bouncelab.fitting.comparison import generator_note

        frame = df if shown is None else shown
        generator = self.section.generator
        mark = generator if marked and generator is not None else None
        md = f"### {title}\n\n" + frame_markdown(frame, percent=percent, missing=missing, mark=mark)
        md += f"\n{note}\n" if note else ""
        if marked and (footnote := generator_note(generator, [str(i) for i in frame.index])) is not None:
            md += f"\n> {footnote}\n"
        self.section.tables[stem] = Table(title, stem, md, df)

    def text(self, stem: str, title: str, md: str) -> None:
        """A section without numbers (its steps were skipped): the markdown that says why, and no CSV."""
        self.section.tables[stem] = Table(title, stem, md)

    def skipped_table(self, key: str, stem: str, title: str, reason: str) -> str:
        """A table that could not be computed; returns the progress display's status."""
        self.text(stem, title, f"### {title}\n\nSkipped: {reason}\n")
        self.skip(key, reason)
        return f"skipped: {reason}"

    @property
    def names(self) -> list[str]:
        return self.section.law_names


def inputs_of(source: str, ds: xr.Dataset) -> Inputs:
    """What a loaded campaign says of its source: the file (or how bouncelab made it), the units read, the
    rows dropped."""
    attrs = ds.attrs
    synthetic = attrs.get("data_kind") == "synthetic surrogate"
    origin = attrs.get("source")
    kind = "synthetic surrogate" if synthetic else str(attrs.get("data_kind", "measured"))
    if synthetic and attrs.get("surrogate"):
        kind = f"synthetic surrogate {attrs['surrogate']!r}"
    units = attrs.get("source_units")
    if units is None:  # a campaign file (netCDF, embedded) or data made in Python: scaled units throughout
        units = "scaled (radii/s, rad/s), as stored"
    if attrs.get("source_form"):
        units += f"; states given as {attrs['source_form']}"
    dropped = tuple(int(r) for r in np.atleast_1d(attrs.get("dropped_rows", [])))
    intervals = None
    if "landing_pi" in ds.data_vars:
        intervals = str(attrs.get("interval_source") or "95 % half-widths (landing_pi, liftoff_pi)")
        if attrs.get("interval_form"):
            intervals += f"; {attrs['interval_form']}"
    return Inputs(source=str(source), origin=None if origin is None else str(origin), kind=kind, units=str(units),
                  bounces=int(ds.sizes["bounce"]), dropped_rows=dropped, intervals=intervals)


def start(name: str, source: str, ds: xr.Dataset) -> tuple[Section, xr.Dataset]:
    """The section of a campaign and its data, with launcher settings (inferred when the data have none)."""
    from dataclasses import replace

    from bouncelab.core import published
    from bouncelab.data.campaign import synthetic_warning
    from bouncelab.data.settings import infer_settings
    from bouncelab.fitting.comparison import generating_law

    camp = str(ds.attrs.get("campaign", "")).upper()
    inputs = inputs_of(source, ds)
    section = Section(name=name, inputs=inputs, synthetic=ds.attrs.get("data_kind") == "synthetic surrogate",
                      generator=generating_law(ds), paper_campaign=camp if camp in published.CAMPAIGNS else None)
    if (note := synthetic_warning(ds)) is not None:
        section.notes.append(note)
    if "setting" not in ds.coords:
        labels = infer_settings(ds)
        ds = ds.assign_coords(setting=("bounce", labels))
        n = len(np.unique(labels))
        section.notes.append(f"The data record no launcher settings; {n} settings were inferred by clustering "
                             "the landing conditions (bouncelab.infer_settings).")
        section.inputs = replace(inputs, settings=f"{n}, inferred by clustering the landings (none in the data)")
    else:
        counts = np.unique(ds.setting.values, return_counts=True)[1]
        low, high = int(counts.min()), int(counts.max())
        each = f"{low} bounce(s) each" if low == high else f"{low} to {high} bounces each"
        section.inputs = replace(inputs, settings=f"{len(counts)} recorded, {each}")
    section.data = ds
    return section, ds


# ------------------------------------------------------------------------------------------------ Table 3
def table3(run: Run) -> str | None:
    """Table 3: every law fitted to all bounces, with held-out errors (grouped 5-fold cross-validation) and,
    for Rigid, the paper's two-stage procedure."""
    from bouncelab.fitting import compare, fit
    from bouncelab.fitting.comparison import SKIPPABLE
    from bouncelab.laws import Rigid

    name, ds, sec = run.name, run.data, run.section
    key = "Table 3: laws fitted to all bounces"
    try:
        cmp = compare(ds, run.laws, seed=run.seed, errors="skip",
                      heldout=[n for n in run.names if n not in NOT_CROSS_VALIDATED])
    except SKIPPABLE as exc:
        return run.skipped_table(key, "table3", f"Laws fitted to campaign {name}", _first_line(exc))
    for law, why in cmp.skipped.items():
        run.skip(f"Table 3: {law}", why)
    for law, why in list(cmp.heldout_skipped.items()):
        if law in NOT_CROSS_VALIDATED:
            cmp.heldout_skipped[law] = NOT_CROSS_VALIDATED_REASON
        else:  # the folds could not be fitted (or one launcher setting only): a step that did not run
            run.skip(f"cross-validation: {law}", why)
    md = cmp.to_markdown()
    if "Rigid" in cmp.results:
        try:
            structured = fit(Rigid, ds, method="structured", seed=run.seed)
            md += ("\n### The paper's two-stage procedure for Rigid (r by least squares on ydot, then mu)\n\n"
                   f"r = {structured.model.r:.4g}, mu = {structured.model.mu:.4g}, "
                   f"delta = {100 * structured.delta:.3g} % (global search: delta = "
                   f"{100 * cmp.results['Rigid'].delta:.3g} %)\n")
        except SKIPPABLE as exc:
            md += f"\n### The paper's two-stage procedure for Rigid\n\nSkipped: {_first_line(exc)}\n"
            run.skip("Table 3: the paper's two-stage procedure for Rigid", _first_line(exc))
    sec.tables["table3"] = Table(key, "table3", md, cmp.side_by_side())
    for law, res in cmp.results.items():
        stem = campaign_file_name(law)  # a user law's key holds ':'
        sec.laws[stem] = LawFile(law, stem, res.model)
    sec.comparison = cmp
    return f"done, {len(cmp.skipped)} law(s) skipped" if cmp.skipped else None


# ------------------------------------------------------------------------------------------------ Table 2
def table2(run: Run) -> str | None:
    """Table 2: the piecewise-affine law on the paper's split (one bounce per launcher setting held out), by
    the paper's SVM plane and by bouncelab's delta-optimal plane."""
    from bouncelab.fitting import fit, split_by_setting
    from bouncelab.fitting.comparison import SKIPPABLE
    from bouncelab.laws import PiecewiseAffine

    name, ds, sec = run.name, run.data, run.section
    key = "Table 2: piecewise-affine law, held-out bounces"
    try:
        run.train, run.test = split_by_setting(ds, run.seed)
    except SKIPPABLE as exc:
        run.split_error = _first_line(exc)
    if "PiecewiseAffine" not in run.names:
        run.leave_out("Table 2", "PiecewiseAffine is not among the laws asked for")
        return "left out (PiecewiseAffine is not among the laws)"
    if run.split_error is not None:
        return run.skipped_table(key, "table2", f"Piecewise-affine law, campaign {name}, on the paper's split",
                                 f"the paper's split cannot be made: {run.split_error}")
    pw: dict[str, Any] = {}
    failed: dict[str, str] = {}
    for method, label in (("svm", "paper's SVM plane"), ("plane", "bouncelab's delta-optimal plane")):
        try:
            pw[label] = fit(PiecewiseAffine, run.train, test=run.test, method=method, seed=run.seed)
        except SKIPPABLE as exc:
            # e.g. the SVM needs enough bounces of both classes; the rest of the report is written
            failed[label] = (f"cannot run on the {run.train.sizes['bounce']} training bounces of the split: "
                             f"{_first_line(exc)}")
            run.skip(f"Table 2: {label}", failed[label])
    if not pw:
        md = (f"### Piecewise-affine law, campaign {name}, on the paper's split\n\n"
              + "".join(f"Skipped ({label}): {why}\n\n" for label, why in failed.items()))
        run.text("table2", key, md)
        return "skipped"
    rows = []
    for label, res in pw.items():
        for data_name in ("train", "test"):
            t = res.errors.loc[data_name]
            diags = res.diagnostics if data_name == "train" else res.test_diagnostics
            for subset in t.index:
                rows.append({"method": label, "data": data_name, "subset": subset, **t.loc[subset].to_dict(),
                             **{k: (v if subset == "all" else np.nan) for k, v in diags.items()}})
    md = table2_markdown(name, pw, ds)
    for label, why in failed.items():
        md += f"\n> {label}: skipped, {why}\n"
    sec.tables["table2"] = Table(key, "table2", md, pd.DataFrame(rows).set_index(["method", "data", "subset"]))
    sec.piecewise = pw
    for label, res in pw.items():
        stem = f"PiecewiseAffine_{'svm' if 'SVM' in label else 'plane'}_train"
        sec.laws[stem] = LawFile(f"PiecewiseAffine, {label}, fitted on the split's training bounces", stem,
                                 res.model, listed=False)
    return "done, one plane skipped" if failed else None


# ------------------------------------------------------------------------------ held-out errors, assessment
def cross_validation(run: Run) -> str | None:
    """The cross-validated delta of every law, from Table 3's comparison (no refits)."""
    cmp = run.section.comparison
    held = {} if cmp is None else cmp.heldout
    if not held:
        return None
    cvt = pd.DataFrame({law: {"fitted_delta": cmp.results[law].delta, "heldout_delta": h.scores["delta"],
                              "heldout_delta_sd": h.scores["delta_sd"]} for law, h in held.items()}).T
    cvt.index.name = "law"
    first = next(iter(held.values()))
    notes = [f"{law}: no held-out delta, {why}." for law, why in cmp.heldout_skipped.items()]
    run.table(cvt, "crossvalidation", f"Cross-validated delta, campaign {run.name} ({first.k} folds grouped by "
              "launcher setting; fitted_delta on all bounces)", percent=True, note="\n\n".join(notes), marked=True)
    return None


def assessment(run: Run) -> str | None:
    """An assessment (:func:`bouncelab.assess`) of each law of :data:`ASSESSED`; the others are named with the
    reason they are not assessed."""
    from bouncelab.fitting import assessment as assessing
    from bouncelab.fitting.comparison import SKIPPABLE
    from bouncelab.laws import law_name

    sec = run.section
    k = min(ASSESS_OPTIONS["k"], len(np.unique(run.data.setting.values)))
    targets = [m for m in run.laws if law_name(m) in ASSESSED]
    failed: dict[str, str] = {}
    for model in targets:
        try:
            sec.assessments[law_name(model)] = assessing.assess(model, run.data, seed=run.seed,
                                                                n_bootstrap=run.bootstrap, **{**ASSESS_OPTIONS, "k": k})
        except SKIPPABLE as exc:
            failed[law_name(model)] = _first_line(exc)
            run.skip(f"assessment: {law_name(model)}", _first_line(exc))
    not_assessed = {n: NOT_ASSESSED.get(n, NOT_ASSESSED_OTHER) for n in run.names if n not in ASSESSED}
    if not (sec.assessments or failed):
        why = f"none of {', '.join(ASSESSED)} is among the laws (bouncelab.assess(law, data) assesses any law)"
        run.leave_out("Assessment of each law", why)
        return f"left out (none of {', '.join(ASSESSED)} is among the laws)"
    options = {**ASSESS_OPTIONS, "k": k, "n_bootstrap": run.bootstrap}
    md = assessment_markdown(run.name, sec.assessments, options, not_assessed=not_assessed, failed=failed,
                             generator=sec.generator)
    title = "Assessment of each law (beyond the paper)"
    if sec.assessments:
        frame = pd.concat({law: a.to_frame() for law, a in sec.assessments.items()}, names=["law", "parameter"])
        sec.tables["assessment"] = Table(title, "assessment", md, frame)
    else:
        run.text("assessment", title, md)
    sec.not_assessed = not_assessed
    if failed:
        return f"done, {len(failed)} law(s) skipped" if sec.assessments else "skipped"
    return None


# ---------------------------------------------------------------------------------------------- lever arm
def lever_arm(run: Run) -> str | None:
    """Where the horizontal impulse acts: the lever arm of the data and of every fitted law."""
    from bouncelab.analysis.impulse import lever_arm_summary

    cmp, sec = run.section.comparison, run.section
    fitted = [] if cmp is None else [res.model for res in cmp.results.values()]
    lever = lever_arm_summary(run.data, fitted)
    generator = sec.generator
    run.table(lever, "lever_arm",
              f"Lever arm of the horizontal impulse, d(omega)/d(xdot) per bounce, campaign {run.name}: data and each "
              "law fitted to all bounces, on the same landings",
              note="A law whose whole horizontal impulse acts at the contact point gives 2.5; the centre fraction "
                   "1 - median/2.5 estimates the share passing through the ball's centre (ploughing)"
                   + (f" of the law that generated these synthetic bounces ({generator}), not of any turf"
                      if sec.synthetic and generator else " in these bounces" if sec.synthetic else "")
                   + ". Bounces whose xdot changes by less than 2 % of the landing speed have no lever arm "
                     "(n_defined).", marked=True)
    return None


# ---------------------------------------------------------------------------------------------- bootstrap
def bootstrap(run: Run) -> str | None:
    """Bootstrap intervals of the rigid family's parameters: the assessment's own bootstrap (no refits)."""
    sec = run.section
    frames, failed = {}, {}
    targets = [law for law in run.names if law in BOOTSTRAPPED]
    for law in targets if run.bootstrap > 0 else []:
        if law in sec.assessments and sec.assessments[law].bootstrap is not None:
            frames[law] = sec.assessments[law].bootstrap.summary()
        else:  # its assessment was skipped (see there)
            failed[law] = "its assessment could not run on these data"
    title = "Parameter uncertainty (beyond the paper)"
    if frames:
        boot_table = pd.concat(frames, names=["law", "parameter"])
        run.table(boot_table, "bootstrap", f"Parameter uncertainty, campaign {run.name}: {run.bootstrap} bootstrap "
                  "resamples of whole launcher settings (95 % percentile intervals)",
                  shown=boot_table.reset_index().set_index("law"),
                  note="\n\n".join(f"{law}: skipped, {why}" for law, why in failed.items()), marked=True)
        return f"done, {len(failed)} law(s) skipped" if failed else None
    if failed:
        md = (f"### Parameter uncertainty, campaign {run.name}\n\n"
              + "\n\n".join(f"{law}: skipped, {why}" for law, why in failed.items()) + "\n")
        run.text("bootstrap", title, md)
        return "skipped"
    why = ("bootstrap resamples set to 0" if run.bootstrap == 0 else
           f"none of {', '.join(BOOTSTRAPPED)} is among the laws")
    run.leave_out("Parameter bootstrap", why)
    return f"left out ({why})"


# ------------------------------------------------------------------------------------------ repeatability
def repeatability(run: Run) -> str | None:
    """The repeatability of each launcher setting (the paper's Fig. 9, as a table)."""
    from bouncelab.analysis import repeats
    from bouncelab.fitting.comparison import SKIPPABLE

    key = "Repeatability"
    counts = np.unique(run.data.setting.values, return_counts=True)[1]
    rep = summ = None
    if not (counts >= 2).any():
        run.repeatability_error = (f"no launcher setting has two or more bounces ({len(counts)} settings, one bounce "
                                   "each), so no repeat can be compared")
    else:
        try:
            rep = repeats.repeatability(run.data)
            summ = repeats.repeatability_summary(rep)
        except SKIPPABLE as exc:
            rep, run.repeatability_error = None, _first_line(exc)
    if run.repeatability_error is not None:
        return run.skipped_table(key, "repeatability_summary", f"Repeatability, campaign {run.name}",
                                 run.repeatability_error)
    run.section.tables["repeatability"] = Table("Repeatability per setting (data)", "repeatability", None,
                                                rep.to_dataframe())
    run.table(summ, "repeatability_summary",
              f"Repeatability, campaign {run.name}: 95 % CI half-widths of the mean per setting", missing="–",
              note="Medians over the settings. The row 'all' pools the three components for the ratio and the "
                   "fraction of settings whose lift-off interval is wider; it has no median half-width, as the "
                   "components' units differ.")
    run.section.repeatability = rep
    return None


# ------------------------------------------------------------------------------ tangential, intervals
def tangential(run: Run) -> str | None:
    """Tangential velocities v_P = xdot + omega at landing and lift-off (the paper's Fig. 7, as a table)."""
    from bouncelab.analysis import contact_velocity
    from bouncelab.fitting.comparison import SKIPPABLE

    try:
        tang = contact_velocity.tangential_summary(run.data)
    except SKIPPABLE as exc:
        return run.skipped_table("Tangential velocities", "tangential", f"Tangential velocity, campaign {run.name}",
                                 _first_line(exc))
    run.table(tang, "tangential", f"Tangential velocity v_P = xdot + omega, campaign {run.name}")
    return None


#: Why Fig. 6 and the prediction-interval table are not made on data without interval columns.
NO_INTERVALS = ("the data have no prediction-interval columns (landing_pi, liftoff_pi: 95 % half-widths or standard "
                "deviations per bounce, as the paper's tracking gives; see docs/data.md)")


def prediction_intervals(run: Run) -> str | None:
    """The median width of the prediction intervals (the paper's Fig. 6, as a table)."""
    ds = run.data
    if "landing_pi" not in ds.data_vars:
        run.leave_out("Prediction intervals (table)", NO_INTERVALS)
        return None
    widths = {}
    for state in ("landing", "liftoff"):
        w = 2 * ds[f"{state}_pi"] / np.abs(ds[state]).mean("bounce")
        widths[state] = w.median("bounce").to_pandas()
    pit = pd.DataFrame(widths)
    pit.index.name = "component"
    run.table(pit, "prediction_intervals",
              f"Median 95 % prediction-interval width / campaign mean |q|, campaign {run.name}", percent=True)
    return None


# ---------------------------------------------------------------------------------------------- reload
def reload_check(run: Run) -> str | None:
    """Every fitted law of Table 3 reloads from its JSON text to the same law (else a bug: RuntimeError)."""
    import json

    from bouncelab.laws.files import law_from_dict

    for law in run.section.laws.values():
        if not law.listed:
            continue
        if law_from_dict(json.loads(law.model.to_json())) != law.model:
            raise RuntimeError(f"the fitted law {law.name} does not reload from its JSON to the same law")
    return None


# ---------------------------------------------------------------------------------------------- caveats
#: Two estimates disagree when they differ by more than this many combined standard errors.
DISAGREE_Z = 2.0


def caveats(run: Run) -> None:
    """What to trust: Table 2's held-out figure against grouped cross-validation, and laws with more
    parameters than these data support (the assessment's verdicts). Nothing is fitted here."""
    sec = run.section
    cmp = sec.comparison
    held = {} if cmp is None else cmp.heldout
    # Table 2's delta-optimal plane is PiecewiseAffine's own fitting method, the one its folds use (the SVM is not)
    plane = sec.piecewise.get("bouncelab's delta-optimal plane")
    if plane is not None and "PiecewiseAffine" in held and run.test is not None:
        text = _split_against_folds("bouncelab's delta-optimal plane", plane, held["PiecewiseAffine"], run.test)
        if text is not None:
            sec.caveats.append(text)
    for name, a in sec.assessments.items():
        flat = [p for p, v in a.verdicts.items() if v == "not identifiable"]
        if flat:
            one = len(flat) == 1
            sec.caveats.append(
                f"{name} has more parameters than these data support: {len(flat)} of its {a.summary()['n_free']} "
                f"free parameters ({', '.join(flat)}) {'is' if one else 'are'} not identifiable (the assessment "
                "finds a flat direction: other values fit these bounces as well). "
                f"{'Its fitted value is' if one else 'Their fitted values are'} one of many; prefer a law with "
                "fewer parameters where it predicts as well held out.")
    for name in sec.law_names:
        if name in sec.assessments or cmp is None or name not in cmp.results:
            continue
        if name in held:
            text = _overfits(name, cmp.results[name], held[name])
            if text is not None:
                sec.caveats.append(text)


def _split_against_folds(label: str, res: Any, folds: Any, test: xr.Dataset) -> str | None:
    """A caveat when Table 2's held-out delta (one split) and grouped cross-validation's differ beyond their
    combined standard error; None when they agree."""
    from bouncelab.metrics import error_terms

    p0, pf = test.landing.values, test.liftoff.values
    terms = error_terms(p0, pf, res.model.predict(p0))[:, 0]  # Table 2's delta is their mean
    split = float(res.errors.loc[("test", "all"), "delta"])
    split_se = float(terms.std(ddof=1) / np.sqrt(len(terms))) if len(terms) > 1 else np.nan
    cv, k = float(folds.scores["delta"]), int(folds.k)
    cv_se = float(folds.scores["delta_sd"]) / np.sqrt(k)
    se = float(np.hypot(split_se, cv_se))
    if not (np.isfinite(se) and abs(split - cv) > DISAGREE_Z * se):
        return None
    direction = "lower" if split < cv else "higher"
    return (f"PiecewiseAffine ({label}): Table 2's held-out delta, {100 * split:.3g} % on {len(terms)} bounces (one "
            f"per launcher setting), is {direction} than grouped cross-validation's, {100 * cv:.3g} % +- "
            f"{100 * float(folds.scores['delta_sd']):.3g} % over {k} folds (Table 3): they differ by "
            f"{100 * abs(split - cv):.3g} points, more than {DISAGREE_Z:g} times their combined standard error "
            f"({100 * se:.2g} points). Trust the cross-validation for bounces at new launcher settings: its folds "
            "hold out whole settings, so each held-out bounce comes from conditions the fit never saw, and it "
            f"averages {k} folds. Table 2's split keeps each held-out bounce's repeats in the fit, so it measures "
            "the error on a repeat of a condition already seen, from a single draw: a law with many parameters "
            "(PiecewiseAffine has 28) can follow each setting there without predicting new ones.")


def _overfits(name: str, res: Any, folds: Any) -> str | None:
    """A caveat for a law not assessed whose held-out delta is far above its training delta (its fit follows
    these bounces more closely than it predicts new settings): more parameters than the data support."""
    train, cv, k = float(res.delta), float(folds.scores["delta"]), int(folds.k)
    se = float(folds.scores["delta_sd"]) / np.sqrt(k)
    if not (cv > 1.5 * train and cv - train > DISAGREE_Z * se):
        return None
    return (f"{name} fits its own bounces far better than it predicts held-out launcher settings (delta "
            f"{100 * train:.3g} % on all bounces, {100 * cv:.3g} % held out over {k} folds grouped by setting, "
            f"{res.n_free} free parameters): more parameters than these data support. Its identifiability is not "
            "assessed here (bouncelab.assess(law, data) does it); compare laws by their held-out errors.")


#: The steps of one campaign, as the progress display shows them: (what it says, the step functions).
STAGES: tuple[tuple[str, tuple[Callable[[Run], str | None], ...]], ...] = (
    ("fitting the paper's laws to all bounces (Table 3)", (table3,)),
    ("piecewise-affine law on the paper's split, SVM and delta plane (Table 2)", (table2,)),
    ("held-out errors and assessment of each law (beyond the paper)", (cross_validation, assessment)),
    ("where the horizontal impulse acts (lever arm, beyond the paper)", (lever_arm,)),
    ("parameter uncertainty, bootstrap over launcher settings (beyond the paper)", (bootstrap,)),
    ("repeatability per launcher setting", (repeatability,)),
    ("tangential velocities and prediction intervals", (tangential, prediction_intervals)),
    ("checking the fitted laws reload", (reload_check,)),
)


def statuses(parts: Sequence[str | None]) -> str:
    """The progress display's word for a stage of several steps."""
    said = [p for p in parts if p]
    return "; ".join(said) if said else "done"
