from ._reach import MAX_BATCH as MAX_BATCH
from ._reach import ReachError as ReachError
from ._reach import Robot as Robot

__all__ = ["MAX_BATCH", "ReachError", "Robot"]
