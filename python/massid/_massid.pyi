"""Type stubs of massid's compiled module (python/src/*.cpp).

Conventions, as in the CLI (docs/conventions): SI units (kg, m, N, N m, rad,
m/s^2); wrenches are [fx, fy, fz, mx, my, mz] in the sensor frame, the wrench
the mechanism exerts on the sensor; gravity is the gravity acceleration in the
sensor frame. Arrays are numpy float64; N is the number of samples.
"""

from os import PathLike
from typing import Any, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

PathType = Union[str, PathLike]
# A data or plan table: a CSV path, or columns keyed by the CSV's column names
# (joint names or JOINT_deg, gx, gy, gz, fx ... mz, t, block; in motion also
# JOINT_vel, JOINT_acc, wx ... az and the joints above the sensor link), each of
# length N.
Data = Union[PathType, Mapping[str, npt.ArrayLike]]

__version__: str

class InputError(ValueError):
    """Bad input (the CLI's exit code 2); the message names file, line and column."""

class IdentifiabilityError(ValueError):
    """The data cannot determine every base parameter (the CLI's exit code 3)."""

class Joint:
    name: str
    type: str  # "revolute" or "prismatic"
    continuous: bool
    limited: bool
    lower: float  # rad or m
    upper: float
    velocity_limit: float

class Link:
    name: str
    parent: int  # index in Model.links, -1 for the sensor link
    joint: str  # joint from the parent ("" for the sensor link)
    joint_type: str  # "fixed", "revolute" or "prismatic"
    mass: float  # nominal, from the URDF
    com: np.ndarray  # [3] nominal centre of mass, link frame

class Model:
    name: str
    source: str
    sensor_link: str
    links: list[Link]
    joints: list[Joint]
    joint_names: list[str]
    held: dict[str, float]  # joints held still (fixed=...)
    num_joints: int
    num_links: int
    nominal_total_mass: float
    standard_parameter_names: list[str]  # "m(link)", "mx(link)", ... [4 L]
    def nominal_parameters(self, dynamic: bool = False) -> np.ndarray:
        """[4 L] URDF m, mx, my, mz per link; dynamic: [10 L] with ixx ... izz about the link origin."""
    def parameter_names(self, dynamic: bool = False) -> list[str]:
        """[4 L] "m(link)", ...; dynamic: [10 L] with "ixx(link)" ... "izz(link)"."""

def load_model(
    urdf: PathType, sensor: Optional[str] = None, fixed: Optional[Mapping[str, float]] = None
) -> Model: ...
def load_model_string(
    xml: str, sensor: Optional[str] = None, fixed: Optional[Mapping[str, float]] = None
) -> Model: ...

class BaseParameter:
    name: str  # "p1", ..., "M"
    unit: str  # "kg", "kg m" or (dynamic) "kg m^2"
    expression: str  # "mx(link2) + 0.198 m(link3)"
    terms: list[Tuple[str, str, float]]  # (link, "m" | "mx" | ... | "izz", coefficient)
    value: float  # nan when not identified
    std: float  # nan when not identified

class BaseParameters:
    params: list[BaseParameter]
    names: list[str]
    unknown_names: list[str]  # names, then offset_fx ... offset_mz with offset=True
    offset: bool
    num_unknowns: int
    dynamic: bool  # ten standard parameters per link (motion)
    gravity: Optional[str]  # dynamic: "level" or "varying"
    moving_sensor: bool  # dynamic: the sensor frame moves
    total_mass_identifiable: bool  # False: M joined offset_fz (dynamic, level, offsets)
    standard_parameter_names: list[str]  # K's columns
    K: np.ndarray  # [num_mass x 4 L] (dynamic: 10 L): base values = K @ standard parameters
    def report(self) -> str: ...  # the text of massid model
    def to_json(self) -> str: ...  # massid model --json

def base_parameters(
    model: Union[PathType, Model],
    offset: bool = False,
    *,
    dynamic: bool = False,
    gravity: str = "varying",  # dynamic: "level" or "varying"
    moving_sensor: bool = False,
    root_gravity: Optional[Sequence[float]] = None,  # the level gravity
) -> BaseParameters: ...
def standard_regressor(
    model: Model,
    q: npt.ArrayLike,
    gravity: npt.ArrayLike,
    *,
    qd: Optional[npt.ArrayLike] = None,
    qdd: Optional[npt.ArrayLike] = None,
    sensor_motion: Optional[npt.ArrayLike] = None,  # [N, 9] wx wy wz dwx dwy dwz ax ay az
) -> np.ndarray:
    """[N, 6, 4 L] Y(q, g): wrench = Y @ standard parameters (paper eqs. 15, 25, 29);
    with qd and qdd [N, 6, 10 L] in motion."""
def regressor(
    model: Model,
    q: npt.ArrayLike,
    gravity: npt.ArrayLike,
    offset: bool = False,
    *,
    qd: Optional[npt.ArrayLike] = None,
    qdd: Optional[npt.ArrayLike] = None,
    sensor_motion: Optional[npt.ArrayLike] = None,
    base: Optional[BaseParameters] = None,
) -> np.ndarray:
    """[N, 6, num_unknowns] Y_b(q, g): wrench = Y_b @ [base values, offsets] (eq. 29);
    with qd and qdd over the dynamic base parameters (base, or the default ones)."""

class Outlier:
    sample: int  # row in the data
    line: int  # file line (row index for a dict)
    score: float  # standardised residual norm, chi with 6 degrees of freedom

class Predictor:
    def __init__(
        self,
        robot: Optional[Union[PathType, Model]],  # None with an Identification (it has its model)
        params: Union[PathType, "Params", "Identification"],
        *,
        physical: bool = False,  # from the physical parameters (identify physical=True): K pi_phys
    ) -> None: ...
    model: Model
    joint_names: list[str]
    dynamic: bool  # dynamic parameters: the full wrench in motion
    offset: Optional[np.ndarray]  # [6] identified offsets (never in the predictions)
    has_offset: bool  # the offsets were identified
    delay: float  # the wrench's clock delay, s (0 without): predict_log applies it from t
    def compensate(self, measured: npt.ArrayLike, predicted: npt.ArrayLike) -> np.ndarray:
        """(measured - predicted) - offset, [N, 6] or [6]: massid predict's fx_comp, to the bit."""
    def sensor_reading(self, predicted: npt.ArrayLike) -> np.ndarray:
        """predicted + offset, [N, 6] or [6]: what the sensor reads."""
    def predict(
        self,
        q: npt.ArrayLike,
        gravity: Optional[npt.ArrayLike] = None,
        qd: Optional[npt.ArrayLike] = None,
        qdd: Optional[npt.ArrayLike] = None,
        *,
        sensor_motion: Optional[npt.ArrayLike] = None,
        t: Optional[npt.ArrayLike] = None,
        cutoff: Optional[float] = None,
    ) -> np.ndarray:
        """[N, 6] for q [N, num_joints] and gravity [N, 3]; [6] for single vectors.
        Dynamic: also qd, qdd (or t: derived by the filter, NaN rows at the ends)."""
    def predict_log(
        self,
        data: Data,
        *,
        cutoff: Optional[float] = None,  # dynamic, derived from t: low-pass cut-off, Hz
        root_gravity: Optional[Sequence[float]] = None,
        level_gravity: Optional[Sequence[float]] = None,  # sensor frame, level: what tilt columns turn
        checks: bool = True,  # the set-up checks (massid predict --no-checks: False)
        columns: Optional[Mapping[str, str]] = None,  # {ROLE: NAME} (massid predict --columns)
    ) -> "LogPrediction":
        """massid predict on a log: the set-up checks (InputError with the CLI's message when
        they refuse; warnings as MassidWarning), the prediction, the compensated wrench and
        the contact notes."""
    def __call__(
        self,
        q: npt.ArrayLike,
        gravity: Optional[npt.ArrayLike] = None,
        qd: Optional[npt.ArrayLike] = None,
        qdd: Optional[npt.ArrayLike] = None,
        *,
        sensor_motion: Optional[npt.ArrayLike] = None,
        t: Optional[npt.ArrayLike] = None,
        cutoff: Optional[float] = None,
    ) -> np.ndarray: ...

class TrackerEstimate:
    """The tracker's estimate after a sample: compensate --track's columns, physically
    consistent (mass >= 0, inertia PSD and within the triangle inequalities)."""

    payload_m: float  # mass, kg
    payload_c: np.ndarray  # [3] centre of mass, the payload link's frame, m
    payload_m_std: float
    payload_c_std: float  # the largest of payload_c_stds, m
    payload_c_stds: np.ndarray  # [3]
    payload_inertia: Optional[np.ndarray]  # [3, 3] about the com, kg m^2; None while undetermined
    offset: np.ndarray  # [6] the sensor offsets fx..mz
    offset_std: np.ndarray  # [6]
    event: str  # '', 'change' or 'contact'
    comp: np.ndarray  # [6] fx_comp..mz_comp: measured - predicted(mechanism, payload) - offset
    d2: float  # the sample's innovation chi^2, 6 dof

class Tracker:
    """A payload on a link and the sensor's drifting offsets, online (massid compensate
    --track's tracker, the same numbers to the bit; docs/tracking.md)."""

    def __init__(
        self,
        predictor: Union[Predictor, PathType, Model],  # a Predictor, or a URDF / Model with params
        params: Optional[Union[PathType, "Params", "Identification"]] = None,
        *,
        payload_link: Optional[str] = None,  # default: the measured link farthest from the sensor
        sigma_force: Optional[float] = None,  # N per axis; default: the params' residual RMS
        sigma_moment: Optional[float] = None,  # N m per axis; likewise
    ) -> None: ...
    payload_link: str
    estimate: TrackerEstimate  # after the last sample
    def update(
        self,
        t: float,  # s, increasing
        q: Optional[npt.ArrayLike],  # [num_joints] (None without joints below the sensor)
        wrench: npt.ArrayLike,  # [6] measured fx..mz
        qd: Optional[npt.ArrayLike] = None,  # dynamic parameters; None: at rest
        qdd: Optional[npt.ArrayLike] = None,
        gravity: Optional[npt.ArrayLike] = None,  # [3] sensor frame; None: from q_upstream
        *,
        sensor_motion: Optional[npt.ArrayLike] = None,  # [9] as Predictor's
        q_upstream: Optional[npt.ArrayLike] = None,  # the joints above the sensor link
        qd_upstream: Optional[npt.ArrayLike] = None,
        qdd_upstream: Optional[npt.ArrayLike] = None,
        root_gravity: Optional[Sequence[float]] = None,  # default 0, 0, -9.80665
    ) -> TrackerEstimate:
        """One sample; the estimate after it."""
    def track(
        self,
        t: npt.ArrayLike,  # [N]
        q: Optional[npt.ArrayLike],  # [N, num_joints]
        wrench: npt.ArrayLike,  # [N, 6]
        qd: Optional[npt.ArrayLike] = None,
        qdd: Optional[npt.ArrayLike] = None,
        gravity: Optional[npt.ArrayLike] = None,  # [N, 3]
        *,
        sensor_motion: Optional[npt.ArrayLike] = None,  # [N, 9]
        q_upstream: Optional[npt.ArrayLike] = None,
        qd_upstream: Optional[npt.ArrayLike] = None,
        qdd_upstream: Optional[npt.ArrayLike] = None,
        root_gravity: Optional[Sequence[float]] = None,
    ) -> dict[str, np.ndarray]:
        """N samples, looped in C++: fx_comp..mz_comp, payload_m .. offset_mz ([N] float,
        payload_ixx..izz NaN while undetermined) and event ([N] str), by name."""

class PhysicalLink:
    name: str
    mass: float  # kg
    com: np.ndarray  # [3] centre of mass, link frame, m
    inertia_com: np.ndarray  # [3, 3] about the centre of mass, link frame, kg m^2
    principal_moments: np.ndarray  # [3] of inertia_com, ascending
    min_eigenvalue: float  # smallest eigenvalue of the pseudo-inertia J
    consistent: bool  # m > 0 and J >= 0 within round-off
    prior_body: bool  # no mass in the URDF: the prior was a tiny body

class PhysicalSummary:
    standard: np.ndarray  # [10 num_links] m, mx, my, mz, ixx .. izz (inertia about the link origin)
    links: list[PhysicalLink]
    mismatch: np.ndarray  # [num base parameters] (K pi_phys - identified) / std
    worst: int  # index of the worst mismatch, -1 when none
    worst_mismatch: float
    static_layout: bool  # identified at rest: inertias about the centres of mass from the URDF
    cost: float
    iterations: int
    solve_seconds: float
    converged: bool
    consistent: bool  # every link

class Identification:
    model: Model
    source: str
    dynamic: bool  # identified in motion (dynamic=True)
    total_mass: float  # nan when not identifiable (dynamic, level, offsets)
    total_mass_std: float
    base_parameters: list[BaseParameter]  # with value and std
    unknown_names: list[str]
    values: np.ndarray  # [p] base parameters, then offsets
    std: np.ndarray  # [p]
    covariance: np.ndarray  # [p, p]
    correlation: np.ndarray  # [p, p]
    offset: Optional[np.ndarray]  # [6] with offset=True (at the end of the log with drift)
    offset_std: Optional[np.ndarray]
    condition_number: float  # paper eq. 36
    chi2_per_dof: float
    sigma: np.ndarray  # [6] noise per axis used as weights
    sigma_estimated: bool
    samples: int
    residual_rms: np.ndarray  # [6]
    residual_max: np.ndarray  # [6]
    q: np.ndarray  # [N, num_joints] rad or m
    qd: Optional[np.ndarray]  # [N, num_joints] dynamic: velocities (given or derived)
    qdd: Optional[np.ndarray]  # [N, num_joints] dynamic: accelerations
    sensor_motion: Optional[np.ndarray]  # [N, 9] dynamic, when the sensor moved
    filter: Optional[dict[str, float]]  # dynamic, derived: cutoff, rate, half_width, decimation, rows
    gravity: np.ndarray  # [N, 3]
    wrench: np.ndarray  # [N, 6] measured
    fitted: np.ndarray  # [N, 6] the fitted model's wrench (offsets and drift included)
    residuals: np.ndarray  # [N, 6] wrench - fitted
    lines: np.ndarray  # [N] file line of each sample (row index for a dict)
    time: Optional[np.ndarray]  # [N] column t
    gravity_from_force: bool
    outliers: list[Outlier]
    outlier_threshold: float
    robust: bool
    used: np.ndarray  # [N] bool: False for samples rejected by robust=True
    drift: Optional[str]  # "linear" or "per-block"
    drift_names: list[str]
    drift_values: np.ndarray
    drift_std: np.ndarray
    warnings: list[str]  # also issued as MassidWarning
    delay: Optional[dict[str, Any]]  # dynamic with delay: value, std (s), estimated, scan
    rest_windows: Optional[dict[str, Any]]  # continuous static log: windows, samples, rows, moving, criterion
    quasi_static: Optional[dict[str, float]]  # continuous static log too slow for its motion to show: rows, windowed_samples, max_speed, inertial_force, inertial_moment, noise_force, noise_moment
    physical: Optional[PhysicalSummary]  # physical=True: physically consistent parameters
    def report(self) -> str: ...  # the CLI's text report
    def to_json(self) -> str: ...  # the params file ("massid-params-1")
    def save(self, path: PathType) -> None: ...  # params file, written atomically
    def predictor(self) -> Predictor: ...

def identify(
    robot: Union[PathType, Model],
    data: Data,
    *,
    offset: bool = False,
    sensor: Optional[str] = None,
    fixed: Optional[Mapping[str, float]] = None,
    robust: bool = False,
    drift: Optional[str] = None,
    sigma_force: Optional[float] = None,
    sigma_moment: Optional[float] = None,
    checks: bool = True,
    dynamic: bool = False,
    cutoff: Optional[float] = None,  # Hz, dynamic without JOINT_vel/_acc
    root_gravity: Optional[Sequence[float]] = None,  # gravity in the URDF root frame (upstream joints)
    level_gravity: Optional[Sequence[float]] = None,  # sensor frame, level: what tilt columns turn
    rest: str = "auto",  # static log with t: "auto" uses its rest windows, "off" every row
    delay: Union[None, str, float] = None,  # dynamic: wrench lag, s, or "auto"
    physical: bool = False,  # also physically consistent standard parameters (.physical)
    columns: Optional[Mapping[str, str]] = None,  # {ROLE: NAME}: columns of other names read as roles
) -> Identification: ...

# The record `massid identify --report` hands to the report: the fit without fitting again.
def load_identification(path: PathType) -> Identification: ...

class Params:
    source: str
    sensor_link: str
    joints: list[str]
    held: dict[str, float]
    gravity_from: str
    samples: int
    total_mass: float  # nan when not identifiable
    dynamic: bool  # "model": "dynamic"
    gravity: Optional[str]  # dynamic: "level" or "varying"
    gravity_vector: Optional[np.ndarray]  # dynamic, level: [3] sensor frame
    moving_sensor: bool
    base_parameters: list[BaseParameter]
    offset: Optional[np.ndarray]
    offset_std: Optional[np.ndarray]
    condition_number: float
    delay: Optional[float]  # the wrench's clock delay, s (identify delay=...)
    residual_rms: np.ndarray
    physical: Optional[dict[str, dict[str, float]]]  # "physical" links: name -> {m, mx, ..., izz}

def load_params(path: PathType) -> Params: ...
def load_predictor(
    robot: Optional[Union[PathType, Model]],
    params: Union[PathType, Params, Identification],
    *,
    physical: bool = False,
) -> Predictor:
    """Predictor(robot, params, physical=physical): the identified model every door loads."""
def predict(
    robot: Union[PathType, Model],
    params: Union[PathType, Params, Identification],
    data: Data,
    *,
    cutoff: Optional[float] = None,
    root_gravity: Optional[Sequence[float]] = None,
    level_gravity: Optional[Sequence[float]] = None,  # sensor frame, level: what tilt columns turn
    physical: bool = False,  # from the physical parameters (identify physical=True)
    columns: Optional[Mapping[str, str]] = None,  # {ROLE: NAME}: columns of other names read as roles
) -> np.ndarray:
    """[N, 6] the mechanism's predicted wrench at every row of data (joint and gravity
    columns), without the identified sensor offsets (massid predict's fx_pred); dynamic
    parameters: in motion, NaN in the rows the derivative filter drops."""

class LogPrediction:
    source: str  # the log's name in notes ("data" for columns by name)
    lines: list[int]  # [N] file line of each predicted row (row index for columns by name)
    predicted: np.ndarray  # [N, 6] the mechanism's wrench, no offset (fx_pred..mz_pred)
    compensated: Optional[np.ndarray]  # [N, 6] fx_comp..mz_comp; None without fx..mz
    warnings: list[str]  # the set-up checks' warnings
    notes: list[str]  # per contact episode, the text of massid predict's "massid: note:" line
    contact: list[dict[str, Any]]  # first_line, last_line, rows, score, threshold, force, moment
    cutoff: Optional[float]  # dynamic, derived from t: the low-pass cut-off, Hz

def column_roles(
    robot: Union[PathType, Model],
    names: Sequence[str],
    *,
    columns: Optional[Mapping[str, str]] = None,
) -> list[str]:
    """The role each column is read as (columns= and the recorders' spellings applied)."""

def predict_log(
    robot: Union[PathType, Model],
    params: Union[PathType, Params, Identification],
    data: Data,
    *,
    cutoff: Optional[float] = None,
    root_gravity: Optional[Sequence[float]] = None,
    level_gravity: Optional[Sequence[float]] = None,  # sensor frame, level: what tilt columns turn
    physical: bool = False,
    checks: bool = True,
    columns: Optional[Mapping[str, str]] = None,  # {ROLE: NAME}: columns of other names read as roles
) -> LogPrediction:
    """Predictor(robot, params, physical=physical).predict_log(data, ...): massid predict's
    pipeline, its set-up checks and contact notes included."""

def simulate(
    robot: Union[PathType, Model],
    plan: Union[Data, "Plan"],
    *,
    noise_force: float = 0.0,
    noise_moment: float = 0.0,
    offset: Optional[Sequence[float]] = None,
    seed: int = 1,
    repeat: int = 1,
    dynamic: bool = False,  # in motion: the trajectory's JOINT_vel, JOINT_acc columns
    root_gravity: Optional[Sequence[float]] = None,
    level_gravity: Optional[Sequence[float]] = None,  # sensor frame, level: what tilt columns turn
    columns: Optional[Mapping[str, str]] = None,  # {ROLE: NAME}: columns of other names read as roles
) -> dict[str, np.ndarray]:
    """The plan's columns with fx ... mz that the URDF's inertials would produce."""

def fourier_trajectory(
    robot: Union[PathType, Model],
    harmonics: int = 5,
    period: float = 10.0,  # s
    duration: float = 30.0,  # s
    rate: float = 1000.0,  # Hz
    seed: int = 1,
    *,
    sensor: Optional[str] = None,
    fixed: Optional[Mapping[str, float]] = None,
    gravity: Sequence[float] = (0.0, 0.0, -9.80665),
    velocity_limit: Optional[Union[float, Mapping[str, float]]] = None,
    acceleration_limit: float = 4.0,
    position_margin: float = 0.1,
) -> dict[str, np.ndarray]:
    """An exciting trajectory: t, joints, JOINT_vel, JOINT_acc, gx, gy, gz."""

def prepare_motion(
    robot: Union[PathType, Model],
    data: Data,
    *,
    cutoff: Optional[float] = None,
    decimation: Optional[int] = None,
    root_gravity: Optional[Sequence[float]] = None,
    level_gravity: Optional[Sequence[float]] = None,  # sensor frame, level: what tilt columns turn
    sensor: Optional[str] = None,
    fixed: Optional[Mapping[str, float]] = None,
    columns: Optional[Mapping[str, str]] = None,  # {ROLE: NAME}
) -> dict[str, np.ndarray]:
    """The samples identify(dynamic=True) and predict make of a motion log, as columns
    (t, joints, JOINT_vel, JOINT_acc, gx, gy, gz, [wx..az], [fx..mz], [block], row)."""

class Plan:
    joint_names: list[str]
    q: np.ndarray  # [N, num_joints]
    gravity: np.ndarray  # [N, 3] sensor frame
    tilt_deg: np.ndarray  # [N, 2] about x, then y
    condition_number: float
    log_det: float
    identifiable: bool
    identifiability_message: str
    unknown_names: list[str]
    predicted_std: np.ndarray  # [num_unknowns] at the given noise
    expected_error: np.ndarray  # [6] RMS prediction error over random feasible poses
    tilt_changes: int
    joint_travel: float
    seconds: float
    def columns(self) -> dict[str, np.ndarray]: ...  # the plan CSV's columns
    def save(self, path: PathType) -> None: ...
    def report(self) -> str: ...

def design(
    robot: Union[PathType, Model],
    poses: int = 30,
    *,
    sensor: Optional[str] = None,
    fixed: Optional[Mapping[str, float]] = None,
    offset: bool = False,
    tilt_max_deg: Optional[float] = None,
    tilt_groups: int = 4,
    tilts_deg: Optional[Sequence[Tuple[float, float]]] = None,
    limits: Optional[Mapping[str, Tuple[float, float]]] = None,
    min_height: Optional[float] = None,
    criterion: str = "cond",
    noise_force: float = 0.05,
    noise_moment: float = 0.005,
    level_gravity: Sequence[float] = (0.0, 0.0, -9.80665),
    seed: int = 1,
    candidates: int = 0,
    level_poses: Optional[int] = None,
) -> Plan: ...

def read_csv(path: PathType) -> dict[str, np.ndarray]:
    """A CSV's numeric columns (the CLI's reader: file:line:column errors)."""
