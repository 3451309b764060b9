"""The wording of structured notes (sealeak.render.notes): loads and pressures written one way, every code worded."""

from __future__ import annotations

import ast
import json
import pickle
import re
from pathlib import Path

import pytest

import sealeak.cases
from sealeak.cases.notes import Note
from sealeak.render.notes import _WORDING, kpa_text, load_text, loads_text, word, worded


def test_a_compression_is_written_in_percent_by_name():
    assert load_text("compression", 0.15) == "compression 15 %"
    assert loads_text("compression", [0.15, 0.2]) == "compression 15, 20 %"
    assert load_text("profile_scale", 1.5) == "profile scale 1.5"


def test_a_squeeze_pressure_is_named_as_p0_in_kpa_like_the_other_loads():
    assert load_text("squeeze_pressure", 2e5) == "P0 = 200 kPa" == loads_text("squeeze_pressure", [2e5])


def test_band_notes_name_the_theory_and_the_loads():
    sealed = word(Note("band_sealed", {"theory": "effective medium", "load_name": "compression", "loads": (0.25, 0.3)}))
    assert sealed.startswith("effective medium: no leak channel at compression 25, 30 %")
    slow = word(Note("band_not_converged", {"theory": "critical junction", "tolerance": 1e-5,
                                             "load_name": "profile_scale", "load": 1.5, "change": 3e-5}))
    assert "converge to 1e-05 at profile scale 1.5" in slow and "last relative change 3e-05" in slow


def test_many_loads_or_pressures_are_written_as_their_range_and_count():
    many = loads_text("profile_scale", [1.0, 1.5, 2.0, 2.5, 3.0])
    assert many.startswith("profile scale 1 .. 3") and "(5 values)" in many
    assert kpa_text([73e3, 100e3]) == "P0 = 73, 100 kPa"
    assert kpa_text([73e3, 80e3, 90e3, 100e3, 234e3]) == "P0 = 73 .. 234 kPa (5 pressures)"


def test_a_sentence_passes_unchanged_and_a_note_is_worded_with_its_values():
    note = Note("band_touches_edge", {"load_name": "compression", "loads": (0.25, 0.3)})
    assert worded(["as it was", note]) == ["as it was", word(note)]
    assert "compression 25, 30 %" in word(note) and "edge of the domain" in word(note)


def test_junction_note_names_only_the_parts_that_apply():
    both = {"grid": 32, "cut_at": None, "zeta_1": 8.0, "min_cells": 8, "coarse": (1e5,), "at_end": (2e5,)}
    text = word(Note("junction_unresolved", both))
    assert "P0 = 100 kPa" in text and "P0 = 200 kPa" in text and "32x32" in text
    coarse_only = word(Note("junction_unresolved", both | {"at_end": ()}))
    assert "very end" not in coarse_only and "P0 = 100 kPa" in coarse_only


def test_notes_survive_pickling_for_the_parallel_runs():
    note = Note("smooth_check_off", {"load_name": "compression", "load": 0.2, "width_error": 0.1,
                                     "pressure_error": -0.05, "tolerance": 0.05, "cells": 12.0, "grid_field": "--grid"})
    assert pickle.loads(pickle.dumps(note)) == note
    assert "compression 20 %" in word(note) and "--grid" in word(note)


def test_an_unknown_code_is_a_programming_error_not_a_silent_blank():
    with pytest.raises(KeyError):
        word(Note("no_such_code"))


# ---------------------------------------------------------------------- the cases layer words no note itself
CASES = Path(sealeak.cases.__file__).parent
#: Lists a result's notes are gathered in: a name that ends in "messages" or "notes" (map_notes, cut_notes, ...).
NOTE_LIST = re.compile(r"(messages|notes)$")


def _name(node: ast.expr) -> str:
    """The name a list is reached by: ``notes``, ``self.notes``, ``notes[-1]`` -> "notes"."""
    while isinstance(node, ast.Subscript):
        node = node.value
    return node.id if isinstance(node, ast.Name) else node.attr if isinstance(node, ast.Attribute) else ""


def _sentences(node: ast.AST) -> list[ast.JoinedStr]:
    """The f-strings in ``node``, but those inside a ``Note(...)`` (a note's plain values may be any text)."""
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "Note":
        return []
    if isinstance(node, ast.JoinedStr):
        return [node]
    return [s for child in ast.iter_child_nodes(node) for s in _sentences(child)]


def worded_in_cases(source: str) -> list[int]:
    """Lines of ``source`` where an f-string goes into a ``messages``/``notes`` list (append, extend, +=, ... = [...])."""
    lines = []
    for node in ast.walk(ast.parse(source)):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
                and node.func.attr in ("append", "extend", "insert") and NOTE_LIST.search(_name(node.func.value))):
            values: list[ast.AST] = list(node.args)
        elif isinstance(node, ast.AugAssign) and NOTE_LIST.search(_name(node.target)):
            values = [node.value]
        elif isinstance(node, (ast.Assign, ast.AnnAssign)) and node.value is not None and any(
                NOTE_LIST.search(_name(t)) for t in (node.targets if isinstance(node, ast.Assign) else [node.target])):
            values = [node.value]
        else:
            continue
        lines += [s.lineno for v in values for s in _sentences(v)]
    return lines


@pytest.mark.parametrize("source", [
    'messages.append(f"{name}: no leak at P0 = {p0:.6g} Pa")',
    'self.notes += [f"cut to {side:.4g} m"]',
    'notes[-1] += f" (h_rms {a:.4g} µm)"',
    'map_notes: list[NoteLike] = [f"{label}: {n}" for n in notes]',
    'messages.extend(f"line {i}" for i in lines)',
])
def test_the_scan_finds_a_sentence_built_in_the_cases_layer(source):
    assert worded_in_cases(source) == [1]


def test_the_scan_lets_a_note_with_plain_values_pass():
    assert worded_in_cases('notes.append(Note("of_map", {"label": f"{name} [window 1,1]", "note": n}))') == []
    assert worded_in_cases('warnings.append(f"check {x}")\nmessages += [strained + "; check [rig] load"]') == []


#: The case builders: what they say about a case's inputs (input warnings, a band seal's source line) is worded
#: where the input is read, with the InputError messages; the scan is of the notes about results.
CASE_BUILDERS = {"builders.py", "seals.py"}


def test_no_module_of_the_cases_layer_words_a_note_itself():
    found = {path.name: lines for path in sorted(CASES.glob("*.py"))
             if path.name not in CASE_BUILDERS and (lines := worded_in_cases(path.read_text(encoding="utf-8")))}
    assert found == {}, f"f-strings put into messages/notes (word them in sealeak/render/notes.py): {found}"


def test_every_code_the_cases_layer_uses_has_its_wording_and_every_wording_a_use():
    used = {code for path in CASES.glob("*.py")
            for code in re.findall(r'\bNote\(\s*"(\w+)"', path.read_text(encoding="utf-8"))}
    assert len(used) > 20  # the scan found the codes at all
    assert used - _WORDING.keys() == set(), "codes without a wording"
    assert _WORDING.keys() - used == set(), "wordings no note uses"


def test_a_map_note_is_prefixed_with_its_map_and_a_note_kept_by_a_task_record_comes_back():
    inner = Note("map_resampled", {"points": (72, 72), "grid": 16})
    assert word(Note("of_map", {"label": "scan.npy", "note": inner})) == \
        "scan.npy: resampled from 72x72 to the 16x16 solver grid (Fourier)"
    kept = Note("threshold_not_found", {"realization": 2, "still_spans": False, "squeeze_pressure": 4.1e7})
    back = Note.of(json.loads(json.dumps(kept.to_mapping())))
    assert back == kept and word(back).startswith("realisation 2: the fluid does not span even at P0 = 4.1e+07 Pa")
    assert Note.of("a sentence an older record kept") == "a sentence an older record kept"


def test_a_grid_cut_note_says_how_much_roughness_the_cut_left_only_when_it_knows():
    values = {"grid": 64, "q_cut": 1e5, "q1": 1e6, "points_per_wavelength": 4, "theory": "critical-junction"}
    plain = word(Note("spectrum_cut_by_grid", values))
    assert "64x64 grid resolves q up to 1e+05 1/m" in plain and "h_rms" not in plain
    assert word(Note("spectrum_cut_by_grid", values | {"h_rms": (2e-6, 1.5e-6)})).endswith(" (h_rms 2 -> 1.5 µm)")
