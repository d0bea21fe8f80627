"""The intermediate form of bouncelab.export: what the front end makes of Python, what the passes keep, and one
program printed in three languages.

The last tests translate a function shaped like the ground phase's kernels (a loop of scalar maths that calls a
law's kernel passed in as a parameter, with the law's values as ``*args``), compile it in C, run it under Node
and Mono, and compare with numba running the same Python.
"""

from __future__ import annotations

import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numba import njit

from bouncelab.export import ir
from bouncelab.export.emit import CEmitter, CSharpEmitter, JSEmitter
from bouncelab.export.errors import ExportError
from bouncelab.export.frontend import FLOAT, INT, FuncType, Translation, TupleType
from bouncelab.export.inline import inline, tails
from bouncelab.laws._kernels import penner_varying_kernel, rigid_kernel

sys.path.insert(0, str(Path(__file__).parent))
from test_layers import import_graph

CC, NODE, MCS, MONO = (shutil.which(x) for x in ("cc", "node", "mcs", "mono"))


def translate(func, *argtypes) -> tuple[Translation, ir.Function]:
    tr = Translation()
    return tr, tr.add(func, argtypes)


# ------------------------------------------------------------------------------ the front end's output
@njit
def _swap(a, b, k):
    a, b = b, a + b  # simultaneous: b's new value reads the old a
    c = a * 2.0  # noqa: F841 (dead: never read)
    total = 0
    for i in range(k):
        total += i
    return a, b + total


def test_simultaneous_assignment_reads_the_old_values_and_dead_code_is_gone():
    _, fn = translate(_swap, FLOAT, FLOAT, INT)
    text = ir.dump(fn)
    assert "c = " not in text and "c:" not in text  # pruned
    assert fn.multi and fn.returns == (ir.F64, ir.F64)
    assigns = [(s.target, ir.dump_expr(s.value)) for s in fn.body if isinstance(s, ir.Assign)]
    # b's new value reads the old a: it is taken first, then a and b are assigned
    assert assigns[:3] == [("t", "(a + b)"), ("a", "b"), ("b", "t")], text


@njit
def _names(int, int_, f_x):  # names C, JavaScript and C# reserve, and an emitter's prefix
    double = int * 2.0
    return double + int_ + f_x


def test_reserved_and_prefixed_names_are_renamed_apart():
    _, fn = translate(_names, FLOAT, FLOAT, FLOAT)
    names = [n for n, _ in fn.params] + list(fn.locals)
    assert len(set(names)) == len(names) == 4
    assert "int" not in names and "double" not in names and not any(n.startswith("f_") for n in names)


@njit
def _tuple_var(xd, k):
    t = (xd, 2.0 * xd, 3.0 * xd)
    u = t[k]  # a variable index into a tuple of one type
    return u + t[-1]


def test_tuples_become_scalars_and_a_variable_index_a_choice():
    _, fn = translate(_tuple_var, FLOAT, INT)
    assert all(t in (ir.F64, ir.I64, ir.BOOL) for t in fn.locals.values())
    assert "t_0" in fn.locals and "t_2" in fn.locals
    assert any(isinstance(e, ir.Select) for e in ir.walk_exprs(fn.body))


@njit
def _early(x):
    if x < 0.0:
        return -x
    y = x * 2.0
    return y


@njit
def _calls_early(x):
    return _early(x) + _early(-x)


def test_inlining_lifts_early_returns_and_keeps_the_numbers():
    tr, _ = translate(_calls_early, FLOAT)
    early = tr.program.function("f_early")
    lifted = tails(early.body)
    assert lifted is not None and isinstance(lifted[-1], ir.If) and lifted[-1].orelse  # the rest went into else
    program = inline(tr.program)
    assert [f.name for f in program.functions] == ["f_calls_early"]  # the callee is gone
    assert not any(isinstance(e, ir.Call) for e in ir.walk_exprs(program.functions[0].body))


@njit
def _returns_in_loop(x):
    for _ in range(3):
        if x > 1.0:
            return x
        x = x * 2.0
    return -x


def test_a_return_inside_a_loop_is_not_inlined():
    _, fn = translate(_returns_in_loop, FLOAT)
    assert tails(fn.body) is None


@njit
def _starred_bad(xd, law, n):
    return law(xd, *n)


def test_starred_argument_must_be_a_tuple_variable():
    with pytest.raises(ExportError) as exc:
        translate(_starred_bad, FLOAT, FuncType.of(rigid_kernel), INT)
    assert exc.value.construct.startswith("a starred argument of type")


def test_export_is_the_only_package_that_imports_the_laws_and_the_emitters():
    """The laws and the ground phase never import export; the translator (front end, IR, inlining, emitters) never
    imports them: only export's law and surface modules join the two."""
    edges = import_graph()
    for module, targets in edges.items():
        if any(t.startswith("bouncelab.export.emit") for t in targets):
            assert module.startswith("bouncelab.export"), module
        if module.startswith("bouncelab.export.emit") or module in ("bouncelab.export.ir",
                                                                    "bouncelab.export.frontend",
                                                                    "bouncelab.export.inline"):
            assert not any(t.startswith(("bouncelab.laws", "bouncelab.ground")) for t in targets), (module, targets)
        if module.startswith(("bouncelab.laws", "bouncelab.ground")):
            assert not any(t.startswith("bouncelab.export") for t in targets), (module, targets)
    assert "bouncelab.laws.base" in edges["bouncelab.export.law"]
    assert {"bouncelab.ground._kernels", "bouncelab.ground.bounce3d"} <= edges["bouncelab.export.ground"]


def test_adding_a_language_is_adding_an_emitter():
    """The three emitters share the front end and the printer: each is a small subclass."""
    import inspect

    from bouncelab.export.emit import base, c, cs, js

    assert all(issubclass(e, base.Emitter) for e in (CEmitter, JSEmitter, CSharpEmitter))
    for module in (c, js, cs):
        assert "import ast" not in inspect.getsource(module)  # none reads Python: that is the front end's


# ------------------------------------------------------------------------------ a ground-like kernel, three languages
@njit
def hops(xd, yd, w, law, args, n):
    """n bounces in a row of the law passed in (each lift-off comes down again at its speed): a made-up loop
    shaped like a ground-phase kernel."""
    total = 0.0
    code = 0
    for _ in range(n):
        xd, yd, w, code = law(xd, yd, w, *args)
        yd = -math.sqrt(yd * yd + 1.0)
        total += xd * 1e-3
    return xd, yd, w, total + code


CASES = [(rigid_kernel, (0.55, 0.4)), (penner_varying_kernel, (0.58, 0.6, 0.0075, 0.0))]
LANDINGS = [(1000.0, -800.0, 300.0), (600.0, -900.0, 1500.0), (-1200.0, -300.0, -50.0), (40.0, -1500.0, 900.0)]


def _program(kernel, args):
    types = (FLOAT, FLOAT, FLOAT, FuncType.of(kernel), TupleType((FLOAT,) * len(args)), INT)
    return translate(hops, *types)


def _expected(kernel, args) -> np.ndarray:
    return np.array([hops(*p, kernel, args, 5) for p in LANDINGS])


def _call_args(p, args) -> list[str]:
    return [repr(v) for v in (*p, *args)] + ["5"]


@pytest.mark.skipif(CC is None, reason="no C compiler: `cc` is not on PATH")
@pytest.mark.parametrize(("kernel", "args"), CASES, ids=["rigid", "penner_varying"])
def test_ground_like_kernel_in_c(tmp_path, kernel, args):
    tr, fn = _program(kernel, args)
    em = CEmitter(tr.program, "g_")
    code = em.definitions()
    calls = "\n".join(f"    {{ {em.struct(fn.returns)} t = g_{fn.name}({', '.join(_call_args(p, args))}); "
                      'printf("%.17g %.17g %.17g %.17g\\n", t.v0, t.v1, t.v2, t.v3); }' for p in LANDINGS)
    (tmp_path / "main.c").write_text(f"#include <math.h>\n#include <stdio.h>\n#include <stdlib.h>\n{code}\n"
                                     f"int main(void) {{\n{calls}\n    return 0;\n}}\n")
    subprocess.run([CC, "-std=c99", "-O2", "-ffp-contract=off", "-Wall", "-Wextra", "-Werror", "main.c", "-lm",
                    "-o", "main"], cwd=tmp_path, check=True, timeout=120)
    out = subprocess.run([str(tmp_path / "main")], capture_output=True, text=True, check=True).stdout
    np.testing.assert_array_equal(np.array([line.split() for line in out.splitlines()], dtype=float),
                                  _expected(kernel, args))


@pytest.mark.skipif(NODE is None, reason="no Node.js: `node` is not on PATH")
@pytest.mark.parametrize(("kernel", "args"), CASES, ids=["rigid", "penner_varying"])
def test_ground_like_kernel_in_js(tmp_path, kernel, args):
    tr, fn = _program(kernel, args)
    em = JSEmitter(tr.program)
    calls = "\n".join("\n".join(em.entry_call(fn.name, _call_args(p, args)))
                      + "\nconsole.log([$R[0], $R[1], $R[2], $R[3]].join(' '));" for p in LANDINGS)
    (tmp_path / "main.mjs").write_text(f"{em.definitions()}\n{calls}\n")
    out = subprocess.run([NODE, "main.mjs"], cwd=tmp_path, capture_output=True, text=True, check=True).stdout
    got = np.array([line.split() for line in out.splitlines()], dtype=float)
    np.testing.assert_allclose(got, _expected(kernel, args), rtol=1e-14)


@pytest.mark.skipif(MCS is None or MONO is None, reason="no Mono: `mcs` and `mono` are not on PATH (Debian: "
                                                        "apt-get install mono-mcs mono-runtime)")
@pytest.mark.parametrize(("kernel", "args"), CASES, ids=["rigid", "penner_varying"])
def test_ground_like_kernel_in_cs(tmp_path, kernel, args):
    tr, fn = _program(kernel, args)
    em = CSharpEmitter(tr.program)
    code = em.definitions()
    ret = [em.type_name(t) for t in fn.returns]
    calls = "\n".join(f"        {{ {ret[0]} a; {ret[1]} b; {ret[2]} c; {ret[3]} d; "
                      f"{fn.name}({', '.join(_call_args(p, args))}, out a, out b, out c, out d); "
                      'Console.WriteLine(a.ToString("R") + " " + b.ToString("R") + " " + c.ToString("R") + " " '
                      '+ d.ToString("R")); }' for p in LANDINGS)
    (tmp_path / "main.cs").write_text(f"using System;\npublic static class G {{\n{code}\n"
                                      f"    public static void Main() {{\n{calls}\n    }}\n}}\n")
    subprocess.run([MCS, "-langversion:ISO-2", "-warnaserror+", "main.cs"], cwd=tmp_path, check=True, timeout=120)
    out = subprocess.run([MONO, "main.exe"], cwd=tmp_path, capture_output=True, text=True, check=True).stdout
    got = np.array([line.split() for line in out.splitlines()], dtype=float)
    np.testing.assert_allclose(got, _expected(kernel, args), rtol=1e-14)



@pytest.mark.parametrize("emitter", [CEmitter, JSEmitter, CSharpEmitter], ids=["c", "js", "cs"])
def test_every_emitter_prints_every_intrinsic(emitter):
    """The intrinsics of the IR (ir.INTRINSICS) are each language's to print: none is missing from an emitter."""
    body = []
    for k, (name, nargs) in enumerate(sorted(ir.INTRINSICS.items())):
        result = ir.BOOL if name in ("isnan", "isinf", "isfinite") else ir.F64
        args = tuple(ir.Var("x", ir.F64) for _ in range(nargs))
        body.append(ir.Assign(f"v{k}", ir.Intrinsic(name, args, result)))
    locals_ = {s.target: s.value.type for s in body}
    total = ir.Const(0.0, ir.F64)
    for s in body:
        if s.value.type == ir.F64:
            total = ir.Binary("+", total, ir.Var(s.target, ir.F64), ir.F64)
    fn = ir.Function("f_all", (("x", ir.F64),), locals_, (ir.F64,), False, (*body, ir.Return((total,))))
    text = emitter(ir.Program([fn], ["f_all"])).definitions()
    assert text.count("v0") >= 2 and "f_all" in text


# ------------------------------------------------------------------------------ stores, empty and integer arrays
# The ground phase's row kernels write their results into arrays, take optional arrays (samples, records) that
# are empty when unused, and call helpers that return nothing: a made-up kernel shaped like them.
@njit(inline="always")
def _put_pair(out, k, a, b):  # returns nothing: called as a statement; into an empty `out` it does nothing
    out[k, 0] = a
    out[k, 1] = b


@njit
def _scan(samples, t):
    """A loop over optional samples (an empty array: the loop is gone from the output)."""
    n = samples.shape[0]
    j = 0
    total = 0.0
    while j < n and samples[j] < t:
        total += samples[j]
        j += 1
    return total, j


@njit
def rows_kernel(X, COUNT, FLAGS, scale, extra, OUT, start, stop):
    empty = np.empty(0)
    dummy = np.empty((0, 2))
    record = dummy.shape[0] > 0
    for i in range(start, stop):
        x, y = X[i, 0], X[i, 1]
        s, _ = _scan(empty, x)
        if record:  # never (numba would write past the empty array): gone from the output
            _put_pair(dummy, i, x, y)
            dummy[i, 0] = 1.0
        k = 0
        while k < dummy.shape[0]:  # never runs either; the call, which does nothing, is not written
            _put_pair(dummy, k, x, y)
            k += 1
        if extra.shape[0] == 0:
            s += 0.5
        OUT[i, 0], OUT[i, 1] = y * scale + s, x
        OUT[i, 0], OUT[i, 1] = OUT[i, 1], OUT[i, 0]  # simultaneous: both read before either is stored
        OUT[i, 2] = X[i - 1, 1]  # a negative index wraps
        FLAGS[i] = x > y  # a boolean into an integer array: 1 or 0
        COUNT[i, 0] = COUNT[i, 0] + i * 2
    return True


def _rows_program():
    from bouncelab.export.frontend import ArrayType

    types = (ArrayType((4, 2)), ArrayType((4, 1), INT), ArrayType((4,), INT), FLOAT, ArrayType((0,)),
             ArrayType((4, 3)), INT, INT)
    return translate(rows_kernel, *types)


def _rows_expected():
    X = np.array([[1.0, 2.0], [3.5, -1.0], [-2.0, 0.25], [7.0, 7.0]])
    count = np.array([[1], [2], [3], [4]], dtype=np.int64)
    flags = np.zeros(4, dtype=np.int64)
    out = np.zeros((4, 3))
    rows_kernel(X, count, flags, 1.5, np.empty(0), out, 0, 4)
    return X, np.column_stack([out, flags, count[:, 0]])


def test_stores_empty_arrays_and_functions_returning_nothing_in_the_ir():
    tr, fn = _rows_program()
    params = [name for name, _ in fn.params]
    assert "extra" not in params and fn.params[1][1] == ir.ArrayType((4, 1), ir.I64)  # empty: no parameter
    assert ir.stores(fn) == {"OUT", "FLAGS", "COUNT"}
    text = ir.dump(tr.program)
    assert "record" not in text and "dummy" not in text and "_put_pair" not in text  # the empty paths are gone
    scan = next(f for f in tr.program.functions if f.name.startswith("f_scan"))
    assert not any(isinstance(s, ir.While) for s in ir.walk(scan.body))  # NaN < t: decided, the loop is gone
    (loop,) = [s for s in ir.walk(fn.body) if isinstance(s, ir.While)]
    assert loop.body == (ir.Assign("k", ir.Binary("+", ir.Var("k", ir.I64), ir.Const(1, ir.I64), ir.I64)),)
    assert "0.5" in text  # extra.shape[0] == 0 decided: the branch is kept, its test gone
    assert any(isinstance(s, ir.Store) for s in ir.walk(fn.body))


@njit
def _writer(out, x):
    out[0] = x
    return x


@njit
def _calls_writer(out, x):
    return _writer(out, x) + 1.0


@njit
def _makes_array(x):
    a = np.empty(3)
    return x + a.shape[0]


def test_a_call_of_a_function_that_stores_and_a_real_array_made_inside_are_refused():
    from bouncelab.export.frontend import ArrayType

    with pytest.raises(ExportError) as exc:
        translate(_calls_writer, ArrayType((1,)), FLOAT)
    assert "assigns array elements" in str(exc.value)
    _, fn = translate(_writer, ArrayType((1,)), FLOAT)  # as an entry point it may
    assert ir.stores(fn) == {"out_"}  # (out is a C# keyword: renamed in every language)
    with pytest.raises(ExportError) as exc:
        translate(_makes_array, FLOAT)
    assert "an array made inside a function" in str(exc.value)


def _rows_call_args() -> str:
    return "X, COUNT, FLAGS, 1.5, OUT, 0, 4"


@pytest.mark.skipif(CC is None, reason="no C compiler: `cc` is not on PATH")
def test_stores_in_c(tmp_path):
    tr, fn = _rows_program()
    X, expected = _rows_expected()
    code = CEmitter(tr.program, "g_").definitions()
    x = ", ".join(f"{{{float(a)!r}, {float(b)!r}}}" for a, b in X)
    main = (f"#include <math.h>\n#include <stdio.h>\n#include <stdlib.h>\n{code}\nint main(void) {{\n"
            f"    double X[4][2] = {{{x}}}; long long COUNT[4][1] = {{{{1}}, {{2}}, {{3}}, {{4}}}};\n"
            "    long long FLAGS[4] = {0, 0, 0, 0}; double OUT[4][3] = {{0}};\n"
            f"    g_{fn.name}((const double (*)[2])X, COUNT, FLAGS, 1.5, OUT, 0, 4);\n"
            '    for (int i = 0; i < 4; i++) printf("%.17g %.17g %.17g %lld %lld\\n", OUT[i][0], OUT[i][1], OUT[i][2],'
            " FLAGS[i], COUNT[i][0]);\n    return 0;\n}\n")
    (tmp_path / "main.c").write_text(main)
    subprocess.run([CC, "-std=c99", "-O2", "-ffp-contract=off", "-Wall", "-Wextra", "-pedantic", "-Werror", "main.c",
                    "-lm", "-o", "main"], cwd=tmp_path, check=True, timeout=120)
    out = subprocess.run([str(tmp_path / "main")], capture_output=True, text=True, check=True).stdout
    np.testing.assert_array_equal(np.array([line.split() for line in out.splitlines()], dtype=float), expected)


@pytest.mark.skipif(NODE is None, reason="no Node.js: `node` is not on PATH")
def test_stores_in_js(tmp_path):
    tr, fn = _rows_program()
    X, expected = _rows_expected()
    em = JSEmitter(tr.program)
    x = ", ".join(f"new Float64Array([{float(a)!r}, {float(b)!r}])" for a, b in X)
    setup = (f"const X = [{x}]; const COUNT = [[1], [2], [3], [4]].map(r => new Float64Array(r));\n"
             "const FLAGS = new Float64Array(4); const OUT = [0, 1, 2, 3].map(() => new Float64Array(3));\n")
    call = "\n".join(em.entry_call(fn.name, ["X", "COUNT", "FLAGS", "1.5", "OUT", "0", "4"]))
    show = "for (let i = 0; i < 4; i++) console.log([...OUT[i], FLAGS[i], COUNT[i][0]].join(' '));"
    (tmp_path / "main.mjs").write_text(f"{em.definitions()}\n{setup}{call}\n{show}\n")
    out = subprocess.run([NODE, "main.mjs"], cwd=tmp_path, capture_output=True, text=True, check=True).stdout
    np.testing.assert_array_equal(np.array([line.split() for line in out.splitlines()], dtype=float), expected)


@pytest.mark.skipif(MCS is None or MONO is None, reason="no Mono: `mcs` and `mono` are not on PATH (Debian: "
                                                        "apt-get install mono-mcs mono-runtime)")
def test_stores_in_cs(tmp_path):
    tr, fn = _rows_program()
    X, expected = _rows_expected()
    em = CSharpEmitter(tr.program)
    x = ", ".join(f"{{{float(a)!r}, {float(b)!r}}}" for a, b in X)
    main = (f"        double[,] X = {{{x}}}; long[,] COUNT = {{{{1}}, {{2}}, {{3}}, {{4}}}};\n"
            "        long[] FLAGS = new long[4]; double[,] OUT = new double[4, 3];\n"
            f"        {fn.name}(X, COUNT, FLAGS, 1.5, OUT, 0, 4);\n"
            "        for (int i = 0; i < 4; i++) Console.WriteLine(OUT[i, 0].ToString(\"R\") + \" \" + "
            "OUT[i, 1].ToString(\"R\") + \" \" + OUT[i, 2].ToString(\"R\") + \" \" + FLAGS[i] + \" \" "
            "+ COUNT[i, 0]);\n")
    (tmp_path / "main.cs").write_text(f"using System;\npublic static class G {{\n{em.definitions()}\n"
                                      f"    public static void Main() {{\n{main}    }}\n}}\n")
    subprocess.run([MCS, "-langversion:ISO-2", "-warnaserror+", "main.cs"], cwd=tmp_path, check=True, timeout=120)
    out = subprocess.run([MONO, "main.exe"], cwd=tmp_path, capture_output=True, text=True, check=True).stdout
    np.testing.assert_array_equal(np.array([line.split() for line in out.splitlines()], dtype=float), expected)
