"""vdtnav: robot localization on Vector Distance Transform maps, from Python.

The C++ library's maps, localizers, readers and evaluation over numpy arrays (docs/python.md):

    import numpy as np, vdtnav
    m = vdtnav.load_map("intel_map.yaml")            # or vdtnav.Map2(occupancy, 0.05)
    r = m.lookup(np.random.rand(1000, 2) * 10)       # DT_v, |DT_v|, gradients, Jacobians
    loc = vdtnav.make_localizer("vdt-opt", m)        # settings: dict, YAML file or Settings
    loc.reset([0.6, 0.0, -0.35], np.diag([0.01, 0.01, 0.0025]))
    res = loc.update([0.1, 0.0, 0.0], ranges=ranges, angle_min=-np.pi / 2, angle_increment=np.pi / 180)
    res.pose, res.covariance, res.status, res.explained, res.iterations

Poses are (x, y, phi) in 2D and 4 x 4 matrices in 3D; covariances those of the C++ API (2D:
(x, y, phi); 3D: the left perturbation (dt, dtheta) in the world frame). Errors raise
vdtnav.Error subclasses (IoError, FormatError, ConfigError) with the C++ messages; bad array
arguments raise ValueError. Solves and lookups release the GIL.
"""
from ._vdtnav import *  # noqa: F401,F403
from ._vdtnav import __doc__ as _core_doc  # noqa: F401

__version__ = "0.1.0"

# The classes and exceptions print as vdtnav.X, where users find them.
for _name in dir():
    _obj = globals()[_name]
    if isinstance(_obj, type) and getattr(_obj, "__module__", "").startswith("vdtnav._vdtnav"):
        try:
            _obj.__module__ = "vdtnav"
        except (AttributeError, TypeError):
            pass
del _name, _obj
