"""Write the tables of docs/outputs.md: every field of the JSON/CSV outputs with its unit and description.

Each result dataclass declares the unit and description of its record fields once
(:func:`sealeak.io.quantities.quantity`); this script lists them per output, between the markers
``<!-- output-fields:start -->`` and ``<!-- output-fields:end -->`` of docs/outputs.md, so the
reference cannot drift from what the code writes.

Usage (from the repository root)::

    .venv/bin/python tools/output_fields.py           # rewrite the tables
    .venv/bin/python tools/output_fields.py --check   # exit 1 if docs/outputs.md differs

tests/unit/test_output_fields_doc.py checks that docs/outputs.md is what this script writes.
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path
from typing import Any

from sealeak.cases import SimulationResult
from sealeak.cases.band import BandColumns, BandEffectiveMediumColumns
from sealeak.cases.capillarity import CapillaryColumns
from sealeak.cases.convergence import Extrapolation, GridStatistics
from sealeak.cases.gas import GasColumns, HeliumColumns, PermeationColumns
from sealeak.cases.leak_tests import DecayPrediction
from sealeak.cases.life_answers import LifeAnswer
from sealeak.cases.linearity_check import LinearityCheck
from sealeak.cases.model import BandSeal, LifePoint
from sealeak.cases.pipeline import GasSimulation
from sealeak.cases.rig import RigPrediction
from sealeak.cases.run import CaseResult
from sealeak.cases.simulation import SimulationCapillarity, SweepRecord, ThresholdRecord
from sealeak.cases.simulation_band import BandRecord, BandSimulationResult
from sealeak.cases.simulation_map import MapInfo, MapSimulationResult
from sealeak.cases.sobol import SensitivityColumns
from sealeak.cases.uncertainty import PassingLoad, UncertaintyColumns
from sealeak.lab.data import LeakData
from sealeak.lab.fitting import LinearFit, ScaleFit
from sealeak.lab.pressure_decay import DecayReadings, PressureDecaySetup, ScaleFromDecay
from sealeak.lab.rig import DecayRigSetup, ReadingsAnalysis, RigSetup
from sealeak.physics.critical_junction import CriticalJunctionResult
from sealeak.physics.effective_medium import EffectiveMediumResult
from sealeak.physics.gas import Gas
from sealeak.physics.spectrum import PowerSpectrum
from sealeak.render.lab import DecayModelRecord, GasFitRow, RigCapillaryRecord, RigModelRecord
from sealeak.topography import BinnedSpectrum, SurfaceStatistics, Topography

DOC = Path(__file__).resolve().parents[1] / "docs" / "outputs.md"
START, END = "<!-- output-fields:start -->", "<!-- output-fields:end -->"

#: (heading, what the section covers, the dataclasses whose fields it lists; a key listed once, first class wins).
SECTIONS: tuple[tuple[str, str, tuple[Any, ...]], ...] = (
    ("sealeak predict --json / --csv",
     "Each object of `results` (JSON) or row (CSV), one per squeeze pressure; a band seal's rows lead with its "
     "load (`compression` or `profile_scale`) and list the band fields instead of the uniform seal's. The "
     "effective-medium fields join when the case asks for that model, the gas fields for a gas (the permeation "
     "fields for a gas case with `rubber.permeability`), the capillarity fields for a liquid with a contact "
     "angle (`_effective_medium` added for that model's). A case of the seal over its life (`[conditions] time` or "
     "`temperature`, `[rubber] relaxation`) leads each row with `time`, `temperature` and `modulus`.",
     (LifePoint, CriticalJunctionResult, EffectiveMediumResult, BandColumns, BandEffectiveMediumColumns, CaseResult,
      GasColumns, HeliumColumns, PermeationColumns, CapillaryColumns)),
    ("sealeak predict --json / --csv (uncertain inputs)",
     "A case file with uncertain inputs (docs/case-files.md, Uncertain inputs) adds these fields to each row; the gas "
     "and helium percentiles where the row has those leak rates, `exceed_probability` with `conditions.max_leak_rate`. "
     "A case file with `conditions.max_leak_rate` but no uncertain input is the nominal prediction alone: its rows add "
     "only `exceed_probability` (0: passes, 1: fails), and its `uncertainty` object has `samples` 0 and no `sampler`, "
     "`seed` or `percentiles` (nothing was sampled). The JSON's `uncertainty` object lists per case its "
     "`passing_loads` (`<load>`: `Pa` for a squeeze pressure, `1` "
     "for a compression or profile scale) and, for the seal over its life with `conditions.max_leak_rate`, per load "
     "its `life` answers (`load`, its `values` in `unit`, and the fields below from `temperatures` on); its `answers` "
     "are the same in words, the sentences `predict` prints under its uncertainty table.",
     (UncertaintyColumns, PassingLoad, LifeAnswer)),
    ("sealeak predict --sensitivity N --json / --csv",
     "With `--sensitivity N` each row adds, per uncertain input (`<input>`: its case-file key, e.g. "
     "`sobol_total[surface.h_rms]`), the Sobol' indices of log10 Q and their intervals (docs/theory.md §15); the JSON's "
     "`sensitivity` object says how they were computed, per row the share of sealed samples and the floor they count "
     "at, and per case one sentence in plain words.",
     (SensitivityColumns,)),
    ("sealeak simulate --json",
     "A uniform seal's per-pressure records (a gas adds its gas leak), then an O-ring's per-compression records; "
     "for an O-ring the gas leak's `leak_rate_pv_critical_junction` is named `leak_rate_pv_series_resistance`; a "
     "liquid with a contact angle adds the capillarity keys.",
     (SimulationResult, GasSimulation, SimulationCapillarity, BandSimulationResult)),
    ("sealeak simulate --json (measured maps: --surface maps)",
     "Per map (or sub-window) its statistics, and per map and squeeze pressure the exact flow and α against both "
     "theories of the map's own C(q).",
     (MapSimulationResult, MapInfo)),
    ("sealeak simulate --grid N1,N2,... --json (a convergence study)",
     "Beside each grid's `simulate` records: the grid's statistics, and each extrapolation to a → 0.",
     (GridStatistics, Extrapolation)),
    ("sealeak fit --json",
     "Per model the fitted α; a gas fit's `rows` hold each row's leak rates (`<model>`: each model's name).",
     (ScaleFit, LeakData, GasFitRow)),
    ("sealeak fit --linearity --json", "The line Q = slope ΔP + intercept and the models' slopes at P0. The per-model "
     "objects (`model_slopes`, `model_intercepts`, `model_nonlinearity`, `capillary_entry_pressure`) are keyed "
     "`critical_junction` and `effective_medium`; `model_labels` gives each its display name (`critical junction (α = 0.2)`).",
     (LinearFit, LinearityCheck)),
    ("sealeak rig --json (a water column)",
     "The load, each model's `models` object and, with `--readings`, the readings; a band seal adds its load and "
     "`band` (the band fields of `predict`, the seal line length and faces); a liquid with a contact angle adds "
     "to each model its capillary entry pressure and where the level stops.",
     (RigPrediction, RigSetup, RigModelRecord, RigCapillaryRecord, ReadingsAnalysis, BandSeal)),
    ("sealeak rig --json (a pressure-decay test)",
     "The test, each model's `models` object and, with `--readings`, the readings and the factor they imply.",
     (DecayPrediction, DecayRigSetup, PressureDecaySetup, Gas, DecayModelRecord, DecayReadings, ScaleFromDecay)),
    ("sealeak surface analyze --json", "The statistics (per source and combined), C(q) and each source's map.",
     (SurfaceStatistics, PowerSpectrum, Topography, BinnedSpectrum)),
    ("Task records of a store (simulate --store DIR: DIR/tasks/*.json)",
     "What each task of an ensemble returns, per load, kept in `result` (plain JSON values).",
     (SweepRecord, ThresholdRecord, BandRecord)),
)


def _fields(classes: tuple[Any, ...]) -> dict[str, tuple[str, str]]:
    """``{record key: (unit, description)}`` of the classes' declared fields, the first class declaring a key wins."""
    out: dict[str, tuple[str, str]] = {}
    for cls in classes:
        for f in dataclasses.fields(cls):
            if "unit" in f.metadata:
                out.setdefault(f.metadata.get("key", f.name), (f.metadata["unit"], f.metadata["description"]))
    return out


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def tables() -> str:
    """The Markdown between the markers: one table per section."""
    lines: list[str] = []
    for heading, what, classes in SECTIONS:
        lines += [f"### {heading}", "", what, "", "| field | unit | description |", "| --- | --- | --- |"]
        for key, (unit, description) in _fields(classes).items():
            shown = {"": "text", "1": "1 (dimensionless)"}.get(unit, f"`{unit}`")
            lines.append(f"| `{key}` | {shown} | {_cell(description)} |")
        lines.append("")
    return "\n".join(lines)


def rewritten(text: str) -> str:
    """``text`` (docs/outputs.md) with the part between the markers replaced by :func:`tables`."""
    head, rest = text.split(START, 1)
    _, tail = rest.split(END, 1)
    return f"{head}{START}\n\n{tables()}\n{END}{tail}"


def main(argv: list[str]) -> int:
    """Rewrite docs/outputs.md, or with ``--check`` return 1 if it differs."""
    text = DOC.read_text(encoding="utf-8")
    new = rewritten(text)
    if "--check" in argv:
        if new != text:
            print(f"{DOC} differs from the fields' metadata: run tools/output_fields.py", file=sys.stderr)
            return 1
        return 0
    DOC.write_text(new, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
