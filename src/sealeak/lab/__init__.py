"""The laboratory: measured leak data, fitting, and the reference paper's water-column rig.

* :mod:`~sealeak.lab.data`: measured leak rates and rig readings from tables with units;
* :mod:`~sealeak.lab.fitting`: the scale factor α by least squares in log Q, straight-line fits
  (docs/theory.md §8);
* :mod:`~sealeak.lab.rig`: the water column A dH/dt = −Q(ρgH) and the leak rate from readings (§4),
  and the pressure-decay rig of a gas (§11.7);
* :mod:`~sealeak.lab.pressure_decay`: V dP/dt = −Q_pV(P, P2), its closed forms, and the leak rate
  and α from (t, P) readings (§11.7).

Applied to a case by :func:`sealeak.cases.run_fit`, :func:`sealeak.cases.linearity` and
:func:`sealeak.cases.rig_prediction`.
"""

from .data import LeakData, read_leak_data, read_rig_readings
from .fitting import LinearFit, ScaleFit, fit_line, fit_scale
from .rig import RIG_KINDS, DecayRigSetup, ReadingsAnalysis, RigSetup, WaterColumn, drain_time, leak_rate_from_readings, read_decay_readings, water_column

__all__ = ["LeakData", "read_leak_data", "read_rig_readings", "LinearFit", "ScaleFit", "fit_line", "fit_scale",
           "ReadingsAnalysis", "RigSetup", "WaterColumn", "drain_time", "leak_rate_from_readings", "water_column",
           "RIG_KINDS", "DecayRigSetup", "read_decay_readings"]
