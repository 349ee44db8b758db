"""Type stubs of massid's compiled module (python/src/*.cpp).

Conventions, as in the CLI (docs/conventions): SI units (kg, m, N, N m, rad,
m/s^2); wrenches are [fx, fy, fz, mx, my, mz] in the sensor frame, the wrench
the mechanism exerts on the sensor; gravity is the gravity acceleration in the
sensor frame. Arrays are numpy float64; N is the number of samples.
"""

from os import PathLike
from typing import Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

PathType = Union[str, PathLike]
# A data or plan table: a CSV path, or columns keyed by the CSV's column names
# (joint names or JOINT_deg, gx, gy, gz, fx ... mz, t, block), each of length N.
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
    def nominal_parameters(self) -> np.ndarray: ...  # [4 L] URDF m, mx, my, mz per link

def load_model(
    urdf: PathType, sensor: Optional[str] = None, fixed: Optional[Mapping[str, float]] = None
) -> Model: ...
def load_model_string(
    xml: str, sensor: Optional[str] = None, fixed: Optional[Mapping[str, float]] = None
) -> Model: ...

class BaseParameter:
    name: str  # "p1", ..., "M"
    unit: str  # "kg" or "kg m"
    expression: str  # "mx(link2) + 0.198 m(link3)"
    terms: list[Tuple[str, str, float]]  # (link, "m" | "mx" | "my" | "mz", coefficient)
    value: float  # nan when not identified
    std: float  # nan when not identified

class BaseParameters:
    params: list[BaseParameter]
    names: list[str]
    unknown_names: list[str]  # names, then offset_fx ... offset_mz with offset=True
    offset: bool
    num_unknowns: int
    K: np.ndarray  # [num_mass x 4 L]: base values = K @ standard parameters

def base_parameters(model: Model, offset: bool = False) -> BaseParameters: ...
def standard_regressor(model: Model, q: npt.ArrayLike, gravity: npt.ArrayLike) -> np.ndarray:
    """[N, 6, 4 L] Y(q, g): wrench = Y @ standard parameters (paper eqs. 15, 25, 29)."""
def regressor(
    model: Model, q: npt.ArrayLike, gravity: npt.ArrayLike, offset: bool = False
) -> np.ndarray:
    """[N, 6, num_unknowns] Y_b(q, g): wrench = Y_b @ [base values, offsets] (eq. 29)."""

class Outlier:
    sample: int  # row in the data
    line: int  # file line (row index for a dict)
    score: float  # standardised residual norm, chi with 6 degrees of freedom

class Predictor:
    def __init__(
        self,
        robot: Optional[Union[PathType, Model]],  # None with an Identification (it has its model)
        params: Union[PathType, "Params", "Identification"],
    ) -> None: ...
    model: Model
    joint_names: list[str]
    def predict(self, q: npt.ArrayLike, gravity: npt.ArrayLike) -> np.ndarray:
        """[N, 6] for q [N, num_joints] and gravity [N, 3]; [6] for single vectors."""
    def __call__(self, q: npt.ArrayLike, gravity: npt.ArrayLike) -> np.ndarray: ...

class Identification:
    model: Model
    source: str
    total_mass: float
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
) -> Identification: ...

class Params:
    source: str
    sensor_link: str
    joints: list[str]
    held: dict[str, float]
    gravity_from: str
    samples: int
    total_mass: float
    base_parameters: list[BaseParameter]
    offset: Optional[np.ndarray]
    offset_std: Optional[np.ndarray]
    condition_number: float
    residual_rms: np.ndarray

def load_params(path: PathType) -> Params: ...
def predict(robot: Union[PathType, Model], params: Union[PathType, Params, Identification], data: Data) -> np.ndarray:
    """[N, 6] predicted gravity wrench at every row of data (joint and gravity columns)."""

def simulate(
    robot: Union[PathType, Model],
    plan: Union[Data, "Plan"],
    *,
    noise_force: float = 0.0,
    noise_moment: float = 0.0,
    offset: Optional[Sequence[float]] = None,
    seed: int = 1,
    repeat: int = 1,
) -> dict[str, np.ndarray]:
    """The plan's columns with fx ... mz that the URDF's inertials would produce."""

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
) -> Plan: ...

def read_csv(path: PathType) -> dict[str, np.ndarray]:
    """A CSV's numeric columns (the CLI's reader: file:line:column errors)."""
