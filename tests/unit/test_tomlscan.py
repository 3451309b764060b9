"""The TOML pre-scan: refuses long dotted keys, deep nesting and long bare words before tomllib reads the text,
in time and memory linear in the text; refuses nothing valid within the limits (strings, comments, dates)."""

import ast
import random
import time
import tomllib
import tracemalloc
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sealeak.cases import example_names, example_text
from sealeak.errors import FileFormatError
from sealeak.io import tomlscan
from sealeak.io.tomlscan import MAX_BARE, MAX_DEPTH, MAX_KEY_PARTS, parse_toml, scan_toml

TESTS = Path(__file__).resolve().parents[1]


def depth(doc):
    """Deepest level of the parsed document: every table and array, and every value a table holds (root: 0)."""
    best, todo = 0, [(doc, 0)]
    while todo:
        node, d = todo.pop()
        if isinstance(node, dict):
            best = max(best, d, d + bool(node))
            todo += [(v, d + 1) for v in node.values()]
        elif isinstance(node, list):
            best = max(best, d)
            todo += [(v, d + 1) for v in node]
    return best


# ------------------------------------------------------------------------------- what is refused, and how
HOSTILE = {
    "dotted key": ("x" + ".x" * 20_000 + " = 1", "dotted key", MAX_KEY_PARTS),
    "table header": ("[" + ".".join(["a"] * 40) + "]\n", "dotted key", MAX_KEY_PARTS),
    "inline tables": ("x = " + "{a = " * 5_000 + "1" + "}" * 5_000, "nested", MAX_DEPTH),
    "arrays": ("x = " + "[" * 100_000 + "]" * 100_000, "nested", MAX_DEPTH),
    "array of tables": ("[[" + ".".join(["a"] * 31) + "]]\nx.y = [1]\n", "nested", MAX_DEPTH),
    "dotted keys in inline tables": ("x = " + "{a.b.c.d = " * 10 + "1" + "}" * 10, "nested", MAX_DEPTH),
    "long integer": ("x = " + "1" * 5_000, "5000 characters", MAX_BARE),
}


@pytest.mark.parametrize("text, what, limit", HOSTILE.values(), ids=list(HOSTILE))
def test_hostile_text_is_refused_in_one_line_naming_source_line_and_limit(text, what, limit):
    with pytest.raises(FileFormatError) as err:
        parse_toml("# a comment\n" + text, "case.toml")
    message = str(err.value)
    assert message.startswith("case.toml: line ") and "\n" not in message and len(message) < 250, message
    assert what in message and f"at most {limit}" in message, message


def test_the_line_named_is_the_line_of_the_offence():
    text = 'a = """\n[[[\n"""\n# [[[[\nb = 1\n' + "c = " + "[" * 40 + "]" * 40 + "\n"
    with pytest.raises(FileFormatError, match=r"^t: line 6: "):
        scan_toml(text, "t")


@pytest.mark.parametrize("limit", [MAX_DEPTH, MAX_KEY_PARTS])
def test_up_to_the_limit_is_accepted(limit):
    assert limit == 32  # the documented limits (docs/case-files.md, Limits)
    assert depth(parse_toml("x = " + "[" * (MAX_DEPTH - 1) + "1" + "]" * (MAX_DEPTH - 1))) == MAX_DEPTH - 1
    assert depth(parse_toml(".".join(["k"] * MAX_KEY_PARTS) + " = 1")) == MAX_KEY_PARTS
    assert parse_toml("[" + ".".join(["k"] * MAX_KEY_PARTS) + "]")


def test_an_integer_too_long_for_python_is_a_format_error_not_a_traceback():
    with pytest.raises(FileFormatError, match=f"at most {MAX_BARE}"):
        parse_toml("x = " + "9" * 4400)


def test_malformed_toml_is_one_line_naming_the_source():
    with pytest.raises(FileFormatError, match=r"^c\.toml: malformed TOML: .*line 2"):
        parse_toml("a = 1\nb = [1,,]\n", "c.toml")


# ------------------------------------------------------------------------------- nothing valid is refused
LOOKALIKES = [
    'a = "[[[[{{{{ . . . # not a comment"',
    "a = '[[[[.....]]]]'",
    'a = """\n[[[[\n{{{{\n"quoted" ""twice"" # x\n"""',
    "a = '''\n[[[[ '' ''\n'''",
    'a = """ends with two quotes"""""',
    'a = "escaped \\" [[[[ quote"',
    'a = """\\\n   continued [[[ \\""" still in"""',
    "# [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[ in a comment\na = 1",
    '"a.b.c.d.e.f.g.h.i.j.k.l.m.n.o.p.q.r.s.t.u.v.w.x.y.z.1.2.3.4.5.6.7.8.9" = 1',
    "a = 1979-05-27T07:32:00.999999-07:00\nb = 1.5e-3\nc = [1.5, 2.5, 3.5]",
    'a = [\n  1, # [[[ comment in an array\n  2,\n]',
    "a = {}\nb = []\nc = [[], [[]], {}]",
    "[[a.b]]\nc = 1\n[[a.b]]\nc = 2\n[ x . 'y.z' . \"w]\" ]\nk = 1",
    "a = '''''\n[[[['''''",
]


@pytest.mark.parametrize("text", LOOKALIKES)
def test_brackets_dots_and_hashes_in_strings_and_comments_count_for_nothing(text, monkeypatch):
    doc = tomllib.loads(text)
    monkeypatch.setattr(tomlscan, "MAX_DEPTH", depth(doc))
    monkeypatch.setattr(tomlscan, "MAX_KEY_PARTS", 3)
    assert parse_toml(text) == doc


def _case_texts_in_tests():
    """Every multi-line string constant of the test modules that tomllib reads as TOML (found with ast)."""
    for path in sorted(TESTS.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and "\n" in node.value and "=" in node.value:
                try:
                    yield path.name, node.value, tomllib.loads(node.value)
                except tomllib.TOMLDecodeError:  # a fragment, edited before use
                    continue


def test_every_bundled_example_and_every_case_text_of_the_tests_passes():
    texts = [(n, example_text(n), tomllib.loads(example_text(n))) for n in example_names()]
    texts += list(_case_texts_in_tests())
    assert len(texts) > len(example_names()) + 40
    for name, text, doc in texts:
        assert parse_toml(text, name) == doc, name


# ----------------------------------------------------- the scanner's depth is the document's, on random TOML
_KEYS = ["a", "b_1", "-", "2", '"q.[#]"', "'l]{.'", '"x\\"y["']
_SCALARS = ["1", "1.5", "-2e3", "true", "1979-05-27T07:32:00.999", '"s [ { . # ]"', "'lit [#.'",
            '"""\nml [ " ""\n{"""', "'''ml'' [\n.'''", '"""a"""""']


def _key(r, n):
    parts = [r.choice(_KEYS) for _ in range(r.randint(0, 3))] + [f"k{n}"]
    return r.choice([".", " . ", "."]).join(parts)


def _value(r, level, counter):
    kind = r.random() if level < 7 else 0.0
    if kind < 0.45:
        return r.choice(_SCALARS)
    if kind < 0.75:
        items = [_value(r, level + 1, counter) for _ in range(r.randint(0, 3))]
        sep = r.choice([", ", ",\n  ", ", # ]] [[ {\n"])
        return "[" + sep.join(items) + (r.choice(["", ","]) if items else "") + "]"
    counter[0] += 1
    items = [f"{_key(r, counter[0] * 10 + i)} = {_value(r, level + 1, counter)}" for i in range(r.randint(0, 3))]
    return "{" + ", ".join(items) + "}" if "\n" not in "".join(items) else r.choice(_SCALARS[:6])


def _document(r):
    lines, counter = [], [0]
    for n in range(r.randint(1, 6)):
        if r.random() < 0.3:
            counter[0] += 1
            name = f"h{counter[0]}" + "".join(r.choice([".", " . "]) + r.choice(_KEYS[:4]) for _ in range(r.randint(0, 3)))
            lines.append(r.choice(["[{}]", "[[{}]]"]).format(name) + r.choice(["", "  # [[{{"]))
        for i in range(r.randint(0, 3)):
            counter[0] += 1
            lines.append(f"{_key(r, counter[0])} = {_value(r, 0, counter)}" + r.choice(["", " # ]]]"]))
    return "\n".join(lines) + "\n"


def _mutated(r, text, n):
    """``text`` with ``n`` characters inserted or deleted: TOML that may or may not still parse."""
    for _ in range(n):
        i = r.randrange(len(text) + 1)
        text = text[:i] + r.choice('[]{}"\'#=,.\n \\') + text[i:] if r.random() < 0.7 else text[:i] + text[i + 1:]
    return text


@settings(max_examples=400, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 8), st.integers(0, 3))
def test_the_scan_refuses_exactly_the_documents_nested_deeper_than_the_limit(seed, limit, mutations):
    """Random documents (valid, or mutated into what tomllib may still accept): the scan stops reading only
    where tomllib fails, so whatever tomllib reads was measured."""
    r = random.Random(seed)
    text = _mutated(r, _document(r), mutations)
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError:  # e.g. a key given twice: nothing to compare
        return
    saved = tomlscan.MAX_DEPTH
    tomlscan.MAX_DEPTH = limit
    try:
        scan_toml(text)
        refused = False
    except FileFormatError:
        refused = True
    finally:
        tomlscan.MAX_DEPTH = saved
    assert refused == (depth(doc) > limit), (text, depth(doc))


# ---------------------------------------------------------------------------- linear time and memory
@pytest.mark.parametrize("text", [
    "".join(f"k{i} = [1, 2]\n" for i in range(80_000)),  # valid, about 1 MB
    "x = [" + "1e3, " * 200_000 + "]",
    'x = "' + "[" * 1_000_000 + '"',
    '"""' * 300_000,
    "x = " + "[" * 1_000_000,
    "x" + ".x" * 500_000 + " = 1",
], ids=["keys", "long list", "long string", "quotes", "open brackets", "dotted key"])
def test_a_megabyte_scans_quickly_in_bounded_memory(text):
    tracemalloc.start()
    start = time.perf_counter()
    try:
        scan_toml(text)
    except FileFormatError:
        pass
    elapsed = time.perf_counter() - start
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 20e6, peak  # a few times the text at most, never a copy per token
    assert elapsed < 20, elapsed  # linear: about a second per megabyte on a slow shared machine
