"""vpmap: single-view metrology from vanishing points -> metric floor map -> occupancy grid -> paths.

photo -> ``detect`` -> scene dict -> ``build`` -> ``Map`` -> ``Map.occupancy`` -> ``Grid``
-> ``plan`` / ``Planner`` -> ``Path``; ``navigate`` drives a robot across a believed map.
Every error raises ``VpmapError`` (a ``ValueError``) with the message the ``vpmap`` command
prints. The compiled module is ``vpmap._vpmap``; this file only re-exports it. See
docs/python.md in the repository.
"""

from ._vpmap import (
    Detection,
    Grid,
    Map,
    Path,
    Planner,
    SmoothPath,
    VpmapError,
    __version__,
    build,
    detect,
    navigate,
    plan,
)

__all__ = [
    "Detection",
    "Grid",
    "Map",
    "Path",
    "Planner",
    "SmoothPath",
    "VpmapError",
    "__version__",
    "build",
    "detect",
    "navigate",
    "plan",
]
