"""Type stubs of the vpmap module (compiled in vpmap._vpmap; see docs/python.md)."""

import os
from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

PathLike = Union[str, "os.PathLike[str]"]
Point = Union[Tuple[float, float], Sequence[float], npt.NDArray[Any]]
PlannerName = Literal["astar", "astar-ps", "theta-star", "mbpp", "mbpp-closer", "optimal"]
OnlinePlannerName = Literal["astar", "astar-ps", "dstar-lite", "mbpp", "astar-ties", "dstar-lite-ties"]

class VpmapError(ValueError):
    """Every error of vpmap, with the message the vpmap command prints."""

class Grid:
    """An occupancy grid: 0 free, 1 occupied, -1 (or 255) unknown; row 0 at the top."""

    def __init__(
        self,
        array: npt.ArrayLike,
        resolution: Optional[float] = None,
        origin: Tuple[float, float] = (0.0, 0.0),
    ) -> None: ...
    @staticmethod
    def load(path: PathLike, robot_radius: Optional[float] = None, resolution: float = 0.05) -> "Grid":
        """Read a ROS map .yaml, a Moving AI .map or a vpmap map.json, as `vpmap plan` does."""
    def save_ros(self, path: PathLike) -> str:
        """Write a ROS map_server map (.yaml and .pgm); returns the image's path."""
    def inflate(self, robot_radius: float) -> "Grid":
        """A copy with obstacles inflated by robot_radius (the grid's units)."""
    def world_from_cell(self, column: int, row: int) -> Tuple[float, float]: ...
    @property
    def array(self) -> npt.NDArray[np.int8]:
        """The cells, read-only int8 (height, width), kept: no copy on later reads."""
    @property
    def resolution(self) -> Optional[float]:
        """Metres a cell, or None for a grid in cells."""
    @property
    def origin(self) -> Optional[Tuple[float, float]]:
        """Lower-left corner of the lower-left cell, metres, or None for a grid in cells."""
    @property
    def shape(self) -> Tuple[int, int]: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def units(self) -> Literal["m", "cells"]: ...
    @property
    def robot_radius(self) -> float: ...
    @property
    def counts(self) -> Tuple[int, int, int]:
        """Cells (free, occupied, unknown)."""

class Map:
    """A metric floor map built from a scene (what map.json holds)."""

    @property
    def camera(self) -> Dict[str, Any]: ...
    @property
    def objects(self) -> List[Dict[str, Any]]: ...
    @property
    def floor(self) -> npt.NDArray[np.float64]:
        """The floor outline, N x 2."""
    @property
    def free_space(self) -> List[Dict[str, Any]]: ...
    @property
    def fit(self) -> Optional[Dict[str, Any]]: ...
    @property
    def units(self) -> Literal["m", "camera_heights"]: ...
    @property
    def method(self) -> Literal["fit", "sideview", "projective"]: ...
    @property
    def warnings(self) -> List[str]: ...
    def to_json(self) -> str:
        """The map as the JSON text of map.json."""
    def to_dict(self) -> Dict[str, Any]: ...
    def occupancy(
        self,
        resolution: float = 0.05,
        robot_radius: float = 0.2,
        grow_confidence: Optional[float] = None,
        hidden_free: bool = False,
    ) -> Grid:
        """The occupancy grid vpmap build writes."""

class Path:
    """A planned path."""

    found: bool
    length: Optional[float]
    expanded: int
    planner: str
    units: Literal["m", "cells"]
    time_s: float
    @property
    def waypoints(self) -> npt.NDArray[np.float64]:
        """N x 2 (x, y) in the grid's units."""
    @property
    def cells(self) -> npt.NDArray[np.int64]:
        """N x 2 (column, row)."""
    @property
    def stats(self) -> Dict[str, Union[int, float]]: ...
    @property
    def alternatives(self) -> List["Path"]: ...
    @property
    def bugs(self) -> List[Dict[str, Any]]: ...
    def __len__(self) -> int: ...

class SmoothPath:
    """A curvature-bounded path (vpmap.plan(..., planner="smooth"))."""

    found: bool
    length: Optional[float]
    units: Literal["m", "cells"]
    time_s: float
    reason: Optional[str]
    max_curvature: Optional[float]
    min_clearance: Optional[float]
    cusps: int
    @property
    def poses(self) -> npt.NDArray[np.float64]:
        """N x 3 (x, y, heading_deg) in the grid's units, at most a quarter cell apart."""
    @property
    def segments(self) -> List[Dict[str, Any]]:
        """The lines and arcs, as vpmap plan --planner smooth --json gives them."""
    @property
    def answer(self) -> Dict[str, Any]:
        """The whole answer of vpmap plan --planner smooth --json."""
    def __len__(self) -> int: ...

class Planner:
    """A planner bound to one grid, keeping its precomputation across queries."""

    def __init__(
        self,
        grid: Union[Grid, npt.ArrayLike],
        planner: PlannerName = "optimal",
        robot_radius: float = 0.0,
        *,
        unknown_passable: bool = False,
        max_expansions: Optional[int] = None,
        max_bug_steps: Optional[int] = None,
        timeout: Optional[float] = None,
    ) -> None: ...
    def plan(self, start: Point, goal: Point) -> Path: ...
    @property
    def grid(self) -> Grid: ...
    @property
    def planner(self) -> str: ...

class Detection:
    """Vanishing points and the camera found in a photo."""

    @property
    def vanishing_points(self) -> List[Dict[str, Any]]: ...
    @property
    def focal_px(self) -> float: ...
    @property
    def principal_point(self) -> Tuple[float, float]: ...
    @property
    def camera_estimate(self) -> Optional[Dict[str, Any]]:
        """focal_px, focal_sd_px, principal_point, principal_point_sd_px (None when held), pitch_deg, pitch_sd_deg, roll_deg, roll_sd_deg, horizon_sd_px."""
    @property
    def lens(self) -> Optional[Dict[str, Any]]:
        """k (division model, barrel negative), k_sd, segments_k_sd; None with lens="none"."""
    @property
    def focal_estimated(self) -> bool: ...
    @property
    def principal_point_off_centre(self) -> bool: ...
    @property
    def pitch_deg(self) -> float: ...
    @property
    def roll_deg(self) -> float: ...
    @property
    def perspective(self) -> Literal["two-point", "three-point"]: ...
    @property
    def image_size(self) -> Tuple[int, int]: ...
    @property
    def segments(self) -> npt.NDArray[np.float64]:
        """N x 5: x0, y0, x1, y1, strength."""
    @property
    def warnings(self) -> List[str]: ...
    def scene(self) -> Dict[str, Any]:
        """The scene dict vpmap detect writes."""
    def scene_json(self) -> str: ...

def build(
    scene: Union[Dict[str, Any], str, "os.PathLike[str]"],
    *,
    method: Literal["fit", "sideview", "projective"] = "fit",
    click_sigma: Optional[float] = None,
) -> Map:
    """Build a scene (dict, JSON text or file path) into a metric floor map, as vpmap build."""

def plan(
    grid: Union[Grid, npt.ArrayLike],
    start: Point,
    goal: Point,
    planner: Union[PlannerName, Literal["smooth"]] = "mbpp",
    robot_radius: float = 0.0,
    *,
    unknown_passable: bool = False,
    tracks: bool = False,
    max_expansions: Optional[int] = None,
    max_bug_steps: Optional[int] = None,
    timeout: Optional[float] = None,
    turning_radius: Optional[float] = None,
    start_heading: Optional[float] = None,
    goal_heading: Optional[float] = None,
    reverse: bool = False,
) -> Union[Path, SmoothPath]:
    """A path from start to goal, as vpmap plan; cells (column, row) or metres."""

def detect(
    image: Union[PathLike, npt.NDArray[np.uint8]],
    *,
    focal_px: Optional[float] = None,
    principal_point: Optional[Tuple[float, float]] = None,
    max_side: Optional[int] = None,
    two_point_tolerance: Optional[float] = None,
    lens: Union[Literal["estimate", "none"], float, None] = None,
) -> Detection:
    """Vanishing points and camera of a photo (path or uint8 array), as vpmap detect."""

def navigate(
    believed: Union[Grid, PathLike, None],
    truth: Union[Grid, PathLike],
    start: Point,
    goal: Point,
    *,
    planner: Union[OnlinePlannerName, Literal["smooth"]] = "dstar-lite",
    sensor_range: Optional[float] = None,
    unknown_blocked: bool = False,
    robot_radius: Optional[float] = None,
    resolution: float = 0.05,
    max_moves: int = 10_000_000,
    max_replans: int = 1_000_000,
    max_expansions: Optional[int] = None,
    timeout: Optional[float] = None,
    svg: bool = False,
    turning_radius: Optional[float] = None,
    start_heading: Optional[float] = None,
    goal_heading: Optional[float] = None,
    reverse: bool = False,
) -> Dict[str, Any]:
    """Drive a robot across a believed map sensing the true one, as vpmap navigate; with
    svg=True the dict's "svg" holds the picture vpmap navigate writes as navigate.svg.
    planner="smooth" (with turning_radius; headings and reverse as vpmap.plan's) drives
    curvature-bounded curves as vpmap navigate --planner smooth; its dict's "poses" are an
    (N, 3) float64 array of (x, y, heading_deg)."""
