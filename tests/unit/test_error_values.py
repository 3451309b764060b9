"""Values in messages are written as the user wrote them in a case file (TOML), never as Python reprs."""

from __future__ import annotations

import datetime
import tomllib

import pytest

from sealeak.errors import SHOWN_VALUE, InputError, show_value


@pytest.mark.parametrize("toml", ["'abc'", '"it\'s"', "64.0", "64", "0.1", "1e-300", "true", "false", "1979-05-27",
                                  "1979-05-27T07:32:00", "07:32:00", "{foo = 1}", "[1, 'a', [true]]",
                                  '{"a b" = {c = 2.5}}', "nan", "inf"])
def test_a_value_shows_as_toml_that_reads_back_as_the_same_value(toml):
    value = tomllib.loads(f"v = {toml}")["v"]
    shown = show_value(value)
    assert "datetime" not in shown and "True" not in shown and "{'" not in shown
    again = tomllib.loads(f"v = {shown}")["v"]
    assert again == value or (value != value and again != again)  # nan is nan


def test_a_float_keeps_its_decimal_point_where_an_integer_was_expected():
    assert str(InputError("simulation.grid", 64.0, "must be an integer")) == "simulation.grid = 64.0: must be an integer"
    assert str(InputError("simulation.grid", 64, "must be even")) == "simulation.grid = 64: must be even"
    assert show_value(datetime.date(2024, 3, 1)) == "2024-03-01"


def test_long_and_deep_values_are_cut_to_one_line():
    deep: list = []
    for _ in range(5000):
        deep = [deep]
    assert len(show_value(deep)) <= 80 and len(show_value(list(range(10**5)))) <= 80
    assert "\n" not in show_value("a\nb")


def test_a_long_value_keeps_its_start_and_its_end():
    """A path longer than a message shows whole (a deep temporary or project folder) keeps the folder's start and the
    file's name, the parts a user recognises; at most SHOWN_VALUE characters."""
    path = "/home/ana/projects/seals/2026/lab-campaign/" + "x" * 200 + "/runs/grid-2048/plot.jpg"
    shown = str(InputError("--plot", path, "must end in .png, .pdf or .svg"))
    value = shown.split(" = ", 1)[1].split(": must", 1)[0]
    assert len(value) == SHOWN_VALUE and value.startswith("'/home/ana/projects/") and value.endswith("/plot.jpg'")
    assert "..." in value
