from ._reach import MAX_BATCH as MAX_BATCH
from ._reach import ReachError as ReachError
from ._reach import Robot as Robot
from ._results import Motion as Motion
from ._results import View as View
from .scene import Scene as Scene

__all__ = ["MAX_BATCH", "Motion", "ReachError", "Robot", "Scene", "View"]
