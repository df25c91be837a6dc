"""Results that show themselves in a notebook: a motion's report (a dict) and a view."""

from __future__ import annotations

import os
from typing import Any, Mapping, Union


class View:
    """A ``reach view`` page of a robot (at a configuration, among a scene's obstacles, or
    playing a motion): ``_repr_html_`` shows it inline in Jupyter (the viewer bundle and the
    data inlined in an ``<iframe srcdoc>``; no network), ``html`` is the whole page,
    ``save(path)`` writes it (what ``reach view -o`` writes)."""

    def __init__(self, robot: Any, request: str, meshes: bool = True) -> None:
        self._robot = robot
        self._request = request
        self._meshes = meshes

    @property
    def html(self) -> str:
        """The self-contained HTML page."""
        return self._robot._view_html(self._request, frame=False, meshes=self._meshes)

    def save(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Writes the page to ``path``."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.html)

    def _repr_html_(self) -> str:
        return self._robot._view_html(self._request, meshes=self._meshes)

    def __repr__(self) -> str:
        return f"View({self._robot.name!r})"


class Motion(dict):
    """The report of a workflow that makes a sampled motion (``move``, ``track``, ``plan``,
    ``path``): a plain dict (the CLI's ``--json`` report, its samples as the arrays ``t``,
    ``q``, ``qd``, ``qdd``) that also shows the motion in the 3-D viewer in a notebook
    (``_repr_html_``) and as a ``View`` (``view()``)."""

    def __init__(self, report: Mapping[str, Any], robot: Any, view: str) -> None:
        super().__init__(report)
        self._robot = robot
        self._view = view

    def view(self, meshes: bool = True) -> View:
        """The motion in the viewer (its samples on the timeline, events marked, the scene's
        obstacles drawn; a URDF robot's meshes unless ``meshes=False``)."""
        return View(self._robot, self._view, meshes)

    def _repr_html_(self) -> str:
        return self._robot._view_html(self._view)

    def __reduce__(self) -> Any:
        return (Motion, (dict(self), self._robot, self._view))
