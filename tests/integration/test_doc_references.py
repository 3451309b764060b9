"""Every reference into docs/theory.md resolves: sections (§N.M, §Title) and equations ((eq. N.M)).

The code and the other pages cite the theory page by section number ("docs/theory.md §6.8", "theory
§10.1", a bare "§11.9" in a docstring), by section title ("§Compressible isothermal viscous flow") and
by equation number ("(eq. 6.3)", "eqs. 2.8, 2.10", "equation 10.1": the number \\tag{6.3} that theory.md gives
a displayed equation; another source's equations are cited after its year or page). A
renumbered section or equation must not leave a dangling citation behind. The mathematics is typeset
by a KaTeX copy that the site serves itself, so that the pages work offline.
"""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
THEORY = DOCS / "theory.md"

HEADING = re.compile(r"^#{2,4} (\d+(?:\.\d+)*)\.? +(.+?)\s*$", re.M)
TAG = re.compile(r"\\tag\{([^}]*)\}")
DISPLAY = re.compile(r"^\$\$\n(.*?)\n\$\$$", re.M | re.S)
# §6.8, §2.7–§2.9, §6.2–6.3 (both ends of a range are references); a § right after a year cites
# that book's section ("Johnson 1985, §4.2"), not the theory page
SECTION_REF = re.compile(r"(?<![0-9] )(?<![0-9], )§ ?(\d+(?:\.\d+)*)(?:\s*[–-]\s*§? ?(\d+(?:\.\d+)*))?")
TITLE_REF = re.compile(r"§([A-Z][^()§]*?)\)")
# "(eq. 6.3)", "eqs. 2.8, 2.10", "eqs. 3.2–3.5", "equation 10.1": a number N.k after eq./eqs./equation(s)
# names theory.md's displayed equation (N.k). An equation of another source is cited after that source's
# year or page ("Johnson 1985 eq. 4.43", "(1985) eqs. 4.43, 4.45", "(2004) 501, eq. 5.4") and is left alone.
EQUATION_REF = re.compile(r"(?<!\d\d\d\d )(?<!\d\d\d\d\) )(?<!\d\d\d, )\b(?:[Ee]qs?\.|[Ee]quations?) ?\(?"
                          r"(\d+\.\d+(?: ?(?:,|–|-|and) ?\d+\.\d+)*)")
NUMBER = re.compile(r"\d+\.\d+")


def _theory() -> str:
    return THEORY.read_text(encoding="utf-8")


def _sections() -> dict[str, str]:
    return {number: title for number, title in HEADING.findall(_theory())}


def _citing_files() -> list[Path]:
    files = sorted((ROOT / "src").rglob("*.py")) + sorted((ROOT / "tests").rglob("*.py"))
    files += sorted(p for p in DOCS.rglob("*.md") if "vendor" not in p.parts)
    return [p for p in files if p != Path(__file__).resolve()] + [ROOT / "README.md"]


def _strip_trailing_dot(number: str) -> str:
    return number.rstrip(".")


def _references(pattern: re.Pattern[str]) -> list[tuple[str, int, str]]:
    """(file relative to the root, line, matched text) of every match of ``pattern`` in the citing files."""
    found = []
    for path in _citing_files():
        text = path.read_text(encoding="utf-8")
        for match in pattern.finditer(text):
            line = text.count("\n", 0, match.start()) + 1
            found.append((str(path.relative_to(ROOT)), line, match.group(0)))
    return found


def test_theory_sections_are_numbered_once_and_in_order():
    numbers = [number for number, _ in HEADING.findall(_theory())]
    assert len(numbers) == len(set(numbers)), "a section number is used twice"
    keys = [tuple(int(part) for part in n.split(".")) for n in numbers]
    assert keys == sorted(keys), "sections out of order"
    # the numbers the code cites most; renumbering them would orphan their citations
    assert {"2.7", "3.5", "6.7", "6.8", "9.11", "10.1", "11.7", "11.7.1", "11.9", "11.9.1"} <= set(numbers)


def test_every_section_reference_resolves():
    sections = _sections()
    refs = _references(SECTION_REF)
    assert len(refs) > 200  # the pattern finds the citations; it cannot pass by matching nothing
    dangling = []
    for file, line, text in refs:
        match = SECTION_REF.fullmatch(text)
        assert match is not None
        for number in filter(None, match.groups()):
            if _strip_trailing_dot(number) not in sections:
                dangling.append(f"{file}:{line}: {text}")
    assert not dangling, "references to sections docs/theory.md does not have:\n" + "\n".join(dangling)


def test_every_section_title_reference_resolves():
    titles = [title for title in _sections().values()]
    refs = _references(TITLE_REF)
    assert refs
    dangling = [f"{file}:{line}: {text}" for file, line, text in refs
                if not any(title.startswith(" ".join(text[1:-1].split())) for title in titles)]
    assert not dangling, "references to section titles docs/theory.md does not have:\n" + "\n".join(dangling)


def test_every_equation_is_numbered_once_in_its_chapter():
    text = _theory()
    chapters = [(m.start(), int(m.group(1))) for m in re.finditer(r"^## (\d+)\. ", text, re.M)]
    displays = list(DISPLAY.finditer(text))
    assert len(displays) > 50
    seen: dict[int, int] = {}
    for display in displays:
        tags = TAG.findall(display.group(1))
        assert len(tags) == 1, f"a displayed equation needs exactly one number: {display.group(1)[:80]}"
        chapter = max(number for start, number in chapters if start < display.start())
        seen[chapter] = seen.get(chapter, 0) + 1
        assert tags[0] == f"{chapter}.{seen[chapter]}", f"equation ({tags[0]}) in chapter {chapter}"
    assert len(TAG.findall(text)) == len(displays), "a \\tag outside a displayed equation"


def _dangling_equations(refs: list[tuple[str, int, str]], tags: set[str]) -> list[str]:
    return [f"{file}:{line}: {text}" for file, line, text in refs
            for number in NUMBER.findall(EQUATION_REF.fullmatch(text).group(1)) if number not in tags]


def test_every_equation_reference_resolves():
    tags = set(TAG.findall(_theory()))
    refs = _references(EQUATION_REF)
    # theory.md's introduction cites one; the physics docstrings cite the equations they evaluate
    assert len(refs) > 40
    assert sum(file.startswith("src/sealeak/physics/") for file, _, _ in refs) >= 25
    dangling = _dangling_equations(refs, tags)
    assert not dangling, "references to equations docs/theory.md does not have:\n" + "\n".join(dangling)


def test_a_wrong_equation_number_is_caught():
    tags = set(TAG.findall(_theory()))
    refs = [("src/x.py", 1, m.group(0)) for m in EQUATION_REF.finditer(
        "G(ζ) (eq. 2.3); ū (eqs. 2.8, 2.99); band (equation 10.1); gas (eqs. 11.11–11.40)")]
    assert _dangling_equations(refs, tags) == ["src/x.py:1: eqs. 2.8, 2.99", "src/x.py:1: eqs. 11.11–11.40"]


def test_the_patterns_see_what_they_should():
    """A broken reference would be caught: the patterns find each form the code uses."""
    sample = ("docs/theory.md §11.3; theory §6.8; (§2.7–§2.9); §6.2–6.3; (eq. 6.3); (eqs. 2.1, 2.4); "
              "(Johnson 1985, §4.2; Johnson 1985 §13.2); §2.3, eq. 2.3; eqs. 3.2–3.5; equation 10.1; "
              "Eq. (10.2); Johnson 1985 eq. 4.43; Contact Mechanics (1985) eqs. 4.43, 4.45; SIAM Review 46 (2004) 501, eq. 5.4")
    numbers = [n for m in SECTION_REF.finditer(sample) for n in m.groups() if n]
    assert numbers == ["11.3", "6.8", "2.7", "2.9", "6.2", "6.3", "2.3"]
    assert [NUMBER.findall(m.group(1)) for m in EQUATION_REF.finditer(sample)] == [
        ["6.3"], ["2.1", "2.4"], ["2.3"], ["3.2", "3.5"], ["10.1"], ["10.2"]]
    assert "99.1" not in _sections() and "99.1" not in TAG.findall(_theory())


def test_the_math_library_is_served_by_the_site():
    config = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")

    def listed(key: str) -> list[str]:
        block = re.search(rf"^{key}:\n((?:  - .*\n)+)", config, re.M)
        assert block, f"mkdocs.yml has no {key} list"
        return re.findall(r"^  - (\S+)", block.group(1), re.M)

    assets = listed("extra_javascript") + listed("extra_css")
    assert any("katex" in asset for asset in assets)
    for asset in assets:
        assert not re.match(r"^(https?:)?//", asset), f"{asset}: the pages must work offline"
        assert (DOCS / asset).is_file(), asset
    assert re.search(r"^  - pymdownx\.arithmatex:", config, re.M)
    katex = DOCS / "vendor" / "katex"
    assert "MIT License" in (katex / "LICENSE").read_text(encoding="utf-8")
    css = (katex / "katex.min.css").read_text(encoding="utf-8")
    fonts = set(re.findall(r"url\((fonts/[^)]+\.woff2)\)", css))
    assert fonts and all((katex / font).is_file() for font in fonts)


@pytest.mark.parametrize("page", ["architecture.md", "user-guide.md"])
def test_moved_implementation_notes_are_linked_from_theory(page):
    assert f"]({page}#" in _theory()
