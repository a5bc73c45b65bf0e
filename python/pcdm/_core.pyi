# Type stubs of pcdm._core, the C extension (python/pcdm/_core.c); pcdm/__init__.py is the API.
from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np

DEFAULT_MIN_ANGLE: float
ANGLE_LIMIT: float
def version() -> str: ...
def parse(switches: str) -> Dict[str, Any]: ...
def triangulate(
    vertices: np.ndarray,
    vertex_markers: Optional[np.ndarray],
    vertex_attributes: Optional[np.ndarray],
    segments: Optional[np.ndarray],
    segment_markers: Optional[np.ndarray],
    holes: Optional[np.ndarray],
    regions: Optional[np.ndarray],
    min_angle: float,
    max_area: float,
    max_steiner: int,
    circumcenters: bool,
    convex_hull: bool,
    region_attributes: bool,
    region_areas: bool,
    no_refine: bool,
    lenses: bool,
    size: Optional[Callable[[np.ndarray, float], bool]],
    refine_areas: Optional[Tuple[np.ndarray, np.ndarray, np.ndarray]],
    edges: bool,
    neighbors: bool,
    background: Optional[Tuple[np.ndarray, np.ndarray, np.ndarray, bool]],
    threads: int = ...,
) -> Tuple[int, str, Optional[Dict[str, np.ndarray]]]: ...
def check(
    vertices: np.ndarray,
    vertex_markers: Optional[np.ndarray],
    segments: Optional[np.ndarray],
    segment_markers: Optional[np.ndarray],
    holes: Optional[np.ndarray],
    regions: Optional[np.ndarray],
    mesh_vertices: np.ndarray,
    mesh_triangles: np.ndarray,
    mesh_segments: Optional[np.ndarray],
    mesh_segment_markers: Optional[np.ndarray],
    triangle_attributes: Optional[np.ndarray],
    min_angle: float,
    max_area: float,
    convex_hull: bool,
    region_attributes: bool,
    region_areas: bool,
) -> Dict[str, Any]: ...
def boundary(vertices: np.ndarray, triangles: np.ndarray) -> Tuple[np.ndarray, np.ndarray]: ...
def main(argv: List[str]) -> int: ...
