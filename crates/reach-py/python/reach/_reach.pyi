"""Type stubs of the extension module ``reach._reach`` (re-exported by ``reach``)."""

from os import PathLike
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

ArrayLike = npt.ArrayLike
Report = Dict[str, Any]

MAX_BATCH: int

class ReachError(ValueError):
    """Bad input rejected by the reach library; the message is the library's (naming the field)."""

class Robot:
    """A robot model: kinematics, IK and every workflow of the reach library."""

    @staticmethod
    def preset(name: str) -> Robot: ...
    @staticmethod
    def presets() -> List[str]: ...
    @staticmethod
    def from_file(path: Union[str, PathLike[str]], base: Optional[str] = None, tip: Optional[str] = None) -> Robot: ...
    @staticmethod
    def from_toml(text: str) -> Robot: ...
    @staticmethod
    def from_dh(
        rows: ArrayLike,
        modified: bool = False,
        degrees: bool = False,
        prismatic: Sequence[int] = ...,
        name: str = "dh",
    ) -> Robot: ...
    @property
    def name(self) -> str: ...
    @property
    def dof(self) -> int: ...
    @property
    def joint_names(self) -> List[str]: ...
    @property
    def joint_kinds(self) -> List[str]: ...
    def limits(self, degrees: bool = False) -> npt.NDArray[np.float64]: ...
    @property
    def qlim(self) -> npt.NDArray[np.float64]: ...
    def home(self, degrees: bool = False) -> npt.NDArray[np.float64]: ...
    def fk(self, q: ArrayLike, degrees: bool = False) -> npt.NDArray[np.float64]: ...
    def jacobian(self, q: ArrayLike, degrees: bool = False) -> npt.NDArray[np.float64]: ...
    def ik(
        self,
        T: ArrayLike,
        all: bool = True,
        degrees: bool = False,
        q0: Optional[ArrayLike] = None,
        solver: Optional[str] = None,
        choose: Optional[str] = None,
        criteria: Optional[Sequence[str]] = None,
        weights: Optional[Sequence[float]] = None,
        joint_weights: Optional[Sequence[float]] = None,
        restarts: Optional[int] = None,
        max_iterations: Optional[int] = None,
        time_budget_s: Optional[float] = None,
    ) -> Report: ...
    def ik_all(
        self,
        T: ArrayLike,
        solver: Optional[str] = None,
        seeds: Optional[ArrayLike] = None,
        degrees: bool = False,
        mask: str = "pose",
        restarts: Optional[int] = None,
        max_iterations: Optional[int] = None,
        time_budget_s: Optional[float] = None,
        position_tolerance_m: Optional[float] = None,
        orientation_tolerance_rad: Optional[float] = None,
    ) -> Report: ...
    def move(self, request: Optional[Mapping[str, Any]] = None, **kwargs: Any) -> Report: ...
    def track(self, request: Optional[Mapping[str, Any]] = None, **kwargs: Any) -> Report: ...
    def plan(self, request: Optional[Mapping[str, Any]] = None, **kwargs: Any) -> Report: ...
    def avoid(self, request: Optional[Mapping[str, Any]] = None, **kwargs: Any) -> Report: ...
    def cspace(self, request: Optional[Mapping[str, Any]] = None, **kwargs: Any) -> Report: ...
    def drive(self, request: Optional[Mapping[str, Any]] = None, **kwargs: Any) -> Report: ...
    def path(self, request: Optional[Mapping[str, Any]] = None, **kwargs: Any) -> Report: ...
    def check(self, request: Optional[Mapping[str, Any]] = None, **kwargs: Any) -> Report: ...
    def run(self, request: Union[str, Mapping[str, Any]]) -> Report: ...
    def __reduce__(self) -> Any: ...
