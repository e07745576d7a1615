"""wornjoint: planar mechanisms with worn clearance revolute joints, from Python.

The simulations run in Rust (the same code as the ``wearsim`` command line, so the numbers
are the same bit for bit) and release the GIL: Python threads run scenes in parallel.

>>> import wornjoint
>>> scene = wornjoint.load("lgres")                 # a dict you can edit
>>> scene["clearance_joints"][0]["clearance"] = 3e-4
>>> r = wornjoint.run(scene, cycles=1, stages=0)    # doctest: +SKIP
>>> r.summary["response"]["dissipated_per_cycle_j"] # doctest: +SKIP
>>> r.contact["A_Fn"].max()                         # doctest: +SKIP

Bad input raises :class:`SceneError` (a ``ValueError``) whose message names the field; a run
that fails raises :class:`RunError`. :func:`sweep` runs a sweep file on local threads or, given
a ``dask.distributed`` client, one task per sample.
"""

from __future__ import annotations

import json
import os
import sys
import time
from typing import Any, Dict, Optional

import numpy as np

from . import _native
from ._native import RunError, SceneError, SweepError

__all__ = [
    "RunError",
    "Result",
    "Scene",
    "SceneError",
    "SweepError",
    "load",
    "run",
    "scenes",
    "sweep",
]


def scenes() -> Dict[str, str]:
    """The built-in scenes: name -> one-line summary."""
    return dict(_native.scenes())


class Scene(dict):
    """A scene as a dict of its file's values (``extends`` merged in, defaults left out).

    Edit it like any dict; :func:`run` validates it. ``name`` is what outputs are filed under.
    """

    def __init__(self, data: Dict[str, Any], name: str = "scene"):
        super().__init__(data)
        self.name = name

    def check(self) -> None:
        """Validate; raises :class:`SceneError` naming the field."""
        _native.check(self, self.name)


def load(name_or_path: "str | os.PathLike[str]") -> Scene:
    """A built-in scene (see :func:`scenes`) or a TOML scene file, validated, as a dict."""
    name, data = _native.load(os.fspath(name_or_path))
    return Scene(data, name)


def _structured(columns) -> Optional[np.ndarray]:
    """A structured array from ``[(name, array), ...]`` (``None`` if there are none)."""
    if not columns:
        return None
    names = [n for n, _ in columns]
    return np.rec.fromarrays([a for _, a in columns], names=names).view(np.ndarray)


class Result:
    """The outcome of :func:`run`.

    - ``summary``: the dict ``summary.json`` holds.
    - ``response``, ``contact``: structured NumPy arrays whose columns are those of
      ``response.csv`` and ``contact.csv`` (``r.response["x"]``, ``r.contact["A_Fn"]``);
      ``worn_response``, ``worn_contact`` the same on the worn surfaces (``None`` without wear
      stages).
    - ``wear``: per joint, ``{"angle_deg": cells, "bearing": stages x cells, "pin": stages x
      cells, "bearing_radius", "pin_radius"}``, depths in m.
    - ``life_distribution``: with ``run.clearance_limit`` reached, the columns of
      ``life_distribution.csv``: ``cycles`` and, per joint and for the mechanism, the fraction
      that reached the limit by them under the ``k_d`` scatter (``failed_A``,
      ``failed_mechanism``); their B10 and B50 are in ``summary["wear"]``; ``None`` without.
      ``r.frame("life_distribution")`` gives it as a pandas DataFrame.
    - ``scene_toml``: the scene as run.

    In a notebook a result displays its report (:meth:`report_html`).
    """

    def __init__(self, raw: Dict[str, Any]):
        self.summary: Dict[str, Any] = json.loads(raw["summary_json"])
        self.scene_toml: str = raw["scene_toml"]
        self.response = _structured(raw["response"])
        self.contact = _structured(raw["contact"])
        self.worn_response = _structured(raw.get("worn_response"))
        self.worn_contact = _structured(raw.get("worn_contact"))
        self.wear: Dict[str, Dict[str, Any]] = raw["wear"]
        self.life_distribution = _structured(raw.get("life_distribution"))
        self._outcome = raw["outcome"]
        self._html: Optional[str] = None

    def report_html(self) -> str:
        """The run's report (as ``report.html`` shows it, without the file list) as an HTML
        fragment with its figures embedded; drawn on first use, then kept."""
        if self._html is None:
            self._html = self._outcome.report_html()
        return self._html

    def _repr_html_(self) -> str:
        return self.report_html()

    def frame(self, which: str = "response"):
        """One of the tables as a pandas DataFrame (needs pandas)."""
        import pandas as pd

        return pd.DataFrame(getattr(self, which))

    def __repr__(self) -> str:
        s = self.summary
        return f"<wornjoint.Result scene={s['scene']!r} cycles={s['response']['cycles']}>"


def run(
    scene: "str | os.PathLike[str] | Dict[str, Any]" = "lgres",
    *,
    cycles: Optional[int] = None,
    stages: Optional[int] = None,
    rtol: Optional[float] = None,
    surfaces: "str | os.PathLike[str] | None" = None,
    cycles_per_stage: Optional[int] = None,
    max_steps: Optional[int] = None,
    max_wall_time: Optional[float] = None,
    name: Optional[str] = None,
    out: "str | os.PathLike[str] | None" = None,
    trajectories: Optional[int] = None,
    threads: Optional[int] = None,
    wear_tolerance: Optional[float] = None,
) -> Result:
    """Simulate a scene like ``wearsim run`` with the same options (``None``: the scene's).

    ``scene`` is a built-in name, a TOML file or a dict (from :func:`load`, edited).
    ``cycles_per_stage`` defaults to 2 as on the command line, spread over 2 ``trajectories``
    (run on ``threads`` threads, default the machine's cores; the results do not depend on
    it). ``wear_tolerance`` (e.g. 0.05) makes the wear sub-steps error-controlled
    (``run.wear_tolerance``). ``out`` also writes the files
    ``wearsim run --out`` writes. Raises :class:`SceneError` for bad input, :class:`RunError`
    when the run fails. The GIL is released while the simulation runs.
    """
    if isinstance(scene, os.PathLike):
        scene = os.fspath(scene)
    if name is None and isinstance(scene, Scene):
        name = scene.name
    raw = _native.run(
        scene,
        name,
        cycles=cycles,
        stages=stages,
        rtol=rtol,
        surfaces=None if surfaces is None else os.fspath(surfaces),
        cycles_per_stage=cycles_per_stage,
        max_steps=max_steps,
        max_wall_time=max_wall_time,
        out=None if out is None else os.fspath(out),
        trajectories=trajectories,
        threads=threads,
        wear_tolerance=wear_tolerance,
    )
    return Result(raw)


class _Progress:
    """Counts finished samples on standard error, at most about once a second and at the end.

    On a terminal the count rewrites one line; elsewhere (a log, a notebook) every update is a
    line of its own, so updates never run into each other.
    """

    def __init__(self, label: str):
        self.label = label
        self.started = time.monotonic()
        self.shown = -1.0
        self.last = ""
        self.terminal = hasattr(sys.stderr, "isatty") and sys.stderr.isatty()

    def update(self, done: int, total: int) -> None:
        now = time.monotonic()
        self.last = f"{self.label}: {done}/{total} samples, {now - self.started:.0f} s"
        if done == total or now - self.shown >= 1.0:
            self._show()
            self.shown = now

    def _show(self) -> None:
        if self.terminal:
            print(f"\r{self.last}", end="", file=sys.stderr, flush=True)
        else:
            print(self.last, file=sys.stderr, flush=True)

    def close(self) -> None:
        if self.terminal and self.last:
            print(file=sys.stderr, flush=True)


def _sample(index: int, plan: str) -> str:
    """One sweep sample (a Dask task): the row as JSON."""
    return _native.sweep_sample(plan, index)


def sweep(
    file: "str | os.PathLike[str]",
    client=None,
    *,
    out: "str | os.PathLike[str] | None" = None,
    resume: bool = False,
    jobs: Optional[int] = None,
    progress: bool = True,
):
    """Run a sweep file and return its rows as a pandas DataFrame.

    Without ``client`` the samples run on local threads (``jobs`` of them), exactly as
    ``wearsim sweep FILE``. With a ``dask.distributed`` client each sample is one task; the rows
    are gathered and written by the same writer, so the file and the rows are the same (but for
    ``wall_time_s``) whatever the engine and the number of workers. Outputs go to ``out``
    (default ``out/sweep/<file stem>``): ``samples.csv`` and the figures. ``resume`` keeps the
    rows already in ``samples.csv`` and runs the rest. With ``progress``, standard error counts
    the finished samples (at most once a second, and at the end): one rewritten line on a
    terminal, a line per update in a log or a notebook.
    """
    import pandas as pd

    plan, name, _ = _native.sweep_plan(os.fspath(file))
    out = os.fspath(out) if out is not None else os.path.join("out", "sweep", name)
    show = _Progress(f"sweep {name}") if progress else None
    if client is None:
        on_row = None if show is None else (lambda done, total: show.update(done, total))
        path = _native.sweep_local(os.fspath(file), out, resume, jobs, on_row)
        if show is not None:
            show.close()
    else:
        from distributed import as_completed

        todo, rows = _native.sweep_pending(plan, out, resume)
        rows = list(rows)
        futures = client.map(_sample, todo, plan=plan, pure=False)
        written = time.monotonic()
        total = len(rows) + len(todo)
        for future in as_completed(futures):
            rows.append(future.result())
            if show is not None:
                show.update(len(rows), total)
            # Keep samples.csv current, as the local engine does, so a resume finds them.
            if time.monotonic() - written >= 1.0:
                _native.sweep_write(plan, rows, out, figures=False)
                written = time.monotonic()
        if show is not None:
            show.close()
        _native.sweep_write(plan, rows, out, figures=True)
        path = os.path.join(out, "samples.csv")
    return pd.read_csv(path, keep_default_na=False, na_values=[""])
