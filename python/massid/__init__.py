"""massid: mass parameters of a mechanism on a force/torque sensor, from static wrenches
and in motion.

The Python face of the massid library (the CLI's commands as functions, on numpy
arrays). Five lines from a URDF to a report::

    import massid
    plan = massid.design("robot.urdf", 30, tilt_max_deg=15)
    data = massid.simulate("robot.urdf", plan, noise_force=0.05, noise_moment=0.005)
    ident = massid.identify("robot.urdf", data)           # or a CSV log
    massid.report.write_identify_report("report.html", ident)

In motion (ten parameters per link, the inertia about each link origin)::

    traj = massid.fourier_trajectory("robot.urdf", harmonics=5, period=10, duration=30)
    data = massid.simulate("robot.urdf", traj, dynamic=True, noise_force=0.1)
    ident = massid.identify("robot.urdf", data, dynamic=True)  # or a log with t only
    wrench = ident.predictor()(q, gravity, qd, qdd)

Online, a payload and the sensor's drifting offsets (massid compensate --track)::

    tracker = massid.Tracker(massid.Predictor("robot.urdf", "params.json"))
    estimate = tracker.update(t, q, wrench, qd, qdd, gravity)  # estimate.payload_m, ...

Conventions (as the CLI): SI units; wrenches [fx, fy, fz, mx, my, mz] in the
sensor frame, the wrench the mechanism exerts on the sensor; gravity in the
sensor frame. Errors raise InputError / IdentifiabilityError with the CLI's
messages; warnings are MassidWarning. The report module (massid.report) needs
matplotlib and is imported on first use.
"""

from ._massid import (  # noqa: F401  (the public API)
    BaseParameter,
    BaseParameters,
    IdentifiabilityError,
    Identification,
    InputError,
    Joint,
    Link,
    LogPrediction,
    Model,
    Outlier,
    Params,
    PhysicalLink,
    PhysicalSummary,
    Plan,
    Predictor,
    Tracker,
    TrackerEstimate,
    __version__,
    base_parameters,
    column_roles,
    design,
    fourier_trajectory,
    identify,
    load_identification,
    load_model,
    load_model_string,
    load_params,
    predict,
    predict_log,
    prepare_motion,
    read_csv,
    regressor,
    simulate,
    standard_regressor,
)


class MassidWarning(UserWarning):
    """A warning about the data or the fit (the CLI's 'massid: warning:' lines)."""


def __getattr__(name: str):
    # massid.report imports matplotlib: only when it is used.
    if name == "report":
        import importlib

        return importlib.import_module(".report", __name__)
    raise AttributeError(f"module 'massid' has no attribute '{name}'")


__all__ = [
    "BaseParameter",
    "BaseParameters",
    "IdentifiabilityError",
    "Identification",
    "InputError",
    "Joint",
    "Link",
    "LogPrediction",
    "MassidWarning",
    "Model",
    "Outlier",
    "Params",
    "PhysicalLink",
    "PhysicalSummary",
    "Plan",
    "Predictor",
    "Tracker",
    "TrackerEstimate",
    "__version__",
    "base_parameters",
    "column_roles",
    "design",
    "fourier_trajectory",
    "identify",
    "load_identification",
    "load_model",
    "load_model_string",
    "load_params",
    "predict",
    "predict_log",
    "prepare_motion",
    "read_csv",
    "regressor",
    "simulate",
    "standard_regressor",
]
