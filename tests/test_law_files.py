"""Issue 22 item 3: laws that travel, and item 7's untyped errors about law files.

A law of a script loads again once the script's module is imported; a law file carries its format, the
bouncelab version, units and conventions, the ball radius and, for a fitted law, its provenance (the data,
synthetic or measured, the generator, the landing ranges fitted); old law files still load.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
import types
import warnings
from pathlib import Path

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.cli.main import main
from bouncelab.cli.messages import EXIT_DATA, EXIT_FIT, EXIT_OK
from bouncelab.core.errors import (
    DataError,
    OutputError,
    OutsideFittedRangeWarning,
    ParameterError,
    SyntheticDataWarning,
    UnknownLawError,
)
from bouncelab.laws import BounceModel, Parameter, Provenance, law_class
from bouncelab.laws.files import LAW_FORMAT_VERSION

ROOT = Path(__file__).resolve().parents[1]

SCRIPT = '''
import numpy as np
import bouncelab as bl
from bouncelab.laws import BounceModel, Parameter


class Simple(BounceModel):
    e = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), unit="1", doc="restitution")
    regimes = ("bounce",)

    def _predict(self, p, e):
        return np.column_stack([p[:, 0], -e * p[:, 1], p[:, 2]])

    def _regime(self, p, e):
        return np.zeros(len(p), dtype=np.int8)


if __name__ == "__main__":
    import sys
    law = bl.fit(Simple, bl.load_campaign("A"), maxeval=40).model
    law.to_json(sys.argv[1])
    print(bl.laws.law_name(law))
    print(bl.load_law(sys.argv[1]) == law)  # and in the script itself
'''


def run_python(code: str, cwd: Path, *args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=f"{cwd}{os.pathsep}{ROOT}")
    return subprocess.run([sys.executable, "-c", code, *args], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=300)


@pytest.fixture(scope="module")
def script_law(tmp_path_factory):
    """A law fitted in `python myscript.py` and written to law.json, in a folder of its own."""
    folder = tmp_path_factory.mktemp("script")
    (folder / "myscript.py").write_text(SCRIPT)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "myscript.py", "law.json"], cwd=folder, env=env, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return folder, proc.stdout.split()


def test_a_script_law_is_saved_under_the_name_its_module_imports(script_law):
    folder, printed = script_law
    assert printed == ["myscript:Simple", "True"]  # named by the script's module; loads in the script too
    d = json.loads((folder / "law.json").read_text())
    assert d["law"] == "myscript:Simple"
    assert d["class"] == {"module": "__main__", "qualname": "Simple", "script": str((folder / "myscript.py").resolve())}


def test_a_script_law_loads_in_another_process_once_its_module_is_imported(script_law):
    folder, _ = script_law
    code = ("import warnings, bouncelab as bl, myscript\nwarnings.simplefilter('ignore')\n"
            "law = bl.load_law('law.json')\nprint(type(law) is myscript.Simple, law.e == json_e)")
    code = "import json\njson_e = json.load(open('law.json'))['parameters']['e']\n" + code
    proc = run_python(code, folder)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["True", "True"]


def test_a_script_law_without_its_module_says_what_to_import(script_law):
    folder, _ = script_law
    code = textwrap.dedent("""
        import bouncelab as bl
        try:
            bl.load_law('law.json')
        except bl.errors.UnknownLawError as exc:
            print(exc.law_name, exc.module, exc.module_imported, exc.script)
            print(exc)
    """)
    proc = run_python(code, folder)
    assert proc.returncode == 0, proc.stderr
    fields, message = proc.stdout.split("\n", 1)
    assert fields.split() == ["myscript:Simple", "myscript", "False", str((folder / "myscript.py").resolve())]
    assert "import myscript" in message and "myscript.py" in message


def test_an_old_main_law_file_loads_once_a_module_defines_the_class(script_law):
    """Files written before issue 22 name a script's law "__main__:Simple" (the docs' own example did)."""
    folder, _ = script_law
    d = json.loads((folder / "law.json").read_text())
    old = {"law": "__main__:Simple", "parameters": d["parameters"], "bouncelab_version": "0.1.0"}
    (folder / "old.json").write_text(json.dumps(old))
    proc = run_python("import bouncelab as bl, myscript\nprint(type(bl.load_law('old.json')).__module__)", folder)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "myscript"


def _user_law(module: str, name: str = "Twin") -> type[BounceModel]:
    return type(name, (BounceModel,), {
        "__module__": module, "regimes": ("bounce",), "e": Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="e"),
        "_predict": lambda self, p, e: p * [1.0, -e, 1.0],
        "_regime": lambda self, p, e: np.zeros(len(p), dtype=np.int8)})


def test_a_main_name_is_the_one_registered_class_of_that_name_else_ambiguous():
    one = _user_law("travel_one", "Lonely")
    assert law_class("__main__:Lonely") is one
    _user_law("travel_a"), _user_law("travel_b")
    with pytest.raises(ParameterError, match=r"ambiguous.*travel_a:Twin.*travel_b:Twin") as err:  # names both
        bl.BounceModel.from_dict({"law": "__main__:Twin", "parameters": {"e": 0.5}})
    assert err.value.law == "__main__:Twin" and not isinstance(err.value, UnknownLawError)
    with pytest.raises(UnknownLawError) as err:  # no script recorded: import (or define) the module first
        bl.BounceModel.from_dict({"law": "__main__:Nobody", "parameters": {}})
    assert (err.value.module, err.value.qualname, err.value.script) == ("__main__", "Nobody", None)


def test_a_missing_module_and_a_missing_class_are_told_apart(monkeypatch):
    monkeypatch.setitem(sys.modules, "travel_present", types.ModuleType("travel_present"))
    _user_law("travel_present", "Here")
    with pytest.raises(UnknownLawError) as err:
        law_class("travel_present:Gone")
    assert err.value.module_imported and "is imported but defines no bounce law 'Gone'" in str(err.value)
    assert "travel_present:Here" in str(err.value)
    with pytest.raises(UnknownLawError) as err:
        law_class("travel_absent_module:Law")
    assert not err.value.module_imported and "import travel_absent_module" in str(err.value)


# ----------------------------------------------------------------------------------------- what a file carries
@pytest.fixture(scope="module")
def fitted_a():
    return bl.fit(bl.Rigid, bl.load_campaign("A"), method="structured")


def test_a_law_file_carries_format_units_conventions_radius_and_provenance(fitted_a, tmp_path):
    law = fitted_a.model
    d = json.loads(law.to_json(tmp_path / "law.json"))
    assert d["format"] == "bouncelab law" and d["format_version"] == LAW_FORMAT_VERSION == 2
    assert d["bouncelab_version"] == bl.__version__
    assert d["units"] == {"xdot": "radius/s", "ydot": "radius/s", "omega": "rad/s"}
    assert "y up" in d["conventions"] and "omega > 0 is backspin" in d["conventions"]
    assert d["ball_radius_m"] == 0.02135 and d["parameter_units"] == {"r": "1", "mu": "1"}
    prov = d["provenance"]
    ds = bl.load_campaign("A")
    assert prov["campaign"] == "A" and prov["n_bounces"] == 330 and prov["synthetic"] is True
    assert prov["data_kind"] == "synthetic surrogate" and prov["surrogate"] == "turf"
    assert prov["generator"] == "CraterContact" and prov["source"] == ds.attrs["source"]
    assert prov["method"] == "structured" and prov["seed"] == 0 and prov["fitted_with"] == bl.__version__
    p0 = ds.landing.values
    assert prov["landing_ranges"]["xdot0"] == [p0[:, 0].min(), p0[:, 0].max()]
    assert prov["landing_ranges"]["omega0"] == [p0[:, 2].min(), p0[:, 2].max()]
    speed = np.hypot(p0[:, 0], p0[:, 1])
    assert prov["landing_ranges"]["speed"] == [speed.min(), speed.max()]
    angle = np.degrees(np.arctan2(-p0[:, 1], np.abs(p0[:, 0])))
    assert prov["landing_ranges"]["angle_deg"] == pytest.approx([angle.min(), angle.max()])
    assert "degrees" in prov["landing_range_units"]["angle_deg"]


def test_the_published_surrogate_names_its_generator():
    law = bl.fit(bl.Rigid, bl.load_campaign("B", surrogate="published"), method="structured").model
    assert law.provenance.generator == "PiecewiseAffine.published('B')" and law.provenance.n_bounces == 693


def test_bare_arrays_say_nothing_about_their_origin():
    ds = bl.load_campaign("A")
    prov = bl.fit(bl.Rigid, (ds.landing.values, ds.liftoff.values), method="structured").model.provenance
    assert prov.data_kind == "unknown" and not prov.synthetic and prov.campaign is None
    assert "not said whether measured or synthetic" in prov.summary()


def test_provenance_is_metadata_not_value(fitted_a):
    law = fitted_a.model
    plain = bl.Rigid(r=law.r, mu=law.mu)
    assert law.provenance is not None and plain.provenance is None
    assert law == plain and hash(law) == hash(plain)
    assert law.replace(mu=law.mu).provenance is None  # a law with other (or re-given) values drops it
    assert bl.Rigid().provenance is None
    with pytest.raises(AttributeError):
        law.r = 0.1  # still immutable


def test_print_and_load_say_a_law_was_fitted_to_synthetic_data(fitted_a, tmp_path):
    law = fitted_a.model
    assert str(law) == (f"{law!r} [fitted to SYNTHETIC bounces (campaign 'A', surrogate 'turf', generated by "
                        "CraterContact), not measured ones]")  # one line: it reads in an f-string too
    assert "330 bounces of campaign 'A' (SYNTHETIC: surrogate 'turf', generated by CraterContact" in \
        law.provenance.summary()
    law.to_json(tmp_path / "law.json")
    with pytest.warns(SyntheticDataWarning, match=r"law.json: this law was fitted to synthetic bounces"):
        again = bl.load_law(tmp_path / "law.json")
    assert again == law and again.provenance == law.provenance
    assert str(bl.Rigid(r=0.5, mu=0.3)) == repr(bl.Rigid(r=0.5, mu=0.3))  # no provenance, no note


def test_a_measured_campaign_gives_no_synthetic_note(tmp_path):
    ds = bl.load_campaign("A")
    measured = bl.make_campaign(ds.landing.values, ds.liftoff.values, campaign="lab", data_kind="measured",
                                source="lab.csv")
    law = bl.fit(bl.Rigid, measured, method="structured").model
    assert str(law) == repr(law) and "330 bounces of campaign 'lab' (measured)" in law.provenance.summary()
    law.to_json(tmp_path / "m.json")
    with warnings.catch_warnings():
        warnings.simplefilter("error", SyntheticDataWarning)
        assert bl.load_law(tmp_path / "m.json").provenance.data_kind == "measured"


# ----------------------------------------------------------------------------------------- old files
OLD_FILES = {
    "rigid.json": '{\n  "law": "Rigid",\n  "parameters": {\n    "r": 0.5186,\n    "mu": 0.3054\n  },\n'
                  '  "bouncelab_version": "0.1.0"\n}\n',
    "crater.json": json.dumps({"law": "CraterContact", "parameters": {
        "r0": 0.51756, "v_r": 10772.0, "mu_k": 0.084598, "mu_s": 0.48538, "v_s": 500.48, "lam": 0.19054,
        "kappa": 0.25053, "e_t": 0.30819, "beta0": 6.536, "beta_n": 0.00012378, "beta_t": 3.889e-06},
        "options": {"fade_xdot": 40.0}, "bouncelab_version": "0.1.0"}, indent=2),
}


@pytest.mark.parametrize("name", sorted(OLD_FILES))
def test_old_law_files_still_load(name, tmp_path):
    path = tmp_path / name
    path.write_text(OLD_FILES[name])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no provenance: no synthetic-data warning either
        law = bl.load_law(path)
    assert law.provenance is None
    d = json.loads(OLD_FILES[name])
    assert law.parameters == d["parameters"] and law.options == d.get("options", {})
    law.to_json(tmp_path / "again.json")  # and rewritten in the current format, the same law
    assert json.loads((tmp_path / "again.json").read_text())["format_version"] == LAW_FORMAT_VERSION
    assert bl.load_law(tmp_path / "again.json") == law


def test_a_newer_format_says_to_upgrade():
    with pytest.raises(ParameterError, match=r"format 3, written by a newer bouncelab.*upgrade") as err:
        bl.BounceModel.from_dict({"law": "Rigid", "parameters": {"r": 0.5, "mu": 0.3}, "format_version": 3})
    assert (err.value.parameter, err.value.value) == ("format_version", 3)


@pytest.mark.parametrize("prov, field", [
    ({"n_bounces": -1}, "provenance.n_bounces"), ({"n_bounces": 3, "seed": "0"}, "provenance.seed"),
    ([1], "provenance"),  # not a mapping
    ({"n_bounces": 3, "landing_ranges": {"speed": [5.0, 1.0]}}, "provenance.landing_ranges['speed']"),
    ({"n_bounces": 3, "landing_ranges": {"spin": [1.0, 5.0]}}, "provenance.landing_ranges['spin']"),
    ({"n_bounces": 3, "ball_radius_m": -0.02}, "provenance.ball_radius_m"),
])
def test_a_malformed_provenance_is_a_parameter_error(prov, field):
    with pytest.raises(ParameterError) as err:
        bl.BounceModel.from_dict({"law": "Rigid", "parameters": {"r": 0.5, "mu": 0.3}, "provenance": prov})
    assert (err.value.law, err.value.parameter) == ("Rigid", field)


# ----------------------------------------------------------------------------------------- outside the fitted ranges
def test_predict_warns_outside_the_fitted_ranges_only_when_asked(fitted_a):
    law = fitted_a.model
    ranges = law.provenance.landing_ranges
    inside = bl.load_campaign("A").landing.values[:5]
    outside = np.array([[1000.0, -800.0, 300.0], [ranges["xdot0"][1] * 1.2, -800.0, 300.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error", OutsideFittedRangeWarning)
        law.predict(outside)  # off by default
        law.predict(inside, warn_outside_fitted=True)
    with pytest.warns(OutsideFittedRangeWarning, match=r"lie outside the ranges Rigid was fitted on.*landing row 2, "
                                                       r"xdot0 .* outside the fitted") as rec:
        out = law.predict(outside, warn_outside_fitted=True)
    assert "of 2 landings" in str(rec[0].message)
    np.testing.assert_array_equal(out, law.predict(outside))  # a warning, not another result
    with pytest.warns(OutsideFittedRangeWarning, match="carries no record of the landings it was fitted on"):
        bl.Rigid(r=0.5, mu=0.3).predict(inside, warn_outside_fitted=True)


def test_outside_the_fitted_ranges_in_physical_units(fitted_a):
    """The check is on the landings the law sees, whatever the units they were given in."""
    law = fitted_a.model
    with pytest.warns(OutsideFittedRangeWarning, match="speed"):
        law.predict([[80.0, 45.0, 2000.0]], units={"velocity": "m/s", "spin": "rpm"}, form="polar",
                    warn_outside_fitted=True)  # 80 m/s: faster than any fitted landing of A (59 m/s)


# ----------------------------------------------------------------------------------------- untyped errors
def test_a_five_thousand_digit_integer_is_a_parameter_error(tmp_path, capsys):
    path = tmp_path / "big.json"
    path.write_text('{"law": "Rigid", "parameters": {"r": ' + "9" * 5000 + ', "mu": 0.3}}')
    with pytest.raises(ParameterError) as err:  # not a JSON law description
        bl.load_law(path)
    assert (err.value.parameter, err.value.value) == ("path", str(path))
    assert main(["predict", str(path), "--landing", "1000", "-800", "200"]) == EXIT_FIT
    err = capsys.readouterr().err
    assert "Traceback" not in err and "not a JSON law description" in err


def test_load_law_of_a_missing_file_or_a_folder_is_a_data_error(tmp_path):
    with pytest.raises(DataError, match="no such law file") as err:
        bl.load_law(tmp_path / "nope.json")
    assert err.value.file == str(tmp_path / "nope.json")
    with pytest.raises(DataError, match="is a directory, not a law file") as err:
        bl.load_law(tmp_path)
    assert err.value.file == str(tmp_path)


def test_to_json_into_a_folder_that_cannot_be_written_is_an_output_error(tmp_path, monkeypatch):
    law = bl.Rigid(r=0.5, mu=0.3)
    target = tmp_path / "law.json"
    for path in (tmp_path / "missing" / "law.json", tmp_path):
        with pytest.raises(OutputError) as err:
            law.to_json(path)
        assert err.value.path == str(path) and isinstance(err.value, OSError)
        assert isinstance(err.value, bl.BouncelabError) and str(path) in str(err.value)
    target.write_text("before")

    def refuse(*args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(os, "replace", refuse)  # what a read-only folder does to the final rename
    with pytest.raises(OutputError) as err:
        law.to_json(target)
    assert (err.value.path, err.value.reason) == (str(target), "Permission denied")
    assert target.read_text() == "before" and sorted(p.name for p in tmp_path.iterdir()) == ["law.json"]


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root writes into read-only folders")
def test_to_json_into_a_read_only_folder(tmp_path):
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o500)
    try:
        with pytest.raises(OutputError) as err:
            bl.Rigid(r=0.5, mu=0.3).to_json(folder / "law.json")
        assert err.value.reason == "Permission denied"
        assert not any(folder.iterdir())
    finally:
        folder.chmod(0o700)


def test_cli_fit_save_into_a_missing_folder_is_still_an_output_problem(tmp_path, capsys):
    code = main(["fit", "Rigid", "--method", "structured", "--save", str(tmp_path / "nowhere" / "law.json")])
    assert code == 2 and "Traceback" not in capsys.readouterr().err


def test_cli_predict_with_a_synthetic_law_file_warns_in_one_line(fitted_a, tmp_path, capsys):
    fitted_a.model.to_json(tmp_path / "law.json")
    assert main(["predict", str(tmp_path / "law.json"), "--landing", "1000", "-800", "200"]) == EXIT_OK
    err = capsys.readouterr().err
    assert "bouncelab predict: warning:" in err and "synthetic bounces" in err and "Traceback" not in err


def test_provenance_round_trips_exactly(fitted_a):
    prov = fitted_a.model.provenance
    assert Provenance.from_dict(json.loads(json.dumps(prov.to_dict()))) == prov


def test_load_law_data_error_from_the_cli_names_the_file(tmp_path, capsys):
    assert main(["predict", str(tmp_path / "gone.json"), "--landing", "1000", "-800", "200"]) == EXIT_DATA
    assert "gone.json" in capsys.readouterr().err


def test_the_value_alone_for_descriptions_that_embed_a_law(fitted_a):
    """A simulated turf embeds its law without the file's metadata (the campaign has its own units)."""
    law = fitted_a.model
    d = law.to_dict(metadata=False)
    assert sorted(d) == ["bouncelab_version", "law", "parameters"]
    assert bl.BounceModel.from_dict(d) == law and bl.BounceModel.from_dict(d).provenance is None
    sim = json.loads(bl.load_campaign("A").attrs["simulation_json"])
    assert sorted(sim["turf"]["law"]) == ["bouncelab_version", "law", "options", "parameters"]
