"""numba compilation that survives read-only installs and damaged caches.

Every compiled function of bouncelab goes through :func:`jit` instead of
``numba.njit(cache=True)``. It caches compiled code on disk like numba, with
three differences:

* **Read-only installs.** numba caches next to the source (``__pycache__``), else
  in ``$NUMBA_CACHE_DIR`` or the user's cache folder; installed root-owned and
  run by a user without a writable home, none is writable and ``cache=True``
  fails at import ("no locator available"). :func:`jit` then caches in a
  private folder of the temporary directory (``bouncelab-numba-<uid>``, mode
  0700, refused if another user owns it), and failing that compiles without a
  cache after one warning line.
* **Damaged caches.** A truncated or corrupted cache file makes numba raise on
  every call until it is deleted. :func:`jit` treats any failure to read an
  entry as a cache miss (one warning line), recompiles and overwrites it.
* **Closures.** numba keys the cache of a function built inside a factory by a
  pickle of its closure, in which a compiled callee carries a random per-process
  id, so closures never hit the cache. :func:`jit` keys compiled callees by their
  bytecode and source file instead (used by :class:`~bouncelab.laws.CompiledLaw`,
  which builds its loops around a law author's kernel).

It also spares a process that only predicts the import of :mod:`scipy.linalg` (about half a second from
a cold disk): numba's CPU target asks for scipy's BLAS as it loads its NumPy registries, whether or not
any compiled function does linear algebra (:func:`_defer_blas`).
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import inspect
import os
import stat
import sys
import tempfile
import warnings
from collections.abc import Callable
from typing import Any

__all__ = ["ROW_FLAGS", "cache_directory", "jit"]

#: The floating-point freedoms of bouncelab's compiled loops: only those that cannot change a finite result
#: (no NaN or infinity reaches a kernel: inputs are checked first). Left out on purpose, so that a bounce
#: gives the same bits whatever its place in a batch and on any x86-64 CPU (tested):
#: "contract" (fused multiply-adds exist on some CPUs and not others, and a vectorised loop body and its
#: scalar tail fused differently: the last bit depended on a row's position), "arcp" (reciprocals),
#: "reassoc" (sums in another order: vector width decides the order) and "afn" (approximate functions).
ROW_FLAGS = {"nnan", "ninf", "nsz"}

_warned: set[str] = set()


def _warn_once(key: str, message: str) -> None:
    if key not in _warned:
        _warned.add(key)
        warnings.warn(message, RuntimeWarning, stacklevel=3)


def cache_directory() -> str | None:
    """The private fall-back cache folder (created on first use), or None if none can be made safely."""
    try:
        uid = os.getuid()
    except AttributeError:  # not POSIX
        uid = 0
    path = os.path.join(tempfile.gettempdir(), f"bouncelab-numba-{uid}")
    try:
        os.makedirs(path, mode=0o700, exist_ok=True)
        st = os.lstat(path)
        if not stat.S_ISDIR(st.st_mode) or st.st_uid != uid or st.st_mode & 0o022:
            return None  # someone else's folder, or writable by others: cached code could be planted there
        tempfile.TemporaryFile(dir=path).close()
    except OSError:
        return None
    return path


def _cache_classes():
    """Our numba cache classes (built on first use; numba's internals are imported late)."""
    global _CLASSES
    if _CLASSES is not None:
        return _CLASSES
    from numba.core import caching, serialize
    from numba.core.dispatcher import Dispatcher

    class TempDirLocator(caching._SourceFileBackedLocatorMixin, caching._CacheLocator):
        """Cache in bouncelab's private folder of the temporary directory."""

        def __init__(self, py_func: Callable, py_file: str) -> None:
            self._py_file = py_file
            self._lineno = py_func.__code__.co_firstlineno
            self._cache_path = os.path.join(cache_directory() or "", self.get_suitable_cache_subpath(py_file))

        def get_cache_path(self) -> str:
            return self._cache_path

        @classmethod
        def from_function(cls, py_func, py_file):
            if cache_directory() is None:
                return None
            return super().from_function(py_func, py_file)

    class Impl(caching.CompileResultCacheImpl):
        _locator_classes = (*caching.CompileResultCacheImpl._locator_classes, TempDirLocator)

    def describe(obj: Any, seen: set[int]) -> Any:
        """A stable description of a closure variable: compiled callees by code and source file."""
        if isinstance(obj, Dispatcher):
            if id(obj) in seen:
                return ("dispatcher", obj.py_func.__qualname__)
            seen.add(id(obj))
            func = obj.py_func
            return ("dispatcher", func.__module__, func.__qualname__, _code_digest(func), _file_stamp(func),
                    tuple(describe(v, seen) for v in _referenced_dispatchers(func)),
                    sorted((k, repr(v)) for k, v in obj.targetoptions.items()))
        return serialize.dumps(obj)

    class RobustCache(caching.FunctionCache):
        _impl_class = Impl

        #: The compile options (fastmath flags, inline...), part of every key: numba's own key leaves them
        #: out, so code compiled with other floating-point flags was loaded after the flags changed.
        options_key: str = ""

        def _index_key(self, sig, codegen):
            if self._py_func.__closure__ is None:
                return (*super()._index_key(sig, codegen), self.options_key)
            cvars = tuple(describe(c.cell_contents, set()) for c in self._py_func.__closure__)
            digest = hashlib.sha256(repr(cvars).encode()).hexdigest()
            return (sig, codegen.magic_tuple(), (hashlib.sha256(self._py_func.__code__.co_code).hexdigest(), digest),
                    self.options_key)

        def load_overload(self, sig, target_context):
            try:
                return super().load_overload(sig, target_context)
            except Exception as exc:  # a damaged entry: treat as a miss and compile afresh
                _warn_once("damaged", f"bouncelab: ignored a damaged numba cache entry ({type(exc).__name__}); "
                                      "recompiling and overwriting it")
                self._discard_index()
                return None

        def save_overload(self, sig, data):
            try:
                super().save_overload(sig, data)
            except Exception:
                self._discard_index()
                with contextlib.suppress(Exception):
                    super().save_overload(sig, data)

        def _discard_index(self) -> None:
            with contextlib.suppress(OSError):
                os.remove(self._cache_file._index_path)

    _CLASSES = RobustCache
    return _CLASSES


_CLASSES = None


def _code_digest(func: Callable) -> str:
    code = func.__code__
    parts = [code.co_code, repr(code.co_consts).encode(), repr(code.co_names).encode()]
    return hashlib.sha256(b"\0".join(parts)).hexdigest()


def _file_stamp(func: Callable) -> tuple:
    try:
        path = inspect.getfile(func)
        st = os.stat(path)
        return (path, st.st_mtime_ns, st.st_size)
    except (OSError, TypeError):
        return ("?",)


def _referenced_dispatchers(func: Callable) -> list:
    from numba.core.dispatcher import Dispatcher

    glb = getattr(func, "__globals__", {})
    out = [glb[n] for n in func.__code__.co_names if isinstance(glb.get(n), Dispatcher)]
    for cell in func.__closure__ or ():
        with contextlib.suppress(ValueError):
            if isinstance(cell.cell_contents, Dispatcher):
                out.append(cell.cell_contents)
    return out


def _defer_blas() -> None:
    """Let numba load its NumPy registries without importing scipy.linalg until linear algebra is compiled.

    ``numba.np.arraymath`` asks at import whether a BLAS exists (``_HAVE_BLAS``), by importing
    ``scipy.linalg.cython_blas`` and so all of scipy.linalg. Here it is imported with that probe
    answered by whether scipy is installed (a dependency of bouncelab); the probe is restored at once,
    so a compiled ``np.dot`` still imports the BLAS when it is compiled. Numba's internals may move: then
    nothing is changed.
    """
    if "numba.np.arraymath" in sys.modules:
        return
    try:
        import numba.np.linalg as linalg

        probe = linalg.ensure_blas
        if importlib.util.find_spec("scipy") is None:
            return

        def installed() -> None:
            return None

        linalg.ensure_blas = installed
        try:
            import numba.np.arraymath  # noqa: F401  (its _HAVE_BLAS probe runs now)
        finally:
            linalg.ensure_blas = probe
    except Exception:  # numba's internals changed: numba does as it always did
        return


def jit(func: Callable | None = None, *, cache: bool = True, **options: Any):
    """``numba.njit`` with a cache that works from read-only installs and recovers from damage.

    Parameters
    ----------
    func
        The function (or use as ``@jit(nogil=True)``).
    cache
        Cache compiled code on disk (see the module notes).
    **options
        numba.njit options (``nogil``, ``fastmath``, ``inline``, ...).
    """
    if func is None:
        return lambda f: jit(f, cache=cache, **options)
    _defer_blas()
    from numba import njit

    disp = njit(**options)(func)
    if not cache or os.environ.get("BOUNCELAB_NO_CACHE"):
        return disp
    try:
        disp._cache = _cache_classes()(disp.py_func)
        disp._cache.options_key = repr(sorted((k, sorted(v) if isinstance(v, set) else v) for k, v in options.items()))
    except RuntimeError as exc:  # no writable cache location at all
        _warn_once("nocache", f"bouncelab: numba cannot cache compiled code here ({exc}); compiling in each process")
    except Exception as exc:  # numba internals changed: fall back to numba's own caching
        try:
            disp.enable_caching()
        except Exception:
            _warn_once("nocache", f"bouncelab: numba caching unavailable ({type(exc).__name__}: {exc}); "
                                  "compiling in each process")
    return disp

