"""Nothing lost, nothing waited on, every error typed (issue 30 item 4, issue 31 item 5).

Each test here is a finding of a fuzzing campaign that the code before failed: a writer that replaced a
FIFO or a device with a regular file, or its own input; a reader that hung on a FIFO or raised a bare
FileNotFoundError; a temporary file that outlived SIGTERM; an untyped exception (OverflowError, TypeError,
UnicodeEncodeError...) for a huge integer, a lone surrogate, text or a bool; a Ctrl-C that exited 1.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import signal
import socket
import stat
import subprocess
import sys
import textwrap
import time
import warnings
from decimal import Decimal
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.core import checks
from bouncelab.core.errors import DataError, FitError, MissingFileError, OutputError, ParameterError

HUGE = 10**400
ROOT = Path(__file__).resolve().parents[1]
needs_fifo = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")


@contextlib.contextmanager
def no_hang(seconds: int = 10):
    """Fail (rather than wait forever) if the block blocks: a reader stuck on a FIFO."""
    def alarm(signum, frame):
        raise AssertionError(f"blocked for {seconds} s (a FIFO read?)")

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def a_device(tmp_path: Path) -> Path:
    """A character device to write at: a null device made in ``tmp_path`` as root (so that a writer that
    replaced it would replace only that node), else a symlink to /dev/null (which no one but root can replace)."""
    if os.geteuid() == 0 and hasattr(os, "mknod"):
        node = tmp_path / "null-device"
        try:
            os.mknod(node, stat.S_IFCHR | 0o666, os.makedev(1, 3))
            return node
        except OSError:
            pass
    if os.geteuid() == 0:
        pytest.skip("cannot make a device node here, and root could replace /dev/null")
    return Path(os.devnull)


# ------------------------------------------------------------------------------------------------- writing
@needs_fifo
def test_writers_refuse_a_fifo_a_device_a_socket_and_a_folder(tmp_path):
    """law.to_json('/dev/null') as root replaced /dev/null with a regular file; a FIFO became a file too."""
    law = bl.Rigid(r=0.5, mu=0.4)
    fifo = tmp_path / "pipe.json"
    os.mkfifo(fifo)
    device = a_device(tmp_path)
    link = tmp_path / "link-to-null.json"
    link.symlink_to(device)
    sock = tmp_path / "s.sock"
    server = socket.socket(socket.AF_UNIX)
    server.bind(str(sock))
    try:
        for target, kind in ((fifo, "a named pipe (FIFO)"), (device, "a character device"),
                             (link, "a character device"), (sock, "a socket"), (tmp_path, "a folder")):
            with pytest.raises(OutputError) as err:
                law.to_json(target)
            assert (err.value.path, err.value.reason) == (str(target), kind)
    finally:
        server.close()
    assert stat.S_ISFIFO(fifo.stat().st_mode) and stat.S_ISCHR(device.stat().st_mode) and link.is_symlink()
    assert stat.S_ISSOCK(sock.stat().st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in (fifo, device, link, sock)) or \
        device == Path(os.devnull)


@needs_fifo
def test_every_kind_of_writer_refuses_a_fifo(tmp_path):
    """Surfaces, campaigns, exported laws, rendered clips: every writer goes through core.atomic."""
    from bouncelab.export import export_surface, to_c
    from bouncelab.ground import preset
    from bouncelab.tracking import render_clip

    clip = render_clip(size=(32, 64), radius_px=4.0, n_before=4, n_after=4, seed=0)
    writers = {"s.json": preset("green-fast").to_json, "law.h": lambda p: to_c(bl.PennerFixed.published("A"), p),
               "surface.cs": lambda p: export_surface("green-fast", "cs", p),
               "clip.npz": clip.save, "c.nc": lambda p: bl.save_campaign(bl.load_campaign("A"), p)}
    for name, write in writers.items():
        fifo = tmp_path / name
        os.mkfifo(fifo)
        with pytest.raises(OutputError) as err:
            write(fifo)
        assert err.value.path == str(fifo) and stat.S_ISFIFO(fifo.stat().st_mode)


def test_an_output_that_is_an_input_is_refused_through_links(tmp_path):
    """`bouncelab export LAW.json -o link-to-LAW.json` overwrote the law file it read."""
    from bouncelab.cli.main import main

    law_file = tmp_path / "law.json"
    bl.PennerFixed.published("A").to_json(law_file)
    before = law_file.read_bytes()
    (tmp_path / "soft.h").symlink_to(law_file)
    os.link(law_file, tmp_path / "hard.h")
    for out in ("soft.h", "hard.h", "law.json"):
        code = main(["export", str(law_file), "--lang", "c", "-o", str(tmp_path / out)])
        assert code == 2
    assert law_file.read_bytes() == before
    assert main(["export", str(law_file), "--lang", "c", "-o", str(tmp_path / "new.h")]) == 0


def test_protect_inputs_guards_any_writer(tmp_path):
    from bouncelab.core.atomic import protect_inputs

    data = tmp_path / "data.json"
    data.write_text("{}")
    os.link(data, tmp_path / "alias.json")
    with protect_inputs([data, "A", tmp_path / "missing.csv"]):  # (names that are no file are ignored)
        with pytest.raises(OutputError) as err:
            bl.Rigid(r=0.5, mu=0.4).to_json(tmp_path / "alias.json")
        assert err.value.reason == "the output is an input"
    bl.Rigid(r=0.5, mu=0.4).to_json(tmp_path / "alias.json")  # outside the block, a file like any other
    assert json.loads((tmp_path / "alias.json").read_text())["law"] == "Rigid" and data.read_text() == "{}"


@needs_fifo
def test_fit_save_to_a_fifo_is_refused_and_the_fifo_kept(tmp_path):
    from bouncelab.cli.main import main

    fifo = tmp_path / "law.json"
    os.mkfifo(fifo)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["fit", "Rigid", "A", "--method", "structured", "--save", str(fifo)]) == 2
    assert stat.S_ISFIFO(fifo.stat().st_mode)


def test_text_no_file_can_hold_is_an_output_error(tmp_path):
    from bouncelab.core.atomic import atomic_write_text

    with pytest.raises(OutputError) as err:
        atomic_write_text(tmp_path / "x.txt", "a\ud800b")
    assert err.value.reason == "text that cannot be encoded" and list(tmp_path.iterdir()) == []
    for name in ("a\ud800", "a\0b", 3):
        with pytest.raises(OutputError):
            atomic_write_text(name if isinstance(name, int) else tmp_path / name, "x")


@pytest.mark.skipif(os.name != "posix", reason="POSIX signals")
def test_sigterm_during_a_write_leaves_no_temporary_file(tmp_path):
    """SIGTERM during a write (e.g. Posterior.to_json, law.to_json) left a hidden temporary file."""
    target = tmp_path / "law.json"
    target.write_text("previous")
    code = textwrap.dedent(f"""
        import os, sys, time
        import bouncelab as bl
        import bouncelab.core.atomic as atomic

        def slow_fsync(fd):  # the write has begun: the temporary file exists
            print("writing", flush=True)
            time.sleep(30)

        atomic.os.fsync = slow_fsync
        bl.Rigid(r=0.5, mu=0.4).to_json({str(target)!r})
    """)
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "writing"
        assert any(p.name.endswith(".tmp") for p in tmp_path.iterdir())  # (the write is under way)
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=30)
    finally:
        proc.kill()
        proc.wait()
    assert proc.returncode == -signal.SIGTERM  # the signal still ends the process, as it would have
    assert [p.name for p in tmp_path.iterdir()] == ["law.json"] and target.read_text() == "previous"


# ------------------------------------------------------------------------------------------------- reading
@needs_fifo
def test_readers_refuse_fifos_and_devices_without_waiting(tmp_path):
    """ground.load_surface read with Path.read_text: a FIFO hung it, /dev/zero ended in MemoryError."""
    from bouncelab.ground import load_surface
    from bouncelab.tracking import open_clip, read_mraw

    fifo = tmp_path / "pipe.json"
    os.mkfifo(fifo)
    zero = tmp_path / "zero.json"
    zero.symlink_to("/dev/zero")
    header = tmp_path / "clip.cihx"
    os.mkfifo(header)
    (tmp_path / "clip.mraw").write_bytes(b"\0" * 64)
    clip_fifo = tmp_path / "clip.npy"
    os.mkfifo(clip_fifo)
    with no_hang():
        for read, path in ((load_surface, fifo), (load_surface, zero), (bl.load_law, fifo), (bl.load_law, zero),
                           (open_clip, clip_fifo), (read_mraw, header)):
            with pytest.raises(DataError) as err:
                read(path)
            assert err.value.file == str(path)


def test_missing_files_are_data_errors_naming_them(tmp_path):
    """A missing surface file was a ParameterError; shots and clips raised bare FileNotFoundError."""
    from bouncelab.ground import load_shots, load_surface
    from bouncelab.tracking import open_clip

    for read, name in ((load_surface, "s.json"), (bl.load_law, "law.json"), (load_shots, "shots.csv"),
                       (open_clip, "clip.npy")):
        path = tmp_path / name
        with pytest.raises(MissingFileError) as err:
            read(path)
        assert err.value.file == str(path)
        assert isinstance(err.value, DataError) and isinstance(err.value, FileNotFoundError)


# ------------------------------------------------------------------------------------- one number check
ODD_NUMBERS = [True, np.bool_(True), "1", b"1", "\ud800", HUGE, -HUGE, 1j, np.complex128(1.0), None, [1.0, 2.0],
               np.array([1.0, 2.0]), object()]


@pytest.mark.parametrize("value", ODD_NUMBERS, ids=repr)
def test_every_kind_of_check_refuses_what_is_no_number(value):
    for check in (checks.finite, checks.positive, checks.fraction):
        with pytest.raises(ParameterError) as err:
            check(value, "x")
        assert (err.value.parameter, err.value.value is value) == ("x", True)
    for check in (lambda v, n: checks.count(v, n, maximum=10**6, error=FitError),
                  lambda v, n: checks.seed(v, n, error=FitError)):
        with pytest.raises(FitError) as err:
            check(value, "n")
        assert err.value.option == "n"


def test_the_checks_accept_real_numbers_of_any_kind():
    for value in (2, 2.0, np.float32(2.0), np.int8(2), np.array(2.0), Fraction(2), Decimal("2")):
        assert checks.positive(value, "x") == 2.0 and type(checks.positive(value, "x")) is float
    assert checks.count(np.int64(5), "n", 1) == 5 and checks.seed(2**63 - 1) == 2**63 - 1
    assert checks.fraction(0.0, "f", closed=True) == 0.0
    with pytest.raises(DataError, match="a count is a whole number"):
        checks.count(5.0, "n", error=DataError)
    for bad in (math.nan, math.inf, -1.0, 0.0):
        with pytest.raises(DataError):
            checks.positive(bad, "x", error=DataError)
    assert "<an integer of" in checks.shown(10**5000)  # (its repr would itself raise)


def test_checks_refuse_lone_surrogates_in_text():
    assert checks.text("ok", "name") == "ok"
    with pytest.raises(ParameterError, match="lone UTF-16 surrogate"):
        checks.text("a\ud800", "name")
    with pytest.raises(ParameterError):
        checks.text("  ", "name", empty=False)


def test_real_arrays_refuse_text_bools_and_huge_integers_among_objects():
    with pytest.raises(DataError, match="element 1"):
        checks.real_array(np.array([1.0, "2"], dtype=object), "landing", error=DataError)
    for bad in ([[True, -800, 0]], [["1000", -800, 0]], [[HUGE, -800, 0]]):  # (True and "1000" were numbers)
        with pytest.raises(DataError) as err:
            bl.Rigid(r=0.5, mu=0.4).predict(np.array(bad, dtype=object), plausible=None)
        assert "element 0" in str(err.value)


def test_one_value_one_refusal_in_every_layer():
    """A bool was accepted as 1.0 by analysis.trajectories and as a count by others; text as a number."""
    from bouncelab.analysis import simulate_tracked_bounce
    from bouncelab.ground import Air, preset, run
    from bouncelab.simulation import Camera, LauncherDesign

    state = ([1000.0, -800.0, 200.0], [600.0, 400.0, -600.0])
    calls = [
        (DataError, lambda v: simulate_tracked_bounce(*state, contact_frames=v)),
        (DataError, lambda v: simulate_tracked_bounce(*state, fps=v)),
        (ParameterError, lambda v: run([10.0, 0, -5], [0, -100.0, 0], preset("green-fast"),
                                       units={"velocity": "m/s", "spin": "rpm"}, rate=v)),
        (ParameterError, lambda v: Air(drag_coefficient=v)),
        (ParameterError, lambda v: Camera(fps=v)),
        (ParameterError, lambda v: LauncherDesign(campaign="A", settings=((5, 2),), speed_scatter=v)),
        (ParameterError, lambda v: bl.PennerFixed.published("A").replace(fade_xdot=v)),
        (FitError, lambda v: bl.fit(bl.Rigid, bl.load_campaign("A"), seed=v)),
    ]
    for error, call in calls:
        for value in (True, "5000", HUGE, 1j):
            with pytest.raises(error) as err:
                call(value)
            assert "must be" in str(err.value)


def test_huge_integers_are_typed_errors():
    """A 400-digit integer in predict_one, radius_m, stimp_m, Air's fields, fade_xdot: bare OverflowError."""
    from bouncelab.ground import Air, Surface, run

    law = bl.Rigid(r=0.5, mu=0.4)
    with pytest.raises(DataError):
        law.predict_one(HUGE, -800.0, 0.0)
    with pytest.raises(DataError):
        law.predict_one(1000.0, -800.0, 0.0, radius_m=HUGE)
    with pytest.raises(ParameterError) as err:
        Surface(name="g", law=law, sliding_friction=0.4, stimp_m=HUGE)
    assert err.value.parameter == "stimp_m"
    with pytest.raises(ParameterError) as err:
        Air(mass_kg=HUGE)
    assert err.value.parameter == "mass_kg"
    with pytest.raises(ParameterError) as err:
        bl.PennerFixed.published("A").replace(fade_xdot=HUGE)
    assert err.value.parameter == "fade_xdot"
    with pytest.raises(DataError) as err:
        run([10.0, 0, -5], [0, -100.0, 0], "green-fast", units={"velocity": "m/s", "spin": "rpm"}, radius_m=HUGE)
    assert err.value.option == "ball_radius_m"
    with pytest.raises(DataError):
        bl.units.velocity_to_scaled([[HUGE]], "m/s")


def test_predict_one_refuses_text_bools_and_complex_numbers_even_on_its_fast_path():
    """The compiled one-landing entry converted "1000" and 1000+0j to floats and True to 1.0."""
    for law in (bl.Rigid(r=0.5, mu=0.4), bl.PennerFixed.published("A")):
        for bad in ("1000", True, np.complex128(1000.0), b"1000"):
            with pytest.raises(DataError) as err:
                law.predict_one(bad, -800.0, 0.0)
            assert err.value.column == "landing.xdot"
        assert law.predict_one(1000, -800, 0) == law.predict_one(1000.0, -800.0, 0.0)  # ints are numbers


def test_a_lone_surrogate_in_a_law_file_is_refused_at_load(tmp_path):
    """It loaded, then crashed print(law) (on a UTF-8 terminal) and `bouncelab export`."""
    d = bl.fit(bl.Rigid, bl.load_campaign("A"), method="structured").model.to_dict()
    d["provenance"]["campaign"] = "\ud800"
    path = tmp_path / "law.json"
    path.write_text(json.dumps(d))
    with pytest.raises(ParameterError) as err:
        bl.load_law(path)
    assert err.value.parameter == "provenance.campaign" and str(path) in str(err.value)
    from bouncelab.cli.main import main

    assert main(["export", str(path), "--lang", "c", "-o", str(tmp_path / "law.h")]) == 4
    assert not (tmp_path / "law.h").exists()


@pytest.mark.parametrize("where", ["landing_ranges", "ball_radius_m", "seed", "null_ranges"])
def test_forged_numbers_in_a_law_files_provenance_are_typed(tmp_path, where):
    d = bl.fit(bl.Rigid, bl.load_campaign("A"), method="structured").model.to_dict()
    prov = d["provenance"]
    if where == "landing_ranges":
        prov["landing_ranges"]["xdot0"] = [HUGE, HUGE + 1]
    elif where == "null_ranges":  # (it raised AttributeError)
        prov["landing_ranges"] = None
    else:
        prov[where] = -HUGE if where == "seed" else HUGE
    path = tmp_path / "law.json"
    path.write_text(json.dumps(d))
    if where == "null_ranges":
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            assert bl.load_law(path).provenance.landing_ranges == {}
        return
    with pytest.raises(ParameterError) as err:
        bl.load_law(path)
    assert err.value.parameter.startswith("provenance.")


def test_forged_surface_files_are_validated_at_load(tmp_path):
    from bouncelab.ground import load_surface, preset

    good = preset("green-fast").to_dict()
    forgeries = {"stimp_m": "3.0", "sliding_friction": True, "pivot_retention": 2.0, "surface": "\ud800",
                 "description": "\ud800", "law": {**good["law"], "options": {"fade_xdot": HUGE}}}
    path = tmp_path / "s.json"
    for key, value in forgeries.items():
        path.write_text(json.dumps({**good, key: value}))
        with pytest.raises(ParameterError) as err:
            load_surface(path)
        assert str(path) in str(err.value)
    path.write_text('{"surface": ' + "1" * 5000 + "}")  # an integer too long to read: a ValueError in json
    with pytest.raises(ParameterError):
        load_surface(path)
    with pytest.raises(ParameterError) as err:
        preset(["x"])  # (a TypeError: unhashable type 'list')
    assert err.value.parameter == "surface"


def test_a_netcdf_ball_radius_that_is_not_a_number_is_a_data_error(tmp_path):
    """ball_radius_m="abc" in a netCDF file raised ValueError: could not convert string to float."""
    ds = bl.load_campaign("A")
    path = tmp_path / "c.nc"
    for value in ("abc", "nan"):  # (written by xarray itself: save_campaign refuses such a campaign)
        ds.assign_attrs(ball_radius_m=value).to_netcdf(path)
        with pytest.raises(DataError) as err:
            bl.load_campaign(path)
        assert (err.value.file, err.value.option) == (str(path), "ball_radius_m")
    ds.assign_attrs(ball_radius_m="0.02135").to_netcdf(path)  # another tool's text that spells the number
    assert bl.load_campaign(path).attrs["ball_radius_m"] == 0.02135


def test_a_path_too_large_is_refused_before_anything_is_allocated():
    """RunResult.sample(rate=1e18) ended in numpy's error after allocating (1e308: OverflowError)."""
    from bouncelab.ground import run

    r = run([10.0, 0, -5], [0, -100.0, 0], "green-fast", units={"velocity": "m/s", "spin": "rpm"})
    for rate in (1e18, 1e308):
        with pytest.raises(ParameterError) as err:
            r.sample(rate=rate)
        assert err.value.parameter == "rate"
    assert r.sample(rate=10.0).sizes["time"] > 1


def test_absurd_sizes_are_refused_before_anything_is_allocated():
    from bouncelab.analysis import simulate_tracked_bounce
    from bouncelab.tracking import render_clip

    state = ([1000.0, -800.0, 200.0], [600.0, 400.0, -600.0])
    for kwargs in ({"contact_frames": 1e18}, {"n_before": 2**62}, {"fps": 1e-320}):
        with pytest.raises(DataError):
            simulate_tracked_bounce(*state, **kwargs)
    for kwargs in ({"size": (10**9, 10**9)}, {"size": 64}, {"seed": -1}, {"noise": HUGE}):
        with pytest.raises(DataError):
            render_clip(**kwargs)
    with pytest.raises(FitError):
        bl.fit(bl.Rigid, bl.load_campaign("A"), maxeval=1e18)
    with pytest.raises(FitError):
        bl.bootstrap(bl.Rigid, bl.load_campaign("A"), n=HUGE)
    with pytest.raises(ParameterError):
        bl.generate_surrogate("A", seed=-1)


def test_track_keeps_a_clip_followed_by_many_frames_without_the_ball():
    """`track` refused a good clip once 61 frames without the ball followed it (the ball's contrast was the
    median over the sampled frames, noise once most of them had no ball)."""
    from bouncelab.tracking import measure_clip, render_clip, track_clip

    clip = render_clip((1063.0, -810.0, 219.0), size=(96, 200), radius_px=10.0, n_before=25, n_after=25, seed=3)
    empty = np.median(clip.frames, axis=0).astype(np.uint8)[None]
    for frames in (np.concatenate([clip.frames, np.repeat(empty, 70, axis=0)]),
                   np.concatenate([np.repeat(empty, 70, axis=0), clip.frames])):
        track = track_clip(frames, fps=clip.fps)
        assert int(track["found"].sum()) == len(clip.frames)
        m = measure_clip(track)
        np.testing.assert_allclose(m["landing"].values[:2], clip.landing[:2], rtol=0.05)


# ------------------------------------------------------------------------------------------------- Ctrl-C
def test_an_interrupt_nlopt_turns_into_forced_stop_is_reraised():
    """NLopt turns a KeyboardInterrupt that lands in its glue into nlopt.ForcedStop: `reproduce` exited 1."""
    import nlopt

    from bouncelab.fitting.search import run_nlopt

    opt = nlopt.opt(nlopt.LN_BOBYQA, 2)
    opt.set_lower_bounds([0.0, 0.0])
    opt.set_upper_bounds([1.0, 1.0])
    opt.set_maxeval(100)
    calls = []

    def objective(x, grad):
        calls.append(1)
        if len(calls) == 3:
            opt.force_stop()  # what NLopt does when an exception escapes where the wrapper cannot see it
        return float(x @ x)

    opt.set_min_objective(objective)
    with pytest.raises(KeyboardInterrupt):
        run_nlopt(opt, np.array([0.5, 0.5]), [])
    calls.clear()
    terminated = SystemExit(143)
    with pytest.raises(SystemExit) as err:  # an interrupt the objective saw is re-raised as itself
        run_nlopt(opt, np.array([0.5, 0.5]), [terminated])
    assert err.value is terminated


@pytest.fixture
def terminal_sigint():
    """SIGINT as at a terminal, where Python raises KeyboardInterrupt. A shell starts a background job (``cmd &``
    without job control: CI scripts, nohup) with SIGINT ignored, and Ctrl-C cannot reach it there at all."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


#: The same in a child process, before it starts the command.
TERMINAL_SIGINT = "import signal; signal.signal(signal.SIGINT, signal.default_int_handler); "


def test_an_interrupt_a_library_swallowed_still_exits_130(monkeypatch, terminal_sigint):
    """numba's compiler drops a KeyboardInterrupt raised in its callbacks: the command went on and exited 0."""
    import bouncelab.cli.main as cli

    def swallowing(args):
        with contextlib.suppress(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(5)
        return 0

    monkeypatch.setattr(cli, "_info", swallowing)
    assert cli.main(["info"]) == 130
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


@pytest.mark.skipif(os.name != "posix", reason="POSIX signals")
@pytest.mark.parametrize("delay", [0.3, 1.2])
def test_ctrl_c_during_a_fit_exits_130(delay):
    # TurfContact's fit takes seconds even with a warm cache, so the interrupt lands inside the command (with
    # PiecewiseAffine, about 1 s warm, a Ctrl-C at 1.2 s sometimes came after the command had ended, in Python's
    # own exit, which then ends of SIGINT: returncode -2, shell status 130, but not bouncelab's message).
    code = (TERMINAL_SIGINT + "import sys, bouncelab.cli.main as m; print('ready', flush=True); "
            "sys.exit(m.main(['fit', 'TurfContact', 'B']))")
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=ROOT)
    try:
        assert proc.stdout.readline().strip() == "ready"
        time.sleep(delay)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
        proc.wait()
    assert proc.returncode == 130, err
    assert err.strip() == "bouncelab fit: interrupted"


def test_json_options_of_thousands_of_digits_are_usage_errors(capsys):
    """`fit --bounds '{"r": [0, 999...]}'` with 5000 digits raised ValueError (exit 1, a traceback)."""
    from bouncelab.cli.main import main

    huge = "9" * 5000
    assert main(["fit", "Rigid", "A", "--bounds", '{"r": [0, ' + huge + "]}"]) == 2
    assert main(["fit", "Rigid", "A", "--option", f"maxeval={huge}"]) == 4  # (kept as text: not a count)
    assert "Traceback" not in capsys.readouterr().err


@pytest.mark.parametrize("value", ["abc", "nan", "-1"])
def test_a_campaign_files_ball_radius_is_checked_before_it_is_compared(tmp_path, value):
    """A netCDF campaign with `ball_radius_m="abc"`, loaded with another radius, was a bare ValueError."""
    from bouncelab.core.errors import DataError

    ds = bl.load_campaign("A")
    ds.attrs["ball_radius_m"] = value
    path = tmp_path / "c.nc"
    ds.to_netcdf(path)
    with pytest.raises(DataError) as err:
        bl.load_campaign(path, ball_radius_m=0.02)
    assert err.value.file == str(path)


@pytest.mark.parametrize("source", [3, None, 3.5, ["A"]])
def test_a_source_that_is_no_path_is_refused_by_name(source):
    from bouncelab.core.errors import DataError

    with pytest.raises(DataError) as err:
        bl.load_campaign(source)
    assert err.value.option == "source"


def test_save_campaign_to_something_that_is_no_path_is_an_output_error():
    from bouncelab.core.errors import OutputError

    with pytest.raises(OutputError) as err:
        bl.save_campaign(bl.load_campaign("A"), 3)
    assert err.value.reason == "not a path"


def test_a_missing_data_file_is_a_typed_error_that_is_still_a_file_not_found_error(tmp_path):
    from bouncelab.core.errors import DataError, MissingFileError
    from bouncelab.data.io.landings import read_landings

    for read in (bl.load_campaign, read_landings):
        with pytest.raises(MissingFileError) as err:
            read(str(tmp_path / "none.csv"))
        assert isinstance(err.value, DataError) and isinstance(err.value, FileNotFoundError)
        assert err.value.file == str(tmp_path / "none.csv")


def test_a_campaign_name_that_no_file_can_hold_is_refused():
    from bouncelab.core.errors import DataError

    with pytest.raises(DataError) as err:
        bl.load_campaign("A", campaign="turf \ud800")
    assert err.value.option == "campaign"


def test_sigterm_that_nlopt_turns_into_a_forced_stop_still_ends_the_process_of_sigterm():
    """A SIGTERM landing in NLopt's glue came out as ForcedStop, then as a Ctrl-C (exit 130 or 1), not SIGTERM."""
    code = ("import os, signal, time, nlopt\n"
            "from bouncelab.core.atomic import sigterm_raises\n"
            "from bouncelab.fitting.search import run_nlopt\n"
            "class Glue:\n"
            "    def optimize(self, x0):\n"
            "        try:\n"
            "            os.kill(os.getpid(), signal.SIGTERM)\n"
            "            time.sleep(5)\n"
            "        except BaseException:\n"
            "            pass\n"
            "        raise nlopt.ForcedStop('stopped in the glue')\n"
            "with sigterm_raises():\n"
            "    run_nlopt(Glue(), [0.0], [])\n"
            "print('survived')\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert proc.returncode == -signal.SIGTERM, proc.stderr
    assert "survived" not in proc.stdout


def test_a_folder_given_as_a_file_is_called_a_folder(tmp_path):
    from bouncelab.core.errors import DataError
    from bouncelab.core.files import check_regular_file, read_regular_file

    for check in (check_regular_file, read_regular_file):
        with pytest.raises(DataError, match="it is a folder, not a regular file") as err:
            check(tmp_path, "the folder")
        assert err.value.file == "the folder"
