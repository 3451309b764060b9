"""The wording of structured notes (sealeak.render.notes): loads and pressures written one way, every code worded."""

from __future__ import annotations

import pickle

import pytest

from sealeak.cases.notes import Note
from sealeak.render.notes import kpa_text, load_text, loads_text, word, worded


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
