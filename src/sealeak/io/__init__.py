"""The edges: quantities written with units (pint), tables of numbers with units, safe output files.

* :mod:`~sealeak.io.units`: ``"44 um"`` → 4.4e-5 (SI floats inside, units only at the edges); one
  parser for every quantity a user writes: one ASCII number and a unit, nothing evaluated, no
  comma in a number (``"2,3 MPa"`` is refused with how to write it);
* :mod:`~sealeak.io.leak_units`: the leak-rate units (m³/s, ml/min, mbar·l/s, Pa·m³/s, sccm, mol/s,
  kg/s), the standard conditions, and every conversion between them;
* :mod:`~sealeak.io.tables`: delimited text tables whose header names each column's unit (the same
  number and unit rules);
* :mod:`~sealeak.io.files`: outputs written atomically, never replaced unasked, and replacing regular
  files only (never a folder, link, device or FIFO); inputs read from regular files only.
"""
