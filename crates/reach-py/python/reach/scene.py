"""Scenes as objects: the obstacles and the tool zone a robot is checked against.

A ``Scene`` is read from a scene file (``Scene.from_file``: the TOML files ``reach check``
and ``--scene`` read, docs/scene-format.md, or a MoveIt planning scene in YAML), from the text
of one (``Scene.from_toml``), or built in code (``Scene()`` then ``add_sphere``, ``add_box``,
… in metres and radians). Every workflow that takes ``scene=`` takes a ``Scene``, a path
(``pathlib.Path`` or a string naming a file) or the text of a scene file. The library parses
and validates the scene (``reach::jobs::world::parse_scene``): a bad entry raises
``ReachError`` naming the entry and its field.
"""

from __future__ import annotations

import json
import math
import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from ._reach import ReachError, _scene_info

#: The fields of each shape (docs/scene-format.md) and how many numbers each holds; every
#: field is a length (metres here) except ``rpy`` (radians here).
SHAPES: Dict[str, Dict[str, int]] = {
    "point": {"at": 3},
    "sphere": {"center": 3, "radius": 1},
    "aabb": {"min": 3, "max": 3},
    "box": {"center": 3, "half_extents": 3, "rpy": 3},
    "capsule": {"a": 3, "b": 3, "radius": 1},
    "cylinder": {"center": 3, "radius": 1, "length": 1, "rpy": 3},
    "halfspace": {"point": 3, "outward_normal": 3},
    "rectangle": {"center": 3, "half_extents": 2, "rpy": 3},
}

_OPTIONAL = {"rpy", "velocity"}


def _numbers(field: str, value: Any, n: int) -> Union[float, List[float]]:
    try:
        a = np.asarray(value, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ReachError(f"{field}: expected {n} number{'s' if n > 1 else ''}, got {value!r}") from None
    if a.size != n:
        raise ReachError(f"{field}: expected {n} number{'s' if n > 1 else ''}, got {a.size}")
    if not np.all(np.isfinite(a)):
        raise ReachError(f"{field}: expected finite numbers, got {value!r}")
    return float(a[0]) if n == 1 and np.ndim(value) == 0 else [float(x) for x in a]


def _toml_value(v: Any) -> str:
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return repr(float(v))


class Scene:
    """Obstacles and tool zone (see the module's docstring). ``robot`` (optional) is the arm
    the scene is drawn with in a notebook (``_repr_html_``); without one the scene shows as a
    table of its entries."""

    def __init__(self, text: Optional[str] = None, robot: Any = None) -> None:
        self._base = text
        self._added: List[Tuple[str, str, Dict[str, Any]]] = []  # (table, shape, SI fields with name)
        self.robot = robot
        self._info = _scene_info(text) if text is not None else None

    @classmethod
    def from_file(cls, path: Union[str, "os.PathLike[str]"], robot: Any = None) -> "Scene":
        """The scene of a file (TOML scene format, or a MoveIt planning scene in YAML)."""
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise OSError(f"cannot read scene file `{os.fspath(path)}`: {e.strerror or e}") from None
        try:
            return cls(text, robot)
        except ReachError as e:
            raise ReachError(f"{os.fspath(path)}: {e}") from None

    @classmethod
    def from_toml(cls, text: str, robot: Any = None) -> "Scene":
        """The scene of a scene file's text."""
        return cls(text, robot)

    # --- building -------------------------------------------------------------------------

    def add(self, name: str, shape: str, *, tool_zone: bool = False, **fields: Any) -> "Scene":
        """Adds an obstacle (or, with ``tool_zone=True``, a tool-zone entry) of ``shape``
        (``point``, ``sphere``, ``aabb``, ``box``, ``capsule``, ``cylinder``, ``halfspace``,
        ``rectangle``) with its fields in metres and radians (``rpy``), and for an obstacle an
        optional ``velocity`` (m/s, 3 numbers). Returns the scene (calls chain)."""
        if shape not in SHAPES:
            raise ReachError(f"shape: unknown shape `{shape}` (known: {', '.join(SHAPES)})")
        if not isinstance(name, str) or not name:
            raise ReachError(f"name: expected a non-empty string, got {name!r}")
        known = dict(SHAPES[shape], velocity=3)
        entry: Dict[str, Any] = {}
        for field, value in fields.items():
            if field not in known:
                raise ReachError(f"{name}: unknown field `{field}` of a {shape} (fields: {', '.join(known)})")
            if value is None and field in _OPTIONAL:
                continue
            entry[field] = _numbers(f"{name}: {field}", value, known[field])
        missing = [f for f in SHAPES[shape] if f not in entry and f not in _OPTIONAL]
        if missing:
            raise ReachError(f"{name}: missing field `{missing[0]}` of a {shape}")
        self._added.append(("tool_zone" if tool_zone else "obstacles", shape, dict(entry, name=name)))
        try:
            self._info = _scene_info(self.to_toml())
        except ReachError:
            self._added.pop()
            raise
        return self

    def add_point(self, name: str, at: Sequence[float], velocity: Optional[Sequence[float]] = None) -> "Scene":
        """A point obstacle at ``at`` (m)."""
        return self.add(name, "point", at=at, velocity=velocity)

    def add_sphere(
        self, name: str, center: Sequence[float], radius: float, velocity: Optional[Sequence[float]] = None
    ) -> "Scene":
        """A ball of ``radius`` (m) about ``center`` (m)."""
        return self.add(name, "sphere", center=center, radius=radius, velocity=velocity)

    def add_aabb(self, name: str, min: Sequence[float], max: Sequence[float]) -> "Scene":
        """An axis-aligned box from corner ``min`` to corner ``max`` (m)."""
        return self.add(name, "aabb", min=min, max=max)

    def add_box(
        self,
        name: str,
        center: Sequence[float],
        half_extents: Sequence[float],
        rpy: Optional[Sequence[float]] = None,
        velocity: Optional[Sequence[float]] = None,
    ) -> "Scene":
        """A box about ``center`` with ``half_extents`` along its axes (m), turned by ``rpy``
        (roll, pitch, yaw, radians)."""
        return self.add(name, "box", center=center, half_extents=half_extents, rpy=rpy, velocity=velocity)

    def add_capsule(self, name: str, a: Sequence[float], b: Sequence[float], radius: float) -> "Scene":
        """The points within ``radius`` of the segment ``a``–``b`` (m)."""
        return self.add(name, "capsule", a=a, b=b, radius=radius)

    def add_cylinder(
        self, name: str, center: Sequence[float], radius: float, length: float, rpy: Optional[Sequence[float]] = None
    ) -> "Scene":
        """A solid cylinder about ``center``, ``length`` long (m) along its z axis after ``rpy``."""
        return self.add(name, "cylinder", center=center, radius=radius, length=length, rpy=rpy)

    def add_halfspace(self, name: str, point: Sequence[float], outward_normal: Sequence[float]) -> "Scene":
        """The solid ``{p : n·(p − point) ≤ 0}``; ``outward_normal`` points to the free side."""
        return self.add(name, "halfspace", point=point, outward_normal=outward_normal)

    def add_rectangle(
        self, name: str, center: Sequence[float], half_extents: Sequence[float], rpy: Optional[Sequence[float]] = None
    ) -> "Scene":
        """A planar rectangle (``half_extents`` ``[hx, hy]``, m) in its local x–y plane."""
        return self.add(name, "rectangle", center=center, half_extents=half_extents, rpy=rpy)

    def add_tool_zone(self, name: str, shape: str, **fields: Any) -> "Scene":
        """A tool-zone entry (the tool point must stay strictly inside every one)."""
        return self.add(name, shape, tool_zone=True, **fields)

    # --- reading --------------------------------------------------------------------------

    @property
    def obstacles(self) -> List[str]:
        """The obstacles' names."""
        return list(self._info["obstacles"]) if self._info else []

    @property
    def tool_zone(self) -> List[str]:
        """The tool-zone entries' names."""
        return list(self._info["tool_zone"]) if self._info else []

    def to_toml(self) -> str:
        """The scene as the text of a scene file (what the workflows are given): the file it
        was read from with the added entries appended in its units, or a file in metres and
        radians."""
        base = self._base
        if base is None:
            base = 'length_unit = "m"\nangle_unit = "rad"\n'
            length, angle = 1.0, 1.0
        elif self._added:
            info = _scene_info(base)
            if info["length_unit"] is None:
                raise ReachError("scene: entries cannot be added to a MoveIt planning scene (YAML); write them in its file")
            length = 1000.0 if info["length_unit"] == "mm" else 1.0
            angle = 180.0 / math.pi if info["angle_unit"] == "deg" else 1.0
        else:
            return base
        parts = [base.rstrip("\n") + "\n"]
        for table, shape, entry in self._added:
            lines = [f"\n[[{table}]]", f"name = {_toml_value(entry['name'])}", f'shape = "{shape}"']
            for field, value in entry.items():
                if field == "name":
                    continue
                scale = angle if field == "rpy" else length
                scaled = [v * scale for v in value] if isinstance(value, list) else value * scale
                lines.append(f"{field} = {_toml_value(scaled)}")
            parts.append("\n".join(lines) + "\n")
        return "".join(parts)

    def __repr__(self) -> str:
        def names(items: List[str]) -> str:
            return ", ".join(repr(n) for n in items) if items else "none"

        n = len(self.obstacles)
        zone = self.tool_zone
        text = f"Scene({n} obstacle{'' if n == 1 else 's'}: {names(self.obstacles)}"
        if zone:
            text += f"; tool zone: {names(zone)}"
        moving = self._info["moving"] if self._info else []
        if moving:
            text += f"; moving: {names(moving)}"
        return text + ")"

    def _repr_html_(self) -> str:
        if self.robot is not None:
            return self.robot.view(scene=self)._repr_html_()
        import html

        rows = "".join(
            f"<tr><td>{html.escape(kind)}</td><td>{html.escape(n)}</td></tr>"
            for kind, items in (("obstacle", self.obstacles), ("tool zone", self.tool_zone))
            for n in items
        )
        return (
            f"<p>{html.escape(repr(self))} — give it a robot (<code>scene.robot = robot</code>) to see it in 3-D</p>"
            f"<table><tr><th>kind</th><th>name</th></tr>{rows}</table>"
        )
