"""Reading MATLAB ``.mat`` files (v5/v7): vectors, matrices, cell arrays of strings and structs as columns."""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np

from bouncelab.core.errors import DataError
from bouncelab.data.io.columns import _header_unit
from bouncelab.data.io.table import _check_duplicates, _Column, _Table, _table_of_columns


def _read_mat(path: Path, file: str) -> _Table:
    import scipy.io
    from scipy.io.matlab import mat_struct

    _probe_in_subprocess(path, file)
    try:
        raw = scipy.io.loadmat(str(path), squeeze_me=True, struct_as_record=False, chars_as_strings=True)
    except NotImplementedError:
        raise DataError(
            "MATLAB v7.3 (HDF5) files cannot be read; in MATLAB save it with "
            "save(name, ..., '-v7') or write a CSV", file=file,
        ) from None
    except Exception as exc:
        raise DataError(f"cannot read it as a MATLAB .mat file ({type(exc).__name__}: {exc})", file=file) from None

    entries: list[tuple[str, str, bool, Any]] = []  # (short, qualified, from_struct, values)
    opaque: list[str] = []

    def add(short: str, parent: str | None, values: Any) -> None:
        qual = short if parent is None else f"{parent}.{short}"
        entries.append((short, qual, parent is not None, values))

    def collect(name: str, parent: str | None, val: Any) -> None:
        qual = name if parent is None else f"{parent}.{name}"
        if isinstance(val, mat_struct):
            for f in val._fieldnames:
                collect(f, qual, getattr(val, f))
            return
        if isinstance(val, bool):
            return
        if isinstance(val, int | float | str | np.number):
            add(name, parent, [val])
            return
        if not isinstance(val, np.ndarray):
            opaque.append(qual)
            return
        if val.dtype.kind == "O" and val.size and all(isinstance(e, mat_struct) for e in val.flat):
            elems = list(val.flat)
            for f in elems[0]._fieldnames:
                cells = [_scalar(getattr(e, f, None)) for e in elems]
                if all(c is not None for c in cells):
                    add(f, qual, cells)
            return
        if val.dtype.kind in "iuf":
            if val.ndim == 0:
                add(name, parent, val.reshape(1).astype(float))
            elif val.ndim == 1:
                add(name, parent, val.astype(float))
            elif val.ndim == 2:
                for k in range(val.shape[1]):
                    add(f"{name}_{k + 1}", parent, val[:, k].astype(float))
            return
        if val.dtype.kind == "U":
            add(name, parent, [str(v) for v in np.atleast_1d(val)])
            return
        if val.dtype.kind == "O" and val.ndim == 1:
            cells = [_scalar(e) for e in val]
            if all(c is not None for c in cells):
                add(name, parent, cells)

    for name, val in raw.items():
        if not name.startswith("__"):
            collect(name, None, val)

    counts: dict[str, int] = {}
    for short, *_ in entries:
        counts[short] = counts.get(short, 0) + 1
    columns = []
    for short, qual, from_struct, values in entries:
        name = qual if (from_struct and counts[short] > 1) else short
        columns.append(_Column(name, values, *_header_unit(name)))
    _check_duplicates([c.name for c in columns], file)
    if not columns:
        hint = (f"; {opaque} cannot be read (a MATLAB table? save table2struct(T, 'ToScalar', true))"
                if opaque else "")
        raise DataError(f"the file holds no numeric vectors, matrices or structs{hint}", file=file)
    return _table_of_columns(file, columns)


#: Seconds the crash probe may take before the file is refused.
MAT_PROBE_TIMEOUT_S = 60.0

_PROBE = (
    "import sys, scipy.io\n"
    "try:\n"
    "    scipy.io.loadmat(sys.argv[1], squeeze_me=True, struct_as_record=False, chars_as_strings=True)\n"
    "except BaseException:\n"
    "    pass\n"
)


def _probe_in_subprocess(path: Path, file: str) -> None:
    """Parse the file once in a child interpreter: a damaged .mat file can make scipy's reader crash
    (a segmentation fault, one changed byte in a data-type tag), and must not take the caller with it.

    Costs one Python start-up with scipy.io (about 0.5 s); the parse itself is deterministic, so a file
    the child survives is then parsed here.
    """
    try:
        proc = subprocess.run([sys.executable, "-c", _PROBE, str(path)], capture_output=True,
                              timeout=MAT_PROBE_TIMEOUT_S, check=False)
    except subprocess.TimeoutExpired:
        raise DataError(f"reading it as a MATLAB file took over {MAT_PROBE_TIMEOUT_S:g} s; the file is damaged",
                        file=file) from None
    if proc.returncode != 0:
        how = (f"signal {signal.Signals(-proc.returncode).name}" if proc.returncode < 0
               and -proc.returncode in signal.Signals._value2member_map_ else f"exit status {proc.returncode}")
        raise DataError(f"the MATLAB reader (scipy.io.loadmat) crashed on it ({how}): the file is damaged; "
                        "save it again from MATLAB or write a CSV", file=file)


def _scalar(v: Any) -> Any:
    """A MATLAB scalar (number or string) as a Python value, else ``None``."""
    if isinstance(v, np.ndarray):
        if v.size != 1:
            return None
        v = v.reshape(()).item()
    if isinstance(v, bool):
        return None
    if isinstance(v, bytes):
        return v.decode("utf-8", "replace")
    if isinstance(v, int | float | str | np.number):
        return v.item() if isinstance(v, np.number) else v
    return None
