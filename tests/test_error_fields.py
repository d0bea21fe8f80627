"""Errors as data (issue 23, item 5) beyond the loader and the laws: the facts are fields, the advice is hints, and
only the command line words them with its flags."""

from __future__ import annotations

import ast
import pickle
from pathlib import Path

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.cli.messages import _FLAGS, _UNIT_FLAGS, flag_hint, message
from bouncelab.core.errors import Code, DataError, FitError, Hint, python_hint
from bouncelab.core.plausibility import check_scaled, landing_error, widen_hints

PACKAGE = Path(bl.__file__).parent


def test_a_data_error_names_the_argument_at_fault_and_keeps_it_through_pickling():
    err = DataError("tol must be a non-negative number of radii/s; got -1", option="tol")
    back = pickle.loads(pickle.dumps(err))
    assert (back.option, back.column, back.row) == ("tol", None, None)
    assert str(back) == err.message  # the message names it; where() is for the place in the data


def test_code_hints_read_as_python_and_as_flags():
    widen = Hint("plausible", Code("PLAUSIBLE_RANGES.widened(max_spin=...)"))
    assert python_hint(widen) == "plausible=PLAUSIBLE_RANGES.widened(max_spin=...)"  # not quoted
    assert widen == Hint("plausible", "PLAUSIBLE_RANGES.widened(max_spin=...)")  # equal to its text
    assert flag_hint(widen) == "plausible=PLAUSIBLE_RANGES.widened(max_spin=...) (in Python)"  # no flag for it
    box = Hint("bounds", {"mu": Code("(low, high)")})
    assert python_hint(box) == "bounds={'mu': (low, high)}"
    assert flag_hint(box) == """--bounds '{"mu": [low, high]}'"""
    assert flag_hint(Hint("bounds", {"mu": (0, 3)})) == """--bounds '{"mu": [0, 3]}'"""
    assert flag_hint(Hint("law_set", ["Rigid", "PennerFixed"])) == "--laws Rigid PennerFixed"
    assert flag_hint(Hint("method", "global")) == "--method global"


def test_the_unit_guard_gives_its_advice_as_hints(campaign_a):
    rpm = campaign_a.landing.values * [1, 1, 60 / (2 * np.pi)]
    with pytest.raises(DataError) as e:
        check_scaled(rpm, campaign_a.liftoff.values)
    assert e.value.hints == widen_hints("max_spin")
    assert "PLAUSIBLE_RANGES" not in e.value.message  # the advice is in the hints, not the facts
    error = landing_error(np.array([[20.0, -15.0, 3000.0]]), units={"velocity": "radius/s", "spin": "rad/s"})
    assert error.hints[0] == Hint("units", {"velocity": "m/s", "spin": "rpm"})  # both look wrong
    assert error.hints[1:] == widen_hints("min_landing_speed")
    assert message(error).endswith("give --velocity-unit m/s --spin-unit rpm or "
                                   "plausible=PLAUSIBLE_RANGES.widened(min_landing_speed=...) (in Python) or "
                                   "plausible=None (in Python)")


def test_a_fit_method_outside_its_box_hints_the_box_and_the_global_method(campaign_a):
    class Loose(bl.Rigid):
        @bl.laws.base.fit_method("closed_form")
        def _fit_closed(self, problem):
            from bouncelab.laws import FitOutcome

            return FitOutcome(model=self.replace(r=0.5, mu=2.0), objective_value=0.0, algorithm="closed form")

    with pytest.raises(FitError) as e:
        bl.fit(Loose, campaign_a, method="closed_form")
    assert e.value.option == "bounds"
    assert message(e.value).endswith("""give --bounds '{"mu": [low, high]}' (a wider box, within the physical range) """
                                     "or --method global (which searches within the bounds)")


def test_the_frame_rate_error_hints_its_options_and_pickles():
    from bouncelab.tracking.tracker import FrameRateError, check_fps

    with pytest.raises(FrameRateError) as e:
        check_fps(None, "clip.avi")
    back = pickle.loads(pickle.dumps(e.value))
    assert (back.fps, back.source, back.file) == (None, "argument", "clip.avi")
    assert [h.option for h in back.hints] == ["fps", "manifest"]
    assert "--fps" not in back.message and "--fps" in message(back)


def _strings(path: Path) -> list[tuple[int, str]]:
    """The string constants of a module, docstrings left out (a docstring may say what the command line does)."""
    tree = ast.parse(path.read_text())
    docs = {id(n.body[0].value) for n in ast.walk(tree)
            if isinstance(n, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef) and n.body
            and isinstance(n.body[0], ast.Expr) and isinstance(n.body[0].value, ast.Constant)}
    return [(n.lineno, n.value) for n in ast.walk(tree)
            if isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docs]


def test_no_library_module_words_its_errors_with_command_line_flags():
    """The flags the command line words hints with appear only in the command line (and in the loader, which
    another part of issue 23 rewrites): the library speaks Python keywords."""
    flags = set(_FLAGS.values()) | set(_UNIT_FLAGS.values())
    found = []
    for path in PACKAGE.rglob("*.py"):
        rel = path.relative_to(PACKAGE).as_posix()
        if rel.startswith(("cli/", "data/io/")) or rel in ("simulation/surrogate.py", "ground/shots.py"):
            continue  # the command line; the loader; scripts with their own command lines
        for line, text in _strings(path):
            found += [f"{rel}:{line}: {flag}" for flag in flags if f"{flag} " in text or text.endswith(flag)]
    assert found == []


@pytest.fixture(scope="module")
def campaign_a():
    return bl.load_campaign("A")


def test_bouncelab_track_words_a_failed_clips_hints_with_its_flags(tmp_path, capsys):
    """A clip that fails in measure_clips is listed with its error in the command line's words."""
    pytest.importorskip("cv2")
    from bouncelab.cli.main import main
    from bouncelab.tracking import render_clip

    clip = render_clip((1063.0, -810.0, 219.0), (696.7, 440.6, -696.7), size=(144, 288), radius_px=18.0,
                       n_before=14, n_after=14, contact_frames=6.0, seed=3)
    for name in ("a.npy", "b.npy"):  # .npy frames store no frame rate
        np.save(tmp_path / name, clip.frames)
    manifest = tmp_path / "m.csv"
    manifest.write_text("clip,fps\na.npy,5000\nb.npy,\n")  # b has none
    main(["track", str(tmp_path / "a.npy"), str(tmp_path / "b.npy"), "--manifest", str(manifest),
          "--out", str(tmp_path / "c.nc"), "--quiet"])
    err = capsys.readouterr().err
    line = next(ln for ln in err.splitlines() if "b.npy:" in ln)
    assert "the frame rate is missing; give --fps" in line and "--manifest (with an fps column)" in line
    assert "fps=" not in line  # not Python's words
