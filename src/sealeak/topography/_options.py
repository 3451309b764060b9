"""The options of a surface analysis as a user types them (text) → the keyword arguments of :func:`analyze`.

``sealeak surface analyze`` and the web app's ``POST /api/surface/analyze`` both read their unit and
range options through :func:`analysis_options`, so both refuse the same values with the same
message, naming the command-line option (``--size``, ``--resolution``, ...).
"""

from __future__ import annotations

from typing import Any

from ..errors import InputError
from ..io.units import parse_quantity, split_quantities

__all__ = ["analysis_options", "lengths_option"]


def lengths_option(text: str | None, field: str) -> float | tuple[float, float] | None:
    """``'1 mm'`` → 1e-3 m; ``'1 mm, 0.5 mm'`` → (1e-3, 5e-4) m; None → None. Each length must be > 0."""
    if text is None:
        return None
    parts = split_quantities(field, text)
    values = [parse_quantity(field, p, "length") for p in parts]
    for v, p in zip(values, parts):
        if v <= 0:
            raise InputError(field, p, "must be a length > 0")
    return values[0] if len(values) == 1 else (values[0], values[1])


def analysis_options(*, size: str | None = None, pixel_size: str | None = None, height_unit: str | None = None,
                     lateral_unit: str | None = None, periodic: bool = False, channel: str | None = None,
                     bins_per_decade: float = 10.0, low_cut: float = 3.0, resolution: str | None = None,
                     resolution_pixels: float = 4.0) -> dict[str, Any]:
    """The unit and reliable-range keyword arguments of :func:`~sealeak.topography.analyze`.

    Lengths are text with units (``size = "1 mm, 0.5 mm"``, ``resolution = "2 um"``) and come out in
    metres; the messages name the command-line options (``--size``, ``--pixel-size``, ``--resolution``).
    """
    if size and pixel_size:
        raise InputError("--size", size, "give either --size or --pixel-size, not both")
    out: dict[str, Any] = dict(size=lengths_option(size, "--size"), pixel_size=lengths_option(pixel_size, "--pixel-size"),
                               height_unit=height_unit, lateral_unit=lateral_unit, periodic=periodic, channel=channel,
                               bins_per_decade=bins_per_decade, low_cut=low_cut, resolution_pixels=resolution_pixels)
    if resolution is not None:
        value = parse_quantity("--resolution", resolution, "length")
        if not value > 0:
            raise InputError("--resolution", resolution, "must be a length > 0, e.g. '2 um'")
        out["resolution"] = value
    return out
