"""Run every documentation snippet and store its real output beside it.

Each ``NAME.py`` (run with this Python) or ``NAME.sh`` (run with bash, the
interpreter's ``bin`` first on PATH) runs in a fresh temporary directory; its
standard output and standard error, merged, are written to ``NAME.out``. Any
PNG file a snippet writes in its directory is copied to ``docs/img/``. The pages
include both files with ``--8<--`` (pymdownx.snippets), so the docs show the
code and the output of the same run.

Usage (from the repository root)::

    .venv/bin/python docs/snippets/run.py            # all snippets
    .venv/bin/python docs/snippets/run.py fit_quick  # only those whose name contains fit_quick
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
IMG = HERE.parent / "img"


def run(path: Path) -> float:
    env = dict(os.environ, MPLBACKEND="Agg", COLUMNS="120", REPO=str(HERE.parents[1]))
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    cmd = [sys.executable, str(path)] if path.suffix == ".py" else ["bash", str(path)]
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="bouncelab-doc-") as tmp:
        proc = subprocess.run(cmd, cwd=tmp, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if proc.returncode != 0 and path.suffix == ".py":
            sys.stderr.write(proc.stdout)
            raise SystemExit(f"{path.name} failed with exit code {proc.returncode}")
        IMG.mkdir(exist_ok=True)
        for png in Path(tmp).glob("*.png"):
            shutil.copy(png, IMG / png.name)
    text = proc.stdout.replace(tmp, "/tmp/work")
    path.with_suffix(".out").write_text(text if text.endswith("\n") or not text else text + "\n")
    return time.perf_counter() - start


def main(argv: list[str]) -> None:
    files = sorted(p for p in HERE.iterdir() if p.suffix in (".py", ".sh") and p.name != "run.py")
    for path in files:
        if argv and not any(a in path.name for a in argv):
            continue
        print(f"{path.name:<32} {run(path):6.1f} s", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
