"""Numerically exact route to the leak rate (docs/theory.md §6).

Small public API over private modules:

* contact:      :func:`solve_contact`, :func:`solve_contact_sweep`, :class:`ContactResult`,
                :func:`contact_memory_bytes` (FFT boundary elements, preconditioned
                Polonsky-Keer constrained conjugate gradient);
* band contact: :func:`solve_band_contact`, :class:`BandContactResult`, :func:`band_displacement`,
                :func:`band_contact_memory_bytes`, :func:`hertz_line_contact`, :func:`contact_edges` (a smooth
                cylinder on a rough surface: periodic along the seal line, free across the band by zero
                padding, DC-FFT);
* flow:         :func:`solve_flow`, :class:`FlowResult`, :func:`flow_memory_bytes`
                (steady Reynolds equation, finite volumes, sparse direct or AMG-CG, every
                solution checked);
* gas flow:     :func:`solve_gas_flow`, :class:`GasFlowResult`, :func:`gas_flow_memory_bytes` (isothermal
                gas with rarefaction: the same linear problem in p², a checked fixed point with slip);
* percolation:  :func:`label_clusters`, :func:`spans`, :func:`spanning_mask`, :func:`critical_constriction`,
                :func:`percolation_threshold`, :class:`ThresholdResult`;
* synthesis:    :func:`synthesize` random periodic surfaces with a given C(q), :func:`wavevector_grid`;
* resources:    :func:`check_memory` refuses a grid that does not fit in memory;
* devices:      :func:`array_namespace_for` (``"cpu"``: NumPy, ``"cuda"``: CuPy, imported only then),
                :func:`device_count`, :func:`device_name`, :func:`device_memory_bytes`,
                :func:`require_device_memory`, :func:`to_numpy`: synthesis and contact run in the namespace of
                their arrays (one code path, array-api-compat); :func:`solve_flow` (``device=``) runs
                its AMG iterations there too, its set-up and checks on the host.

Arrays are indexed [x, y] with flow along x (axis 0) and periodicity along y (axis 1); all
quantities are SI (m, Pa, Pa·s, m³/s).
"""

from __future__ import annotations

from typing import Literal

from ..errors import InputError
from ._band_contact import (
    BandContactResult,
    band_contact_memory_bytes,
    band_displacement,
    contact_edges,
    hertz_line_contact,
    solve_band_contact,
)
from ._contact import ContactField, ContactOptions, ContactResult, contact_memory_bytes, solve_contact, solve_contact_sweep
from ._device import DEVICES, array_namespace_for, device_count, device_memory_bytes, device_name, require_device_memory
from ._flow import FlowResult, flow_memory_bytes, solve_flow
from ._gas_flow import GasFlowResult, gas_flow_memory_bytes, solve_gas_flow
from ._memory import available_memory_bytes, require_memory
from ._percolation import ThresholdResult, critical_constriction, label_clusters, percolation_threshold, spanning_mask, spans
from ._xp import to_numpy
from .synthesis import synthesis_memory_bytes, synthesize, wavevector_grid

__all__ = [
    "synthesize",
    "synthesis_memory_bytes",
    "wavevector_grid",
    "ContactResult",
    "ContactOptions",
    "FlowResult",
    "ThresholdResult",
    "solve_contact",
    "solve_contact_sweep",
    "BandContactResult",
    "solve_band_contact",
    "band_displacement",
    "band_contact_memory_bytes",
    "hertz_line_contact",
    "contact_edges",
    "solve_flow",
    "GasFlowResult",
    "solve_gas_flow",
    "gas_flow_memory_bytes",
    "label_clusters",
    "spans",
    "critical_constriction",
    "spanning_mask",
    "percolation_threshold",
    "contact_memory_bytes",
    "flow_memory_bytes",
    "check_memory",
    "available_memory_bytes",
    "require_memory",
    "ContactField",
    "DEVICES",
    "array_namespace_for",
    "device_count",
    "device_name",
    "device_memory_bytes",
    "require_device_memory",
    "to_numpy",
]


def check_memory(n: int, kind: Literal["contact", "flow"], *, available: float | None = None) -> int:
    """Estimated bytes for an n×n ``kind`` problem; raises ResourceError if above ``available``.

    ``available`` defaults to the memory the OS reports available. Returns the estimate.
    """
    if kind == "contact":
        need = contact_memory_bytes(n)
    elif kind == "flow":
        need = flow_memory_bytes(n)
    else:
        raise InputError("kind", kind, "allowed: 'contact', 'flow'")
    require_memory(need, f"the {n}x{n} {kind} problem", available)
    return need
