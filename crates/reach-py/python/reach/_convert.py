"""Conversions between the library's JSON and Python: requests from keyword arguments (numpy
values allowed), reports with their numeric lists as numpy arrays."""

from __future__ import annotations

import json
import os
from numbers import Number
from typing import Any, Mapping, Optional

import numpy as np


def _is_number(x: Any) -> bool:
    return isinstance(x, Number) and not isinstance(x, bool)


def arrays(value: Any) -> Any:
    """``value`` (parsed JSON) with every non-empty list of numbers, and every non-empty list of
    equally long lists of numbers, turned into a numpy array (int64 when all are whole, else
    float64). Everything else is kept as it is."""
    if isinstance(value, dict):
        return {k: arrays(v) for k, v in value.items()}
    if isinstance(value, list):
        if value and all(_is_number(x) for x in value):
            return np.asarray(value)
        if (
            value
            and all(isinstance(x, list) and x and all(_is_number(y) for y in x) for x in value)
            and len({len(x) for x in value}) == 1
        ):
            return np.asarray(value)
        return [arrays(x) for x in value]
    return value


def _default(x: Any) -> Any:
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(f"cannot put a {type(x).__name__} into a request")


def scene_text(scene: Any) -> str:
    """The text of a scene file from what a workflow's ``scene=`` takes: a ``reach.Scene``, a
    path (``os.PathLike``, or a one-line string naming an existing file) or the text itself."""
    from .scene import Scene

    if isinstance(scene, Scene):
        return scene.to_toml()
    if isinstance(scene, (str, os.PathLike)):
        text = os.fspath(scene)
        looks_like_text = "\n" in text or "=" in text
        if isinstance(scene, os.PathLike) or (not looks_like_text and os.path.isfile(text)):
            return Scene.from_file(scene).to_toml()
        if not looks_like_text and ": " not in text:
            raise ValueError(f"scene: no such scene file `{text}` (give a reach.Scene, a path or a scene file's text)")
        return text
    raise ValueError(f"scene: expected a reach.Scene, a path or a scene file's text, got a {type(scene).__name__}")


def request_json(request: Mapping[str, Any]) -> str:
    """A request dict (numpy arrays allowed) as JSON text; its ``scene`` may be any form
    ``scene_text`` takes."""
    request = dict(request)
    if request.get("scene") is not None:
        request["scene"] = scene_text(request["scene"])
    try:
        return json.dumps(request, default=_default, allow_nan=False)
    except ValueError as e:  # NaN or infinity
        raise ValueError(f"request: expected finite numbers ({e})") from None


def workflow(kind: str, request: Optional[Mapping[str, Any]], kwargs: Mapping[str, Any]) -> str:
    """The JSON of a ``kind`` request from a dict and/or keyword arguments (keywords win)."""
    merged: dict = dict(request or {})
    merged.update(kwargs)
    if "kind" in merged and merged["kind"] != kind:
        raise ValueError(f"request: kind `{merged['kind']}` given to the `{kind}` workflow")
    merged["kind"] = kind
    return request_json(merged)
