"""vdtnav: robot localization on Vector Distance Transform maps, from Python.

Type stubs of the package vdtnav: everything it re-exports from the compiled core
vdtnav._vdtnav (python/src/*.cpp), and the core's submodule _timing. Poses are (x, y, phi) in
2D and 4 x 4 matrices in 3D; covariances those of the C++ API (2D: (x, y, phi); 3D: the left
perturbation (dt, dtheta) in the world frame). Errors raise vdtnav.Error subclasses with the C++
messages; bad array arguments raise ValueError. Solves and lookups release the GIL.

python/tests/test_stubs.py checks these stubs against the built module (names, members,
parameter names, writable attributes).
"""

import os
import types
from collections.abc import Sequence
from typing import Any, Literal, TypeAlias, TypedDict, overload

import numpy as np
import numpy.typing as npt

__version__: str

_F64: TypeAlias = npt.NDArray[np.float64]
# What path arguments take (std::filesystem::path): a str or an os.PathLike (pathlib.Path).
_Path: TypeAlias = str | os.PathLike[str]
# N x D points read in place (no copy): float32 or float64, any layout (C, Fortran, strided).
_Points: TypeAlias = npt.NDArray[np.float32] | npt.NDArray[np.float64]
# Occupancy arrays: bool or uint8, nonzero = occupied.
_Occupancy: TypeAlias = npt.NDArray[np.bool_] | npt.NDArray[np.uint8]
# What `settings` arguments take: None (the defaults of the call), a Settings, a dict with the
# settings file's sections and keys, or the path of a YAML settings file.
_SettingsLike: TypeAlias = Settings | dict[str, Any] | str | os.PathLike[str] | None
_Status: TypeAlias = Literal[
    "converged", "not_converged", "too_few_observations", "diverged", "refused", "lost",
    "bridged",
]

class _Frame(TypedDict):
    """A map's frame (Map2.frame, Map3.frame)."""

    resolution: float
    origin: _F64
    yaw: float
    size: list[int]

# ---------------------------------------------------------------------------------------------
# Exceptions

class Error(RuntimeError):
    """vdtnav's errors (a RuntimeError); the message is the C++ one."""

class IoError(Error):
    """A file that cannot be read or written."""

class FormatError(Error):
    """A malformed file: `file:line: what was expected`."""

class ConfigError(Error):
    """An option out of its domain (an unknown method, key or value: the message names it)."""

# ---------------------------------------------------------------------------------------------
# Maps

class Lookup:
    """The result of Map2.lookup / Map3.lookup (see lookup's doc). value, jacobian, inside and
    hessian are filled by the lookup; distance and gradient are computed from them when first
    read (then kept). All read-only."""

    @property
    def points(self) -> _Points:
        """The array read (the very object passed in: no copy was made)."""
    @property
    def value(self) -> _F64:
        """N x D: DT_v(p) = p - c(p), metres (thesis eq. 2.5-2.8)."""
    @property
    def distance(self) -> _F64:
        """N: |DT_v|, metres (computed on first read)."""
    @property
    def gradient(self) -> _F64 | None:
        """N x D: the gradient of |DT_v| = J^T DT_v / |DT_v| (thesis eq. 2.8: J ~ I off the
        medial axis; 0 where |DT_v| = 0), computed on first read; None when looked up with
        jacobian=False."""
    @property
    def jacobian(self) -> _F64 | None:
        """N x D x D: dDT_v/dp, [k, c] the gradient of component c at point k; None when looked
        up with jacobian=False."""
    @property
    def inside(self) -> npt.NDArray[np.bool_]:
        """N: False where the point lies outside the map (its values are the clamped point's)."""
    @property
    def hessian(self) -> _F64 | None:
        """N x D x D x D, [k, c] the Hessian of component c of DT_v at point k; None unless
        hessian=True."""

class Map2:
    """A 2D map: its occupancy grid, its exact VDT (thesis Ch. 2) and, for maps drawn from
    scans, the unknown cells (lost detection does not hold scans into them against the map)."""

    def __init__(
        self,
        occupancy: _Occupancy,
        resolution: float,
        origin: npt.ArrayLike | None = None,
        yaw: float = 0.0,
    ) -> None:
        """A map from an occupancy array of shape (ny, nx), bool or uint8 (nonzero: occupied);
        cell [j, i] is the square of side `resolution` whose lower-left corner is
        origin + R(yaw) (i, j) resolution. Every cell is known (a floor plan)."""
    @staticmethod
    def from_ros_cells(
        cells: npt.ArrayLike,
        resolution: float,
        origin: npt.ArrayLike | None = None,
        yaw: float = 0.0,
    ) -> Map2:
        """A map from ROS occupancy values (int8, shape (ny, nx): -1 unknown, 0..100 the
        occupancy probability in percent, occupied from 65 as map_server's trinary mode)."""
    def lookup(self, points: _Points, jacobian: bool = True, hessian: bool = False) -> Lookup:
        """The VDT at each point (thesis eq. 2.5-2.8: DT_v(p) = p - c(p), c the nearest occupied
        point, interpolated by the cubic B-spline of eq. 2.9).

        points: an N x 2 array of float32 or float64 in the map's world frame, any layout (C or
        Fortran order, strided slices): read in place, not copied (no lists: ValueError /
        TypeError). jacobian: also dDT_v/dp and the gradient of the distance (about twice the
        work; else Lookup.jacobian and Lookup.gradient are None). hessian: also the Hessians of
        DT_v's components (one call per point: slower). Returns a Lookup. The GIL is released
        during the lookup."""
    @property
    def occupancy(self) -> npt.NDArray[np.uint8]:
        """The occupancy grid, uint8 (ny, nx), 1 = occupied."""
    @property
    def cells(self) -> npt.NDArray[np.int8] | None:
        """The ROS cell values (int8, -1 unknown) or None (every cell known)."""
    @property
    def frame(self) -> _Frame:
        """resolution, origin (lower-left corner), yaw and size (nx, ny)."""
    @property
    def resolution(self) -> float:
        """The cell edge, metres."""
    @property
    def memory_bytes(self) -> int:
        """The VDT map's memory, bytes."""
    @property
    def source(self) -> str:
        """Where the map came from (occupancy array, ros map PATH, vdt map file PATH, ...)."""
    def save_ros(self, prefix: _Path) -> None:
        """Writes PREFIX.yaml and PREFIX.pgm (map_server's format)."""
    def save_vdt(self, path: _Path) -> None:
        """Writes the VDT map (.vdt, `vdtnav map`'s format)."""

class Map3:
    """A 3D VDT map, dense (VdtMap3) or sparse (SparseVdtMap3: bricks near surfaces)."""

    def __init__(
        self,
        occupancy: _Occupancy,
        resolution: float,
        origin: npt.ArrayLike | None = None,
        sparse: bool = False,
    ) -> None:
        """A map from an occupancy array of shape (nz, ny, nx), bool or uint8; voxel [k, j, i]
        has its lowest corner at origin + (i, j, k) resolution."""
    def lookup(self, points: _Points, jacobian: bool = True, hessian: bool = False) -> Lookup:
        """The VDT at each point (thesis eq. 2.5-2.8, the cubic B-spline of eq. 2.9): points
        N x 3, float32 or float64, read in place; see Map2.lookup. Returns a Lookup."""
    @property
    def sparse(self) -> bool:
        """True for a SparseVdtMap3."""
    @property
    def frame(self) -> _Frame:
        """resolution, origin (lowest corner), yaw and size (nx, ny, nz)."""
    @property
    def resolution(self) -> float:
        """The voxel edge, metres."""
    @property
    def memory_bytes(self) -> int:
        """The VDT map's memory, bytes."""
    @property
    def source(self) -> str:
        """Where the map came from."""

def set_threads(n: int) -> None:
    """Threads of the work that runs in parallel (map building, global search, 3D multi-start),
    process-wide; 0: the machine's cores (the default). Results are the same for any count."""

def threads() -> int:
    """The threads of the work that runs in parallel (set_threads())."""

def load_map(
    path: _Path,
    resolution: float = 0.0,
    sparse: bool = False,
    margin: float = 1.0,
    crop: npt.ArrayLike | None = None,
) -> Map2 | Map3:
    """Loads any map file the CLI loads (vdtnav::load_map): a ROS map YAML (.yaml: a Map2 with
    its unknown cells), an uncertain map file (.umap) or a 2D .vdt (Map2); a 3D .vdt, .svdt, OctoMap (.bt, .ot) or point cloud (.pcd, .ply, .vtk,
    .xyz/.txt/.csv) as a Map3 (builds with the 3D front ends; else ConfigError). resolution: the
    voxel edge for clouds (0: 0.1 m) and octrees (0: their leaf size); sparse: build a
    SparseVdtMap3; margin: free border around a cloud or octree, metres; crop: (xmin, ymin, zmin,
    xmax, ymax, zmax), metres: only the cloud points inside this box are kept (`vdtnav
    localize3d --crop`; point clouds only, else ConfigError; None: all). Raises IoError /
    FormatError (file, line, what was expected)."""

def build_occupancy_map(
    poses: npt.NDArray[Any], scans: Sequence[LaserScan], resolution: float = 0.05
) -> Map2:
    """A map drawn from scans at known poses (`vdtnav map`): log-odds ray casting (OctoMap's
    hit/miss probabilities), poses an N x 3 numpy array (x, y, phi) and any sequence of N
    LaserScans (a list, a tuple, CarmenLog.scans); unknown cells kept."""

# ---------------------------------------------------------------------------------------------
# 2D localization

class Settings:
    """Every localizer setting (docs/settings.md; `vdtnav localize --print-config`). Read from
    YAML or a dict with the settings file's sections and keys: unknown keys, wrong types and
    non-finite numbers raise ConfigError naming the key."""

    def __init__(self) -> None:
        """The defaults (`vdtnav localize`'s, the C++ constructors', the ROS node's): real logs on maps drawn from scans."""
    @staticmethod
    def log() -> Settings:
        """The defaults, by name: the same as Settings()."""
    @staticmethod
    def exact_map() -> Settings:
        """The thesis's localizers on an exact map (generated floor plans): no robust loss, 25 iterations, no map-error correlation, the velocity motion model."""
    @staticmethod
    def cloud() -> Settings:
        """`vdtnav localize3d`'s defaults: real 3D clouds."""
    @staticmethod
    def load(path: _Path, base: _SettingsLike = None) -> Settings:
        """A YAML settings file read over `base` (default Settings.log())."""
    @staticmethod
    def from_yaml(text: str, base: _SettingsLike = None) -> Settings:
        """YAML settings text read over `base` (default Settings.log())."""
    def updated(self, keys: dict[str, Any]) -> Settings:
        """These settings with the keys of a dict ({'vdt-opt': {'loss': 'huber'}})."""
    def yaml(self, method: str = "") -> str:
        """The settings as a documented YAML file (all sections, or one method's)."""

class LocalizationResult:
    """The result of a 2D localization step."""

    @property
    def pose(self) -> _F64:
        """(x, y, phi): metres, radians."""
    @property
    def covariance(self) -> _F64:
        """3 x 3 covariance of (x, y, phi)."""
    @property
    def status(self) -> _Status:
        """converged, not_converged, too_few_observations, diverged, refused, lost or bridged."""
    @property
    def converged(self) -> bool:
        """status == 'converged'."""
    @property
    def published(self) -> bool:
        """Whether the CLI's default TUM file and the ROS node hold this pose (converged or
        bridged)."""
    @property
    def has_covariance(self) -> bool:
        """False for estimators that report none."""
    @property
    def iterations(self) -> int:
        """Solver iterations of the whole update."""
    @property
    def explained(self) -> float:
        """Fraction of the observations the map explains at the pose (< 0: not measured)."""
    @property
    def inliers(self) -> int:
        """Beams used after gating."""
    @property
    def dropped(self) -> int:
        """Beams dropped: invalid readings, outside the map, gated."""
    @property
    def final_cost(self) -> float:
        """The solver's final cost."""
    @property
    def work(self) -> dict[str, int]:
        """What the update ran besides one solve: solves, coarse_to_fine, window_searches,
        bridged, global_searches, search_boxes, candidates (localizer.hpp's Work)."""

class LocalizationResult3:
    """The result of a 3D localization step."""

    @property
    def pose(self) -> _F64:
        """4 x 4 homogeneous pose."""
    @property
    def covariance(self) -> _F64:
        """6 x 6 covariance of the left perturbation (dt, dtheta) in the world frame; NaN rows
        for held components."""
    @property
    def status(self) -> _Status:
        """converged, not_converged, too_few_observations, diverged, refused, lost or bridged."""
    @property
    def converged(self) -> bool:
        """status == 'converged'."""
    @property
    def published(self) -> bool:
        """Whether the CLI's default TUM file and the ROS node hold this pose (converged or
        bridged)."""
    @property
    def has_covariance(self) -> bool:
        """False for estimators that report none."""
    @property
    def iterations(self) -> int:
        """Solver iterations of the whole update."""
    @property
    def explained(self) -> float:
        """Fraction of the observations the map explains at the pose (< 0: not measured)."""
    @property
    def inliers(self) -> int:
        """Readings used after gating."""
    @property
    def dropped(self) -> int:
        """Readings dropped: invalid, outside the map, gated."""
    @property
    def final_cost(self) -> float:
        """The solver's final cost."""
    @property
    def work(self) -> dict[str, int]:
        """What the update ran besides one solve: solves, coarse_to_fine, window_searches,
        bridged, global_searches, search_boxes, candidates (localizer.hpp's Work)."""

class LaserScan:
    """One planar scan (sensor_msgs/LaserScan semantics)."""

    time: float
    """Seconds."""
    angle_min: float
    """Radians, the angle of beam 0 in the sensor frame."""
    angle_increment: float
    """Radians between beams."""
    range_min: float
    """Metres; readings < range_min are dropped."""
    range_max: float
    """Metres; readings >= range_max are dropped (no return)."""
    sigma_range: float
    """Range noise standard deviation, metres."""
    def __init__(
        self,
        ranges: npt.ArrayLike,
        angles: npt.ArrayLike | None = None,
        angle_min: float = 0.0,
        angle_increment: float = 0.0,
        range_min: float = 0.1,
        range_max: float = 30.0,
        sigma_range: float = 0.02,
        mount: npt.ArrayLike | None = None,
        time: float = 0.0,
    ) -> None:
        """ranges (metres; NaN, inf and readings outside [range_min, range_max) are dropped),
        explicit angles or angle_min + i angle_increment (radians), the range noise sigma_range
        (metres), the sensor's mount (x, y, phi) in the robot frame."""
    @property
    def ranges(self) -> _F64:
        """The ranges, metres (a copy)."""
    @ranges.setter
    def ranges(self, value: npt.ArrayLike) -> None: ...
    @property
    def angles(self) -> _F64:
        """Every beam's angle (explicit or from angle_min and angle_increment)."""
    @angles.setter
    def angles(self, value: npt.ArrayLike) -> None: ...
    @property
    def mount(self) -> _F64:
        """The sensor's pose (x, y, phi) in the robot frame."""
    @mount.setter
    def mount(self, value: npt.ArrayLike) -> None: ...
    def points(self) -> _F64:
        """The valid beams' endpoints in the robot frame (N x 2), as the localizers use them."""

class OdometryStep:
    """What odometry reports between two scans."""

    dt: float
    """Seconds since the previous scan."""
    v: float
    """Measured linear velocity, m/s (velocity model)."""
    w: float
    """Measured angular velocity, rad/s."""
    def __init__(self, delta: npt.ArrayLike, dt: float = 0.0) -> None:
        """The increment (dx, dy, dphi) in the previous robot frame over dt seconds; v and w are
        its arc length and turn over dt (as odometry_steps makes them; 0 when dt is 0)."""
    @property
    def delta(self) -> _F64:
        """The measured increment (dx, dy, dphi) in the previous robot frame."""
    @delta.setter
    def delta(self, value: npt.ArrayLike) -> None: ...

def odometry_steps(times: npt.ArrayLike, poses: npt.ArrayLike) -> list[OdometryStep]:
    """The steps between consecutive odometry poses (N x 3) at `times`: step k from pose k-1 to
    pose k (step 0 zero)."""

def localizer_methods() -> list[str]:
    """The methods make_localizer knows."""

class Localizer2D:
    """A 2D localizer (make_localizer): predict with odometry, correct with a scan, one step at
    a time."""

    def reset(self, pose: npt.ArrayLike, covariance: npt.ArrayLike) -> None:
        """Starts (again) at pose (x, y, phi) with covariance (3 x 3)."""
    def update(
        self,
        odometry: OdometryStep | npt.ArrayLike,
        scan: LaserScan | None = None,
        *,
        ranges: npt.ArrayLike | None = None,
        angles: npt.ArrayLike | None = None,
        angle_min: float | None = None,
        angle_increment: float | None = None,
        range_min: float = 0.1,
        range_max: float = 30.0,
        sigma_range: float = 0.02,
        dt: float = 0.0,
    ) -> LocalizationResult:
        """Predicts with the odometry (an OdometryStep, or an increment (dx, dy, dphi) over dt
        seconds), then corrects with a LaserScan or ranges with angles (or angle_min and
        angle_increment). Returns a LocalizationResult; the GIL is released meanwhile."""
    @property
    def name(self) -> str:
        """The localizer's name."""
    @property
    def recoveries(self) -> int | None:
        """Re-acquisitions after being lost (None: no lost detection around this method)."""
    @property
    def map(self) -> Map2:
        """The map the localizer holds on to."""

def make_localizer(
    method: str, map: Map2, settings: _SettingsLike = None, knowledge: bool = True
) -> Localizer2D:
    """A 2D localizer by name (localizer_methods(): vdt-opt, vdt-ekf, udt-opt, udt-ekf, pf,
    active-ekf, passive-ekf). settings: a Settings, a dict or a YAML file over Settings.log()
    (`vdtnav localize`'s defaults; None: those). vdt-opt and vdt-ekf come with lost detection and
    recovery unless settings['recovery']['detect'] is false. knowledge: hold scans into the map's
    unknown cells not against it. Raises ConfigError for an unknown method; map=None is refused
    (TypeError)."""

class GlobalLocalizationResult:
    """The result of global_localize."""

    @property
    def result(self) -> LocalizationResult:
        """The refined pose: converged when accepted, refused when the scan is unexplained or the
        pose ambiguous (too_few_observations for a scan without readings)."""
    @property
    def ambiguous(self) -> bool:
        """True when other distinct poses explain the scan as well."""
    @property
    def alternatives(self) -> _F64:
        """K x 3: distinct refined poses that explain the scan as well."""
    @property
    def explained(self) -> float:
        """Fraction of the scan the best pose explains."""
    @property
    def nodes(self) -> int:
        """Boxes scored (branch and bound) or poses (sampling)."""
    @property
    def seconds(self) -> float:
        """Wall time of the search and the refinement."""

def global_localize(
    map: Map2, scan: LaserScan, settings: _SettingsLike = None
) -> GlobalLocalizationResult:
    """Global localization from no prior (branch and bound on the VDT's min-pooled pyramid, then
    vdt-opt's refinement; `vdtnav localize --init global`): refused when the scan is unexplained
    or ambiguous (alternatives). settings over Settings.log(). map=None is refused (TypeError)."""

# ---------------------------------------------------------------------------------------------
# 3D localization (builds with the 3D front ends: pcl and octomap)

class OdometryStep3:
    """What odometry and an IMU report between scans."""

    dt: float
    """Seconds since the previous scan."""
    roll: float
    """The IMU's roll of the robot at this scan, radians (NaN: no IMU)."""
    pitch: float
    """The IMU's pitch of the robot at this scan, radians (NaN: no IMU)."""
    def __init__(
        self, delta: npt.ArrayLike, dt: float = 0.0, roll: float = ..., pitch: float = ...
    ) -> None:
        """The increment (4 x 4) in the previous robot frame over dt seconds, and the IMU's roll
        and pitch at this scan (radians; default NaN: no IMU)."""
    @property
    def delta(self) -> _F64:
        """The measured increment (4 x 4) in the previous robot frame."""
    @delta.setter
    def delta(self, value: npt.ArrayLike) -> None: ...

def localize3d(
    map: Map3,
    cloud: _Points,
    init: npt.ArrayLike,
    dof: int = 6,
    settings: _SettingsLike = None,
    sigma_range: float = 0.03,
    voxel: float = -1.0,
    range_min: float = 0.0,
    range_max: float = ...,
    sensor_in_robot: npt.ArrayLike | None = None,
) -> LocalizationResult3:
    """Localizes one cloud from the guess `init` (4 x 4), as `vdtnav localize3d` does a single
    scan: Algorithm 1 in SE(3) (dof 6) or with roll and pitch held (dof 4), refused when the
    solution explains less than accept_fraction. settings: over Settings.cloud() (section
    localize3d). Returns a LocalizationResult3 (4 x 4 pose, 6 x 6 covariance, status, explained).
    cloud: N x 3 (float32 or float64) in the sensor's frame; sigma_range: range noise, metres
    (default VLP-16's 0.03); voxel: thinning cube, metres (< 0: the map's resolution, as the CLI;
    0: every reading); range_min / range_max (default inf): readings kept; sensor_in_robot: 4 x 4
    pose of the sensor in the robot frame. NaN and inf points are dropped. map=None is refused
    (TypeError)."""

class GlobalLocalization3:
    """What a 3D global localization found (global_localize3d)."""

    @property
    def result(self) -> LocalizationResult3:
        """The refined best pose (LocalizationResult3): status converged when accepted, refused
        when unexplained or ambiguous."""
    @property
    def ambiguous(self) -> bool:
        """A distinct pose explains the cloud as well: refused, not guessed."""
    @property
    def alternatives(self) -> list[_F64]:
        """The distinct refined poses (4 x 4) that explain the cloud as well."""
    @property
    def explained(self) -> float:
        """Fraction of the readings the best pose explains."""
    @property
    def nodes(self) -> int:
        """Cubes scored."""
    @property
    def seconds(self) -> float:
        """Wall time of the search and the refinement."""

def global_localize3d(
    map: Map3,
    cloud: _Points,
    roll: float = 0.0,
    pitch: float = 0.0,
    settings: _SettingsLike = None,
    sigma_range: float = 0.03,
    voxel: float = -1.0,
    range_min: float = 0.0,
    range_max: float = ...,
    sensor_in_robot: npt.ArrayLike | None = None,
) -> GlobalLocalization3:
    """Localizes one cloud with no prior, as `vdtnav localize3d --init global` does its first
    scans: branch and bound over x, y, z, yaw with roll and pitch given (radians, from gravity;
    0: level), refined in 6 DOF (global_localization3d.hpp; settings: section localize3d.global).
    The search grid is built on each call (~0.6 s on the CATEC map). Returns a
    GlobalLocalization3. cloud, sigma_range, voxel, range_min / range_max, sensor_in_robot: as
    localize3d's. map=None is refused (TypeError)."""

class Localizer3D:
    """The sequential 3D localizer with lost detection and recovery (`vdtnav localize3d
    --scans`): make_localizer3d."""

    def reset(self, pose: npt.ArrayLike, covariance: npt.ArrayLike) -> None:
        """Starts (again) at pose (4 x 4) with covariance (6 x 6)."""
    def update(self, odometry: OdometryStep3 | npt.ArrayLike, cloud: _Points) -> LocalizationResult3:
        """Predicts with the odometry (an OdometryStep3 or a 4 x 4 increment), corrects with the
        cloud. Returns a LocalizationResult3 (status lost while lost)."""
    @property
    def name(self) -> str:
        """The localizer's name."""
    @property
    def recoveries(self) -> int:
        """Re-acquisitions after being lost."""

def make_localizer3d(
    map: Map3,
    dof: int = 6,
    settings: _SettingsLike = None,
    sigma_range: float = 0.03,
    voxel: float = -1.0,
    range_min: float = 0.0,
    range_max: float = ...,
    sensor_in_robot: npt.ArrayLike | None = None,
) -> Localizer3D:
    """The sequential 3D localizer (vdt_localizer3d.hpp) with lost detection and recovery, on
    `map`; reset() it at a pose first. cloud arguments as localize3d: sigma_range: range noise,
    metres (default VLP-16's 0.03); voxel: thinning cube, metres (< 0: the map's resolution;
    0: every reading); range_min / range_max (default inf): readings kept; sensor_in_robot:
    4 x 4 pose of the sensor in the robot frame. map=None is refused (TypeError)."""

# ---------------------------------------------------------------------------------------------
# Readers

class CarmenLog:
    """A CARMEN log's laser messages (FLASER, ROBOTLASER1) and ODOM lines."""

    def __len__(self) -> int:
        """The number of laser messages (scans)."""
    @property
    def times(self) -> _F64:
        """Each scan's time, seconds."""
    @property
    def poses(self) -> _F64:
        """N x 3: each scan's laser pose (x, y, theta): corrected poses in corrected logs,
        odometry in raw."""
    @property
    def odom(self) -> _F64:
        """N x 3: each scan's odometry pose (x, y, theta)."""
    def scan(self, i: int) -> LaserScan:
        """Scan i as a LaserScan (a copy; negative i counts from the end); IndexError out of
        range."""
    @property
    def scans(self) -> list[LaserScan]:
        """Every scan (copies)."""
    @property
    def ranges(self) -> _F64 | None:
        """The ranges, scans x beams (None when scans differ in beam count)."""
    @property
    def lines(self) -> list[int]:
        """Each scan's 1-based line in the file."""
    @property
    def params(self) -> dict[str, str]:
        """PARAM name -> value (the last one wins)."""

def read_carmen_log(
    path: _Path, max_range: float = 80.0, range_min: float = 0.1, skip_malformed: bool = False
) -> CarmenLog:
    """Reads a CARMEN log (plain or gzip). max_range: the no-return threshold (metres); raises
    FormatError `file:line: what was expected` for a malformed line."""

def join_odometry_table(log: CarmenLog, table_path: _Path) -> tuple[CarmenLog, CarmenLog]:
    """Joins a corrected log with a raw-odometry table (`vdtnav join-odometry`): (raw, corrected)
    logs on the table's absolute time base."""

def log_odometry(log: CarmenLog, scans: Sequence[int] | npt.NDArray[np.integer[Any]]) -> _F64:
    """The odometry pose at each scan of `scans` (ODOM lines interpolated, else the scans' odom
    fields), N x 3."""

def read_relations(path: _Path) -> _F64:
    """Reads a relation file (Kümmerle et al. 2009): N x 5 rows (t1, t2, x, y, yaw), the pose at
    t2 in the frame of the pose at t1."""

def read_tum(path: _Path) -> _F64:
    """Reads a TUM trajectory: N x 8 rows (t, x, y, z, qx, qy, qz, qw)."""

def write_tum(path: _Path, times: npt.ArrayLike, poses: npt.ArrayLike) -> None:
    """Writes a TUM trajectory (t, x, y, z, qx, qy, qz, qw rows) of planar poses (N x 3: x, y,
    phi) or 4 x 4 poses (N x 4 x 4); `vdtnav eval --traj` reads it."""

def read_point_cloud(path: _Path) -> _F64:
    """Reads a point cloud (.pcd, .ply, .vtk, text/CSV with x, y, z columns) as N x 3 float64
    (NaN points kept: the localizers drop them). Builds with the 3D front ends."""

# ---------------------------------------------------------------------------------------------
# Bags (builds with the ROS front end)

class _BagTopic(TypedDict):
    """A topic of a bag (bag_topics)."""

    name: str
    type: str
    count: int
    first: float
    last: float

class _BagScans(TypedDict):
    """A 2D LiDAR run from a bag (read_bag_scans)."""

    scans: list[LaserScan]
    times: _F64
    odometry: _F64
    scan_topic: str
    odometry_source: str
    mount_source: str
    skipped_no_odometry: int

class _BagCloud(TypedDict):
    """One PointCloud2 message of a bag (read_bag_clouds)."""

    stamp: float
    frame: str
    points: _F64
    times: _F64 | None
    mount: _F64
    odometry: _F64 | None
    roll: float
    pitch: float

def bag_topics(path: _Path) -> list[_BagTopic]:
    """The topics of a ROS 1 bag (.bag) or ROS 2 bag (folder): name, type, count, first and last
    recorded times (s), as `vdtnav bag info` lists them."""

def read_bag_scans(
    path: _Path,
    scan_topic: str = "",
    odom_topic: str = "",
    odom_frame: str = "odom",
    base_frame: str = "base_link",
    laser_pose: npt.ArrayLike | None = None,
    sigma_range: float = 0.02,
    max_range: float = ...,
) -> _BagScans:
    """A 2D LiDAR run from a bag (`vdtnav localize --bag`): a dict with scans (LaserScans, mount
    set from TF or laser_pose), times (s), odometry (N x 3, base_frame in odom_frame at each scan,
    from odom_topic, TF or the only Odometry topic) and where each came from. max_range (default
    NaN: the messages' own range_max): readings at or beyond it are no returns.
    odometry_steps(times, odometry) gives the localizers' steps."""

def read_bag_clouds(
    path: _Path,
    cloud_topic: str = "",
    odom_topic: str = "",
    imu_topic: str = "",
    odom_frame: str = "odom",
    base_frame: str = "base_link",
    lidar_pose: npt.ArrayLike | None = None,
    max_clouds: int = 0,
) -> list[_BagCloud]:
    """The PointCloud2 messages of a bag (`vdtnav localize3d --bag`): a list of dicts with stamp
    (s), frame, points (N x 3, the cloud's frame, NaN points dropped), times (per point, s after
    the stamp, or None), mount (4 x 4, cloud frame in base_frame), odometry (4 x 4 or None) and
    the IMU's roll and pitch (NaN: none). max_clouds: stop after so many (0: all)."""

# ---------------------------------------------------------------------------------------------
# Evaluation

class RelationMetric:
    """The relation metric over a set of relations."""

    @property
    def used(self) -> int:
        """Relations used."""
    @property
    def skipped(self) -> int:
        """Relations skipped: skipped_no_stamp + skipped_outside + skipped_in_gap."""
    @property
    def skipped_no_stamp(self) -> int:
        """Skipped: interpolate off and no estimate sample within stamp_tolerance of an end."""
    @property
    def skipped_outside(self) -> int:
        """Skipped: interpolate on and an end before the first or after the last sample."""
    @property
    def skipped_in_gap(self) -> int:
        """Skipped: interpolate on and an end in a gap longer than max_gap."""
    @property
    def translation_mean(self) -> float:
        """Mean |e_xy|, metres."""
    @property
    def translation_std(self) -> float:
        """Standard deviation of |e_xy|, metres."""
    @property
    def rotation_mean(self) -> float:
        """Mean |e_yaw|, radians."""
    @property
    def rotation_std(self) -> float:
        """Standard deviation of |e_yaw|, radians."""
    @property
    def translation_squared_mean(self) -> float:
        """Mean of |e_xy|^2, m^2 (the paper's translational part)."""
    @property
    def rotation_squared_mean(self) -> float:
        """Mean of e_yaw^2, rad^2 (the paper's rotational part)."""
    @property
    def translation_errors(self) -> _F64:
        """Per relation |e_xy| (NaN where skipped)."""
    @property
    def rotation_errors(self) -> _F64:
        """Per relation |e_yaw| (NaN where skipped)."""

def relation_metric(
    times: npt.ArrayLike,
    poses: npt.ArrayLike,
    relations: npt.ArrayLike,
    stamp_tolerance: float = 1e-6,
    interpolate: bool = False,
    max_gap: float = 1.0,
) -> RelationMetric:
    """The relation metric (Kümmerle et al. 2009) of a planar trajectory (times, N x 3 poses) on
    relations (N x 5, read_relations): mean and std of |e_xy| and |e_yaw|,
    e = between(delta*, delta), and the means of their squares (the paper's metric). Ends matched
    to samples within stamp_tolerance seconds, or, with interpolate, interpolated between samples
    at most max_gap seconds apart."""

class RelationNees:
    """The NEES of each relation (relation_nees)."""

    @property
    def used(self) -> int:
        """Relations with a finite NEES."""
    @property
    def skipped_no_stamp(self) -> int:
        """Skipped: an end has no estimate sample within stamp_tolerance."""
    @property
    def skipped_no_covariance(self) -> int:
        """Skipped: an end's covariance is missing (not finite)."""
    @property
    def skipped_singular(self) -> int:
        """Skipped: the relative pose's covariance is not positive definite."""
    @property
    def mean(self) -> float:
        """Mean NEES (0 when used == 0)."""
    @property
    def median(self) -> float:
        """Median NEES (0 when used == 0)."""
    @property
    def fraction_inside(self) -> float:
        """Fraction of the used relations with NEES <= bound (chi^2_3 95 %: 7.81)."""
    @property
    def values(self) -> _F64:
        """One NEES per relation, NaN where skipped, input order."""

def relation_nees(
    times: npt.ArrayLike,
    poses: npt.ArrayLike,
    covariances: npt.ArrayLike,
    relations: npt.ArrayLike,
    stamp_tolerance: float = 1e-6,
    bound: float = 7.814727903251178,
) -> RelationNees:
    """The NEES of each relation under the covariance of the relative pose (both ends'
    covariances propagated through between(); relation_nees.hpp); covariances N x 3 x 3, NaN
    where the estimator gave none."""

@overload
def nees(
    estimate: npt.ArrayLike,
    truth: npt.ArrayLike,
    covariance: npt.ArrayLike,
    return_dof: Literal[False] = False,
) -> float: ...
@overload
def nees(
    estimate: npt.ArrayLike,
    truth: npt.ArrayLike,
    covariance: npt.ArrayLike,
    return_dof: Literal[True],
) -> tuple[float, int]: ...
@overload
def nees(
    estimate: npt.ArrayLike,
    truth: npt.ArrayLike,
    covariance: npt.ArrayLike,
    return_dof: bool = False,
) -> float | tuple[float, int]:
    """e^T P^-1 e of a pose estimate: planar (x, y, phi) with a 3 x 3 covariance, or 4 x 4 poses
    with the 6 x 6 covariance of the left perturbation (components whose rows are zero or NaN,
    held and not estimated, left out). NaN when P is not positive definite. return_dof: return
    (nees, the chi-square's degrees of freedom: 3 in 2D, those kept in 3D) instead."""

class Anees:
    """The average NEES of a run and its chi-square test."""

    @property
    def count(self) -> int:
        """Finite NEES values averaged."""
    @property
    def failures(self) -> int:
        """NaN/inf values (left out of the mean; any makes the run inconsistent)."""
    @property
    def anees(self) -> float:
        """Mean of the finite values (0 when count == 0)."""
    @property
    def interval(self) -> tuple[float, float]:
        """anees_interval(count, dof, confidence): (lower, upper)."""
    @property
    def consistent(self) -> bool:
        """count > 0, no failures and anees inside the interval."""

def anees(
    nees: Sequence[float] | npt.NDArray[np.floating[Any]], dof: int, confidence: float = 0.95
) -> Anees:
    """ANEES of NEES values with `dof` degrees of freedom each and its two-sided interval
    [chi^2_{(1-c)/2}(n d) / n, chi^2_{(1+c)/2}(n d) / n]."""

def anees_interval(n: int, dof: int, confidence: float = 0.95) -> tuple[float, float]:
    """The interval the mean of n NEES values of `dof` degrees of freedom lies in with
    probability `confidence` (Wilson-Hilferty)."""

class ErrorStatistics:
    """Summary of a list of non-negative errors (all zero when there are none)."""

    @property
    def count(self) -> int:
        """Errors summarised."""
    @property
    def rmse(self) -> float:
        """sqrt(mean of the squares)."""
    @property
    def mean(self) -> float:
        """Arithmetic mean."""
    @property
    def median(self) -> float:
        """Middle value (mean of the two middle ones for an even count)."""
    @property
    def p99(self) -> float:
        """99th percentile by nearest rank: the ceil(0.99 n)-th smallest value."""
    @property
    def std(self) -> float:
        """Sample standard deviation (n - 1); 0 when count < 2."""
    @property
    def min(self) -> float:
        """Smallest error."""
    @property
    def max(self) -> float:
        """Largest error."""

class Ate:
    """The absolute trajectory error (absolute_trajectory_error), aligned and not."""

    @property
    def alignment(self) -> _F64:
        """(x, y, phi): the rigid SE(2) transform T minimising sum |p_ref - T p_est|^2 (Umeyama,
        no scale); the aligned estimate is T composed with the estimate's poses."""
    @property
    def translation(self) -> ErrorStatistics:
        """|p_ref - T p_est|, metres (aligned; zero when the alignment is degenerate: fewer than 2
        distinct matched positions)."""
    @property
    def rotation(self) -> ErrorStatistics:
        """|wrap(yaw_ref - yaw(T) - yaw_est)|, radians (aligned)."""
    @property
    def unaligned_translation(self) -> ErrorStatistics:
        """|p_ref - p_est|, metres."""
    @property
    def unaligned_rotation(self) -> ErrorStatistics:
        """|wrap(yaw_ref - yaw_est)|, radians."""

def absolute_trajectory_error(
    times: npt.ArrayLike,
    poses: npt.ArrayLike,
    ref_times: npt.ArrayLike,
    ref_poses: npt.ArrayLike,
    max_time_difference: float = 0.01,
) -> Ate:
    """The ATE (Sturm et al. 2012) of a planar trajectory (times, N x 3 poses) against a
    reference (ref_times, M x 3): samples associated one to one within max_time_difference
    seconds, statistics of the position and yaw errors after the best rigid alignment and
    without it (trajectory_metrics.hpp). Stamps strictly increasing (else ConfigError)."""

class Rpe:
    """The relative pose error (relative_pose_error)."""

    @property
    def pairs(self) -> int:
        """(i, j) pairs the errors are over."""
    @property
    def translation(self) -> ErrorStatistics:
        """|trans(E_ij)|, metres."""
    @property
    def rotation(self) -> ErrorStatistics:
        """|angle(E_ij)|, radians."""

def relative_pose_error(
    times: npt.ArrayLike, poses: npt.ArrayLike, ref_times: npt.ArrayLike, ref_poses: npt.ArrayLike
) -> Rpe:
    """The RPE (Sturm et al. 2012) of a planar trajectory against a reference over consecutive
    associated frames (trajectory_metrics.hpp's defaults: delta 1 frame, samples associated
    within 0.01 s): E_ij = between(between(Q_i, Q_j), between(P_i, P_j)), no alignment."""

# ---------------------------------------------------------------------------------------------
# The compiled core and its submodule _timing (not re-exported: vdtnav._vdtnav._timing)

class _TimingModule(types.ModuleType):
    """vdtnav._vdtnav._timing: the bindings' calls timed in C++ (bench/python/overhead.py):
    median seconds."""

    @staticmethod
    def lookup2(
        map: Map2,
        points: _Points,
        jacobian: bool = True,
        repeats: int = 20,
        fresh_output: bool = True,
    ) -> float:
        """The median seconds of a C++ batch lookup (VdtField::evaluate) of the points on a 2D
        map. fresh_output: one call as a C++ program makes it (the points as Eigen vectors,
        converted when float32 or strided; a new vector of samples; the lookup); False: the
        lookup alone into a reused vector, the points converted beforehand."""
    @staticmethod
    def lookup3(
        map: Map3,
        points: _Points,
        jacobian: bool = True,
        repeats: int = 20,
        fresh_output: bool = True,
    ) -> float:
        """As lookup2, on a 3D map."""
    @staticmethod
    def update2(
        localizer: Localizer2D,
        pose: npt.ArrayLike,
        covariance: npt.ArrayLike,
        odometry: OdometryStep,
        scan: LaserScan,
        repeats: int = 20,
    ) -> float:
        """reset(pose, covariance) then update(odometry, scan), timed in C++."""

class _CoreModule(types.ModuleType):
    """vdtnav._vdtnav: the compiled core (every public name above is re-exported from it)."""

    _timing: _TimingModule
    def __getattr__(self, name: str) -> Any: ...

_vdtnav: _CoreModule
