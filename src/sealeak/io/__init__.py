"""The edges: quantities written with units (pint), tables of numbers with units, safe output files.

* :mod:`~sealeak.io.units`: ``"44 um"`` → 4.4e-5 (SI floats inside, units only at the edges);
* :mod:`~sealeak.io.tables`: delimited text tables whose header names each column's unit;
* :mod:`~sealeak.io.files`: outputs written atomically, never replaced unasked.
"""
